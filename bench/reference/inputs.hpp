// Pre-generated benchmark inputs, shared by chiang_bench and bench_crosscheck: 65536
// tuples (wo, wi, u, h) so that neither the RNG nor one cached input is measured, the
// fibers built from them, and the calibration loop's (a, b) pairs.
//
// Why 65536 and not fewer: a branch predictor learns a short cycle of inputs. Where a
// branch depends on the data (the octant of an atan2 chosen by a conditional expression),
// it goes wrong about every other call on a renderer's random directions, but over a cycle
// of 4096 inputs the predictor learned the outcomes, and the benchmarks flattered every
// such branch, ours and the reference's alike. chiang_bench's BM_Atan2Cycle measures the
// difference over cycles of 4096 and 65536 (bench/results/chiang_*.txt).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

#include <hairscatter/hairscatter.hpp>

#include "pbrt_style.hpp"

namespace bench_ref {

constexpr std::size_t kInputs = 65536;  // a power of two: the index wraps with a mask
constexpr std::size_t kMask = kInputs - 1;
// The calibration loop (calibration.hpp) keeps the cycle of 4096 it had when the speed goals
// were stated in its unit: the unit is a yardstick of the machine, and libm's branches make
// it about 1.3× longer over 65536 (chiang_bench's BM_CalibLong), which would move the goals.
constexpr std::size_t kCalibInputs = 4096;
constexpr std::size_t kCalibMask = kCalibInputs - 1;

// β_m cases of the benchmarks (the benchmark argument is the index into this table).
constexpr double kBetaM[3] = {0.05, 0.3, 1.0};
constexpr double kBetaN = 0.3;
constexpr double kAlphaDeg = 2.0;
constexpr double kEta = 1.55;
constexpr double kEumelanin = 1.3;

template <typename T> hairscatter::FiberParams<T> bench_params(int beta_index) {
    hairscatter::FiberParams<T> p;
    p.eta = T(kEta);
    p.beta_m = T(kBetaM[beta_index]);
    p.beta_n = T(kBetaN);
    p.alpha = hairscatter::radians(T(kAlphaDeg));
    p.sigma_a = hairscatter::sigma_a_from_concentrations(T(kEumelanin), T(0));
    return p;
}

template <typename T> HairBxDF<T> make_ref(int beta_index, T h) {
    const hairscatter::FiberParams<T> p = bench_params<T>(beta_index);
    return HairBxDF<T>(h, p.eta, p.sigma_a, p.beta_m, p.beta_n, p.alpha);
}

// The raw tuples, generated once in double (so float and double see the same inputs up
// to rounding): wo and wi_uniform uniform on the sphere, u in [0, 1)^4, h in [-1, 1),
// and wi_sampled[b] = ChiangFiber<double>(β_m index b, h).sample(wo, u2).wi — directions
// that hit the lobe peaks — with u2 independent of u.
struct RawInputs {
    std::vector<glm::dvec3> wo, wi_uniform, wi_sampled[3];
    std::vector<glm::dvec4> u;
    std::vector<double> h, calib_a, calib_b;

    RawInputs() {
        std::mt19937_64 rng(20240611);
        std::uniform_real_distribution<double> U(0.0, 1.0);
        auto sphere = [&]() {
            const double z = 1.0 - 2.0 * U(rng), r = std::sqrt(std::max(0.0, 1.0 - z * z));
            const double phi = 2.0 * hairscatter::kPi<double> * U(rng);
            return glm::dvec3(z, r * std::cos(phi), r * std::sin(phi));
        };
        std::vector<glm::dvec4> u2;
        for (std::size_t i = 0; i < kInputs; ++i) {
            wo.push_back(sphere());
            wi_uniform.push_back(sphere());
            u.emplace_back(U(rng), U(rng), U(rng), U(rng));
            u2.emplace_back(U(rng), U(rng), U(rng), U(rng));
            h.push_back(2.0 * U(rng) - 1.0);
            calib_a.push_back(U(rng));
            calib_b.push_back(U(rng));
        }
        for (int b = 0; b < 3; ++b) {
            const hairscatter::ChiangMaterial<double> mat(bench_params<double>(b));
            for (std::size_t i = 0; i < kInputs; ++i)
                wi_sampled[b].push_back(hairscatter::ChiangFiber<double>(mat, h[i]).sample(wo[i], u2[i]).wi);
        }
    }
};

inline const RawInputs& raw_inputs() {
    static const RawInputs in;
    return in;
}

// The same inputs in the working type, with the fibers (ours and the reference) built.
template <typename T> struct Inputs {
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    std::vector<V3> wo, wi[2][3];  // wi[0][b]: uniform (same for every b), wi[1][b]: sampled
    std::vector<V4> u;
    std::vector<T> h, calib_a, calib_b;
    std::vector<hairscatter::ChiangMaterial<T>> materials;
    std::vector<hairscatter::ChiangFiber<T>> fibers[3];
    std::vector<HairBxDF<T>> refs[3];

    Inputs() {
        const RawInputs& r = raw_inputs();
        for (std::size_t i = 0; i < kInputs; ++i) {
            wo.push_back(V3(r.wo[i]));
            u.push_back(V4(r.u[i]));
            h.push_back(T(r.h[i]));
            calib_a.push_back(T(r.calib_a[i]));
            calib_b.push_back(T(r.calib_b[i]));
        }
        for (int b = 0; b < 3; ++b) {
            materials.emplace_back(bench_params<T>(b));
            for (std::size_t i = 0; i < kInputs; ++i) {
                wi[0][b].push_back(V3(r.wi_uniform[i]));
                wi[1][b].push_back(V3(r.wi_sampled[b][i]));
            }
        }
        for (int b = 0; b < 3; ++b) {
            fibers[b].reserve(kInputs);
            refs[b].reserve(kInputs);
            for (std::size_t i = 0; i < kInputs; ++i) {
                fibers[b].emplace_back(materials[std::size_t(b)], h[i]);
                refs[b].push_back(make_ref<T>(b, h[i]));
            }
        }
    }
};

template <typename T> const Inputs<T>& inputs() {
    static const Inputs<T> in;
    return in;
}

}  // namespace bench_ref
