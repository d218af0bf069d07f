// The plain C++ loop that bench/python_bench.py times the module's vectorised eval against:
// ChiangFiber<T>(material, h[i]).eval(wo[i], wi[i]) over N directions held in arrays, as the
// module's loop reads them, with the same parameters (bench/python_bench.py's MODEL).
//
//   python_eval_loop N REPEATS float32|float64   → prints "median_s=… min_s=… checksum=…"
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <hairscatter/hairscatter.hpp>

namespace hs = hairscatter;

namespace {

template <typename T> int run(std::size_t n, int repeats) {
    hs::FiberParams<T> p;
    p.eta = T(1.55), p.beta_m = T(0.3), p.beta_n = T(0.3), p.alpha = T(0.035);
    p.sigma_a = glm::vec<3, T>(glm::dvec3(0.6, 0.9, 1.6));
    const hs::ChiangMaterial<T> material(p);

    // Uniform directions and offsets (64-bit LCG), stored as the module's (N, 3) arrays.
    std::vector<T> wo(3 * n), wi(3 * n), h(n), out(3 * n);
    std::uint64_t state = 12345;
    auto uniform = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return double(state >> 11) * (1.0 / 9007199254740992.0);
    };
    auto direction = [&](T* w) {
        const double z = 2 * uniform() - 1, phi = 6.283185307179586 * uniform(), r = std::sqrt(1 - z * z);
        w[0] = T(z), w[1] = T(r * std::cos(phi)), w[2] = T(r * std::sin(phi));
    };
    for (std::size_t i = 0; i < n; ++i) {
        direction(&wo[3 * i]);
        direction(&wi[3 * i]);
        h[i] = T(2 * uniform() - 1);
    }

    std::vector<double> seconds;
    double checksum = 0;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        for (std::size_t i = 0; i < n; ++i) {
            const glm::vec<3, T> o(wo[3 * i], wo[3 * i + 1], wo[3 * i + 2]), w(wi[3 * i], wi[3 * i + 1], wi[3 * i + 2]);
            const glm::vec<3, T> f = hs::ChiangFiber<T>(material, h[i]).eval(o, w);
            out[3 * i] = f.x, out[3 * i + 1] = f.y, out[3 * i + 2] = f.z;
        }
        seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        for (std::size_t k = 0; k < 3 * n; k += 997) checksum += double(out[k]);
    }
    std::sort(seconds.begin(), seconds.end());
    std::printf("median_s=%.6f min_s=%.6f checksum=%.6g\n", seconds[seconds.size() / 2], seconds.front(), checksum);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: python_eval_loop N REPEATS float32|float64\n");
        return 2;
    }
    const std::size_t n = std::strtoull(argv[1], nullptr, 10);
    const int repeats = std::atoi(argv[2]);
    const std::string dtype = argv[3];
    if (n == 0 || repeats < 1 || (dtype != "float32" && dtype != "float64")) {
        std::fprintf(stderr, "python_eval_loop: bad arguments\n");
        return 2;
    }
    return dtype == "float32" ? run<float>(n, repeats) : run<double>(n, repeats);
}
