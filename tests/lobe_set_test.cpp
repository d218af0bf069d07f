// Compile-time lobe selection (lobes/lobe_set.hpp) on the Chiang fiber: the kept lobes'
// terms are exactly those of the full model, sampling picks only among them (chi-square),
// and the extremes stay finite. The cost side (a dropped lobe costs nothing) is measured
// in bench/chiang_bench.cpp.
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

#include "support/checks.hpp"
#include "support/chi2.hpp"

namespace hs = hairscatter;
using hs::Lobes;

namespace {

template <typename T> hs::FiberParams<T> params(double beta_m, double beta_n, double alpha_deg, double sigma) {
    hs::FiberParams<T> p;
    p.beta_m = T(beta_m);
    p.beta_n = T(beta_n);
    p.alpha = T(alpha_deg * 3.14159265358979323846 / 180);
    p.sigma_a = glm::vec<3, T>(T(sigma), T(0.6 * sigma), T(0.3 * sigma));
    return p;
}

glm::dvec3 random_direction(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> uni(0, 1);
    const double z = 2 * uni(rng) - 1, a = 2 * 3.14159265358979323846 * uni(rng), r = std::sqrt(1 - z * z);
    return {z, r * std::cos(a), r * std::sin(a)};
}

// The four singleton fibers sum to the full model; any subset is the sum of its members.
TEST(LobeSet, SubsetsSumToTheFullModel) {
    const hs::ChiangMaterial<double> mat(params<double>(0.3, 0.4, 2, 0.4));
    std::mt19937_64 rng(7);
    for (int k = 0; k < 500; ++k) {
        const double h = std::uniform_real_distribution<double>(-1, 1)(rng);
        const glm::dvec3 wo = random_direction(rng), wi = random_direction(rng);
        const glm::dvec3 full = hs::ChiangFiber<double>(mat, h).eval(wo, wi);
        const glm::dvec3 r = hs::BasicChiangFiber<double, Lobes::kR>(mat, h).eval(wo, wi);
        const glm::dvec3 tt = hs::BasicChiangFiber<double, Lobes::kTT>(mat, h).eval(wo, wi);
        const glm::dvec3 trt = hs::BasicChiangFiber<double, Lobes::kTRT>(mat, h).eval(wo, wi);
        const glm::dvec3 res = hs::BasicChiangFiber<double, Lobes::kResidual>(mat, h).eval(wo, wi);
        const glm::dvec3 primary = hs::BasicChiangFiber<double, Lobes::kPrimary>(mat, h).eval(wo, wi);
        const glm::dvec3 r_trt = hs::BasicChiangFiber<double, Lobes::kR | Lobes::kTRT>(mat, h).eval(wo, wi);
        for (int c = 0; c < 3; ++c) {
            const double tol = 1e-12 * (1 + full[c]);
            EXPECT_NEAR(r[c] + tt[c] + trt[c] + res[c], full[c], tol) << k;
            EXPECT_NEAR(r[c] + tt[c] + trt[c], primary[c], tol) << k;
            EXPECT_NEAR(r[c] + trt[c], r_trt[c], tol) << k;
            EXPECT_GE(r[c], 0.0);
            EXPECT_GE(tt[c], 0.0);
        }
        // The albedo of a subset is the sum of its lobes' A_p.
        const glm::dvec3 a_full = hs::ChiangFiber<double>(mat, h).albedo(wo);
        const glm::dvec3 a_sum = hs::BasicChiangFiber<double, Lobes::kR>(mat, h).albedo(wo) +
                                 hs::BasicChiangFiber<double, Lobes::kTT | Lobes::kTRT | Lobes::kResidual>(mat, h).albedo(wo);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(a_sum[c], a_full[c], 1e-14);
    }
}

// The pdf of a subset is a normalised density over the kept lobes only, and sample()
// draws from it: chi-square for several subsets, with a negative control (the full
// model's pdf is not the R+TT sampler's density).
template <typename T, unsigned kSet> void chi2_case(double theta_o_deg, double h, double& min_p, int num_tests) {
    const hs::BasicChiangFiber<T, kSet> fiber(hs::ChiangMaterial<T>(params<T>(0.25, 0.35, 2, 0.3)), T(h));
    const double t = theta_o_deg * 3.14159265358979323846 / 180;
    const glm::vec<3, T> wo(T(std::sin(t)), T(std::cos(t) * std::cos(0.4)), T(std::cos(t) * std::sin(0.4)));
    chi2::Options o;
    o.num_tests = num_tests;
    const auto r = chi2::test(
        [&](const glm::dvec4& u) {
            const auto s = fiber.sample(wo, glm::vec<4, T>(u));
            EXPECT_TRUE(hs::keeps_lobe(kSet, s.lobe)) << "sampled a dropped lobe " << s.lobe;
            return glm::dvec3(s.wi);
        },
        [&](const glm::dvec3& wi) { return double(fiber.pdf(wo, glm::vec<3, T>(wi))); }, o);
    min_p = std::min(min_p, r.p_value);
    EXPECT_TRUE(r.passed) << "set " << kSet << " θo " << theta_o_deg << " h " << h << "\n" << r.report;
    EXPECT_NEAR(r.expected_total, 1.0, 1e-3);
}

TEST(LobeSet, SamplerMatchesPdfForSubsets) {
    const int n = 10;
    double min_p = 1;
    chi2_case<double, Lobes::kR>(30, 0.3, min_p, n);
    chi2_case<double, Lobes::kTT>(-50, -0.6, min_p, n);
    chi2_case<double, Lobes::kTRT | Lobes::kResidual>(70, 0.1, min_p, n);
    chi2_case<double, Lobes::kPrimary>(10, 0.8, min_p, n);
    chi2_case<double, Lobes::kR | Lobes::kTT>(85, -0.2, min_p, n);
    chi2_case<float, Lobes::kR>(30, 0.3, min_p, n);
    chi2_case<float, Lobes::kTT>(-50, -0.6, min_p, n);
    chi2_case<float, Lobes::kTRT | Lobes::kResidual>(70, 0.1, min_p, n);
    chi2_case<float, Lobes::kPrimary>(10, 0.8, min_p, n);
    chi2_case<float, Lobes::kR | Lobes::kTT>(85, -0.2, min_p, n);
    std::printf("[ lobe set ] 10 subset cases, smallest p-value %.3g (threshold %.3g)\n", min_p, 0.01 / n);
}

TEST(LobeSet, NegativeControlFullPdfForSubsetSampler) {
    const hs::ChiangMaterial<double> mat(params<double>(0.25, 0.35, 2, 0.3));
    const hs::BasicChiangFiber<double, Lobes::kR | Lobes::kTT> subset(mat, 0.2);
    const hs::ChiangFiber<double> full(mat, 0.2);
    const glm::dvec3 wo(0.5, 0.8, std::sqrt(1 - 0.25 - 0.64));
    chi2::Options o;
    o.num_tests = 10;
    const auto r = chi2::test([&](const glm::dvec4& u) { return subset.sample(wo, u).wi; },
                              [&](const glm::dvec3& wi) { return full.pdf(wo, wi); }, o);
    EXPECT_FALSE(r.passed) << "the full pdf was accepted for the R+TT sampler (p = " << r.p_value << ")";
}

// An opaque fiber without R: every kept lobe vanishes, and pdf, sample and eval stay 0
// and finite rather than dividing by a zero total weight.
TEST(LobeSet, OpaqueFiberWithoutRIsZeroNotNaN) {
    const hs::BasicChiangFiber<float, Lobes::kTT | Lobes::kTRT> fiber(hs::ChiangMaterial<float>(params<float>(0.3, 0.3, 2, 1e4)), 0.0f);
    const glm::vec3 wo(0.2f, 0.97f, 0.13f), wi(-0.3f, -0.9f, 0.3f);
    EXPECT_EQ(fiber.pdf(wo, glm::normalize(wi)), 0.0f);
    const auto s = fiber.sample(wo, glm::vec4(0.5f));
    EXPECT_TRUE(std::isfinite(s.pdf));
    EXPECT_EQ(s.weight, glm::vec3(0.0f));
}

// Extremes: every subset stays finite at grazing angles, h = ±1, tiny and huge roughness.
template <unsigned kSet> void sweep() {
    const double betas[] = {0.01, 0.3, 1.0};
    const double thetas[] = {-90, -89.99, 0, 60, 89.99, 90};
    const double hs_[] = {-1, 0, 0.999, 1};
    for (double bm : betas)
        for (double bn : betas)
            for (double sigma : {0.0, 50.0}) {
                const hs::ChiangMaterial<float> mat(params<float>(bm, bn, 22.5, sigma));
                for (double h : hs_)
                    for (double to : thetas)
                        for (double ti : thetas) {
                            const hs::BasicChiangFiber<float, kSet> fiber(mat, float(h));
                            const double a = to * 3.14159265358979323846 / 180, b = ti * 3.14159265358979323846 / 180;
                            const glm::vec3 wo(float(std::sin(a)), float(std::cos(a)), 0.0f);
                            const glm::vec3 wi(float(std::sin(b)), float(-std::cos(b) * 0.6), float(std::cos(b) * 0.8));
                            const auto e = fiber.eval_pdf(wo, wi);
                            ASSERT_TRUE(std::isfinite(e.pdf) && e.pdf >= 0);
                            for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(e.f[c]) && e.f[c] >= 0);
                            for (float u : {0.0f, 0.5f, 0.99999994f}) {
                                const auto s = fiber.sample(wo, glm::vec4(u, 1 - u, u, 0.3f));
                                ASSERT_TRUE(valid_sample(s)) << "set " << kSet;
                            }
                        }
            }
}

TEST(LobeSet, ExtremesStayFinite) {
    sweep<Lobes::kR>();
    sweep<Lobes::kTT>();
    sweep<Lobes::kTRT | Lobes::kResidual>();
    sweep<Lobes::kPrimary>();
}

}  // namespace
