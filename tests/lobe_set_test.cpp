// Compile-time lobe selection (lobes/lobe_set.hpp) on the Chiang fiber: the kept lobes'
// terms are exactly those of the full model. That sampling picks only among them
// (chi-square) and the extremes stay finite is the contract suite's, run on every subset
// (tests/contract/chiang_subsets_*.cpp). The cost side (a dropped lobe costs nothing) is
// measured in bench/chiang_bench.cpp.
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

#include "support/chi2.hpp"
#include "support/model_specs.hpp"

namespace hs = hairscatter;
using hs::LobeSet;

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
        const glm::dvec3 r = hs::BasicChiangFiber<double, LobeSet::kR>(mat, h).eval(wo, wi);
        const glm::dvec3 tt = hs::BasicChiangFiber<double, LobeSet::kTT>(mat, h).eval(wo, wi);
        const glm::dvec3 trt = hs::BasicChiangFiber<double, LobeSet::kTRT>(mat, h).eval(wo, wi);
        const glm::dvec3 res = hs::BasicChiangFiber<double, LobeSet::kResidual>(mat, h).eval(wo, wi);
        const glm::dvec3 primary = hs::BasicChiangFiber<double, LobeSet::kPrimary>(mat, h).eval(wo, wi);
        const glm::dvec3 r_trt = hs::BasicChiangFiber<double, LobeSet::kR | LobeSet::kTRT>(mat, h).eval(wo, wi);
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
        const glm::dvec3 a_sum = hs::BasicChiangFiber<double, LobeSet::kR>(mat, h).albedo(wo) +
                                 hs::BasicChiangFiber<double, LobeSet::kTT | LobeSet::kTRT | LobeSet::kResidual>(mat, h).albedo(wo);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(a_sum[c], a_full[c], 1e-14);
    }
}

// Negative control for the subsets (the contract suite's chi-square runs every subset
// sampler against its own pdf): the full model's pdf is not the R+TT sampler's density.
TEST(LobeSet, NegativeControlFullPdfForSubsetSampler) {
    const hs::ChiangMaterial<double> mat(params<double>(0.25, 0.35, 2, 0.3));
    const hs::BasicChiangFiber<double, LobeSet::kR | LobeSet::kTT> subset(mat, 0.2);
    const hs::ChiangFiber<double> full(mat, 0.2);
    const glm::dvec3 wo(0.5, 0.8, std::sqrt(1 - 0.25 - 0.64));
    const auto r = chi2::test([&](const glm::dvec4& u) { return subset.sample(wo, u).wi; },
                              [&](const glm::dvec3& wi) { return full.pdf(wo, wi); },
                              specs::ChiangSpec<double, LobeSet::kR | LobeSet::kTT>::chi2_options());
    EXPECT_FALSE(r.passed) << "the full pdf was accepted for the R+TT sampler (p = " << r.p_value << ")";
}

// An opaque fiber without R: every kept lobe vanishes, and pdf, sample and eval stay 0
// and finite rather than dividing by a zero total weight.
TEST(LobeSet, OpaqueFiberWithoutRIsZeroNotNaN) {
    const hs::ChiangMaterial<float> mat(params<float>(0.3, 0.3, 2, 1e4));
    const hs::BasicChiangFiber<float, LobeSet::kTT | LobeSet::kTRT> fiber(mat, 0.0f);
    const glm::vec3 wo(0.2f, 0.97f, 0.13f), wi(-0.3f, -0.9f, 0.3f);
    EXPECT_EQ(fiber.pdf(wo, glm::normalize(wi)), 0.0f);
    const auto s = fiber.sample(wo, glm::vec4(0.5f));
    EXPECT_TRUE(std::isfinite(s.pdf));
    EXPECT_EQ(s.weight, glm::vec3(0.0f));
}

}  // namespace
