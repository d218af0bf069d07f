// The float lane code as the speed benchmarks build it (-march=native): with AVX, exp_each
// takes groups of eight through one 8-lane vector (elementary.hpp); the other test programs
// are built for the baseline x86-64 and only reach the 4-lane form. Checks both widths bit
// for bit against the scalar lane exp, and the Chiang fiber's float eval and the dual BCSDF's
// against their double forms, built here with the same flags.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include <hairscatter/dual.hpp>
#include <hairscatter/hairscatter.hpp>

#include "../support/dual_layer_checks.hpp"

namespace hs = hairscatter;

namespace {
bool same(float a, float b) {
    std::uint32_t ba, bb;
    std::memcpy(&ba, &a, 4);
    std::memcpy(&bb, &b, 4);
    return ba == bb || (std::isnan(a) && std::isnan(b));
}
}  // namespace

TEST(LanesNative, ExpGroupsOfFourAndEightMatchTheScalarLaneExp) {
#if defined(__AVX__)
    std::printf("[ native   ] AVX: groups of eight are one 8-lane vector\n");
#else
    std::printf("[ native   ] no AVX: groups of four only\n");
#endif
    long mismatches = 0, checked = 0;
    auto check = [&](const auto& x) {
        constexpr int n = int(sizeof(x) / sizeof(float));
        float y[n];
        for (int k = 0; k < n; ++k) y[k] = x[k];
        hs::elem::exp_each(y);
        for (int k = 0; k < n; ++k, ++checked)
            if (!same(y[k], hs::elem::detail::exp_float<true>(x[k]))) ++mismatches;
    };
    for (double x0 = -90.0; x0 <= 90.0; x0 += 3.1e-4) {
        float x4[4], x8[8], x16[16];
        for (int k = 0; k < 16; ++k) x16[k] = float(-x0 + 0.3e-4 * k);
        for (int k = 0; k < 8; ++k) x8[k] = float(x0 + 0.7e-4 * k);
        for (int k = 0; k < 4; ++k) x4[k] = float(x0 * (1 + 0.1 * k));
        check(x4);
        check(x8);
        check(x16);
    }
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    const float specials[8] = {-87.3f, std::nextafter(-87.3f, 0.0f), 88.0f, 0.0f, -0.0f, inf, -inf, nan};
    check(specials);
    EXPECT_EQ(mismatches, 0) << "of " << checked;
}

// Float against double at random directions: the relative L1 over the RGB sum is at the
// level of float rounding through ~20 operations (measured 1e-6 or less); 1e-5 catches a lane
// that reads the wrong lobe or a stale value, which moves it by percents.
TEST(LanesNative, FloatChiangAndDualAgreeWithDouble) {
    hs::FiberParams<double> pd;
    pd.sigma_a = hs::sigma_a_from_concentrations(0.4, 0.1);
    hs::FiberParams<float> pf;
    pf.sigma_a = glm::vec3(pd.sigma_a);
    const hs::ChiangMaterial<double> md(pd);
    const hs::ChiangMaterial<float> mf(pf);
    const auto td = hs::DualScatteringTables<double>::build<hs::ChiangFiber<double>>(md);
    const auto tf = hs::DualScatteringTables<float>::build<hs::ChiangFiber<float>>(mf);
    hs::DualScatteringLight<double> ld;
    ld.n = 3;
    ld.beyond = 7;
    ld.direct_fraction = 0.25;
    hs::DualScatteringLight<float> lf;
    lf.n = 3;
    lf.beyond = 7;
    lf.direct_fraction = 0.25f;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> uni(0, 1);
    auto dir = [&] {
        const double z = 2 * uni(rng) - 1, p = 6.283185307179586 * uni(rng), r = std::sqrt(1 - z * z);
        return glm::dvec3(z, r * std::cos(p), r * std::sin(p));
    };
    double err[2] = {0, 0}, ref[2] = {0, 0};
    for (int i = 0; i < 20000; ++i) {
        const double h = 2 * uni(rng) - 1;
        const glm::dvec3 wo = dir(), wi = dir();
        const hs::ChiangFiber<double> fd(md, h);
        const hs::ChiangFiber<float> ff(mf, float(h));
        const glm::dvec3 a[2] = {fd.eval(wo, wi), hs::DualScatteringBcsdf<hs::ChiangFiber<double>>(fd, td).eval(wo, wi, ld)};
        const glm::dvec3 b[2] = {glm::dvec3(ff.eval(glm::vec3(wo), glm::vec3(wi))),
                                 glm::dvec3(hs::DualScatteringBcsdf<hs::ChiangFiber<float>>(ff, tf)
                                                .eval(glm::vec3(wo), glm::vec3(wi), lf))};
        for (int k = 0; k < 2; ++k)
            for (int c = 0; c < 3; ++c) {
                ASSERT_TRUE(std::isfinite(b[k][c]));
                err[k] += std::abs(b[k][c] - a[k][c]);
                ref[k] += std::abs(a[k][c]);
            }
    }
    std::printf("[ native   ] float vs double relative L1: Chiang %.3g, dual %.3g\n", err[0] / ref[0], err[1] / ref[1]);
    EXPECT_LT(err[0] / ref[0], 1e-5);
    EXPECT_LT(err[1] / ref[1], 1e-5);
}

// The dual BCSDF's stacks above and below a point as one batch of eight float lanes (one
// AVX vector): each lane bit for bit what the stack of its own depth gives alone.
TEST(LanesNative, TwoDepthLayerBatchMatchesTwoStacks) {
#if defined(__AVX__)
    EXPECT_TRUE(hs::DualLayers<float>::kTwoDepthBatch);
#endif
    dual_checks::two_depth_stacks<float>();
}

// sqrt_each as the native build compiles it: with AVX, groups of eight floats or four
// doubles go through one 256-bit VSQRT (elementary.hpp); the baseline build only reaches the
// SSE form. Either is correctly rounded, so every lane must be std::sqrt's bit for bit,
// zeros, subnormals, +Inf and NaN included (a negative input gives NaN).
template <typename T, std::size_t N> static void check_sqrt_each(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> expo(-40.0, 40.0);
    const T special[] = {T(0), T(-0.0), std::numeric_limits<T>::denorm_min(), std::numeric_limits<T>::min(),
                         std::numeric_limits<T>::max(), std::numeric_limits<T>::infinity(), T(-1),
                         std::numeric_limits<T>::quiet_NaN()};
    for (int round = 0; round < 200; ++round) {
        T x[N], r[N];
        for (std::size_t k = 0; k < N; ++k)
            x[k] = round == 0 ? special[k % 8] : T(std::exp2(expo(rng)) * (1 + 1e-3 * double(k)));
        for (std::size_t k = 0; k < N; ++k) r[k] = x[k];
        hs::elem::sqrt_each(r);
        for (std::size_t k = 0; k < N; ++k) {
            const T want = std::sqrt(x[k]);
            if (std::isnan(want)) ASSERT_TRUE(std::isnan(r[k])) << "x=" << x[k];
            else ASSERT_EQ(std::memcmp(&want, &r[k], sizeof(T)), 0) << "x=" << x[k] << " lane " << k;
        }
    }
}
TEST(LanesNative, SqrtEachIsStdSqrtBitForBit) {
    std::mt19937_64 rng(11);
    check_sqrt_each<float, 8>(rng);
    check_sqrt_each<float, 16>(rng);
    check_sqrt_each<float, 4>(rng);
    check_sqrt_each<float, 12>(rng);
    check_sqrt_each<double, 4>(rng);
    check_sqrt_each<double, 8>(rng);
    check_sqrt_each<double, 2>(rng);
    check_sqrt_each<double, 6>(rng);
}
