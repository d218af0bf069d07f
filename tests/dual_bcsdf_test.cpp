// The dual-scattering BCSDF: its terms and their limits, the 1D adding model, the mixture
// sampler against its pdf (chi-square with negative controls, float and double), extremes,
// any model behind the contract, the variance gain over uniform sampling, and agreement
// with a path-traced slab of explicit fibers.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include <hairscatter/dual.hpp>

#include "support/chi2.hpp"
#include "support/dual_layer_checks.hpp"
#include "support/fiber_slab.hpp"

namespace hs = hairscatter;
using glm::dvec3;
using glm::dvec4;
using slab::draw4;

namespace {

using Dual = hs::DualScatteringBcsdf<hs::ChiangFiber<double>>;

struct Hair {
    const char* name;
    double eumelanin;  // < 0: lossless
};
const Hair kHairs[] = {{"white", -1}, {"blond", 0.3}, {"dark", 8.0}};

hs::FiberParams<double> params_of(const Hair& h) {
    hs::FiberParams<double> p;
    p.sigma_a = h.eumelanin < 0 ? dvec3(0) : hs::sigma_a_from_concentrations(h.eumelanin, 0.0);
    return p;
}

struct HairSetup {
    hs::ChiangMaterial<double> material;
    hs::DualScatteringTables<double> tables;
    explicit HairSetup(const Hair& h, hs::DualScatteringSettings<double> s = {})
        : material(params_of(h)), tables(build(material, s)) {}
    static hs::DualScatteringTables<double> build(const hs::ChiangMaterial<double>& m, hs::DualScatteringSettings<double> s) {
        hs::DualTableOptions<double> o;
        o.settings = s;
        return hs::DualScatteringTables<double>::build<hs::ChiangFiber<double>>(m, o);
    }
};

dvec3 direction(double theta_deg, double phi) {
    const double t = theta_deg * hs::kPi<double> / 180;
    return dvec3(std::sin(t), std::cos(t) * std::cos(phi), std::cos(t) * std::sin(phi));
}

hs::DualScatteringLight<double> shadowed(double n, double beyond = hs::kUnbounded<double>) {
    hs::DualScatteringLight<double> l;
    l.direct_fraction = 0;
    l.n = n;
    l.beyond = beyond;
    return l;
}

double mean(const dvec3& v) { return (v.x + v.y + v.z) / 3; }

}  // namespace

// (In this baseline build the float batch is two of four; lanes_native_test checks the
// eight-lane one.)
TEST(DualLayers, TwoDepthBatchMatchesTwoStacks) {
    dual_checks::two_depth_stacks<float>();
    dual_checks::two_depth_stacks<double>();
}

TEST(DualLayers, AddingFormulaMatchesIterationAndClosedForms) {
    for (double af : {0.0, 0.3, 0.7, 0.9}) {
        for (double ab : {0.0, 0.05, 0.1}) {
            if (af + ab > 1) continue;
            double R = 0, T = 1;
            for (int N = 1; N <= 40; ++N) {
                const double den = 1 - ab * R;
                T = af * T / den;
                R = ab + af * af * R / den;
                const auto s = hs::layered_stack(af, ab, double(N));
                EXPECT_NEAR(s.R, R, 1e-12) << af << " " << ab << " " << N;
                EXPECT_NEAR(s.T_, T, 1e-12 + 1e-9 * T) << af << " " << ab << " " << N;
            }
        }
    }
    // Lossless: R_N = N b / (1 + (N - 1) b) and R + T = 1, even a million layers deep (the
    // 20 squarings of a nearly singular matrix leave ~1e-7 of rounding there).
    const double b = 0.1;
    for (double N : {1.0, 7.0, 1000.0, 1e6}) {
        const auto s = hs::layered_stack(1 - b, b, N);
        const double tol = N > 1e5 ? 1e-6 : 1e-9;
        EXPECT_NEAR(s.R, N * b / (1 + (N - 1) * b), tol);
        EXPECT_NEAR(s.R + s.T_, 1.0, tol);
    }
    // The deep stack's closed form is the limit of the stack (absorbing layers; a lossless
    // stack approaches 1 only as 1/N, so it is checked on its own).
    for (double af : {0.2, 0.7, 0.85})
        EXPECT_NEAR(hs::deep_reflectance(af, 0.1), hs::layered_stack(af, 0.1, 1e9).R, 1e-9) << af;
    EXPECT_NEAR(hs::deep_reflectance(0.9, 0.1), 1.0, 1e-9);  // lossless
    // Fractional depth lies between whole layers.
    const auto a = hs::layered_stack(0.8, 0.1, 3.0), c = hs::layered_stack(0.8, 0.1, 4.0), m = hs::layered_stack(0.8, 0.1, 3.25);
    EXPECT_GT(m.R, a.R);
    EXPECT_LT(m.R, c.R);
    EXPECT_LT(m.T_, a.T_);
    EXPECT_GT(m.T_, c.T_);
    // float stays finite and close at depths where sinh would overflow
    const auto f = hs::layered_stack(0.9f, 0.05f, 1e5f);
    const auto d = hs::layered_stack(0.9, 0.05, 1e5);
    EXPECT_NEAR(f.R, d.R, 1e-5);
    EXPECT_NEAR(f.T_, 0.0f, 1e-30f);
}

TEST(DualBcsdf, DirectlyLitPointIgnoresTheCountTowardTheLight) {
    const HairSetup s(kHairs[1]);
    const hs::ChiangFiber<double> fiber(s.material, 0.3);
    const Dual d(fiber, s.tables);
    const dvec3 wo = direction(20, 0.3);
    hs::DualScatteringLight<double> lit, lit_n = lit;
    lit_n.n = 12;
    for (double phi : {0.1, 1.0, 2.5, -3.0}) {
        const dvec3 wi = direction(-10, phi);
        const dvec3 a = d.eval(wo, wi, lit), b = d.eval(wo, wi, lit_n);
        EXPECT_EQ(a, b);
        // and it is the single fiber plus a backward-only local term
        const dvec3 single = fiber.eval(wo, wi);
        if (std::abs(hs::relative_azimuth(wo, wi)) > hs::kHalfPi<double>) {
            EXPECT_NEAR(mean(a), mean(single), 1e-15);
        } else {
            EXPECT_GT(mean(a), mean(single));
        }
    }
}

TEST(DualBcsdf, GlobalTermReachesEveryAzimuth) {
    // Zinke's forward-only f_s^G vanishes at backward azimuths; the window does not.
    // d_b = 0 in both: only the global single-scattering term is left.
    hs::DualScatteringSettings<double> a, b = hs::DualScatteringSettings<double>::zinke2008();
    a.d_b = b.d_b = 0;
    const HairSetup improved(kHairs[1], a), zinke(kHairs[1], b);
    const hs::ChiangFiber<double> fiber(improved.material, 0.0);
    const dvec3 wo = direction(10, 0), wi = direction(-5, 0.6);  // 0.6 rad: same side as the viewer
    const hs::DualScatteringLight<double> sh = shadowed(3);
    EXPECT_GT(mean(Dual(fiber, improved.tables).eval(wo, wi, sh)), 0.0);
    EXPECT_EQ(mean(Dual(fiber, zinke.tables).eval(wo, wi, sh)), 0.0);
}

TEST(DualBcsdf, TransmittanceIsConditionedOnTheShadowRay) {
    const HairSetup s(kHairs[1]);
    const auto e = s.tables.lookup(0.2);
    // n → 0 with a blocked shadow ray: one fiber, not none.
    const auto f0 = hs::dual_forward(shadowed(1e-9), e, hs::DualFormulation::kImproved);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f0.transmittance[c], e.a_f[c], 1e-6);
    // n = 2: a_f^(2 / (1 - e^-2)); Zinke: a_f^2.
    const double nc = 2 / (1 - std::exp(-2.0));
    const auto f2 = hs::dual_forward(shadowed(2), e, hs::DualFormulation::kImproved);
    const auto z2 = hs::dual_forward(shadowed(2), e, hs::DualFormulation::kZinke2008);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(f2.transmittance[c], std::pow(e.a_f[c], nc), 1e-12);
        EXPECT_NEAR(z2.transmittance[c], std::pow(e.a_f[c], 2.0), 1e-12);
    }
    // Lossless hair over a deep volume: the downward flux stays 1 at any depth.
    const HairSetup w(kHairs[0]);
    const auto ew = w.tables.lookup(0.2);
    for (double n : {1.0, 10.0, 100.0}) {
        const auto f = hs::dual_forward(shadowed(n), ew, hs::DualFormulation::kImproved);
        EXPECT_NEAR(f.flux.x, 1.0, 1e-4) << n;
    }
}

// An exact count (a renderer that counts its shadow ray's fibers) is used as it is: n = 2
// attenuates by a_f², not by a_f^(2 / (1 − e^-2)); a count below one fiber still reads as
// one (the ray was blocked); Zinke's formulation ignores the flag. The BCSDF's value follows.
TEST(DualBcsdf, ExactCountsAreNotConditionedAgain) {
    const HairSetup s(kHairs[1]);
    const auto e = s.tables.lookup(0.2);
    hs::DualScatteringLight<double> exact = shadowed(2);
    exact.exact_count = true;
    const auto f2 = hs::dual_forward(exact, e, hs::DualFormulation::kImproved);
    const auto z2 = hs::dual_forward(exact, e, hs::DualFormulation::kZinke2008);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(f2.transmittance[c], std::pow(e.a_f[c], 2.0), 1e-12);
        EXPECT_NEAR(z2.transmittance[c], std::pow(e.a_f[c], 2.0), 1e-12);
    }
    hs::DualScatteringLight<double> below_one = shadowed(0.25);
    below_one.exact_count = true;
    const auto f1 = hs::dual_forward(below_one, e, hs::DualFormulation::kImproved);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f1.transmittance[c], e.a_f[c], 1e-12);
    // The BCSDF: an exact count of 2 equals the expectation whose conditioned mean is 2
    // (x / (1 − e^-x) = 2 at x = 1.5936…, by Newton's method).
    double x = 1.5;
    for (int k = 0; k < 50; ++k) {
        const double q = -std::expm1(-x), g = x / q - 2, dg = (q - x * std::exp(-x)) / (q * q);
        x -= g / dg;
    }
    const hs::ChiangFiber<double> fiber(s.material, 0.3);
    const Dual dual(fiber, s.tables);
    const dvec3 wo = direction(20, 0.4), wi = direction(-10, 2.5);
    const dvec3 a = dual.eval(wo, wi, exact), b = dual.eval(wo, wi, shadowed(x));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-9 * std::max(1.0, b[c])) << c;
    EXPECT_GT(mean(a), 0.0);
}

// The conditioned count against exact intersection counts on generated blocks: fibers
// (radius 1) placed as a Poisson process in the cross-section (eight blocks), shadow rays
// of length L from points outside every fiber. The expected count a density source reports
// is n = 2ρL (centres within 1 of the segment, minus the unit disc around the origin that
// no fiber's centre may occupy). Over the rays that hit a fiber, the mean count is
// n / (1 − e^{−n}), which the improved formulation uses, not n.
TEST(DualCount, ConditionedCountMatchesExactIntersections) {
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> U;
    const double box = 300, rho = 0.02;
    std::vector<std::vector<glm::dvec2>> blocks(8);
    for (auto& centres : blocks) {
        std::poisson_distribution<int> count(rho * box * box);
        for (int k = count(rng); k > 0; --k) centres.emplace_back(box * U(rng), box * U(rng));
    }
    for (double L : {6.0, 20.0, 60.0}) {
        const double n = 2 * rho * L;
        double hits = 0, blocked = 0;
        for (int r = 0; r < 16000; ++r) {
            const auto& centres = blocks[std::size_t(r) % blocks.size()];
            const glm::dvec2 o(70 + 160 * U(rng), 70 + 160 * U(rng));
            const double a = 2 * hs::kPi<double> * U(rng);
            const glm::dvec2 d(std::cos(a), std::sin(a));
            bool inside = false;
            int crossed = 0;
            for (const glm::dvec2& c : centres) {
                const glm::dvec2 oc = c - o;
                if (glm::dot(oc, oc) < 1) inside = true;
                const double t = std::clamp(glm::dot(oc, d), 0.0, L);
                const glm::dvec2 q = o + t * d - c;
                if (glm::dot(q, q) < 1) ++crossed;
            }
            if (inside) continue;  // a shading point lies on a fiber's surface, not inside one
            if (crossed > 0) {
                hits += crossed;
                blocked += 1;
            }
        }
        const double measured = hits / blocked, conditioned = n / (1 - std::exp(-n));
        std::printf("[ count    ] n = %.2f: mean count of blocked rays %.3f, n / (1 - e^-n) = %.3f\n", n, measured,
                    conditioned);
        EXPECT_NEAR(measured, conditioned, 0.03 * conditioned) << "L " << L;
        if (n < 1) {
            EXPECT_GT(std::abs(measured - n), 0.25 * measured);  // the unconditional n is far off
        }
    }
}

TEST(DualBcsdf, BackscatterGrowsWithTheHairBeyond) {
    const HairSetup s(kHairs[1]);
    const auto e = s.tables.lookup(0.1);
    double prev = -1;
    for (double m : {0.0, 1.0, 3.0, 10.0, 100.0}) {
        const double a = mean(hs::dual_backscatter(e, m, hs::DualFormulation::kImproved));
        EXPECT_GT(a, prev);
        prev = a;
    }
    const double deep = mean(hs::dual_backscatter(e, hs::kUnbounded<double>, hs::DualFormulation::kImproved));
    EXPECT_NEAR(prev, deep, 1e-6);
    // A deep volume gets Zinke's A_1 + A_3 itself (the finite-depth factor is 1 there).
    EXPECT_NEAR(deep, mean(e.A_b), 1e-9);
    EXPECT_EQ(mean(hs::dual_backscatter(e, 0.0, hs::DualFormulation::kZinke2008)), mean(e.A_b));
}

namespace {
struct SamplerCase {
    int hair;
    double theta_o, h, spread;
    bool zinke;
};
std::vector<SamplerCase> sampler_cases() {
    return {{0, 30, 0.2, 0.0, false}, {1, -60, -0.5, 0.05, false}, {2, 80, 0.9, 0.2, false},
            {1, 0, 0.0, 0.0, true},   {1, 45, 0.3, 0.1, true}};
}
}  // namespace

TEST(DualBcsdf, SampleMatchesPdfChi2) {
    const auto cases = sampler_cases();
    const int n_tests = int(cases.size()) + 2;
    double min_p = 1;
    for (const SamplerCase& c : cases) {
        const HairSetup s(kHairs[c.hair], c.zinke ? hs::DualScatteringSettings<double>::zinke2008()
                                               : hs::DualScatteringSettings<double>{});
        const hs::ChiangFiber<double> fiber(s.material, c.h);
        const auto at = Dual(fiber, s.tables).at(direction(c.theta_o, 0.4), c.spread);
        chi2::Options opt;
        opt.num_tests = n_tests;
        opt.samples = 200000;
        opt.max_depth = 5;
        const auto r = chi2::test([&](const dvec4& u) { return at.sample(u).wi; },
                                  [&](const dvec3& wi) { return at.pdf(wi); }, opt);
        min_p = std::min(min_p, r.p_value);
        EXPECT_TRUE(r.passed) << kHairs[c.hair].name << " θo " << c.theta_o << "\n" << r.report;
        EXPECT_NEAR(r.expected_total, 1.0, 1e-3);
    }
    std::printf("[ chi2     ] %zu dual-scattering cases, smallest p-value %.3g\n", cases.size(), min_p);

    // Negative controls: a pdf 5 % too large, and the global component's azimuths flipped
    // to the other side of the light.
    const HairSetup s(kHairs[1]);
    const hs::ChiangFiber<double> fiber(s.material, 0.2);
    const auto at = Dual(fiber, s.tables).at(direction(30, 0.4));
    chi2::Options opt;
    opt.num_tests = n_tests;
    opt.samples = 200000;
    opt.max_depth = 5;
    // Both controls share the pdf's table: one scales it, the other moves the samples.
    const chi2::Expected expected = chi2::expected_counts([&](const dvec3& wi) { return at.pdf(wi); }, opt);
    const chi2::Result scaled =
        chi2::compare(chi2::histogram([&](const dvec4& u) { return at.sample(u).wi; }, opt), expected.scaled(1.05), opt);
    EXPECT_FALSE(scaled.passed) << "pdf × 1.05 accepted, p = " << scaled.p_value;
    const dvec3 wo = at.wo();
    const chi2::Histogram rotated = chi2::histogram(
        [&](const dvec4& u) {
            const auto r = at.sample(u);
            if (r.component != hs::DualComponent::kGlobal) return r.wi;
            const double phi = hs::relative_azimuth(wo, r.wi);
            return hs::direction_from_azimuth(wo, r.wi.x, hs::wrap_pi(phi + 0.5));
        },
        opt);
    const chi2::Result moved = chi2::compare(rotated, expected, opt);
    EXPECT_FALSE(moved.passed) << "rotated global samples accepted, p = " << moved.p_value;
    std::printf("[ chi2     ] negative controls: p = %.3g (pdf × 1.05), %.3g (global lobe rotated 0.5 rad)\n",
                scaled.p_value, moved.p_value);
}

TEST(DualBcsdf, FloatSamplerMatchesPdfAndAgreesWithQuery) {
    hs::FiberParams<float> p;
    p.sigma_a = hs::sigma_a_from_concentrations(0.3f, 0.0f);
    const hs::ChiangMaterial<float> mat(p);
    const auto tables = hs::DualScatteringTables<float>::build<hs::ChiangFiber<float>>(mat);
    const hs::ChiangFiber<float> fiber(mat, 0.4f);
    const auto at = hs::DualScatteringBcsdf<hs::ChiangFiber<float>>(fiber, tables).at(glm::vec3(0.5f, 0.6f, 0.62449f), 0.05f);
    chi2::Options opt;
    opt.samples = 200000;
        opt.max_depth = 5;
    const auto r = chi2::test(
        [&](const dvec4& u) { return dvec3(at.sample(glm::vec4(u)).wi); },
        [&](const dvec3& wi) { return double(at.pdf(glm::vec3(wi))); }, opt);
    EXPECT_TRUE(r.passed) << r.report;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> U(0, 1);
    double worst = 0;
    for (int k = 0; k < 20000; ++k) {
        const auto s = at.sample(glm::vec4(draw4(U, rng)));
        ASSERT_GT(s.pdf, 0.0f);
        worst = std::max(worst, double(std::abs(at.pdf(s.wi) - s.pdf) / s.pdf));
    }
    EXPECT_LT(worst, 1e-4);
}

TEST(DualBcsdf, AnyModelBehindTheContract) {
    // A lobe subset builds its own tables (the dropped lobes are absent from them) and
    // samples consistently.
    using RTT = hs::BasicChiangFiber<double, hs::LobeSet::kR | hs::LobeSet::kTT>;
    const hs::ChiangMaterial<double> mat(params_of(kHairs[1]));
    const auto t = hs::DualScatteringTables<double>::build<RTT>(mat);
    const auto full = hs::DualScatteringTables<double>::build<hs::ChiangFiber<double>>(mat);
    EXPECT_LT(mean(t.entry(32).a_f), mean(full.entry(32).a_f));
    EXPECT_EQ(mean(t.window(0.1, 2, 1.0)), 0.0);  // no TRT
    const RTT fiber(mat, 0.1);
    const auto at = hs::DualScatteringBcsdf<RTT>(fiber, t).at(direction(20, 0.1));
    chi2::Options opt;
    opt.samples = 200000;
    const auto r = chi2::test([&](const dvec4& u) { return at.sample(u).wi; }, [&](const dvec3& wi) { return at.pdf(wi); }, opt);
    EXPECT_TRUE(r.passed) << r.report;
}

// The far field and the tabulated fiber (no h: one fiber per material) build tables whose
// entries match the Chiang fiber's h average (the same model integrated over h), and
// sample consistently.
TEST(DualBcsdf, FarFieldAndTabulatedModels) {
    hs::FiberParams<double> p = params_of(kHairs[1]);
    const hs::ChiangMaterial<double> chiang(p);
    const hs::DeonFarFieldMaterial<double> far(p);
    const hs::TabulatedMaterial<double> tab(p);
    hs::DualTableOptions<double> small;  // coarse tables: the same grid for all three
    small.theta_samples = 16;
    small.psi_samples = 17;
    const auto tc = hs::DualScatteringTables<double>::build<hs::ChiangFiber<double>>(chiang, small);
    const auto tf = hs::DualScatteringTables<double>::build<hs::DeonFarFieldFiber<double>>(far, small);
    const auto tt = hs::DualScatteringTables<double>::build<hs::TabulatedFiber<double>>(tab, small);
    // The far field is d'Eon's Gaussian detector where Chiang has a logistic: the tables
    // agree to a few per cent, not to rounding.
    for (int i : {3, 8, 12})
        for (double psi : {0.0, 1.0, 2.0, 3.1}) {
            const double c = mean(tc.window(tc.theta_of(i), 1, psi)), f = mean(tf.window(tf.theta_of(i), 1, psi)),
                         t = mean(tt.window(tt.theta_of(i), 1, psi));
            EXPECT_NEAR(f, c, 0.05 * mean(tc.window(tc.theta_of(i), 1, 3.1)) + 1e-4) << i << " " << psi;
            EXPECT_NEAR(t, f, 0.02 * mean(tf.window(tf.theta_of(i), 1, 3.1)) + 1e-4) << i << " " << psi;
        }
    for (int i = 0; i < tf.size(); ++i) {
        EXPECT_NEAR(mean(tf.entry(i).a_f + tf.entry(i).a_b), mean(tc.entry(i).a_f + tc.entry(i).a_b), 2e-3);
        EXPECT_NEAR(mean(tt.entry(i).a_f + tt.entry(i).a_b), mean(tf.entry(i).a_f + tf.entry(i).a_b), 2e-3);
    }
    const hs::DeonFarFieldFiber<double> fiber(far);
    const auto at = hs::DualScatteringBcsdf<hs::DeonFarFieldFiber<double>>(fiber, tf).at(direction(25, 0.3));
    chi2::Options opt;
    opt.samples = 100000;
    opt.max_depth = 4;
    const auto r = chi2::test([&](const dvec4& u) { return at.sample(u).wi; }, [&](const dvec3& wi) { return at.pdf(wi); }, opt);
    EXPECT_TRUE(r.passed) << r.report;
}

TEST(DualBcsdf, NoNaNAtExtremes) {
    const HairSetup s(kHairs[0]);
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    std::vector<dvec3> dirs = {dvec3(1, 0, 0), dvec3(-1, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, -1), direction(89.999, 3.14159),
                               dvec3(nan, 0, 1), dvec3(inf, inf, 0)};
    std::vector<hs::DualScatteringLight<double>> lights = {shadowed(0), shadowed(1e6, 0), shadowed(nan, nan), shadowed(inf)};
    hs::DualScatteringLight<double> odd;
    odd.direct_fraction = nan;
    lights.push_back(odd);
    // A renderer's own T_f and σ̄²_f, broken (found by bench/stress.cpp: a NaN T_f or an
    // infinite σ̄²_f gave NaN).
    for (double t : {nan, inf, -inf})
        for (double s2 : {0.0, inf, nan}) {
            hs::DualScatteringLight<double> own = shadowed(0);
            own.use_transmittance = true;
            own.T_f = dvec3(0.5, t, 0.5);
            own.sigma2_f = s2;
            lights.push_back(own);
        }
    for (double h : {-1.0, 0.0, 1.0}) {
        const hs::ChiangFiber<double> fiber(s.material, h);
        const Dual d(fiber, s.tables);
        for (const dvec3& wo : dirs)
            for (const dvec3& wi : dirs) {
                const bool finite_in = std::isfinite(wo.x + wo.y + wo.z) && std::isfinite(wi.x + wi.y + wi.z);
                for (const auto& l : lights) {
                    const dvec3 f = d.eval(wo, wi, l);
                    if (finite_in) {
                        EXPECT_TRUE(std::isfinite(f.x + f.y + f.z) && f.x >= 0) << wo.x << " " << wi.x;
                    }
                }
                const double p = d.pdf(wo, wi);
                if (finite_in) {
                    EXPECT_TRUE(std::isfinite(p) && p >= 0);
                }
                for (const dvec4& u : {dvec4(0), dvec4(1), dvec4(nan), dvec4(1 - 1e-16, 0.5, 0.5, 1 - 1e-16)}) {
                    const auto smp = d.sample(wo, u);  // must not crash; finite when inputs are
                    if (finite_in && std::isfinite(u.x + u.y + u.z + u.w)) {
                        EXPECT_TRUE(std::isfinite(smp.pdf));
                    }
                }
                // Any spread hint, even an infinite one (n β̄²_f over unbounded hair), gives a
                // finite density that its own sampler matches.
                for (double spread : {1e-3, 1e7, inf, nan}) {
                    const auto at = d.at(wo, spread);
                    const auto smp = at.sample(dvec4(0.6, 0.3, 0.7, 0.2));
                    if (finite_in) {
                        const double pa = at.pdf(wi);
                        EXPECT_TRUE(std::isfinite(pa) && pa >= 0) << "spread " << spread;
                        EXPECT_TRUE(std::isfinite(smp.pdf) && smp.pdf >= 0) << "spread " << spread;
                    }
                }
            }
    }
}

TEST(DualBcsdf, ImportanceSamplingReducesVariance) {
    // One shading point under a white environment: the estimator of ∫ F dω by the mixture
    // against uniform directions at equal sample counts, for a lit and a shadowed point (the
    // sampler does not know which: half its samples serve each state).
    const HairSetup s(kHairs[1]);
    const hs::ChiangFiber<double> fiber(s.material, 0.3);
    hs::DualScatteringLight<double> lit;
    lit.beyond = 5;
    const auto dark = shadowed(2, 5);
    // the sampler's spread hint: what the renderer knows toward its main light
    const double spread = hs::dual_forward(dark, s.tables.lookup(-0.35), hs::DualFormulation::kImproved).spread;
    const auto at = Dual(fiber, s.tables).at(direction(20, 0.2), spread);
    for (const auto& light : {lit, dark}) {
        std::mt19937_64 rng(5);
        std::uniform_real_distribution<double> U;
        const int N = 200000;
        double m1 = 0, m2 = 0, u1 = 0, u2 = 0;
        for (int k = 0; k < N; ++k) {
            const auto si = at.sample(draw4(U, rng));
            const double vi = si.pdf > 0 ? mean(at.eval(si.wi, light)) / si.pdf : 0;
            const double su_u1 = U(rng);
            const auto su = hs::uniform_sphere_sample(su_u1, U(rng));
            const double vu = mean(at.eval(su.wi, light)) / su.pdf;
            m1 += vi, m2 += vi * vi, u1 += vu, u2 += vu * vu;
        }
        const double mi = m1 / N, mu = u1 / N, var_i = m2 / N - mi * mi, var_u = u2 / N - mu * mu;
        EXPECT_NEAR(mi, mu, 5 * std::sqrt(var_u / N));  // both estimate the same integral
        const bool is_lit = light.direct_fraction > 0;
        EXPECT_GT(var_u / var_i, is_lit ? 5.0 : 2.0);
        std::printf("[ variance ] %s blond point, white environment: uniform / importance = %.1f\n",
                    is_lit ? "lit" : "shadowed", var_u / var_i);
    }
}

TEST(DualBcsdf, AgreesWithPathTracedSlabOfExplicitFibers) {
    // Tolerance 20 % on the mean over first hits (measured: blond 0.95–1.15, dark 0.94–0.97),
    // where the path estimate's own noise (2σ, checked) is below 8 % (measured 3.5–5.7 %). The improved
    // formulation must also beat Zinke's text where that one is far off (blond seen from the
    // light's side). Views through the ten-fiber slab carry too little light to test here
    // (docs/slab.md has them at other depths).
    const dvec3 wl = glm::normalize(dvec3(0.3, 0.35, 0.9));
    const dvec3 geometry[] = {glm::normalize(dvec3(-0.1, -0.2, 0.95)), glm::normalize(dvec3(0.2, 0.5, 0.7))};
    const char* names[] = {"seen from the light's side", "grazing"};
    for (int hair : {1, 2}) {
        for (int g = 0; g < 2; ++g) {
            const slab::Sums r = slab::compare_dual(params_of(kHairs[hair]), 10, wl, geometry[g], 20000);
            const double m = r.path / r.hits, noise = 2 * std::sqrt(std::max(0.0, r.path_sq / r.hits - m * m) / r.hits);
            ASSERT_LT(noise, 0.08 * m) << "the path-traced reference is too noisy to compare with";
            const double ratio = r.improved / r.path, ratio_z = r.zinke / r.path;
            std::printf("[ slab     ] %s, %s: dual / path = %.3f (Zinke 2008: %.3f; path noise %.1f %%)\n",
                        kHairs[hair].name, names[g], ratio, ratio_z, 100 * noise / m);
            EXPECT_NEAR(ratio, 1.0, 0.2) << kHairs[hair].name << " " << names[g];
            if (hair == 1 && g == 0) {
                EXPECT_LT(std::abs(ratio - 1), std::abs(ratio_z - 1));
            }
        }
    }
}

// Lobe gains above 1 (accepted up to kMaxLobeGain) make a fiber return more light than it
// receives; the multiple-scattering sums over fiber counts would diverge. Every output stays
// finite for every count, in both precisions, and the tables stay physical (a_f + a_b ≤ 1),
// so they save and load. Before: float gain 100 at n = 50 gave f = inf, gain 1e6 at n = 0
// NaN, and double gain 10 at n = 1e6 inf.
template <typename T> void check_dual_finite(const hs::ChiangMaterial<T>& m, const hs::DualTableOptions<T>& o, T gain, int lobe) {
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    const T unbounded = hs::kUnbounded<T>;
    const auto tables = hs::DualScatteringTables<T>::template build<hs::ChiangFiber<T>>(m, o);
    for (int i = 0; i < tables.size(); ++i) {
        const auto& e = tables.entry(i);
        for (int ch = 0; ch < 3; ++ch) {
            EXPECT_LE(double(e.a_f[ch]) + double(e.a_b[ch]), 1.0 + 1e-5) << "gain " << gain << " lobe " << lobe;
            for (int k = 0; k < hs::DualScatteringEntry<T>::kFields; ++k)
                EXPECT_TRUE(std::isfinite(double(e.fields()[k][ch]))) << "field " << k;
        }
    }
    for (T h : {T(-1), T(0), T(0.5)}) {
        const hs::ChiangFiber<T> fiber(m, h);
        const hs::DualScatteringBcsdf<hs::ChiangFiber<T>> d(fiber, tables);
        for (T n : {T(0), T(1), T(50), T(1e6), unbounded}) {
            hs::DualScatteringLight<T> l;
            l.direct_fraction = T(0);
            l.n = n;
            for (T to : {T(-80), T(0), T(30)})
                for (T ti : {T(-60), T(0), T(45), T(89)})
                    for (T ph : {T(0), T(1), T(3.14159)}) {
                        const T a = to * hs::kPi<T> / 180, b = ti * hs::kPi<T> / 180;
                        const V3 wo(std::sin(a), std::cos(a), T(0));
                        const V3 wi(std::sin(b), std::cos(b) * std::cos(ph), std::cos(b) * std::sin(ph));
                        const V3 f = d.eval(wo, wi, l);
                        ASSERT_TRUE(std::isfinite(double(f.x + f.y + f.z)) && f.x >= 0 && f.y >= 0 && f.z >= 0)
                            << "gain " << gain << " lobe " << lobe << " n " << n << " f " << f.x << " " << f.y << " " << f.z;
                        const auto smp = d.sample(wo, V4(T(0.3), T(0.6), T(0.2), T(0.9)));
                        ASSERT_TRUE(std::isfinite(double(smp.pdf)) && smp.pdf >= 0);
                        if (smp.pdf > 0) {
                            const V3 fs = d.eval(wo, smp.wi, l);
                            ASSERT_TRUE(std::isfinite(double(fs.x + fs.y + fs.z)));
                        }
                    }
            // The two-stream estimator's coefficients over the same entries.
            for (int i = 0; i < tables.size(); ++i)
                for (T beyond : {T(0), T(3), unbounded}) {
                    const auto st = hs::dual_streams(tables.entry(i), n, beyond);
                    for (int ch = 0; ch < 3; ++ch) {
                        ASSERT_TRUE(std::isfinite(double(st.forward[ch])) && st.forward[ch] >= 0);
                        ASSERT_TRUE(std::isfinite(double(st.back[ch])) && st.back[ch] >= 0);
                    }
                }
        }
    }
}

template <typename T> void check_gains_finite() {
    for (int lobe = -1; lobe < 4; ++lobe)  // -1: every lobe
        for (T gain : {T(1), T(10), T(100), T(1e6)}) {
            hs::LobeControls<T> c;
            for (int p = 0; p < 4; ++p)
                if (lobe < 0 || p == lobe) c.gain[p] = gain;
            for (double eu : {-1.0, 0.3}) {
                hs::FiberParams<T> p;
                p.sigma_a = eu < 0 ? glm::vec<3, T>(T(0)) : glm::vec<3, T>(hs::sigma_a_from_concentrations(eu, 0.0));
                const hs::ChiangMaterial<T> m(p, c);
                for (auto settings : {hs::DualScatteringSettings<T>::improved(), hs::DualScatteringSettings<T>::zinke2008()}) {
                    hs::DualTableOptions<T> o;
                    o.theta_samples = 16;
                    o.settings = settings;
                    check_dual_finite(m, o, gain, lobe);
                }
            }
        }
}

TEST(DualBcsdf, FiniteForGainsUpToTheLimit) {
    check_gains_finite<float>();
    check_gains_finite<double>();
}

// Finite directions of any length are normalised, as the models do (models/contract.hpp);
// a zero vector gives 0. Before, FLT_MAX components gave NaN.
namespace {
// Blond hair (melanin 0.3), tables of 16 inclinations, the BCSDF at h = 0.3 (built in place:
// the fiber points to the material, the BCSDF views the tables).
struct SmallDual {
    static hs::FiberParams<float> params() {
        hs::FiberParams<float> p;
        p.sigma_a = glm::vec3(hs::sigma_a_from_concentrations(0.3, 0.0));
        return p;
    }
    static hs::DualTableOptions<float> options() {
        hs::DualTableOptions<float> o;
        o.theta_samples = 16;
        return o;
    }
    const hs::ChiangMaterial<float> m{params()};
    const hs::DualScatteringTables<float> tables =
        hs::DualScatteringTables<float>::build<hs::ChiangFiber<float>>(m, options());
    const hs::DualScatteringBcsdf<hs::ChiangFiber<float>> d{hs::ChiangFiber<float>(m, 0.3f), tables};
};
}  // namespace

TEST(DualBcsdf, NonUnitDirectionsAreNormalised) {
    using V3 = glm::vec3;
    const SmallDual small;
    const auto& d = small.d;
    hs::DualScatteringLight<float> l;
    l.direct_fraction = 0.5f;
    l.n = 3;
    const V3 wo = glm::normalize(V3(0.3f, 0.8f, 0.2f)), wi = glm::normalize(V3(-0.4f, -0.7f, 0.5f));
    const V3 f = d.eval(wo, wi, l);
    const float pdf = d.pdf(wo, wi);
    ASSERT_GT(pdf, 0.0f);
    for (float scale : {std::numeric_limits<float>::max() / 2, 3.0f, 1e-3f, 1e-30f}) {
        const V3 fs = d.eval(wo * scale, wi * scale, l);
        EXPECT_NEAR(fs.x, f.x, 1e-4f * f.x) << scale;
        EXPECT_NEAR(d.pdf(wo * scale, wi * scale), pdf, 1e-4f * pdf) << scale;
        const auto s = d.sample(wo * scale, glm::vec4(0.3f, 0.5f, 0.6f, 0.2f));
        EXPECT_TRUE(hs::is_finite(s.wi) && std::isfinite(s.pdf)) << scale;
    }
    EXPECT_EQ(d.pdf(V3(0), wi), 0.0f);
    EXPECT_EQ(d.eval(wo, V3(0), l), V3(0));
}

// A path continues from a dual sample in one call: with the light state (fixed, or per
// sampled direction through sample_with), the sample carries f = eval(wi, light) and
// weight = f / pdf bit for bit, the direction and pdf are those of sample(u) alone, and
// the light callback sees the sampled direction once. No sample, no call, zero weight.
TEST(DualBcsdf, SampleCarriesItsWeightGivenTheLight) {
    using V3 = glm::vec3;
    const SmallDual small;
    const auto& d = small.d;
    const auto at = d.at(glm::normalize(V3(0.3f, 0.8f, 0.2f)));
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    int samples = 0;
    for (int i = 0; i < 2000; ++i) {
        const glm::vec4 u(u01(rng), u01(rng), u01(rng), u01(rng));
        hs::DualScatteringLight<float> light;
        light.direct_fraction = u01(rng) < 0.5f ? 1.0f : 0.0f;
        light.n = 4 * u01(rng);
        light.beyond = 10 * u01(rng);
        const hs::DualSample<float> plain = at.sample(u);
        const hs::DualSample<float> fixed = at.sample(u, light);
        int calls = 0;
        V3 seen(0);
        const hs::DualSample<float> with = at.sample_with(u, [&](const V3& wi) {
            ++calls;
            seen = wi;
            return light;
        });
        ASSERT_EQ(plain.f, V3(0));
        ASSERT_EQ(plain.weight, V3(0));
        for (const auto* s : {&fixed, &with}) {
            ASSERT_EQ(s->wi, plain.wi);
            ASSERT_EQ(s->pdf, plain.pdf);
            ASSERT_EQ(s->component, plain.component);
            if (plain.pdf > 0) {
                ASSERT_EQ(s->f, at.eval(plain.wi, light));
                ASSERT_EQ(s->weight, at.eval(plain.wi, light) / plain.pdf);
            } else {
                ASSERT_EQ(s->weight, V3(0));
            }
        }
        ASSERT_EQ(calls, plain.pdf > 0 ? 1 : 0);
        if (plain.pdf > 0) {
            ASSERT_EQ(seen, plain.wi);
            ++samples;
        }
    }
    EXPECT_GT(samples, 1900);
    // The top-level call is the bound one.
    hs::DualScatteringLight<float> l;
    l.n = 2;
    const glm::vec4 u(0.3f, 0.5f, 0.6f, 0.2f);
    const auto s = d.sample(glm::normalize(V3(0.3f, 0.8f, 0.2f)), u, l);
    EXPECT_EQ(s.weight, at.sample(u, l).weight);
    // Non-finite u: no sample, no weight, no call.
    const float nan = std::numeric_limits<float>::quiet_NaN();
    bool called = false;
    const auto none = at.sample_with(glm::vec4(nan), [&](const V3&) {
        called = true;
        return l;
    });
    EXPECT_EQ(none.pdf, 0.0f);
    EXPECT_EQ(none.weight, V3(0));
    EXPECT_FALSE(called);
}
