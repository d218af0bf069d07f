#pragma once
// A small generator for tables simulated while a material is built (splitmix64, Steele, Lea
// & Flood 2014): the tables are the same for the same parameters, run after run.
#include <cstdint>

namespace hairscatter {

class SplitMix64 {
  public:
    explicit SplitMix64(std::uint64_t seed) : s_(seed) {}
    // Uniform in [0, 1), 53 bits.
    double uniform() {
        std::uint64_t z = (s_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        z ^= z >> 31;
        return double(z >> 11) * (1.0 / 9007199254740992.0);
    }

  private:
    std::uint64_t s_;
};

}  // namespace hairscatter
