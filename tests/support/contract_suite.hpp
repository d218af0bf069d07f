// The model contract (include/hairscatter/models/contract.hpp) checked once for every model:
// a typed GoogleTest suite over "specs", each naming a fiber type and the materials to try.
// tests/contract/*.cpp instantiate it (into contract_test) for every model in float and
// double and for subsets of the Chiang lobes. A spec S provides
//   using Fiber;                                   the fiber type under test;
//   static Instance<Fiber> random(rng, k);         the k-th random material (sample/pdf check);
//   static constexpr int kRandomMaterials, kRandomDirections;
//   static std::vector<Instance<Fiber>> extremes(); the edge-case materials;
//   static std::vector<Chi2Case<Fiber>> chi2_cases(); chi2::Options chi2_options();
//   static constexpr double kPdfTotalTolerance;     how far the cubature's ∫ pdf may be from 1;
//   static bool may_sample(hs::SampledLobe);         the lobes sample() may report;
//   static Instance<Fiber> lossless();             moderate roughness, σa = 0 (furnace);
//   static constexpr bool kConservesEnergy;         whether albedo is 1 for σa = 0;
//   static constexpr double kFurnaceTolerance;      ∫ eval dω against albedo(wo);
//   static constexpr int kFurnaceDepth;             the cubature's deepest refinement;
//   static std::vector<Invalid> invalid();          constructions that must throw.
#pragma once

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include <hairscatter/models/contract.hpp>

#include "checks.hpp"
#include "chi2.hpp"

namespace contract {

constexpr double kPi = 3.14159265358979323846;

inline glm::dvec3 dir(double theta, double phi) {
    return {std::sin(theta), std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi)};
}

// A fiber and the material it refers to (kept alive as long as the instance).
template <typename Fiber> struct Instance {
    std::shared_ptr<const void> material;
    Fiber fiber;
    std::string label;
};
template <typename Fiber, typename Material, typename... Args>
Instance<Fiber> make_instance(std::shared_ptr<const Material> material, std::string label, Args... args) {
    Fiber fiber(*material, args...);
    return Instance<Fiber>{std::move(material), fiber, std::move(label)};
}

template <typename Fiber> struct Chi2Case {
    Instance<Fiber> instance;
    double theta_o_deg;
};

// A construction that must throw std::invalid_argument whose message names `field`.
struct Invalid {
    std::function<void()> construct;
    std::string field;
};

template <typename Spec> class ModelContract : public ::testing::Test {};
TYPED_TEST_SUITE_P(ModelContract);
// Instantiated by the translation units of tests/contract/ only (one per model, with and
// without lobe controls, so that the build compiles them in parallel), linked into
// contract_test; the model tests include the specs.
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(ModelContract);

// Instance names: numbers from kFirst, so that the parts of one instantiation prefix
// (AllModels, ChiangLobeSubsets) in different translation units never share a test name
// (ctest shows the spec type too).
template <int kFirst> struct NumberedFrom {
    template <typename> static std::string GetName(int i) { return std::to_string(kFirst + i); }
};

// The trait of models/contract.hpp accepts the fiber.
TYPED_TEST_P(ModelContract, SatisfiesTheTrait) {
    using Fiber = typename TypeParam::Fiber;
    EXPECT_TRUE(hairscatter::is_fiber_model_v<Fiber>);
    EXPECT_FALSE(hairscatter::is_fiber_model_v<hairscatter::UniformSphereSampling<Fiber>>);  // no at(), no albedo()
}

// Bad parameters are rejected at construction with a message naming the field.
TYPED_TEST_P(ModelContract, ValidationRejectsBadParameters) {
    const std::vector<Invalid> bad = TypeParam::invalid();
    ASSERT_FALSE(bad.empty());
    for (const Invalid& b : bad) {
        try {
            b.construct();
            ADD_FAILURE() << "accepted a bad " << b.field;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(b.field), std::string::npos) << e.what();
        }
    }
}

// sample's pdf is pdf(wo, wi) and its weight eval/pdf, to rounding: 1e-9 relative in double,
// 1e-4 in float (pdf() recomputes φ by atan2 from the rounded wi, which moves φ by ~1e-7
// inside the narrowest azimuthal lobes); eval_pdf is eval and pdf exactly; only the lobes
// the model keeps are drawn, and each of them is.
TYPED_TEST_P(ModelContract, SampleAgreesWithPdfAndEval) {
    using Fiber = typename TypeParam::Fiber;
    using T = typename Fiber::Real;
    const double tol = sizeof(T) == 4 ? 1e-4 : 1e-9;
    std::mt19937_64 rng(23);
    std::uniform_real_distribution<double> uni(0, 1);
    double worst_pdf = 0, worst_w = 0;
    int drawn[Fiber::kLobes + 1] = {};
    for (int k = 0; k < TypeParam::kRandomMaterials; ++k) {
        const Instance<Fiber> in = TypeParam::random(rng, k);
        for (int j = 0; j < TypeParam::kRandomDirections; ++j) {
            const glm::vec<3, T> wo(dir(std::asin(-1 + 2 * uni(rng)), 2 * kPi * uni(rng)));
            const auto s = in.fiber.sample(wo, glm::vec<4, T>(T(uni(rng)), T(uni(rng)), T(uni(rng)), T(uni(rng))));
            ASSERT_GT(s.pdf, T(0)) << in.label;
            EXPECT_TRUE(TypeParam::may_sample(s.lobe)) << in.label << ": lobe " << hairscatter::lobe_index(s.lobe);
            if (TypeParam::may_sample(s.lobe)) ++drawn[hairscatter::lobe_index(s.lobe)];
            EXPECT_NEAR(double(glm::length(s.wi)), 1.0, 10 * std::numeric_limits<T>::epsilon());
            const auto e = in.fiber.eval_pdf(wo, s.wi);
            EXPECT_EQ(e.pdf, in.fiber.pdf(wo, s.wi)) << in.label;
            EXPECT_EQ(e.f, in.fiber.eval(wo, s.wi)) << in.label;
            worst_pdf = std::max(worst_pdf, std::abs(double(e.pdf / s.pdf) - 1));
            for (int ch = 0; ch < 3; ++ch)
                if (e.f[ch] > T(1e-20)) worst_w = std::max(worst_w, std::abs(double(s.weight[ch] * e.pdf / e.f[ch]) - 1));
        }
    }
    std::printf("[ worst    ] sample pdf vs pdf(): %.3g, weight vs eval/pdf: %.3g\n", worst_pdf, worst_w);
    EXPECT_LT(worst_pdf, tol);
    EXPECT_LT(worst_w, tol);
    for (int p = 0; p <= Fiber::kLobes; ++p) {
        if (TypeParam::may_sample(hairscatter::lobe_tag(p))) {
            EXPECT_GT(drawn[p], 0) << "lobe " << p << " never sampled";
        }
    }
}

// at(wo) hoists the wo terms; its eval, pdf, eval_pdf and sample are the fiber's exactly.
TYPED_TEST_P(ModelContract, BoundToWoMatchesUnbound) {
    using Fiber = typename TypeParam::Fiber;
    using T = typename Fiber::Real;
    std::mt19937_64 rng(31);
    std::uniform_real_distribution<double> uni(0, 1);
    for (int k = 0; k < 10; ++k) {
        const Instance<Fiber> in = TypeParam::random(rng, k);
        const glm::vec<3, T> wo(dir(std::asin(-1 + 2 * uni(rng)), 2 * kPi * uni(rng)));
        const auto at = in.fiber.at(wo);
        for (int j = 0; j < 20; ++j) {
            const glm::vec<3, T> wi(dir(std::asin(-1 + 2 * uni(rng)), 2 * kPi * uni(rng)));
            EXPECT_EQ(at.eval(wi), in.fiber.eval(wo, wi)) << in.label;
            EXPECT_EQ(at.pdf(wi), in.fiber.pdf(wo, wi)) << in.label;
            EXPECT_EQ(at.eval_pdf(wi).f, in.fiber.eval_pdf(wo, wi).f) << in.label;
            const glm::vec<4, T> u(T(uni(rng)), T(uni(rng)), T(uni(rng)), T(uni(rng)));
            const auto a = at.sample(u), b = in.fiber.sample(wo, u);
            EXPECT_EQ(a.wi, b.wi);
            EXPECT_EQ(a.pdf, b.pdf);
            EXPECT_EQ(a.weight, b.weight);
            EXPECT_TRUE(a.lobe == b.lobe);
        }
    }
}

// ∫ eval dωi (adaptive cubature over sinθi × φ) equals albedo(wo); for the models that
// conserve energy the albedo of a lossless fiber is 1 (Marschner's is an estimate:
// checked against the integral, not against 1).
// The cubatures here and in LobeSplitAddsUp, and SampleMatchesPdfChi2's samples and
// cubature, call the model at one wo hundreds of thousands of times: through at(wo), whose
// eval, pdf and sample are the fiber's to the bit (BoundToWoMatchesUnbound), the wo terms
// are computed once instead of per call (Huang's path walk: most of a stateless call).
TYPED_TEST_P(ModelContract, FurnaceAndAlbedo) {
    using Fiber = typename TypeParam::Fiber;
    using T = typename Fiber::Real;
    const Instance<Fiber> in = TypeParam::lossless();
    for (double theta_o : {-70.0, 0.0, 35.0}) {
        const glm::vec<3, T> wo(dir(theta_o * kPi / 180, 0.3));
        const auto at = in.fiber.at(wo);
        const chi2::CellIntegrator integrate(
            [&](double x, double phi) {
                const double c = std::sqrt(std::max(0.0, 1 - x * x));
                const glm::vec<3, T> f = at.eval(glm::vec<3, T>(T(x), T(c * std::cos(phi)), T(c * std::sin(phi))));
                return double(f.x + f.y + f.z) / 3;
            },
            2, TypeParam::kFurnaceDepth);
        double total = 0;
        for (int i = 0; i < 8; ++i)
            for (int j = 0; j < 16; ++j)
                total += integrate.integrate(-1 + i * 0.25, -1 + (i + 1) * 0.25, -kPi + j * kPi / 8, -kPi + (j + 1) * kPi / 8);
        const glm::vec<3, T> a = in.fiber.albedo(wo);
        const double albedo = double(a.x + a.y + a.z) / 3;
        std::printf("[ furnace  ] %s θo %.0f°: ∫ f dω = %.8f, albedo %.8f\n", in.label.c_str(), theta_o, total, albedo);
        EXPECT_NEAR(total, albedo, TypeParam::kFurnaceTolerance) << in.label << " θo " << theta_o;
        if (TypeParam::kConservesEnergy) {
            EXPECT_NEAR(albedo, 1.0, sizeof(T) == 4 ? 1e-5 : 1e-12) << in.label;
        }
    }
}

// Where the model splits its albedo per lobe: Σ_p a_p is albedo(wo), and Σ_p a_p·backward_p
// is ∫ over the backward half |φ| < π/2 of eval (channel sums).
TYPED_TEST_P(ModelContract, LobeSplitAddsUp) {
    using Fiber = typename TypeParam::Fiber;
    using T = typename Fiber::Real;
    if constexpr (hairscatter::has_lobe_split_v<Fiber>) {
        std::mt19937_64 rng(37);
        const Instance<Fiber> in = TypeParam::random(rng, 1);
        for (double theta_o : {-50.0, 20.0}) {
            const glm::vec<3, T> wo(dir(theta_o * kPi / 180, 0.3));
            const auto split = in.fiber.lobe_split(wo);
            glm::dvec3 sum(0.0);
            double back = 0;
            for (int p = 0; p <= Fiber::kLobes; ++p) {
                sum += glm::dvec3(split.a[p]);
                back += double(split.backward[p]) * double(split.a[p].x + split.a[p].y + split.a[p].z);
                EXPECT_GE(split.backward[p], T(0));
                EXPECT_LE(split.backward[p], T(1));
            }
            const glm::dvec3 a(in.fiber.albedo(wo));
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c], a[c], 1e-5 * a[c]);
            const auto at = in.fiber.at(wo);
            const chi2::CellIntegrator integrate(
                [&](double x, double phi) {
                    const double c = std::sqrt(std::max(0.0, 1 - x * x));
                    const glm::vec<3, T> wi(T(x), T(c * std::cos(phi)), T(c * std::sin(phi)));
                    const glm::vec<3, T> f = at.eval(wi);
                    return double(f.x + f.y + f.z);
                },
                2, 6);
            // φ is relative to wo's azimuth (0.3): the backward half is 0.3 ± π/2.
            double total = 0;
            for (int i = 0; i < 8; ++i)
                for (int j = 0; j < 8; ++j)
                    total += integrate.integrate(-1 + i * 0.25, -1 + (i + 1) * 0.25, 0.3 - kPi / 2 + j * kPi / 8,
                                                 0.3 - kPi / 2 + (j + 1) * kPi / 8);
            EXPECT_NEAR(back, total, 1e-3 * total) << in.label << " θo " << theta_o;
        }
    } else {
        GTEST_SKIP() << "no lobe_split";
    }
}

// Chi-square goodness of fit of sample against pdf over the spec's grid (the options carry
// the Bonferroni count, over both precisions), with a negative control: the first case's
// sampler against its pdf × 1.05 must be rejected.
TYPED_TEST_P(ModelContract, SampleMatchesPdfChi2) {
    using Fiber = typename TypeParam::Fiber;
    using T = typename Fiber::Real;
    using V3 = glm::vec<3, T>;
    const std::vector<Chi2Case<Fiber>> cases = TypeParam::chi2_cases();
    const int n = int(cases.size());
    double min_p = 1;
    for (int k = 0; k < n; ++k) {
        const Chi2Case<Fiber>& c = cases[std::size_t(k)];
        const V3 wo(dir(c.theta_o_deg * kPi / 180, 0.7));
        const Fiber& fiber = c.instance.fiber;
        const chi2::Options opt = TypeParam::chi2_options();
        // Sample and pdf through at(wo) (see FurnaceAndAlbedo).
        const auto at = fiber.at(wo);
        const chi2::Histogram hist =
            chi2::histogram([&](const glm::dvec4& u) { return glm::dvec3(at.sample(glm::vec<4, T>(u)).wi); }, opt);
        const chi2::Expected expected =
            chi2::expected_counts([&](const glm::dvec3& wi) { return double(at.pdf(V3(wi))); }, opt);
        const chi2::Result r = chi2::compare(hist, expected, opt);
        min_p = std::min(min_p, r.p_value);
        EXPECT_TRUE(r.passed) << "case " << k << " (" << c.instance.label << ", θo " << c.theta_o_deg << "°)\n" << r.report;
        EXPECT_NEAR(r.expected_total, 1.0, TypeParam::kPdfTotalTolerance) << "case " << k << ": ∫ pdf dω";
        if (k == 0) {
            const chi2::Result scaled = chi2::compare(hist, expected.scaled(1.05), opt);
            EXPECT_FALSE(scaled.passed) << "pdf × 1.05 was accepted (p = " << scaled.p_value << ")";
        }
    }
    std::printf("[ chi2     ] %d cases, smallest p-value %.3g, Bonferroni threshold %.3g\n", n, min_p,
                0.01 / TypeParam::chi2_options().num_tests);
}

// Edge-case materials and directions: eval, pdf, albedo and sample never give NaN or Inf,
// f and pdf are non-negative, sampled directions are unit vectors.
TYPED_TEST_P(ModelContract, ExtremesStayFinite) {
    using Fiber = typename TypeParam::Fiber;
    using T = typename Fiber::Real;
    using V3 = glm::vec<3, T>;
    const T one_minus = std::nextafter(T(1), T(0));
    const T rim = std::sqrt(1 - one_minus * one_minus);
    std::vector<V3> dirs = {V3(1, 0, 0), V3(-1, 0, 0), V3(0, 1, 0), V3(0, 0, -1), V3(one_minus, 0, rim),
                            V3(-one_minus, rim, 0)};
    std::mt19937_64 rng(29);
    std::uniform_real_distribution<double> uni(0, 1);
    for (int k = 0; k < 10; ++k) dirs.push_back(V3(dir(std::asin(-1 + 2 * uni(rng)), 2 * kPi * uni(rng))));
    const std::vector<T> us = {T(0), T(1e-30), T(1e-7), T(0.5), one_minus, T(1)};
    long checked = 0;
    for (const Instance<Fiber>& in : TypeParam::extremes()) {
        for (std::size_t d = 0; d < dirs.size(); ++d) {
            const V3& wo = dirs[d];
            if (d % 8 == 0) {  // Marschner's albedo is 4096 samples: at two directions only
                const V3 a = in.fiber.albedo(wo);
                for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(a[c]) && a[c] >= T(0)) << in.label;
            }
            for (const V3& wi : {wo, -wo, dirs[0], dirs[1], dirs[std::size_t(checked + 3) % dirs.size()]}) {
                const auto e = in.fiber.eval_pdf(wo, wi);
                for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(e.f[c]) && e.f[c] >= T(0)) << in.label;
                ASSERT_TRUE(std::isfinite(e.pdf) && e.pdf >= T(0)) << in.label;
                ++checked;
            }
            for (T u0 : us)
                for (T u3 : {us[0], us[2], us[5]}) {
                    const glm::vec<4, T> u(u0, us[std::size_t(checked + 1) % us.size()],
                                           us[std::size_t(checked + 2) % us.size()], u3);
                    const auto s = in.fiber.sample(wo, u);
                    ++checked;
                    ASSERT_TRUE(valid_sample(s)) << in.label << ", wo (" << wo.x << ", " << wo.y << ", " << wo.z
                                                 << "), u (" << u.x << ", " << u.y << ", " << u.z << ", " << u.w << ")";
                }
        }
    }
    std::printf("[ sweep    ] %ld edge-case calls without NaN/Inf\n", checked);
}

REGISTER_TYPED_TEST_SUITE_P(ModelContract, SatisfiesTheTrait, ValidationRejectsBadParameters,
                            SampleAgreesWithPdfAndEval, BoundToWoMatchesUnbound, FurnaceAndAlbedo, LobeSplitAddsUp,
                            SampleMatchesPdfChi2, ExtremesStayFinite);

}  // namespace contract
