// Special functions, distributions and the single lobes against Boost.Math references.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/special_functions/bessel.hpp>
#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

#include "support/reference_chiang.hpp"

namespace hs = hairscatter;

namespace {

// Arguments from 1e-8 to 1e4 on a log grid, plus both sides of the x = 6 split.
std::vector<double> bessel_arguments() {
    std::vector<double> xs = {0.0, 6.0, std::nextafter(6.0, 0.0), std::nextafter(6.0, 10.0)};
    for (double e = -8; e <= 4; e += 0.01) xs.push_back(std::pow(10.0, e));
    return xs;
}

template <typename T> void check_i0(double tol) {
    double worst = 0, worst_x = 0;
    for (double xd : bessel_arguments()) {
        const T x = T(xd);
        const long double xl = (long double)x;  // compare at the argument actually used
        const long double ref_i0e =
            boost::math::cyl_bessel_i(0, xl < 5000 ? xl : 5000.0L) * std::exp(-(xl < 5000 ? xl : 5000.0L));
        if (xl < 5000) {
            const double e = double(std::abs(hs::i0e(x) / ref_i0e - 1));
            if (e > worst) worst = e, worst_x = xd;
        }
        // log of I0 = 1 + y + y²/4 + … loses x²/4 to rounding for tiny x: use its series there
        // (the next term, y⁴/576, is below 1e-15 relative for x < 0.1).
        const long double y = xl * xl / 4;
        const long double ref_log = xl < 0.1L    ? std::log1p(y + y * y / 4 + y * y * y / 36)
                                    : xl < 5000 ? std::log(boost::math::cyl_bessel_i(0, xl))
                                                : ref::log_i0(double(xl));
        if (xl > 0) {
            const double e = double(std::abs(hs::log_i0(x) / ref_log - 1));
            if (e > worst) worst = e, worst_x = xd;
        }
        if (xl < (sizeof(T) == 4 ? 80 : 700)) {
            const double e = double(std::abs(hs::i0(x) / boost::math::cyl_bessel_i(0, xl) - 1));
            if (e > worst) worst = e, worst_x = xd;
        }
    }
    std::printf("[ worst    ] I0/i0e/log_i0 relative error %.3g at x = %.6g\n", worst, worst_x);
    EXPECT_LT(worst, tol);
}

}  // namespace

// The library promises 1e-6 relative accuracy for every argument in float and double.
TEST(BesselI0, AccurateEverywhereDouble) { check_i0<double>(1e-8); }
TEST(BesselI0, AccurateEverywhereFloat) { check_i0<float>(1e-6); }

TEST(BesselI0, NoOverflowInScaledForms) {
    for (float x : {1e4f, 1e20f, std::numeric_limits<float>::max()}) {
        EXPECT_TRUE(std::isfinite(hs::i0e(x)));
        EXPECT_TRUE(std::isfinite(hs::log_i0(x)));
        EXPECT_GT(hs::i0e(x), 0.0f);
    }
}

// ∫ M_p(v, θi, θo) cosθi dθi = 1 (d'Eon et al. 2011) for v from 1e-4 to 10 and θo to 89.9°,
// integrated by adaptive Gauss–Kronrod split at the lobe's peak θi = -θo.
template <typename T> double worst_mp_normalisation() {
    // The adaptive rule's target: a float integrand is rounded at ~6e-8 relative, so asking
    // for 1e-12 only makes the rule bisect to its depth limit; 1e-6 sits 20× under the
    // float bound asserted below.
    const double tol = sizeof(T) == 4 ? 1e-6 : 1e-12;
    double worst = 0;
    for (double v : {1e-4, 3e-4, 1e-3, 1e-2, 0.05, 0.1, 0.3, 1.0, 3.0, 10.0}) {
        const hs::DeonLongitudinal<T> m{T(v)};
        for (double deg : {0.0, 10.0, 30.0, 60.0, 80.0, 89.0, 89.9, -45.0, -89.9}) {
            const double to = deg * ref::kPi / 180;
            const T so = T(std::sin(to)), co = T(std::cos(to));
            auto integrand = [&](double ti) {
                return double(m.eval(T(std::sin(ti)), T(std::cos(ti)), so, co)) * std::cos(ti);
            };
            const double peak = -to, w = std::sqrt(v);
            double total = 0;
            // Split around the peak so the adaptive rule sees the narrow lobe.
            std::vector<double> cuts = {-ref::kPi / 2, peak - 8 * w, peak - w, peak, peak + w, peak + 8 * w,
                                        ref::kPi / 2};
            std::sort(cuts.begin(), cuts.end());
            for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
                const double a = std::clamp(cuts[k], -ref::kPi / 2, ref::kPi / 2);
                const double b = std::clamp(cuts[k + 1], -ref::kPi / 2, ref::kPi / 2);
                if (b > a) total += boost::math::quadrature::gauss_kronrod<double, 31>::integrate(integrand, a, b, 15, tol);
            }
            const double e = std::abs(total - 1);
            worst = std::max(worst, e);
            EXPECT_NEAR(total, 1.0, sizeof(T) == 4 ? 2e-5 : 1e-8) << "v = " << v << ", θo = " << deg;
        }
    }
    return worst;
}

TEST(DeonLongitudinal, IntegratesToOneDouble) {
    std::printf("[ worst    ] |∫M cosθ dθ - 1| = %.3g (double)\n", worst_mp_normalisation<double>());
}
TEST(DeonLongitudinal, IntegratesToOneFloat) {
    std::printf("[ worst    ] |∫M cosθ dθ - 1| = %.3g (float)\n", worst_mp_normalisation<float>());
}

// Against the paper's own direct and log-space forms (tests/support/reference_chiang.hpp).
TEST(DeonLongitudinal, MatchesPaperFormula) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> ang(-1.55, 1.55);
    double worst = 0;
    for (double v : {1e-4, 1e-3, 0.01, 0.0999, 0.1001, 0.5, 2.0, 10.0}) {
        const hs::DeonLongitudinal<double> m(v);
        for (int k = 0; k < 2000; ++k) {
            const double ti = ang(rng), to = (k % 2) ? ang(rng) : -ti + 0.01 * ang(rng);
            const double r = ref::mp(v, std::sin(ti), std::cos(ti), std::sin(to), std::cos(to));
            const double ours = m.eval(std::sin(ti), std::cos(ti), std::sin(to), std::cos(to));
            if (r > 1e-200) worst = std::max(worst, std::abs(ours / r - 1));
        }
    }
    std::printf("[ worst    ] M_p relative error vs paper form %.3g\n", worst);
    EXPECT_LT(worst, 1e-8);
}

// No switch in our form, but I0 has one at a = 6: M must be continuous across it.
TEST(DeonLongitudinal, ContinuousAcrossBesselSplit) {
    for (double v : {1e-4, 0.01, 0.1, 1.0}) {
        const hs::DeonLongitudinal<double> m(v);
        // At the peak θi = -θo with a = cos²θo / v = 6, where M is far from underflow.
        const double co = std::sqrt(6 * v);
        if (co >= 1) continue;
        const double so = std::sqrt(1 - co * co);
        const double lo = std::nextafter(co, 0.0), hi = std::nextafter(co, 1.0);
        const double a = m.eval(-std::sqrt(1 - lo * lo), lo, so, co), b = m.eval(-std::sqrt(1 - hi * hi), hi, so, co);
        ASSERT_GT(b, 0.0);
        EXPECT_NEAR(a / b, 1.0, 1e-8) << "v = " << v;
    }
}

// The sampler reproduces M_p: compare the CDF of sampled θi with the integrated pdf
// (Kolmogorov–Smirnov distance with 2e5 samples; the 12 cases share a 1 % level:
// sqrt(ln(2·12/0.01)/2)/sqrt(n) = 0.0044).
TEST(DeonLongitudinal, SamplerMatchesDensityKS) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> uni(0, 1);
    for (double v : {1e-4, 0.01, 0.3, 5.0}) {
        for (double deg : {0.0, 40.0, 85.0}) {
            const hs::DeonLongitudinal<double> m(v);
            const double to = deg * ref::kPi / 180, so = std::sin(to), co = std::cos(to);
            const int n = 200000;
            std::vector<double> ti(n);
            for (auto& t : ti) t = std::asin(m.sample_sin_theta(so, co, uni(rng), uni(rng)));
            std::sort(ti.begin(), ti.end());
            auto cdf = [&](double x) {
                auto f = [&](double t) { return m.eval(std::sin(t), std::cos(t), so, co) * std::cos(t); };
                double s = 0, a = -ref::kPi / 2;
                const double w = std::sqrt(v), peak = -to;
                for (double c : {peak - 8 * w, peak, peak + 8 * w, x}) {
                    const double b = std::min(c, x);
                    if (b > a) s += boost::math::quadrature::gauss_kronrod<double, 31>::integrate(f, a, b, 12, 1e-10), a = b;
                }
                return s;
            };
            double d = 0;
            for (int q = 1; q < 200; ++q) {
                const double x = ti[std::size_t(q) * n / 200];
                d = std::max(d, std::abs(cdf(x) - double(q) / 200));
            }
            EXPECT_LT(d, 0.0044) << "v = " << v << ", θo = " << deg;
        }
    }
}

TEST(TrimmedLogistic, IntegratesToOneAndInverts) {
    for (double beta_n : {0.01, 0.1, 0.3, 0.7, 1.0}) {
        const double s = hs::logistic_scale(beta_n);
        const hs::TrimmedLogistic<double> d(s);
        auto f = [&](double x) { return d.pdf(x); };
        const double cuts[] = {-ref::kPi, -0.1, 0.0, 0.1, ref::kPi};  // the peak is at 0
        double total = 0;
        for (int k = 0; k < 4; ++k)
            total += boost::math::quadrature::gauss_kronrod<double, 31>::integrate(f, cuts[k], cuts[k + 1], 15, 1e-12);
        EXPECT_NEAR(total, 1.0, 1e-8) << "beta_n = " << beta_n;
        // pdf against the paper's form; sample ∘ cdf = identity.
        for (double x = -3.1; x <= 3.1; x += 0.05) {
            EXPECT_NEAR(d.pdf(x), ref::trimmed_logistic(x, s), 1e-9 * (1 + ref::trimmed_logistic(x, s)));
            const double u = d.cdf(x);
            if (u > 1e-12 && u < 1 - 1e-12) {
                EXPECT_NEAR(d.sample(u), x, 1e-6 * (1 + std::abs(x)));
            }
        }
    }
}

TEST(TrimmedLogistic, SampleNeverNaNOnClosedUnitInterval) {
    for (float beta_n : {1e-3f, 0.01f, 0.3f, 1.0f}) {
        const hs::TrimmedLogistic<float> d(hs::logistic_scale(beta_n));
        for (float u : {0.0f, 1e-30f, 1e-7f, 0.5f, std::nextafter(1.0f, 0.0f), 1.0f}) {
            const float x = d.sample(u);
            EXPECT_TRUE(std::isfinite(x));
            EXPECT_LE(std::abs(x), 3.1415927f);
            EXPECT_TRUE(std::isfinite(d.pdf(x)));
        }
    }
}

// N_p of Chiang's model integrates to 1 over φ for every p and h.
TEST(AzimuthalLogistic, IntegratesToOneOverPhi) {
    const hs::TrimmedLogistic<double> d(hs::logistic_scale(0.3));
    for (int p = 0; p < 3; ++p)
        for (double h : {-1.0, -0.5, 0.0, 0.7, 1.0}) {
            const double gt = std::asin(h / 1.6);
            const double Phi = hs::exit_azimuth(p, std::asin(h), gt);
            auto f = [&](double phi) { return hs::azimuthal_logistic(d, phi, Phi); };
            const double c = hs::wrap_pi(Phi);
            double total = boost::math::quadrature::gauss_kronrod<double, 31>::integrate(f, -ref::kPi, c, 15, 1e-12) +
                           boost::math::quadrature::gauss_kronrod<double, 31>::integrate(f, c, ref::kPi, 15, 1e-12);
            EXPECT_NEAR(total, 1.0, 1e-8) << "p = " << p << ", h = " << h;
        }
}

// The N exponent of a difference d = φ - Φ (both in [-π, π]) is the exponent of d wrapped
// once, bit for bit: min(|d|, 2π - |d|) is the wrap's result, since 2π - |d| is exact there.
template <typename T> void check_exponent_of_difference() {
    const hs::TrimmedLogistic<T> d(hs::logistic_scale(T(0.3)));
    std::mt19937 rng(7);
    std::uniform_real_distribution<T> u(-hs::kPi<T>, hs::kPi<T>);
    std::vector<std::pair<T, T>> pairs = {{hs::kPi<T>, -hs::kPi<T>}, {-hs::kPi<T>, hs::kPi<T>}, {hs::kPi<T>, T(0)},
                                          {T(0), T(0)},           {T(-0.0), T(0)},          {hs::kPi<T>, hs::kPi<T>}};
    for (int i = 0; i < 200000; ++i) pairs.emplace_back(u(rng), u(rng));
    for (const auto& [phi, centre] : pairs) {
        const T a = d.exponent_of_difference(phi - centre), b = d.exponent(hs::wrap_pi_once(phi - centre));
        ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << phi << " - " << centre << ": " << a << " vs " << b;
    }
}
TEST(TrimmedLogistic, ExponentOfDifferenceIsTheWrappedExponent) {
    check_exponent_of_difference<float>();
    check_exponent_of_difference<double>();
}

TEST(Fresnel, KnownValues) {
    // Normal incidence: ((η - 1)/(η + 1))²; grazing: 1; against the reference elsewhere.
    EXPECT_NEAR(hs::fresnel_dielectric(1.0, 1.55), std::pow(0.55 / 2.55, 2), 1e-15);
    EXPECT_NEAR(hs::fresnel_dielectric(0.0, 1.55), 1.0, 1e-15);
    for (double c = 0.0; c <= 1.0; c += 0.01) EXPECT_NEAR(hs::fresnel_dielectric(c, 1.55), ref::fresnel(c, 1.55), 1e-14);
}

TEST(WrapPi, WrapsIntoRange) {
    for (double x = -13; x <= 13; x += 0.013) {
        const double w = hs::wrap_pi(x);
        EXPECT_LE(std::abs(w), ref::kPi);
        EXPECT_NEAR(std::remainder(w - x, 2 * ref::kPi), 0.0, 1e-12);
    }
}

// all_finite(a, b) (the stateless calls' input test) is is_finite of every component: one
// non-finite value in any position of either vector makes it false, and the extreme finite
// values (largest, smallest subnormal, -0) keep it true.
template <typename T> void check_all_finite() {
    using L = std::numeric_limits<T>;
    const T bad[] = {L::quiet_NaN(), -L::quiet_NaN(), L::infinity(), -L::infinity()};
    const T good[] = {T(0), -T(0), L::max(), -L::max(), L::denorm_min(), -L::denorm_min(), L::min(), T(1)};
    for (const T g : good) {
        EXPECT_TRUE(hs::all_finite(glm::vec<3, T>(g), glm::vec<4, T>(g)));
        for (const T x : bad) {
            for (int i = 0; i < 7; ++i) {
                glm::vec<3, T> a(g);
                glm::vec<4, T> b(g);
                if (i < 3) a[i] = x;
                else b[i - 3] = x;
                EXPECT_FALSE(hs::all_finite(a, b)) << "position " << i << " value " << double(x);
                EXPECT_EQ(hs::all_finite(a, b), hs::is_finite(a) && hs::is_finite(b));
            }
        }
    }
}
TEST(Functions, AllFiniteFindsEveryNonFiniteComponent) {
    check_all_finite<float>();
    check_all_finite<double>();
}

// pairwise_sum groups as a balanced tree: (x0 + x1) + (x2 + x3) and so on. Terms chosen
// so that the grouping shows in the result (1 + 2^-24 rounds away against 1, not
// against 2^-24 + 2^-24), and small integers, whose sums every grouping gets exactly.
TEST(Functions, PairwiseSumIsABalancedTree) {
    const float e = std::ldexp(1.0f, -24);
    const float four[4] = {1.0f, e, e, e};  // (1 + e) + (e + e) = 1 + 2^-23; the loop gives 1
    EXPECT_EQ(hs::pairwise_sum<4>(four), (1.0f + e) + (e + e));
    EXPECT_EQ(hs::pairwise_sum<4>(four), 1.0f + std::ldexp(1.0f, -23));
    const float three[3] = {e, e, 1.0f};  // (e + e) + 1 = 1 + 2^-23 (the loop: the same here)
    EXPECT_EQ(hs::pairwise_sum<3>(three), 1.0f + std::ldexp(1.0f, -23));
    double x[9];
    for (int k = 0; k < 9; ++k) x[k] = double(k + 1);
    EXPECT_EQ(hs::pairwise_sum<1>(x), 1.0);
    EXPECT_EQ(hs::pairwise_sum<2>(x), 3.0);
    EXPECT_EQ(hs::pairwise_sum<5>(x), 15.0);
    EXPECT_EQ(hs::pairwise_sum<8>(x), 36.0);
    EXPECT_EQ(hs::pairwise_sum<9>(x), 45.0);
    const float neg_zero[2] = {-0.0f, -0.0f};  // no leading +0: the sum of -0s stays -0
    EXPECT_TRUE(std::signbit(hs::pairwise_sum<2>(neg_zero)));
}

// The device-safe machine constants are the standard library's.
static_assert(hs::kEpsilon<float> == std::numeric_limits<float>::epsilon());
static_assert(hs::kEpsilon<double> == std::numeric_limits<double>::epsilon());
static_assert(hs::kMinNormal<float> == std::numeric_limits<float>::min());
static_assert(hs::kMinNormal<double> == std::numeric_limits<double>::min());

// The float hot-path versions of exp, atan2 and asin (math/elementary.hpp) against the
// standard library in double: exp within 2e-7 relative over [-87, 88] (its float result
// is below 1 ulp from the polynomial, plus the input's rounding), atan2 within 4e-7 rad
// over the whole circle, asin within 4e-7 relative on [-1, 1].
TEST(Elementary, FloatVersionsAreAccurate) {
    double we = 0, wa = 0, ws = 0;
    for (double x = -87.0; x <= 88.0; x += 3e-4) {
        const float f = float(x);
        we = std::max(we, std::abs(double(hs::elem::exp(f)) / std::exp(double(f)) - 1));
    }
    for (double t = -3.14159; t <= 3.14159; t += 3e-5)
        for (double r : {1e-30, 1.0, 1e30}) {
            const float y = float(r * std::sin(t)), x = float(r * std::cos(t));
            wa = std::max(wa, std::abs(double(hs::elem::atan2(y, x)) - std::atan2(double(y), double(x))));
        }
    for (double x = -1; x <= 1; x += 3e-6) {
        const float f = float(x);
        const double r = std::asin(double(f));
        if (r != 0) ws = std::max(ws, std::abs(double(hs::elem::asin(f)) / r - 1));
    }
    // Arguments whose x log2 e lies at or next to a half-integer, where the rounding of n
    // (the shifter's ties to even, or the conversion's away from zero) decides the reduction.
    for (int k = -251; k <= 253; k += 2) {
        const float mid = float(k * 0.5 * 0.69314718055994530942);
        for (float f : {std::nextafter(mid, -100.0f), mid, std::nextafter(mid, 100.0f)})
            if (f > -87.3f && f < 88.0f)
                we = std::max(we, std::abs(double(hs::elem::exp(f)) / std::exp(double(f)) - 1));
    }
    std::printf("[ worst    ] float exp %.3g rel, atan2 %.3g rad, asin %.3g rel\n", we, wa, ws);
    EXPECT_LT(we, 2e-7);
    EXPECT_LT(wa, 4e-7);
    EXPECT_LT(ws, 4e-7);
    EXPECT_EQ(hs::elem::exp(-100.0f), 0.0f);
    EXPECT_EQ(hs::elem::exp(0.0f), 1.0f);
    EXPECT_EQ(hs::elem::atan2(0.0f, 0.0f), 0.0f);
    // The octant and quadrant reflections are sign-bit operations (no branch): the signed
    // zeros and the axes come out as std::atan2 gives them.
    EXPECT_TRUE(std::signbit(hs::elem::atan2(-0.0f, 1.0f)) && hs::elem::atan2(-0.0f, 1.0f) == 0.0f);
    EXPECT_EQ(hs::elem::atan2(0.0f, -0.0f), hs::kPi<float>);
    EXPECT_EQ(hs::elem::atan2(-0.0f, -0.0f), -hs::kPi<float>);
    EXPECT_EQ(hs::elem::atan2(0.0f, -1.0f), hs::kPi<float>);
    EXPECT_EQ(hs::elem::atan2(1.0f, 0.0f), hs::kHalfPi<float>);
    EXPECT_EQ(hs::elem::atan2(-1.0f, -0.0f), -hs::kHalfPi<float>);
    EXPECT_TRUE(std::isnan(hs::elem::atan2(std::nanf(""), 1.0f)));
    EXPECT_TRUE(std::isnan(hs::elem::atan2(1.0f, std::nanf(""))));
    EXPECT_EQ(hs::elem::asin(1.5f), hs::kHalfPi<float>);  // clamped, not NaN
    EXPECT_EQ(hs::elem::asin(-1.5f), -hs::kHalfPi<float>);
}

// The float exp of lanes (every model's batches of lobe terms): groups of four (eight with
// AVX) go through detail::exp_float_lanes (GCC/Clang vector extensions), the rest through
// the scalar lane exp.
// Both against the standard library in double (2e-7 relative, as the scalar exp above) and
// bit for bit against each other, with the range ends, zeros, ±Inf and NaN; and sqrt_each
// (SQRTPS on x86) bit for bit against std::sqrt. exp_each_nonpositive (the lobes' exps,
// without the clamp at 88) bit for bit against exp_each wherever it is defined, x ≤ 88
// (-Inf and NaN included).
TEST(Elementary, FloatExpAndSqrtLanesMatchTheScalarForms) {
    double we = 0;
    long mismatches = 0;
    auto same = [](float a, float b) {
        std::uint32_t ba, bb;
        std::memcpy(&ba, &a, 4);
        std::memcpy(&bb, &b, 4);
        return ba == bb || (std::isnan(a) && std::isnan(b));
    };
    auto check = [&](const auto& x) {
        constexpr int n = int(sizeof(x) / sizeof(float));
        float y[n], r[n], z[n];
        for (int k = 0; k < n; ++k) y[k] = r[k] = z[k] = x[k];
        hs::elem::exp_each(y);
        hs::elem::sqrt_each(r);
        bool bounded = true;  // every x ≤ 88 or NaN: exp_each_nonpositive's domain
        for (int k = 0; k < n; ++k) bounded = bounded && !(x[k] > 88.0f);
        if (bounded) hs::elem::exp_each_nonpositive(z);
        for (int k = 0; k < n; ++k) {
            if (!same(y[k], hs::elem::detail::exp_float<true>(x[k]))) ++mismatches;
            if (bounded && !same(z[k], y[k])) ++mismatches;
            if (!same(r[k], std::sqrt(x[k]))) ++mismatches;
            if (x[k] >= -87.0f && x[k] <= 88.0f)
                we = std::max(we, std::abs(double(y[k]) / std::exp(double(x[k])) - 1));
        }
    };
    for (double x0 = -90.0; x0 <= 90.0; x0 += 2.3e-4) {
        float x4[4], x8[8], x3[3];
        for (int k = 0; k < 8; ++k) x8[k] = float(x0 + 0.7e-4 * k);
        for (int k = 0; k < 4; ++k) x4[k] = float(-x0 * (1 + 0.1 * k));
        for (int k = 0; k < 3; ++k) x3[k] = float(x0 + 1e-5 * k);
        check(x4);
        check(x8);
        check(x3);
    }
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    const float specials[8] = {-87.3f, std::nextafter(-87.3f, 0.0f), 88.0f, 0.0f, -0.0f, inf, -inf, nan};
    check(specials);
    const float tiny[4] = {1e-38f, -1e-38f, 1e-45f, 3e38f};
    check(tiny);
    const float bounded_specials[8] = {-87.3f, std::nextafter(-87.3f, 0.0f), 88.0f, 0.0f, -0.0f, -3e38f, -inf, nan};
    check(bounded_specials);
    std::printf("[ worst    ] float exp lanes %.3g rel; %ld mismatches against the scalar forms\n", we,
                mismatches);
    EXPECT_LT(we, 2e-7);
    EXPECT_EQ(mismatches, 0);
    float edge[4] = {-inf, -100.0f, nan, 0.0f};
    hs::elem::exp_each(edge);
    EXPECT_EQ(edge[0], 0.0f);
    EXPECT_EQ(edge[1], 0.0f);
    EXPECT_TRUE(std::isnan(edge[2]));
    EXPECT_EQ(edge[3], 1.0f);
}

// The float expm1 and log1p (the dual-scattering layer stacks, the d'Eon normalisation)
// against the standard library in double, relative: expm1 within 4e-7 over [-87, 20]
// (near 0 the series, beyond ±1/2 exp - 1, whose subtraction at most 2.6× exp's 1.2e-7),
// log1p within 3e-7 over (-1, 1e30] (the series near 0, the float log of 1 + x beyond,
// whose rounding of 1 + x costs up to 3 ulp at x = 0.41).
TEST(Elementary, FloatExpm1AndLog1pAreAccurate) {
    double we = 0, wl = 0;
    for (double x = -87.0; x <= 20.0; x += 1.1e-4) {
        const float f = float(x);
        const double r = std::expm1(double(f));
        if (r != 0) we = std::max(we, std::abs(double(hs::elem::expm1(f)) / r - 1));
    }
    for (double e = -40; e <= 0; e += 1e-3)  // tiny arguments of either sign
        for (double sign : {-1.0, 1.0}) {
            const float f = float(sign * std::exp2(e));
            we = std::max(we, std::abs(double(hs::elem::expm1(f)) / std::expm1(double(f)) - 1));
        }
    for (double x = -0.999; x <= 3.0; x += 1.3e-5) {
        const float f = float(x);
        const double r = std::log1p(double(f));
        if (r != 0) wl = std::max(wl, std::abs(double(hs::elem::log1p(f)) / r - 1));
    }
    for (double e = -40; e <= 100; e += 1e-3) {
        const float f = float(std::exp2(e));
        wl = std::max(wl, std::abs(double(hs::elem::log1p(f)) / std::log1p(double(f)) - 1));
    }
    std::printf("[ worst    ] float expm1 %.3g rel, log1p %.3g rel\n", we, wl);
    EXPECT_LT(we, 4e-7);
    EXPECT_LT(wl, 3e-7);
    EXPECT_EQ(hs::elem::expm1(0.0f), 0.0f);
    EXPECT_EQ(hs::elem::expm1(-std::numeric_limits<float>::infinity()), -1.0f);
    EXPECT_TRUE(std::isnan(hs::elem::expm1(std::numeric_limits<float>::quiet_NaN())));
    EXPECT_EQ(hs::elem::log1p(0.0f), 0.0f);
    EXPECT_TRUE(std::isnan(hs::elem::log1p(std::numeric_limits<float>::quiet_NaN())));
    EXPECT_EQ(hs::elem::log1p(std::numeric_limits<float>::infinity()), std::numeric_limits<float>::infinity());
}

// The lane forms (expm1_each, log1p_each: the dual BCSDF's batched lobe norms and layer
// stacks) choose between the same two forms by a select: the same accuracy over the same
// ranges (log1p_each takes x ≥ 0), and the same special values.
TEST(Elementary, FloatExpm1AndLog1pLanesAreAccurate) {
    constexpr int kN = 8;
    double we = 0, wl = 0;
    auto expm1_lanes = [&](double x0, double step, int count) {
        for (int j = 0; j < count; j += kN) {
            float x[kN];
            for (int k = 0; k < kN; ++k) x[k] = float(x0 + step * (j + k));
            float y[kN];
            std::copy(x, x + kN, y);
            hs::elem::expm1_each(y);
            for (int k = 0; k < kN; ++k) {
                const double r = std::expm1(double(x[k]));
                if (r != 0) we = std::max(we, std::abs(double(y[k]) / r - 1));
            }
        }
    };
    expm1_lanes(-87.0, 1.1e-4, 970000);
    expm1_lanes(-1e-6, 1.3e-12, 1600000);  // tiny arguments of either sign
    for (double x0 : {0.0, 1e-30, 1e-10, 1e-3, 0.4, 3.0, 1e10}) {
        float x[kN], y[kN];
        for (int k = 0; k < kN; ++k) x[k] = y[k] = float(x0 * (1 + 0.37 * k));
        hs::elem::log1p_each(y);
        for (int k = 0; k < kN; ++k) {
            const double r = std::log1p(double(x[k]));
            if (r != 0) wl = std::max(wl, std::abs(double(y[k]) / r - 1));
        }
    }
    for (double x0 = 0; x0 <= 3.0; x0 += 1.3e-5 * kN) {
        float x[kN], y[kN];
        for (int k = 0; k < kN; ++k) x[k] = y[k] = float(x0 + 1.3e-5 * k);
        hs::elem::log1p_each(y);
        for (int k = 0; k < kN; ++k) {
            const double r = std::log1p(double(x[k]));
            if (r != 0) wl = std::max(wl, std::abs(double(y[k]) / r - 1));
        }
    }
    std::printf("[ worst    ] float expm1_each %.3g rel, log1p_each %.3g rel\n", we, wl);
    EXPECT_LT(we, 4e-7);
    EXPECT_LT(wl, 3e-7);
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    float e[4] = {0.0f, -inf, nan, -100.0f};
    hs::elem::expm1_each(e);
    EXPECT_EQ(e[0], 0.0f);
    EXPECT_EQ(e[1], -1.0f);
    EXPECT_TRUE(std::isnan(e[2]));
    EXPECT_EQ(e[3], -1.0f);
    float l[4] = {0.0f, inf, nan, 3.0e38f};
    hs::elem::log1p_each(l);
    EXPECT_EQ(l[0], 0.0f);
    EXPECT_EQ(l[1], inf);
    EXPECT_TRUE(std::isnan(l[2]));
    EXPECT_NEAR(double(l[3]), std::log1p(3.0e38), 1e-5 * std::log1p(3.0e38));
}

// pow_each (the dual BCSDF's transmittance a_f^n through n ≥ 1 layers): in float e^(y ln x)
// as one batch, whose error grows with |y ln x| (the log's 1.8e-7 relative, times it):
// within 2.5e-7 (|y ln x| + 1) relative of the standard library's pow in double wherever
// the result is a normal float, and 0 at x = 0.
TEST(Elementary, FloatPowLanesAreAccurate) {
    double worst = 0;
    for (double y : {1.0, 1.0001, 1.7, 5.0, 40.0, 1000.0}) {
        for (double x0 = 0; x0 <= 1.0; x0 += 1e-4 * 8) {
            float x[8];
            for (int k = 0; k < 8; ++k) x[k] = float(std::min(1.0, x0 + 1e-4 * k));
            float r[8];
            std::copy(x, x + 8, r);
            hs::elem::pow_each(r, float(y));
            for (int k = 0; k < 8; ++k) {
                const double ref = std::pow(double(x[k]), y);
                if (x[k] == 0.0f) {
                    EXPECT_EQ(r[k], 0.0f);
                } else if (ref > 1e-37) {
                    const double tol = 2.5e-7 * (std::abs(y * std::log(double(x[k]))) + 1);
                    worst = std::max(worst, std::abs(double(r[k]) / ref - 1) / tol);
                }
            }
        }
    }
    std::printf("[ worst    ] float pow_each: %.3g of its tolerance 2.5e-7 (|y ln x| + 1)\n", worst);
    EXPECT_LT(worst, 1.0);
}

// expm1_each, log1p_each and pow_each take whole groups of four (eight with AVX) lanes as
// vectors (elem::detail::each_group): bit-identical to the scalar lane forms they replace,
// for arrays of 4, 8, 16 and (the scalar loop) 3 lanes, specials included. With FMA
// (-march=native) the compiler may fuse a multiply and an add in the scalar reference
// inlined here and not in the lanes, or the other way round: 1 ulp apart is allowed then
// (seen with GCC -O3, in log1p).
TEST(Elementary, FloatLaneGroupsMatchTheScalarLaneForms) {
    namespace ed = hs::elem::detail;
#if defined(__FMA__)
    constexpr std::int64_t kUlps = 1;
#else
    constexpr std::int64_t kUlps = 0;
#endif
    long mismatches = 0, checked = 0;
    auto same = [&](float a, float b) {
        std::int32_t ba, bb;
        std::memcpy(&ba, &a, 4);
        std::memcpy(&bb, &b, 4);
        ++checked;
        const std::int64_t ulps = std::abs(std::int64_t(ba) - std::int64_t(bb));  // (same signs here)
        if (!(ulps <= kUlps || (std::isnan(a) && std::isnan(b)))) ++mismatches;
    };
    auto check = [&](const auto& x, float y) {
        constexpr int n = int(sizeof(x) / sizeof(float));
        float e[n], l[n], p[n];
        for (int k = 0; k < n; ++k) {
            e[k] = x[k];
            l[k] = std::abs(x[k]);
            p[k] = std::min(std::abs(x[k]), 1.0f);
        }
        hs::elem::expm1_each(e);
        hs::elem::log1p_each(l);
        hs::elem::pow_each(p, y);
        for (int k = 0; k < n; ++k) {
            const float ax = std::abs(x[k]), px = std::min(ax, 1.0f);
            same(e[k], hs::select(std::fabs(x[k]) < 0.5f, ed::expm1_series(x[k]), ed::exp_float<true>(x[k]) - 1.0f));
            const float r = hs::select((ax > -0.29f) & (ax < 0.41f), ed::log1p_series(ax), ed::log_float(1.0f + ax));
            same(l[k], hs::select(ax <= 3.0e38f, r, ax));
            same(p[k], ed::exp_float<true>(y * ed::log_float(px)));
        }
    };
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> mag(-8, 3), sign(-1, 1);
    for (int i = 0; i < 20000; ++i) {
        float x16[16], x8[8], x4[4], x3[3];
        auto draw = [&] { return std::copysign(std::pow(10.0f, mag(rng)), sign(rng)); };
        for (float& v : x16) v = draw();
        for (float& v : x8) v = draw();
        for (float& v : x4) v = draw();
        for (float& v : x3) v = draw();
        const float y = 1.0f + 50.0f * std::abs(sign(rng));
        check(x16, y);
        check(x8, y);
        check(x4, y);
        check(x3, y);
    }
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    const float specials[8] = {0.5f, -0.5f, 0.41f, 1e-38f, 0.0f, inf, nan, 88.0f};
    check(specials, 3.0f);
    EXPECT_EQ(mismatches, 0) << "of " << checked;
}

// The float log (sampling M_p and the logistic) and sincos (sampled azimuths) against the
// standard library in double: log within 2e-7 relative away from 1 and 1e-7 absolute
// near it, over every binade of normal floats; sin and cos within 2e-7 absolute on
// [-2π, 2π].
TEST(Elementary, FloatLogAndSincosAreAccurate) {
    double wl = 0, wla = 0, wsc = 0;
    for (double e = -125.9; e < 127.9; e += 1.37e-3) {
        const float x = float(std::exp2(e));
        const double r = std::log(double(x));
        const double d = std::abs(double(hs::elem::log(x)) - r);
        if (std::abs(r) > 0.1) wl = std::max(wl, d / std::abs(r));
        else wla = std::max(wla, d);
    }
    for (double x = 0.9; x < 1.1; x += 1e-6) {
        const float f = float(x);
        wla = std::max(wla, std::abs(double(hs::elem::log(f)) - std::log(double(f))));
    }
    for (double x = -6.3; x <= 6.3; x += 1e-5) {
        const float f = float(x);
        float s, c;
        hs::elem::sincos(f, s, c);
        wsc = std::max({wsc, std::abs(double(s) - std::sin(double(f))), std::abs(double(c) - std::cos(double(f)))});
    }
    std::printf("[ worst    ] float log %.3g rel (%.3g abs near 1), sincos %.3g abs\n", wl, wla, wsc);
    EXPECT_LT(wl, 2e-7);
    EXPECT_LT(wla, 1e-7);
    EXPECT_LT(wsc, 2e-7);
}

// mul_each is the element-wise product, bit for bit, in its vector form (float, four
// elements) and its loop (other sizes, double), Inf, NaN, -0 and subnormals included.
TEST(Elementary, MulEachIsTheElementwiseProduct) {
    const float fx[] = {1.5f, -0.0f, std::numeric_limits<float>::infinity(), 1e-40f, 3.0f, 7.0f, -2.5f, 0.1f};
    const float fy[] = {2.0f, 5.0f, 0.5f, 1e20f, std::numeric_limits<float>::quiet_NaN(), -0.0f, 1e-30f, 3.0f};
    for (int start = 0; start + 4 <= 8; ++start) {
        float x[4], y[4];
        for (int k = 0; k < 4; ++k) x[k] = fx[start + k], y[k] = fy[(start + 2 * k) % 8];
        float want[4];
        for (int k = 0; k < 4; ++k) want[k] = x[k] * y[k];
        hs::elem::mul_each(x, y);
        for (int k = 0; k < 4; ++k) EXPECT_EQ(std::memcmp(&x[k], &want[k], sizeof(float)), 0) << start << " " << k;
    }
    float x3[3] = {1.0f, 2.0f, 3.0f};
    hs::elem::mul_each(x3, {4.0f, 0.5f, -1.0f});
    EXPECT_EQ(x3[0], 4.0f);
    EXPECT_EQ(x3[1], 1.0f);
    EXPECT_EQ(x3[2], -3.0f);
    double xd[4] = {1.0, -2.0, 1e-310, 3.0};
    hs::elem::mul_each(xd, {0.25, 3.0, 2.0, -0.0});
    EXPECT_EQ(xd[0], 0.25);
    EXPECT_EQ(xd[1], -6.0);
    EXPECT_EQ(xd[2], 2e-310);
    EXPECT_TRUE(std::signbit(xd[3]) && xd[3] == 0.0);
}

TEST(Elementary, DoubleExpFlushesSubnormalsToZero) {
    EXPECT_EQ(hs::elem::exp(-709.0), 0.0);
    EXPECT_EQ(hs::elem::exp(-1e300), 0.0);
    EXPECT_EQ(hs::elem::exp(-700.0), std::exp(-700.0));
    EXPECT_EQ(hs::elem::exp(1.5), std::exp(1.5));
}

// exp_lanes_nonpositive (double: a polynomial in vector lanes, HuangFiber's transmittances)
// against libm's exp over x ≤ 0 in lanes and in the scalar remainder of a batch of seven:
// within 2 ulp (under -ffast-math, which may fold the two-part reduction, |x|·1e-16
// relative more), 0 below -708.39 as exp<double>, -Inf to 0, NaN to NaN; and sqrt_each
// of doubles (SQRTPD on x86) bit for bit std::sqrt.
TEST(Elementary, DoubleExpLanesAreWithinTwoUlpOfLibm) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> wide(-720.0, 0.0), narrow(-8.0, 0.0);
    double worst = 0;
    for (int it = 0; it < 40000; ++it) {
        double x[7], y[7];
        for (double& v : x) v = it % 2 == 0 ? wide(rng) : narrow(rng);
        std::copy(x, x + 7, y);
        hs::elem::exp_lanes_nonpositive(y);
        for (int k = 0; k < 7; ++k) {
            const double e = hs::elem::exp(x[k]);
            if (e == 0) {
                ASSERT_EQ(y[k], 0.0) << "x = " << x[k];
                continue;
            }
            double slack = 2;
#if defined(__FAST_MATH__)
            slack += std::fabs(x[k]) * 1e-16 / std::numeric_limits<double>::epsilon();
#endif
            const double ulp = std::nextafter(e, 2 * e) - e, d = std::fabs(y[k] - e) / ulp;
            worst = std::max(worst, d);
            ASSERT_LE(d, slack) << "x = " << x[k];
        }
    }
    std::printf("exp_lanes_nonpositive<double>: worst %.2f ulp from libm\n", worst);
    double s[8] = {0.0, -0.0, -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN(),
                   -708.38, -708.4, -1e300, -1.0};
    hs::elem::exp_lanes_nonpositive(s);
    EXPECT_EQ(s[0], 1.0);
    EXPECT_EQ(s[1], 1.0);
    EXPECT_EQ(s[2], 0.0);
    EXPECT_TRUE(std::isnan(s[3]));
    EXPECT_GT(s[4], 0.0);
    EXPECT_EQ(s[5], 0.0);
    EXPECT_EQ(s[6], 0.0);
    EXPECT_NEAR(s[7], std::exp(-1.0), 4e-16);
    double r[6] = {0.0, 2.0, 1e-300, 7.5, 1e300, 0.3}, q[6];
    std::copy(r, r + 6, q);
    hs::elem::sqrt_each(q);
    for (int k = 0; k < 6; ++k) EXPECT_EQ(q[k], std::sqrt(r[k]));
}

namespace {

// Stratified u over [0, 1): the frequency of each entry, the leftover's worst distance
// from uniform per entry (Kolmogorov–Smirnov) and its reconstruction of u.
template <typename T> void check_discrete(const std::vector<T>& w) {
    const int n = int(w.size()), m = 200000;
    T total = T(0);
    for (T x : w) total += x;
    std::vector<std::vector<double>> left(w.size());
    for (int k = 0; k < m; ++k) {
        const T u = T((k + 0.5) / m);
        const hs::DiscreteChoice<T> c = hs::sample_discrete(w.data(), n, u);
        ASSERT_GE(c.index, 0);
        ASSERT_LT(c.index, n);
        ASSERT_GT(w[std::size_t(c.index)], T(0)) << "u = " << u;
        ASSERT_GE(c.rescaled, T(0));
        ASSERT_LE(c.rescaled, T(1));
        double before = 0;
        for (int i = 0; i < c.index; ++i) before += double(w[std::size_t(i)]);
        EXPECT_NEAR((before + double(c.rescaled) * double(w[std::size_t(c.index)])) / double(total), double(u),
                    8 * std::numeric_limits<T>::epsilon());
        left[std::size_t(c.index)].push_back(double(c.rescaled));
    }
    for (int i = 0; i < n; ++i) {
        std::vector<double>& v = left[std::size_t(i)];
        EXPECT_NEAR(double(v.size()) / m, double(w[std::size_t(i)] / total), 2.0 / m) << "entry " << i;
        if (v.empty()) continue;
        std::sort(v.begin(), v.end());
        double ks = 0;
        for (std::size_t k = 0; k < v.size(); ++k)
            ks = std::max({ks, std::abs(v[k] - double(k) / v.size()), std::abs(v[k] - double(k + 1) / v.size())});
        EXPECT_LT(ks, 2.0 / v.size() + 1e-5) << "entry " << i;
    }
}

}  // namespace

// Entry i with probability w_i / Σw, and the leftover of u a fresh uniform number.
TEST(SampleDiscrete, ProbabilitiesAndUniformLeftover) {
    check_discrete<double>({0.0, 0.5, 0.0, 1.5, 2.0, 0.0});
    check_discrete<float>({0.0f, 0.5f, 0.0f, 1.5f, 2.0f, 0.0f});
    check_discrete<float>({0.3f, 1e-3f, 0.1f});
    check_discrete<double>({1.0});
}

// u ≈ 1 past the rounded sum (with the sum or with 1 as the total) never lands on an
// empty entry; all-zero weights pick entry 0 and keep u.
TEST(SampleDiscrete, NeverPicksAnEmptyEntry) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> uni(0, 1);
    const float us[] = {0.0f, 0.5f, std::nextafter(1.0f, 0.0f), 1.0f};
    for (int k = 0; k < 2000; ++k) {
        float w[5], total = 0;
        for (float& x : w) {
            x = uni(rng) < 0.4f ? 0.0f : uni(rng);
            total += x;
        }
        float normalised[5];
        for (int i = 0; i < 5; ++i) normalised[i] = total > 0 ? w[i] / total : 0.0f;
        for (float u : us) {
            for (const hs::DiscreteChoice<float>& c :
                 {hs::sample_discrete(w, 5, u), hs::sample_discrete(normalised, 5, u, 1.0f)}) {
                if (total > 0) {
                    EXPECT_GT(w[c.index], 0.0f) << "u = " << u;
                    EXPECT_GE(c.rescaled, 0.0f);
                    EXPECT_LE(c.rescaled, 1.0f);
                } else {
                    EXPECT_EQ(c.index, 0);
                    EXPECT_EQ(c.rescaled, u);
                }
            }
        }
    }
    // A last entry of weight 0 after weights whose sum rounds below 1.
    const double w[] = {0.1, 0.2, 0.7 - 1e-16, 0.0};
    for (double u : {std::nextafter(1.0, 0.0), 1.0}) {
        const hs::DiscreteChoice<double> c = hs::sample_discrete(w, 4, u, 1.0);
        EXPECT_EQ(c.index, 2);
        EXPECT_LE(c.rescaled, 1.0);
    }
    const double zero[] = {0.0, 0.0, 0.0};
    for (double u : {0.0, 0.3, 1.0}) {
        EXPECT_EQ(hs::sample_discrete(zero, 3, u).index, 0);
        EXPECT_EQ(hs::sample_discrete(zero, 3, u).rescaled, u);
    }
    // A u outside [0, 1] (a caller's error) still leaves a leftover in [0, 1], whatever the
    // weights: the model fuzzer found a huge leftover of all-zero weights reaching an asin.
    for (double u : {-4.8e35, -1e-3, 1.5, 3e38}) {
        for (const double* weights : {zero, w}) {
            const hs::DiscreteChoice<double> c = hs::sample_discrete(weights, 3, u);
            EXPECT_GE(c.rescaled, 0.0) << u;
            EXPECT_LE(c.rescaled, 1.0) << u;
        }
    }
}

// chosen_index (the branch-free pick of Chiang's stateless sample) is the index that
// sample_discrete(w, N, u, total) picks, given u·total: for normalised weights (total 1)
// and for weights that are not (Chiang's: sums of A_p's channels, total their pairwise sum,
// which may round above or below the sum in index order), with zeros anywhere (leading,
// inner, trailing, all), u on and next to every cumulative fraction, 0, 1 and past both
// ends, and sums that round below 1.
TEST(SampleDiscrete, ChosenIndexMatchesSampleDiscrete) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    long compared = 0;
    auto check = [&](const float (&w)[4], float total) {
        std::vector<float> us = {0.0f, 1.0f, -0.5f, 1.5f, std::nextafter(1.0f, 0.0f)};
        float cum = 0;
        for (float x : w) {
            cum += x;
            const float c = total > 0 ? cum / total : cum;
            for (float u : {c, std::nextafter(c, 0.0f), std::nextafter(c, 2.0f)}) us.push_back(u);
        }
        for (int i = 0; i < 64; ++i) us.push_back(uni(rng));
        for (float u : us) {
            EXPECT_EQ(hs::chosen_index<4>(w, u * total), hs::sample_discrete(w, 4, u, total).index)
                << "u = " << u << ", total = " << total;
            ++compared;
        }
    };
    for (int i = 0; i < 4000; ++i) {
        float w[4], total = 0;
        for (float& x : w) {
            x = uni(rng) < 0.35f ? 0.0f : uni(rng);
            total += x;
        }
        const float scale = std::ldexp(1.0f, int(uni(rng) * 120) - 60);
        float raw[4];
        for (int k = 0; k < 4; ++k) raw[k] = w[k] * scale;
        check(raw, hs::pairwise_sum<4>(raw));
        for (float& x : w) x = total > 0 ? x / total : 0.0f;
        check(w, 1.0f);
    }
    check({0.1f, 0.2f, 0.7f - 1e-7f, 0.0f}, 1.0f);
    check({0.0f, 0.0f, 0.0f, 0.0f}, 1.0f);
    check({0.0f, 0.0f, 0.0f, 0.0f}, 0.0f);
    check({0.0f, 0.0f, 0.0f, 1.0f}, 1.0f);
    check({1.0f, 0.0f, 0.0f, 0.0f}, 1.0f);
    check({3.0f, 1e-8f, 5.0f, 1e-8f}, 8.0f);
    EXPECT_GT(compared, 2 * 4000 * 70);
}

// The piecewise-linear CDF's inverse: C(x) = target to rounding, including flat (zero
// density) cells and both ends.
TEST(InvertPiecewiseLinear, InvertsTheCdf) {
    const double g[] = {0.0, 1.0, 3.0, 0.0, 0.0, 2.0, 2.0};
    const int n = 7;
    const double h = 0.25;
    double c[n] = {0.0};
    for (int k = 1; k < n; ++k) c[k] = c[k - 1] + 0.5 * h * (g[k - 1] + g[k]);
    auto cdf_at = [&](double x) {
        const int k = std::min(int(x / h), n - 2);
        const double d = x - k * h;
        return c[k] + d * (g[k] + 0.5 * d * (g[k + 1] - g[k]) / h);
    };
    for (int k = 0; k <= 1000; ++k) {
        const double target = c[n - 1] * k / 1000;
        const hs::PiecewiseLinearPoint<double> p = hs::invert_piecewise_linear(
            [&](int i) { return c[i]; }, [&](int i) { return g[i]; }, n, h, 1 / h, target);
        ASSERT_GE(p.cell, 0);
        ASSERT_LE(p.cell, n - 2);
        ASSERT_GE(p.offset, 0.0);
        ASSERT_LE(p.offset, h);
        EXPECT_NEAR(cdf_at(p.cell * h + p.offset), target, 1e-14) << "target " << target;
        // Never inside a cell without mass.
        EXPECT_FALSE(p.cell == 3 && p.offset > 0 && p.offset < h) << "target " << target;
    }
}
