// render — a small deterministic random number generator (PCG32, O'Neill 2014) and the
// per-pixel seeding that makes every image reproducible regardless of thread count.
#pragma once

#include <cstdint>

namespace render {

// SplitMix64 finaliser: decorrelates nearby seeds (pixel indices).
inline std::uint64_t mix64(std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

class Pcg32 {
  public:
    Pcg32(std::uint64_t seed, std::uint64_t stream) : inc_((stream << 1u) | 1u) {
        next();
        state_ += seed;
        next();
    }
    std::uint32_t next() {
        const std::uint64_t old = state_;
        state_ = old * 6364136223846793005ull + inc_;
        const std::uint32_t xorshifted = std::uint32_t(((old >> 18u) ^ old) >> 27u);
        const std::uint32_t rot = std::uint32_t(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
    }
    // Uniform in [0, 1): 24 random bits, so the result is never rounded up to 1.
    float uniform() { return float(next() >> 8) * (1.0f / 16777216.0f); }

  private:
    std::uint64_t state_ = 0, inc_;
};

// The generator of pixel (x, y) for a render seed: one stream per pixel, so the image does
// not depend on how tiles are scheduled.
inline Pcg32 pixel_rng(std::uint64_t seed, int x, int y) {
    const std::uint64_t key = (std::uint64_t(std::uint32_t(y)) << 32) | std::uint32_t(x);
    return Pcg32(mix64(seed ^ mix64(key)), mix64(key + 0x632be59bd9b4e019ull));
}

}  // namespace render
