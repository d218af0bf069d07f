// Materials built per hit (ChiangMaterial::per_hit, clamped_params): the same material as
// the checked constructor's for valid parameters, bit for bit; finite, in-range materials
// for any input at all; and the cheaper constants they share with the checked path
// (TrimmedLogistic's normaliser, the tilt's sine, DeonLobes' lanes) against their
// standard-library forms; the per-hit calls (ChiangFiber::per_hit_eval, per_hit_pdf,
// per_hit_sample, per_hit_vertex) against the same calls from their parts.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

namespace hs = hairscatter;

namespace {

template <typename T> std::vector<hs::FiberParams<T>> random_valid_params(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<hs::FiberParams<T>> v;
    for (int i = 0; i < n; ++i) {
        hs::FiberParams<T> p;
        p.eta = T(1.0001 + 2.0 * u(rng));
        p.beta_m = T(1e-3 + (1.0 - 1e-3) * u(rng));
        p.beta_n = T(1e-3 + (1.0 - 1e-3) * u(rng));
        p.alpha = T((2.0 * u(rng) - 1.0) * 0.39269908169872414);
        p.sigma_a = hs::sigma_a_from_concentrations(T(3.0 * u(rng)), T(u(rng)));
        v.push_back(p);
    }
    return v;
}

template <typename T> bool same_bits(T a, T b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Every constant a fiber reads from its material, compared bit for bit.
template <typename T> void expect_same_material(const hs::ChiangMaterial<T>& a, const hs::ChiangMaterial<T>& b) {
    for (int p = 0; p <= 3; ++p) {
        EXPECT_TRUE(same_bits(a.lobe_variance(p), b.lobe_variance(p))) << p;
        EXPECT_TRUE(same_bits(a.lobe_exp_m2_over_v(p), b.lobe_exp_m2_over_v(p))) << p;
        EXPECT_TRUE(same_bits(a.lobe_shift(p), b.lobe_shift(p))) << p;
    }
    EXPECT_TRUE(same_bits(a.azimuthal().scale(), b.azimuthal().scale()));
    EXPECT_TRUE(same_bits(a.azimuthal().inv_scale(), b.azimuthal().inv_scale()));
    EXPECT_TRUE(same_bits(a.azimuthal().density(T(0.5)), b.azimuthal().density(T(0.5))));
    for (int c = 0; c < hs::kChannelLanes; ++c) EXPECT_TRUE(same_bits(a.sigma_a_lanes()[c], b.sigma_a_lanes()[c]));
    EXPECT_TRUE(same_bits(a.params().eta, b.params().eta));
    EXPECT_EQ(a.has_lobe_weights(), b.has_lobe_weights());
}

template <typename T> void per_hit_is_the_checked_material() {
    const auto params = random_valid_params<T>(300, 7u);
    std::mt19937 rng(11u);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (const auto& p : params) {
        const hs::ChiangMaterial<T> checked(p);
        const auto hit = hs::ChiangMaterial<T>::per_hit(p);
        expect_same_material(checked, hit);
        // And so the fibers' values, bit for bit.
        const T h = T(2.0 * u(rng) - 1.0);
        const glm::vec<3, T> wo = glm::normalize(glm::vec<3, T>(T(u(rng) - 0.5), T(u(rng) - 0.5), T(u(rng) - 0.5)));
        const glm::vec<3, T> wi = glm::normalize(glm::vec<3, T>(T(u(rng) - 0.5), T(u(rng) - 0.5), T(u(rng) - 0.5)));
        const glm::vec<4, T> uu(T(u(rng)), T(u(rng)), T(u(rng)), T(u(rng)));
        const hs::ChiangFiber<T> a(checked, h), b(hit, h);
        const auto ea = a.eval(wo, wi), eb = b.eval(wo, wi);
        for (int c = 0; c < 3; ++c) EXPECT_TRUE(same_bits(ea[c], eb[c]));
        EXPECT_TRUE(same_bits(a.pdf(wo, wi), b.pdf(wo, wi)));
        const auto sa = a.sample(wo, uu), sb = b.sample(wo, uu);
        EXPECT_TRUE(same_bits(sa.pdf, sb.pdf));
        for (int c = 0; c < 3; ++c) EXPECT_TRUE(same_bits(sa.wi[c], sb.wi[c]));
    }
}

// |a - b| within `rel` of the larger magnitude (or both below `tiny`).
template <typename T> bool close(T a, T b, T rel, T tiny) {
    return std::abs(a - b) <= rel * std::max(std::abs(a), std::abs(b)) || std::max(std::abs(a), std::abs(b)) < tiny;
}

// ChiangFiber::per_hit_eval, per_hit_pdf, per_hit_sample and per_hit_vertex against the
// same calls from their parts (ChiangMaterial::per_hit, then the fiber): the same arithmetic, so equal but
// for the compiler's FMA contraction, which may fuse differently once the material is a
// local of the call. Bound: 1e-6 relative in float, 1e-13 in double (measured: bit for bit
// without FMA, 2.2e-16 in double with GCC -O3 -ffp-contract=fast; the worst is printed).
// Under -ffast-math (HAIRSCATTER_ALLOW_FAST_MATH) 1e-4 and 1e-12.
template <typename T> void per_hit_calls_are_the_composed_calls() {
#if defined(__FAST_MATH__)  // (reassociated differently in the two: 5.5e-6 and 7.6e-15 seen)
    const T rel = std::is_same<T, float>::value ? T(1e-4) : T(1e-12);
#else
    const T rel = std::is_same<T, float>::value ? T(1e-6) : T(1e-13);
#endif
    const T tiny = std::is_same<T, float>::value ? T(1e-30) : T(1e-290);
    const auto params = random_valid_params<T>(400, 13u);
    std::mt19937 rng(17u);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    double worst = 0.0;
    auto track = [&worst](T a, T b) {
        const double m = std::max(std::abs(double(a)), std::abs(double(b)));
        if (m > 0.0) worst = std::max(worst, std::abs(double(a) - double(b)) / m);
    };
    for (const auto& p : params) {
        const T h = T(2.0 * u(rng) - 1.0);
        const glm::vec<3, T> wo(T(u(rng) - 0.5), T(u(rng) - 0.5), T(u(rng) - 0.5));  // (not unit: both normalise)
        const glm::vec<3, T> wi(T(u(rng) - 0.5), T(u(rng) - 0.5), T(u(rng) - 0.5));
        const glm::vec<4, T> uu(T(u(rng)), T(u(rng)), T(u(rng)), T(u(rng)));
        const auto m = hs::ChiangMaterial<T>::per_hit(p);
        const hs::ChiangFiber<T> fiber(m, h);
        const auto e = hs::ChiangFiber<T>::per_hit_eval(p, h, wo, wi), e_ref = fiber.eval(wo, wi);
        for (int c = 0; c < 3; ++c) {
            EXPECT_TRUE(close(e[c], e_ref[c], rel, tiny)) << e[c] << " vs " << e_ref[c];
            track(e[c], e_ref[c]);
        }
        const T pdf = hs::ChiangFiber<T>::per_hit_pdf(p, h, wo, wi), pdf_ref = fiber.pdf(wo, wi);
        EXPECT_TRUE(close(pdf, pdf_ref, rel, tiny)) << pdf << " vs " << pdf_ref;
        track(pdf, pdf_ref);
        const auto s = hs::ChiangFiber<T>::per_hit_sample(p, h, wo, uu), s_ref = fiber.sample(wo, uu);
        EXPECT_EQ(s.lobe, s_ref.lobe);
        EXPECT_TRUE(close(s.pdf, s_ref.pdf, rel, tiny)) << s.pdf << " vs " << s_ref.pdf;
        track(s.pdf, s_ref.pdf);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(s.wi[c], s_ref.wi[c], rel);
            EXPECT_TRUE(close(s.weight[c], s_ref.weight[c], rel, tiny)) << s.weight[c] << " vs " << s_ref.weight[c];
            track(s.weight[c], s_ref.weight[c]);
        }
        // The vertex: eval_pdf and sample of the bound fiber.
        const auto at = fiber.at(wo);
        const auto v = hs::ChiangFiber<T>::per_hit_vertex(p, h, wo, wi, uu);
        const auto ep = at.eval_pdf(wi);
        const auto sv = at.sample(uu);
        for (int c = 0; c < 3; ++c) {
            EXPECT_TRUE(close(v.light.f[c], ep.f[c], rel, tiny)) << v.light.f[c] << " vs " << ep.f[c];
            EXPECT_TRUE(close(v.next.weight[c], sv.weight[c], rel, tiny)) << v.next.weight[c] << " vs " << sv.weight[c];
            EXPECT_NEAR(v.next.wi[c], sv.wi[c], rel);
            track(v.light.f[c], ep.f[c]);
            track(v.next.weight[c], sv.weight[c]);
        }
        EXPECT_TRUE(close(v.light.pdf, ep.pdf, rel, tiny)) << v.light.pdf << " vs " << ep.pdf;
        EXPECT_TRUE(close(v.next.pdf, sv.pdf, rel, tiny)) << v.next.pdf << " vs " << sv.pdf;
        EXPECT_EQ(v.next.lobe, sv.lobe);
        track(v.light.pdf, ep.pdf);
        track(v.next.pdf, sv.pdf);
        // A sample's pdf is the per-hit pdf of its own direction, to the rounding of that
        // direction's round trip through wi (1e-4 relative seen in float).
        if (s.pdf > T(0)) {
            const T at_wi = hs::ChiangFiber<T>::per_hit_pdf(p, h, wo, s.wi);
            const T trip = std::is_same<T, float>::value ? T(1e-3) : T(1e-9);
            EXPECT_TRUE(close(s.pdf, at_wi, trip, tiny)) << s.pdf << " vs " << at_wi;
        }
    }
    std::printf("per-hit calls against their parts: worst relative difference %.3g\n", worst);
}

}  // namespace

TEST(PerHit, PerHitCallsAreTheComposedCallsFloat) { per_hit_calls_are_the_composed_calls<float>(); }
TEST(PerHit, PerHitCallsAreTheComposedCallsDouble) { per_hit_calls_are_the_composed_calls<double>(); }

TEST(PerHit, ValidParametersGiveTheCheckedMaterialFloat) { per_hit_is_the_checked_material<float>(); }
TEST(PerHit, ValidParametersGiveTheCheckedMaterialDouble) { per_hit_is_the_checked_material<double>(); }

TEST(PerHit, ClampedParamsKeepValidOnesAndMoveTheRestIntoRange) {
    for (const auto& p : random_valid_params<float>(200, 3u)) {
        const auto q = hs::clamped_params(p);
        EXPECT_TRUE(same_bits(p.eta, q.eta) && same_bits(p.beta_m, q.beta_m) && same_bits(p.beta_n, q.beta_n) &&
                    same_bits(p.alpha, q.alpha));
        for (int c = 0; c < 3; ++c) EXPECT_TRUE(same_bits(p.sigma_a[c], q.sigma_a[c]));
    }
    // The extreme-input sweep: every field through NaN, ±Inf, ±huge, ±0, negative and just
    // out of range, one at a time and all together; each result passes validate() and its
    // fiber gives finite, non-negative values.
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const float bad[] = {nan, inf, -inf, 3e38f, -3e38f, 0.0f, -0.0f, -1.0f, 1.0f, 1e-30f, 0.5f, 2.0f, 1e7f};
    const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, 0.5f, -0.8f)), wi = glm::normalize(glm::vec3(-0.2f, -0.6f, 0.7f));
    for (int field = 0; field < 8; ++field) {
        for (float x : bad) {
            hs::FiberParams<float> p;
            p.sigma_a = glm::vec3(0.5f, 0.8f, 1.5f);
            float* f[7] = {&p.eta, &p.beta_m, &p.beta_n, &p.alpha, &p.sigma_a[0], &p.sigma_a[1], &p.sigma_a[2]};
            if (field < 7)
                *f[field] = x;
            else
                for (float* g : f) *g = x;
            const auto q = hs::clamped_params(p);
            EXPECT_EQ(hs::validate(q), "") << "field " << field << " = " << x;
            const auto m = hs::ChiangMaterial<float>::per_hit(p);
            const hs::ChiangFiber<float> fib(m, 0.3f);
            const glm::vec3 e = fib.eval(wo, wi);
            const float pdf = fib.pdf(wo, wi);
            const auto s = fib.sample(wo, glm::vec4(0.3f, 0.6f, 0.2f, 0.9f));
            for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(e[c]) && e[c] >= 0.0f) << field << " " << x;
            EXPECT_TRUE(std::isfinite(pdf) && pdf >= 0.0f) << field << " " << x;
            EXPECT_TRUE(std::isfinite(s.pdf) && s.pdf >= 0.0f) << field << " " << x;
            // The per-hit calls, which build the same material inside the call.
            const glm::vec3 e2 = hs::ChiangFiber<float>::per_hit_eval(p, 0.3f, wo, wi);
            const float pdf2 = hs::ChiangFiber<float>::per_hit_pdf(p, 0.3f, wo, wi);
            const auto s2 = hs::ChiangFiber<float>::per_hit_sample(p, 0.3f, wo, glm::vec4(0.3f, 0.6f, 0.2f, 0.9f));
            for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(e2[c]) && e2[c] >= 0.0f) << field << " " << x;
            EXPECT_TRUE(std::isfinite(pdf2) && pdf2 >= 0.0f) << field << " " << x;
            EXPECT_TRUE(std::isfinite(s2.pdf) && s2.pdf >= 0.0f) << field << " " << x;
            for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(s2.weight[c]) && s2.weight[c] >= 0.0f);
            const auto v2 = hs::ChiangFiber<float>::per_hit_vertex(p, 0.3f, wo, wi, glm::vec4(0.3f, 0.6f, 0.2f, 0.9f));
            for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(v2.light.f[c]) && v2.light.f[c] >= 0.0f);
            EXPECT_TRUE(std::isfinite(v2.light.pdf) && v2.light.pdf >= 0.0f && std::isfinite(v2.next.pdf));
        }
    }
    // Non-finite directions and numbers give nothing, as the fiber's own calls do.
    {
        const float nan = std::numeric_limits<float>::quiet_NaN();
        const hs::FiberParams<float> p;
        const glm::vec3 bad(nan, 0.0f, 1.0f);
        EXPECT_EQ(hs::ChiangFiber<float>::per_hit_eval(p, 0.3f, bad, wi), glm::vec3(0.0f));
        EXPECT_EQ(hs::ChiangFiber<float>::per_hit_eval(p, 0.3f, wo, glm::vec3(0.0f)), glm::vec3(0.0f));
        EXPECT_EQ(hs::ChiangFiber<float>::per_hit_pdf(p, 0.3f, wo, bad), 0.0f);
        const auto v = hs::ChiangFiber<float>::per_hit_vertex(p, 0.3f, bad, wi, glm::vec4(0.5f));
        EXPECT_EQ(v.light.f, glm::vec3(0.0f));
        EXPECT_EQ(v.light.pdf, 0.0f);
        EXPECT_EQ(v.next.pdf, 0.0f);
        EXPECT_EQ(hs::ChiangFiber<float>::per_hit_sample(p, 0.3f, wo, glm::vec4(nan)).pdf, 0.0f);
        const auto m = hs::ChiangMaterial<float>::per_hit(p);
        EXPECT_EQ(hs::ChiangFiber<float>::per_hit_sample(p, nan, wo, glm::vec4(0.5f)).pdf,
                  hs::ChiangFiber<float>(m, nan).sample(wo, glm::vec4(0.5f)).pdf);
    }
    // NaN goes to the lower end, a value above the range to the upper one. (Under
    // -ffast-math, allowed by HAIRSCATTER_ALLOW_FAST_MATH, the compares may send a NaN to
    // either end; the sweep above holds there too.)
    hs::FiberParams<float> p;
    p.beta_m = nan;
    p.beta_n = 5.0f;
    p.eta = 1.0f;
    const auto q = hs::clamped_params(p);
#if defined(__FAST_MATH__)
    EXPECT_TRUE(q.beta_m == hs::kMinRoughness<float> || q.beta_m == 1.0f);
#else
    EXPECT_EQ(q.beta_m, hs::kMinRoughness<float>);
#endif
    EXPECT_EQ(q.beta_n, 1.0f);
    EXPECT_GT(q.eta, 1.0f);
}

// FiberParamBounds::clamp (in float on the host four fields per vector) against the rule it
// documents, written here field by field: a finite value is moved into [lo, hi], NaN and
// ±Inf go to lo. Random bit patterns (every exponent, NaN and Inf among them) and the
// special values, in every field at once, for the default bounds and a narrower box.
template <typename T> T clamp_rule(T x, T lo, T hi) {
    if (!std::isfinite(x)) return lo;
    return x < lo ? lo : (x > hi ? hi : x);
}
template <typename T> void clamp_is_the_rule(const hs::FiberParamBounds<T>& bounds) {
    using Bits = typename std::conditional<sizeof(T) == 4, std::uint32_t, std::uint64_t>::type;
    std::mt19937_64 rng(5u);
    const T specials[] = {std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::infinity(),
                          -std::numeric_limits<T>::infinity(), T(0), -T(0), std::numeric_limits<T>::denorm_min(),
                          std::numeric_limits<T>::max(), -std::numeric_limits<T>::max(), T(1), T(-1), T(0.3), T(2)};
    const hs::FiberParams<T>&lo = bounds.lo(), &hi = bounds.hi();
    for (int i = 0; i < 20000; ++i) {
        T x[7];
        for (T& v : x) {
            if (rng() % 4 == 0) {
                v = specials[rng() % (sizeof specials / sizeof specials[0])];
            } else {
                const Bits b = Bits(rng());
                std::memcpy(&v, &b, sizeof v);
            }
        }
        hs::FiberParams<T> p;
        p.eta = x[0], p.beta_m = x[1], p.beta_n = x[2], p.alpha = x[3];
        p.sigma_a = glm::vec<3, T>(x[4], x[5], x[6]);
        const hs::FiberParams<T> q = bounds.clamp(p);
        EXPECT_TRUE(same_bits(q.eta, clamp_rule(x[0], lo.eta, hi.eta))) << x[0];
        EXPECT_TRUE(same_bits(q.beta_m, clamp_rule(x[1], lo.beta_m, hi.beta_m))) << x[1];
        EXPECT_TRUE(same_bits(q.beta_n, clamp_rule(x[2], lo.beta_n, hi.beta_n))) << x[2];
        EXPECT_TRUE(same_bits(q.alpha, clamp_rule(x[3], lo.alpha, hi.alpha))) << x[3];
        for (int c = 0; c < 3; ++c)
            EXPECT_TRUE(same_bits(q.sigma_a[c], clamp_rule(x[4 + c], lo.sigma_a[c], hi.sigma_a[c]))) << x[4 + c];
    }
}
template <typename T> void clamp_is_the_rule() {
    clamp_is_the_rule(hs::FiberParamBounds<T>());
    hs::FiberParams<T> lo, hi;
    lo.eta = T(1.4), hi.eta = T(1.7);
    lo.beta_m = T(0.1), hi.beta_m = T(0.6);
    lo.beta_n = T(0.2), hi.beta_n = T(0.5);
    lo.alpha = T(-0.05), hi.alpha = T(0.1);
    lo.sigma_a = glm::vec<3, T>(T(0.1), T(0.2), T(0.3));
    hi.sigma_a = glm::vec<3, T>(T(2), T(3), T(4));
    clamp_is_the_rule(hs::FiberParamBounds<T>::checked(lo, hi));
}

#if !defined(__FAST_MATH__)  // (the rule's std::isfinite and NaN compares need IEEE semantics)
TEST(PerHit, ClampIsTheRuleBitForBitFloat) { clamp_is_the_rule<float>(); }
TEST(PerHit, ClampIsTheRuleBitForBitDouble) { clamp_is_the_rule<double>(); }
#endif

// The normaliser tanh(π/2s) as -m/(2 + m), m = expm1(-π/s), read back through the density
// at 0, (1/s) / (4 tanh(π/2s)), against the same in double with std::tanh: within 6 float
// ulp over every scale β_n ∈ [1e-3, 1] maps to (the float expm1 is exp - 1 beyond
// |x| = 1/2, which loses at most a factor 2.6 of exp's 1-ulp error there; 1/s, the quotient
// and the density's own products add an ulp each).
TEST(PerHit, LogisticNormaliserMatchesTanh) {
    for (int i = 0; i <= 2000; ++i) {
        const double beta_n = 1e-3 + (1.0 - 1e-3) * i / 2000.0;
        const float s = hs::logistic_scale(float(beta_n));
        const hs::TrimmedLogistic<float> n(s);
        const double truth = (1.0 / double(s)) / (4.0 * std::tanh(hs::kHalfPi<double> / double(s)));
        EXPECT_NEAR(double(n.density(1.0f)) / truth, 1.0, 6.0 * std::numeric_limits<float>::epsilon())
            << "beta_n " << beta_n;
        const hs::TrimmedLogistic<double> nd{double(s)};
        EXPECT_NEAR(nd.density(1.0) / truth, 1.0, 8.0 * std::numeric_limits<double>::epsilon()) << "beta_n " << beta_n;
    }
}

// Where expm1(-π/s) rounds to -1 the normaliser skips it (TrimmedLogistic's constructor):
// the density's numerator is then (1/s) / (-m / (2 + m)) with m = elem::expm1(-π/s), the
// unshortened formula, bit for bit, over scales on both sides of the switch (float 0.179,
// double 0.082) and far from it.
template <typename T> void logistic_shortcut_is_the_formula() {
    for (int i = 0; i <= 20000; ++i) {
        const T s = T(1e-3) + (T(0.5) - T(1e-3)) * T(i) / T(20000);
        const T inv_s = T(1) / s, m = hs::elem::expm1(-hs::kPi<T> * inv_s);
        const T want = inv_s / (-m / (T(2) + m));
        EXPECT_TRUE(same_bits(hs::TrimmedLogistic<T>(s).density_numerator(T(1)), want)) << "s " << s;
    }
}
TEST(PerHit, LogisticShortcutIsTheFormulaFloat) { logistic_shortcut_is_the_formula<float>(); }
TEST(PerHit, LogisticShortcutIsTheFormulaDouble) { logistic_shortcut_is_the_formula<double>(); }

// expm1_each_given_exp (DeonLobes' one exp for both of its constants) returns expm1_each's
// values bit for bit, on either side of its switch at |x| = 1/2 and down to underflow.
TEST(PerHit, Expm1GivenExpIsExpm1Each) {
    for (int i = 0; i < 40000; ++i) {
        float x[4], e[4], y[4];
        for (int k = 0; k < 4; ++k) {
            x[k] = -std::ldexp(1.0f + float(i % 1000) / 1000.0f, i / 1000 - 24 + k);  // -2^-24 … -2^19
            e[k] = y[k] = x[k];
        }
        hs::elem::exp_each(e);
        hs::elem::expm1_each(x);
        hs::elem::expm1_each_given_exp(y, e);
        for (int k = 0; k < 4; ++k) EXPECT_TRUE(same_bits(x[k], y[k])) << x[k];
    }
}

// DeonLobes' lane constants (one exp vector in float, the expm1s from it; in double the
// residual's copied from TRT's) are DeonLongitudinal(v_p)'s, bit for bit: its M_p at a few
// angles and its θi sample, which reads e^(-2/v), over β_m ∈ [1e-3, 1].
template <typename T> void deon_lanes_are_deon_longitudinal() {
    const T angles[][4] = {{T(0.3), T(0.9539392), T(-0.2), T(0.9797959)}, {T(-0.8), T(0.6), T(0.5), T(0.8660254)}};
    for (int i = 0; i <= 4000; ++i) {
        const T beta_m = T(1e-3) + (T(1) - T(1e-3)) * T(i) / T(4000);
        const hs::DeonLobes<T> lanes(beta_m, T(0));
        for (int p = 0; p <= 3; ++p) {
            const hs::DeonLongitudinal<T> lane = lanes.longitudinal(p), own(lanes.lobe_variance(p));
            for (const auto& a : angles)
                EXPECT_TRUE(same_bits(lane.eval(a[0], a[1], a[2], a[3]), own.eval(a[0], a[1], a[2], a[3])))
                    << "beta_m " << beta_m << " p " << p;
            EXPECT_TRUE(same_bits(lane.sample_sin_theta(T(0.3), T(0.95), T(1e-4), T(0.3)),
                                  own.sample_sin_theta(T(0.3), T(0.95), T(1e-4), T(0.3))))
                << "beta_m " << beta_m << " p " << p;
        }
    }
}
TEST(PerHit, DeonLanesAreDeonLongitudinalFloat) { deon_lanes_are_deon_longitudinal<float>(); }
TEST(PerHit, DeonLanesAreDeonLongitudinalDouble) { deon_lanes_are_deon_longitudinal<double>(); }

// The tilt's sine: in float its Taylor series within |α| ≤ π/8, within 1 ulp of std::sin
// (the truncation, 4e-13, is far below float's rounding); in double std::sin itself.
TEST(PerHit, TiltSineMatchesStdSin) {
    for (int i = -1000; i <= 1000; ++i) {
        const double a = 0.39269908169872414 * i / 1000.0;
        const hs::CuticleTilt<double> td(a);
        const hs::CuticleTilt<float> tf{float(a)};
        // rotate(TT) by +α at θo = 0: (sin α, cos α).
        EXPECT_EQ(td.rotate(1, 0.0, 1.0).sin_theta, std::sin(a));
        const float sf = tf.rotate(1, 0.0f, 1.0f).sin_theta, want = std::sin(float(a));
        EXPECT_LE(std::fabs(sf - want), std::fabs(std::nextafter(want, 1.0f) - want)) << a;
    }
}

// Every lobe's rotation, (sin, cos) of -2α, α, 4α and 0 (CuticleTilt: in float for |α| ≤ π/8
// Taylor polynomials of the four angles side by side), against double std::sin and std::cos
// over the whole validated range of α: the sine within 3 float ulp of its own magnitude, the
// cosine within 2^-22 absolute (it falls to 0 at 4α = π/2, where no relative bound holds;
// the rotation needs it absolute). Measured: 2.2 ulp and 1.1·2^-23, where the former sine
// of α, square root and double angles reached 4.4 ulp and 2.3·2^-23. The residual's
// rotation is exactly (0, 1).
TEST(PerHit, TiltRotationsMatchStdSinCos) {
    const auto ulp = [](double v) { return std::ldexp(1.0, std::max(std::ilogb(v), -126) - 23); };
    for (int i = -20000; i <= 20000; ++i) {
        const float a = float(0.39269908169872414 * i / 20000.0);
        const hs::CuticleTilt<float> t(a);
        const double angle[3] = {-2.0 * double(a), double(a), 4.0 * double(a)};
        for (int p = 0; p < 3; ++p) {
            const auto r = t.rotation(p);
            const double s = std::sin(angle[p]), c = std::cos(angle[p]);
            if (s != 0.0) {
                EXPECT_LE(std::fabs(double(r.sin_theta) - s), 3.0 * ulp(s)) << "alpha " << a << " lobe " << p;
            }
            EXPECT_LE(std::fabs(double(r.cos_theta) - c), std::ldexp(1.0, -22)) << "alpha " << a << " lobe " << p;
        }
        EXPECT_EQ(t.rotation(3).sin_theta, 0.0f);
        EXPECT_EQ(t.rotation(3).cos_theta, 1.0f);
    }
}
