// Robustness: hostile inputs never crash and never give silent garbage. Non-finite wo, wi
// or u give 0 (eval, pdf) and the empty sample (pdf 0, weight 0) in every model; validate()
// rejects the roughness values that underflow (and NaN/Inf, also under -ffast-math: every
// finiteness check here reads the bits, as the library does); the float elementary
// functions handle NaN, ±Inf and large arguments without converting them to integers; the
// tabulated fiber's sample and pdf agree near the fiber axis. This file is also built with
// -ffast-math (scripts/test.sh step fastmath), where std::isfinite would fold to true.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

namespace hs = hairscatter;

namespace {

template <typename T> T quiet_nan() { return std::numeric_limits<T>::quiet_NaN(); }
template <typename T> T infinity() { return std::numeric_limits<T>::infinity(); }

template <typename T> bool finite3(const glm::vec<3, T>& v) { return hs::is_finite(v); }

template <typename T> glm::vec<3, T> unit(double theta, double phi) {
    return glm::vec<3, T>(T(std::sin(theta)), T(std::cos(theta) * std::cos(phi)), T(std::cos(theta) * std::sin(phi)));
}

// The non-finite inputs: NaN and ±Inf in each component of a unit vector.
template <typename T, int N> std::vector<glm::vec<N, T>> poisoned(const glm::vec<N, T>& good) {
    std::vector<glm::vec<N, T>> r;
    for (int i = 0; i < N; ++i)
        for (T bad : {quiet_nan<T>(), infinity<T>(), -infinity<T>()}) {
            glm::vec<N, T> v = good;
            v[i] = bad;
            r.push_back(v);
        }
    return r;
}

// Chiang and the tabulated fiber also have at(wo); the far field and Marschner do not.
template <typename F, typename = void> struct has_at : std::false_type {};
template <typename F>
struct has_at<F, std::void_t<decltype(std::declval<const F&>().at(std::declval<typename F::V3>()))>> : std::true_type {};

// The contract of models/chiang.hpp's HairSample comment, for one fiber (any model).
template <typename T, typename Fiber> void expect_zero_on_nonfinite(const Fiber& fiber, const char* name) {
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    const V3 wo = unit<T>(0.3, 0.2), wi = unit<T>(-0.4, 2.5);
    const V4 u(T(0.3), T(0.6), T(0.2), T(0.7));
    // The good inputs give a non-zero answer (so the zeros below are the guard's).
    ASSERT_GT(fiber.pdf(wo, wi), T(0)) << name;
    for (const V3& bad : poisoned<T, 3>(wo)) {
        EXPECT_EQ(fiber.eval(bad, wi), V3(T(0))) << name << " wo " << bad.x << " " << bad.y << " " << bad.z;
        EXPECT_EQ(fiber.pdf(bad, wi), T(0)) << name;
        const hs::HairEvalPdf<T> ep = fiber.eval_pdf(bad, wi);
        EXPECT_EQ(ep.f, V3(T(0))) << name;
        EXPECT_EQ(ep.pdf, T(0)) << name;
        const hs::HairSample<T> s = fiber.sample(bad, u);
        EXPECT_EQ(s.pdf, T(0)) << name;
        EXPECT_EQ(s.weight, V3(T(0))) << name;
        EXPECT_TRUE(finite3(s.wi)) << name;
        if constexpr (has_at<Fiber>::value) {
            const auto at = fiber.at(bad);
            EXPECT_EQ(at.eval(wi), V3(T(0))) << name;
            EXPECT_EQ(at.pdf(wi), T(0)) << name;
            EXPECT_EQ(at.sample(u).pdf, T(0)) << name;
        }
    }
    for (const V3& bad : poisoned<T, 3>(wi)) {
        EXPECT_EQ(fiber.eval(wo, bad), V3(T(0))) << name << " wi " << bad.x << " " << bad.y << " " << bad.z;
        EXPECT_EQ(fiber.pdf(wo, bad), T(0)) << name;
        if constexpr (has_at<Fiber>::value) {
            EXPECT_EQ(fiber.at(wo).eval(bad), V3(T(0))) << name;
            EXPECT_EQ(fiber.at(wo).pdf(bad), T(0)) << name;
        }
    }
    for (const V4& bad : poisoned<T, 4>(u)) {
        const hs::HairSample<T> s = fiber.sample(wo, bad);
        EXPECT_EQ(s.pdf, T(0)) << name << " u " << bad.x << " " << bad.y << " " << bad.z << " " << bad.w;
        EXPECT_EQ(s.weight, V3(T(0))) << name;
        if constexpr (has_at<Fiber>::value) {
            EXPECT_EQ(fiber.at(wo).sample(bad).pdf, T(0)) << name;
        }
    }
}

template <typename T> hs::FiberParams<T> brown() {
    hs::FiberParams<T> p;
    p.sigma_a = hs::sigma_a_from_concentrations(T(1.3), T(0));
    return p;
}

// Calls check(fiber, name) for a fiber of every model made from p (Marschner's from its
// defaults with p's absorption).
template <typename T, typename Check> void for_each_model(const hs::FiberParams<T>& p, const Check& check) {
    const hs::ChiangMaterial<T> chiang(p);
    check(hs::ChiangFiber<T>(chiang, T(0.3)), "chiang");
    const hs::DeonFarFieldMaterial<T> far(p);
    check(hs::DeonFarFieldFiber<T>(far), "far field");
    const hs::TabulatedMaterial<T> tab(p);
    check(hs::TabulatedFiber<T>(tab), "tabulated");
    const hs::TabulatedMaterial<T> fast(p, hs::TabulatedOptions::fast());
    check(hs::TabulatedFiber<T>(fast), "tabulated fast()");
    hs::MarschnerParams<T> mp;
    mp.sigma_a = p.sigma_a;
    const hs::MarschnerMaterial<T> marschner(mp);
    check(hs::MarschnerFiber<T>(marschner), "marschner");
}

template <typename T> void every_model_nonfinite() {
    for_each_model<T>(brown<T>(), [](const auto& fiber, const char* name) { expect_zero_on_nonfinite<T>(fiber, name); });
}

TEST(NonFiniteInput, EveryModelReturnsZeroFloat) { every_model_nonfinite<float>(); }
TEST(NonFiniteInput, EveryModelReturnsZeroDouble) { every_model_nonfinite<double>(); }

// The table coordinates themselves: a NaN never becomes an index (the old clamp let it
// through to int(NaN)).
TEST(NonFiniteInput, TableCellIsNanSafe) {
    EXPECT_EQ(hs::table_cell(quiet_nan<float>(), 10), 0);
    EXPECT_EQ(hs::table_cell(-infinity<float>(), 10), 0);
    EXPECT_EQ(hs::table_cell(infinity<double>(), 10), 10);
    EXPECT_EQ(hs::table_cell(3.7f, 10), 3);
    EXPECT_EQ(hs::table_cell(10.5, 10), 10);
}

TEST(Finite, BitsNotComparisons) {
    EXPECT_FALSE(hs::is_finite(quiet_nan<float>()));
    EXPECT_FALSE(hs::is_finite(-infinity<float>()));
    EXPECT_FALSE(hs::is_finite(quiet_nan<double>()));
    EXPECT_FALSE(hs::is_finite(infinity<double>()));
    EXPECT_TRUE(hs::is_finite(std::numeric_limits<float>::max()));
    EXPECT_TRUE(hs::is_finite(std::numeric_limits<double>::denorm_min()));
    EXPECT_FALSE(hs::is_finite(glm::vec3(1.0f, quiet_nan<float>(), 0.0f)));
}

// The float exp and sincos: NaN stays NaN and ±Inf / huge arguments are handled without a
// float → int conversion out of range (UBSan's float-cast-overflow); and the rounding of
// the argument reduction survives -ffast-math (the 1.5·2^23 trick did not).
// Under -ffast-math (HAIRSCATTER_ALLOW_FAST_MATH, scripts/test.sh step fastmath) NaN does
// not propagate (-ffinite-math-only) and the reduction loses the bits config.hpp states.
#if defined(__FAST_MATH__)
constexpr double kExpBound = 5e-6, kSincosBound = 2e-5;
constexpr bool kNanPropagates = false;
#else
constexpr double kExpBound = 1e-6, kSincosBound = 1e-6;
constexpr bool kNanPropagates = true;
#endif

TEST(Elementary, FloatExpSpecialAndRounding) {
    if (kNanPropagates) {
        EXPECT_FALSE(hs::is_finite(hs::elem::exp(quiet_nan<float>())));
    }
    EXPECT_EQ(hs::elem::exp(-infinity<float>()), 0.0f);
    EXPECT_EQ(hs::elem::exp(-1000.0f), 0.0f);
    EXPECT_TRUE(hs::is_finite(hs::elem::exp(infinity<float>())));
    // Every x whose x·log2(e) sits at a rounding midpoint or near one: the reduction
    // must keep |r| ≤ ln2/2, or the polynomial's error grows by orders of magnitude.
    double worst = 0;
    for (int k = -1740; k <= 0; ++k) {
        const float x = float(k) * 0.05f;
        const double ref = std::exp(double(x));
        if (ref < 1e-37) continue;
        worst = std::max(worst, std::abs(double(hs::elem::exp(x)) - ref) / ref);
    }
    EXPECT_LT(worst, kExpBound);
}

TEST(Elementary, FloatSincosSpecialAndLarge) {
    float s = 0, c = 0;
    if (kNanPropagates) {
        hs::elem::sincos(quiet_nan<float>(), s, c);
        EXPECT_FALSE(hs::is_finite(s));
        EXPECT_FALSE(hs::is_finite(c));
        hs::elem::sincos(infinity<float>(), s, c);
        EXPECT_FALSE(hs::is_finite(s));
    }
    for (float x : {1e4f, -3e5f, 1e9f, 3e38f}) {
        hs::elem::sincos(x, s, c);
        EXPECT_NEAR(s, std::sin(double(x)), 1e-6) << x;
        EXPECT_NEAR(c, std::cos(double(x)), 1e-6) << x;
    }
    double worst = 0;
    for (int k = -4000; k <= 4000; ++k) {
        const float x = float(k) * 0.0251f;
        hs::elem::sincos(x, s, c);
        worst = std::max({worst, std::abs(double(s) - std::sin(double(x))), std::abs(double(c) - std::cos(double(x)))});
    }
    EXPECT_LT(worst, kSincosBound);
}

// validate(): the roughness limits, NaN and Inf, in float and double.
template <typename T> void validation_limits() {
    hs::FiberParams<T> p;
    EXPECT_EQ(hs::validate(p), "");
    for (T beta : {T(1e-19), T(1e-37), T(9e-4), T(0), quiet_nan<T>(), infinity<T>(), -infinity<T>()}) {
        hs::FiberParams<T> q;
        q.beta_m = beta;
        EXPECT_NE(hs::validate(q).find("beta_m"), std::string::npos) << double(beta);
        q = hs::FiberParams<T>();
        q.beta_n = beta;
        EXPECT_NE(hs::validate(q).find("beta_n"), std::string::npos) << double(beta);
        hs::MarschnerParams<T> m;
        m.beta_r = beta == T(9e-4) ? T(9e-5) : beta;  // β_R's limit is 1e-4 rad
        EXPECT_NE(hs::validate(m).find("beta_r"), std::string::npos) << double(beta);
        m = hs::MarschnerParams<T>();
        m.beta_n = beta;
        EXPECT_NE(hs::validate(m).find("beta_n"), std::string::npos) << double(beta);
    }
    for (T bad : {quiet_nan<T>(), infinity<T>()}) {
        hs::FiberParams<T> q;
        q.eta = bad;
        EXPECT_NE(hs::validate(q).find("eta"), std::string::npos);
        q = hs::FiberParams<T>();
        q.alpha = bad;
        EXPECT_NE(hs::validate(q).find("alpha"), std::string::npos);
        q = hs::FiberParams<T>();
        q.sigma_a.g = bad;
        EXPECT_NE(hs::validate(q).find("sigma_a.g"), std::string::npos);
    }
    hs::FiberParams<T> at_limit;
    at_limit.beta_m = at_limit.beta_n = hs::kMinRoughness<T>;
    EXPECT_EQ(hs::validate(at_limit), "");
    hs::MarschnerParams<T> m_limit;
    m_limit.beta_r = hs::kMinMarschnerWidth<T>;
    m_limit.beta_n = hs::kMinRoughness<T>;
    EXPECT_EQ(hs::validate(m_limit), "");
}

TEST(Validation, RoughnessLimitsAndNonFiniteFloat) { validation_limits<float>(); }
TEST(Validation, RoughnessLimitsAndNonFiniteDouble) { validation_limits<double>(); }

// TabulatedOptions::fast() with β_m = 1e-19 in float: the variance underflowed, a NaN
// became a table index and the first eval segfaulted. Now refused when the material is made.
TEST(Validation, FastTableTinyBetaIsRejected) {
    hs::FiberParams<float> p;
    p.beta_m = 1e-19f;
    EXPECT_THROW(hs::TabulatedMaterial<float>(p, hs::TabulatedOptions::fast()), std::invalid_argument);
    p.beta_m = 0.3f;
    p.beta_n = 1e-37f;
    EXPECT_THROW(hs::TabulatedMaterial<float>(p, hs::TabulatedOptions::fast()), std::invalid_argument);
}

// Every model at the smallest accepted roughness (both β at the limit, then one at a
// time), float and double: finite, non-negative eval, pdf and sample over random pairs.
template <typename T, typename Fiber> void expect_finite_over_sphere(const Fiber& fiber, const char* name, int n) {
    using V3 = glm::vec<3, T>;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u01(0, 1);
    int bad = 0;
    for (int i = 0; i < n; ++i) {
        const V3 wo = unit<T>(std::asin(2 * u01(rng) - 1), 6.283 * u01(rng));
        const V3 wi = unit<T>(std::asin(2 * u01(rng) - 1), 6.283 * u01(rng));
        const hs::HairEvalPdf<T> e = fiber.eval_pdf(wo, wi);
        const hs::HairSample<T> s =
            fiber.sample(wo, glm::vec<4, T>(T(u01(rng)), T(u01(rng)), T(u01(rng)), T(u01(rng))));
        const bool ok = finite3(e.f) && hs::is_finite(e.pdf) && e.pdf >= T(0) && e.f.x >= T(0) && e.f.y >= T(0) &&
                        e.f.z >= T(0) && hs::is_finite(s.pdf) && s.pdf >= T(0) && finite3(s.weight) &&
                        finite3(s.wi) && s.weight.x >= T(0);
        bad += ok ? 0 : 1;
    }
    EXPECT_EQ(bad, 0) << name << " (" << n << " pairs)";
}

template <typename T> void every_model_at_limit() {
    const T lim = hs::kMinRoughness<T>;
    for (int which = 0; which < 3; ++which) {
        hs::FiberParams<T> p = brown<T>();
        if (which != 1) p.beta_m = lim;
        if (which != 2) p.beta_n = lim;
        const hs::ChiangMaterial<T> chiang(p);
        expect_finite_over_sphere<T>(hs::ChiangFiber<T>(chiang, T(-1)), "chiang h = -1", 2000);
        expect_finite_over_sphere<T>(hs::ChiangFiber<T>(chiang, T(0.5)), "chiang", 2000);
        const hs::DeonFarFieldMaterial<T> far(p);
        expect_finite_over_sphere<T>(hs::DeonFarFieldFiber<T>(far), "far field", 100);
        const hs::TabulatedMaterial<T> tab(p, hs::TabulatedOptions::coarse());
        expect_finite_over_sphere<T>(hs::TabulatedFiber<T>(tab), "tabulated", 2000);
        const hs::TabulatedMaterial<T> fast(p, hs::TabulatedOptions::fast());
        expect_finite_over_sphere<T>(hs::TabulatedFiber<T>(fast), "tabulated fast()", 2000);
        hs::MarschnerParams<T> mp;
        mp.sigma_a = p.sigma_a;
        if (which != 1) mp.beta_r = hs::kMinMarschnerWidth<T>;
        if (which != 2) mp.beta_n = lim;
        const hs::MarschnerMaterial<T> marschner(mp);
        expect_finite_over_sphere<T>(hs::MarschnerFiber<T>(marschner), "marschner", 200);
    }
}

TEST(Limits, EveryModelFiniteAtMinimumRoughnessFloat) { every_model_at_limit<float>(); }
TEST(Limits, EveryModelFiniteAtMinimumRoughnessDouble) { every_model_at_limit<double>(); }

// Indices at the ends of what validation accepts (η just above 1, and η whose square
// overflows), with wo and wi along the axis, where sinθo = ±1 meets the refracted path:
// every model stays finite and non-negative (a fuzzer found the overflowing square in an
// earlier form of the refraction, which gave NaN for Marschner at η = 2.7e23). Under
// -ffast-math (-ffinite-math-only: the compiler assumes no Inf) the indices whose square
// overflows are not supported (docs/robustness.md): there the list stops at η = 1e4.
template <typename T> void every_model_at_extreme_eta() {
    using V3 = glm::vec<3, T>;
#if defined(__FAST_MATH__)
    const T etas[] = {std::nextafter(T(1), T(2)), T(1.0001), T(100), T(1e4)};
#else
    const T etas[] = {std::nextafter(T(1), T(2)), T(1.0001), T(1e4), T(3e19), T(2.7e23), std::numeric_limits<T>::max()};
#endif
    const V3 axis[] = {V3(T(-1), T(1.8e-39), T(1.5e-42)), V3(T(1), T(0), T(0)), V3(T(-1), T(0), T(0)),
                       unit<T>(1.5707, 0.3), unit<T>(-1.5707, 2.0)};
    for (const T eta : etas) {
        hs::FiberParams<T> p = brown<T>();
        p.eta = eta;
        hs::MarschnerParams<T> mp;
        mp.sigma_a = p.sigma_a;
        mp.eta = eta;
        ASSERT_EQ(hs::validate(p), "") << double(eta);
        ASSERT_EQ(hs::validate(mp), "") << double(eta);
        const hs::ChiangMaterial<T> chiang(p);
        const hs::DeonFarFieldMaterial<T> far(p, 16);
        const hs::MarschnerMaterial<T> marschner(mp);
        auto check = [&](const auto& fiber, const char* name) {
            expect_finite_over_sphere<T>(fiber, name, 200);
            for (const V3& wo : axis)
                for (const V3& wi : axis) {
                    const hs::HairEvalPdf<T> e = fiber.eval_pdf(wo, wi);
                    EXPECT_TRUE(finite3(e.f) && e.f.x >= T(0) && e.f.y >= T(0) && e.f.z >= T(0) &&
                                hs::is_finite(e.pdf) && e.pdf >= T(0))
                        << name << " eta " << double(eta) << " wo.x " << double(wo.x) << " wi.x " << double(wi.x);
                }
        };
        check(hs::ChiangFiber<T>(chiang, T(0.5)), "chiang");
        check(hs::ChiangFiber<T>(chiang, T(1)), "chiang h = 1");
        check(hs::DeonFarFieldFiber<T>(far), "far field");
        check(hs::MarschnerFiber<T>(marschner), "marschner");
    }
}

TEST(Limits, EveryModelFiniteAtExtremeEtaFloat) { every_model_at_extreme_eta<float>(); }
TEST(Limits, EveryModelFiniteAtExtremeEtaDouble) { every_model_at_extreme_eta<double>(); }

// wo on the fiber axis (exactly, and within 1e-6 of it): sample()'s pdf is the pdf of
// its direction. Exactly on the axis wo has no azimuth; sample measured φ from the y axis
// while pdf took atan2(0, 0) = 0 for every wi, so the two disagreed for every model.
template <typename T, typename Fiber> void expect_axis_agreement(const Fiber& fiber, const char* name) {
    using V3 = glm::vec<3, T>;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u01(0.001, 0.999);
    const V3 wos[] = {V3(T(1), T(0), T(0)), V3(T(-1), T(0), T(0)), V3(T(1), T(7e-7), T(-3e-7)),
                      V3(T(-1), T(-2e-7), T(9e-7))};
    for (const V3& wo : wos) {
        int bad = 0, compared = 0;
        double worst = 0;
        for (int i = 0; i < 400; ++i) {
            const hs::HairSample<T> s =
                fiber.sample(wo, glm::vec<4, T>(T(u01(rng)), T(u01(rng)), T(u01(rng)), T(u01(rng))));
            if (!(s.pdf > T(0)) || (s.wi.y == T(0) && s.wi.z == T(0))) continue;
            const double back = double(fiber.pdf(wo, s.wi)), diff = std::abs(back - double(s.pdf));
            ++compared;
            if (diff > 1e-2 * std::max(back, double(s.pdf)) + 1e-3) {
                ++bad;
                worst = std::max(worst, diff / std::max(back, double(s.pdf)));
            }
        }
        EXPECT_GT(compared, 300) << name;
        EXPECT_EQ(bad, 0) << name << " wo (" << wo.x << ", " << wo.y << ", " << wo.z << "): worst relative " << worst;
    }
}

template <typename T> void every_model_on_axis() {
    for_each_model<T>(brown<T>(), [](const auto& fiber, const char* name) { expect_axis_agreement<T>(fiber, name); });
}

TEST(Axis, SampleAndPdfAgreeAlongTheFiberFloat) { every_model_on_axis<float>(); }
TEST(Axis, SampleAndPdfAgreeAlongTheFiberDouble) { every_model_on_axis<double>(); }

// Every model of the contract, Huang's included (small quadrature: the checks here are of
// the front and the samplers, not of accuracy), for one roughness pair.
template <typename T, typename Check> void for_each_model_with_huang(T beta_m, T beta_n, const Check& check) {
    hs::FiberParams<T> p = brown<T>();
    p.beta_m = beta_m;
    p.beta_n = beta_n;
    for_each_model<T>(p, check);
    hs::HuangParams<T> hp;
    hp.sigma_a = p.sigma_a;
    hp.roughness = std::max(beta_m, hs::kMinHuangRoughness<T>);  // (one roughness, ≥ 0.02)
    hp.aspect_ratio = T(0.7);
    const hs::HuangMaterial<T> huang(hp, hs::HuangQuadrature{8, 16, 2});
    check(hs::HuangFiber<T>(huang), "huang");
}

// Exact poles (θ = ±90°) of wo, of the sampled wi (u.y at 0 and 1, and u outside [0, 1],
// which every model clamps), and near them: a sample's pdf is pdf(wo, wi) of its direction
// and its weight is eval / pdf there, within 1e-4; a failed sample has weight 0. Before, at
// a pole the sampler kept the density of the azimuth it drew while pdf(wo, wi) measured
// another (Chiang float: 6e-6 against 3.5; Marschner's weight 2.72 against 2.66), and the
// far field gave a NaN direction for u = 2.
template <typename T, typename Fiber> void expect_pole_agreement(const Fiber& fiber, const char* name) {
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    const T one_minus = T(1) - std::numeric_limits<T>::epsilon() / T(2);
    const V3 wos[] = {V3(T(1), T(0), T(0)), V3(T(-1), T(0), T(0)), unit<T>(0.4, 0.3), unit<T>(-1.2, 2.0), unit<T>(0, 1)};
    const T ys[] = {T(0), T(1), one_minus, T(2), T(-1)};
    int compared = 0, bad = 0;
    for (const V3& wo : wos)
        for (int i = 0; i < 200; ++i) {
            V4 u(T(u01(rng)), ys[i % 5], T(u01(rng)), T(u01(rng)));
            if (i % 7 == 0) u.x = T(2);
            if (i % 11 == 0) u.w = T(-1);
            const hs::HairSample<T> s = fiber.sample(wo, u);
            ASSERT_TRUE(finite3(s.wi)) << name;
            if (!(s.pdf > T(0))) {
                EXPECT_EQ(s.weight, V3(T(0))) << name;
                continue;
            }
            ++compared;
            const hs::HairEvalPdf<T> back = fiber.eval_pdf(wo, s.wi);
            // The sample's f = weight · pdf and its pdf against eval_pdf of its direction,
            // within 1e-4 of the range they take when wi moves by 4 ulps of 1 along an axis
            // (where a narrow lobe is steep, the rounding of the sampled angles into wi moves
            // them more than that: bench/stress.cpp counts these apart as rounding).
            const T e = T(4) * std::numeric_limits<T>::epsilon();
            double lo[4], hi[4];
            for (int k = 0; k < 4; ++k) lo[k] = hi[k] = k < 3 ? double(back.f[k]) : double(back.pdf);
            const double want[4] = {double(s.weight.x) * double(s.pdf), double(s.weight.y) * double(s.pdf),
                                    double(s.weight.z) * double(s.pdf), double(s.pdf)};
            // (Under -ffast-math subnormal intermediates flush to 0, so densities below
            // about 1e-20 may underflow on one path and not the other.)
#ifdef __FAST_MATH__
            const double floor = 1e-20;
#else
            const double floor = 1e-30;
#endif
            auto inside = [&] {
                for (int k = 0; k < 4; ++k)
                    if (want[k] < lo[k] * (1 - 1e-4) - floor || want[k] > hi[k] * (1 + 1e-4) + floor) return false;
                return true;
            };
            bool ok = inside();
            for (int axis = 0; axis < 3 && !ok; ++axis)
                for (T sign : {T(-1), T(1)}) {
                    V3 w = s.wi;
                    w[axis] += sign * e;
                    const hs::HairEvalPdf<T> moved = fiber.eval_pdf(wo, glm::normalize(w));
                    for (int k = 0; k < 4; ++k) {
                        const double v = k < 3 ? double(moved.f[k]) : double(moved.pdf);
                        lo[k] = std::min(lo[k], v);
                        hi[k] = std::max(hi[k], v);
                    }
                }
            ok = ok || inside();
            if (!ok && bad++ < 5)
                ADD_FAILURE() << name << " wo (" << wo.x << ", " << wo.y << ", " << wo.z << ") u (" << u.x << ", " << u.y
                              << ", " << u.z << ", " << u.w << "): wi (" << s.wi.x << ", " << s.wi.y << ", " << s.wi.z
                              << ") sample pdf " << s.pdf << " weight " << s.weight.x << ", pdf(wi) " << back.pdf
                              << " f(wi) " << back.f.x;
        }
    EXPECT_GT(compared, 200) << name;
    // wi exactly at a pole: a density only where f is non-zero too (Marschner's f has the
    // factor cosθi, so its density there is 0).
    for (const V3& wo : wos)
        for (T sign : {T(-1), T(1)}) {
            const hs::HairEvalPdf<T> e = fiber.eval_pdf(wo, V3(sign, T(0), T(0)));
            if (e.pdf > T(0)) {
                EXPECT_GT(e.f.x + e.f.y + e.f.z, T(0)) << name << " wi at the pole " << sign;
            }
        }
}

template <typename T> void every_model_at_poles() {
    for (T beta : {T(0.3), hs::kMinRoughness<T>})
        for_each_model_with_huang<T>(beta, beta, [](const auto& fiber, const char* name) { expect_pole_agreement<T>(fiber, name); });
}

TEST(Poles, SampleAgreesWithPdfAndEvalFloat) { every_model_at_poles<float>(); }
TEST(Poles, SampleAgreesWithPdfAndEvalDouble) { every_model_at_poles<double>(); }

// Whether a model offers lobe_split(wo, centre) (Marschner's does not).
template <typename F, typename = void> constexpr bool kHasLobeSplit = false;
template <typename F>
constexpr bool kHasLobeSplit<F, std::void_t<decltype(std::declval<const F&>().lobe_split(
                                    std::declval<glm::vec<3, typename F::Real>>(), typename F::Real(0)))>> = true;

// Finite but not unit directions are normalised (the contract above HairSample): the
// largest finite components, tiny ones and any other length give the unit direction's
// values, and a zero vector gives 0 / no sample. Before, FLT_MAX components gave NaN in every
// float model, and Huang with a tiny wo sampled a pdf of 0.057 with wi = (-inf, NaN, NaN).
template <typename T, typename Fiber> void expect_normalised(const Fiber& fiber, const char* name) {
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    const T big = std::numeric_limits<T>::max();
    const V3 wo = unit<T>(0.3, 0.2), wi = unit<T>(-0.4, 2.5);
    const V4 u(T(0.3), T(0.6), T(0.2), T(0.7));
    const hs::HairEvalPdf<T> ref = fiber.eval_pdf(wo, wi);
    const hs::HairSample<T> ref_s = fiber.sample(wo, u);
    ASSERT_GT(ref.pdf, T(0)) << name;
    auto close = [](double a, double b) { return std::abs(a - b) <= 1e-3 * std::max(std::abs(a), std::abs(b)) + 1e-6; };
    // (Under -ffast-math, this file's second build, subnormal numbers read as 0, so a vector
    // of subnormal components has no direction there: docs/robustness.md.)
#ifdef __FAST_MATH__
    const T tiny = T(1e-30);
#else
    const T tiny = std::numeric_limits<T>::denorm_min() * T(1e6);
#endif
    for (T scale : {big, big / T(3), T(3), T(1e-3), T(1e-30), tiny}) {
        // Scaled so that the largest component is `scale` (the others may round to less).
        const V3 so = wo * (scale / std::max({std::abs(wo.x), std::abs(wo.y), std::abs(wo.z)}));
        const V3 si = wi * (scale / std::max({std::abs(wi.x), std::abs(wi.y), std::abs(wi.z)}));
        if (!finite3(so) || !finite3(si)) continue;
        const hs::HairEvalPdf<T> e = fiber.eval_pdf(so, si);
        EXPECT_TRUE(close(double(e.pdf), double(ref.pdf))) << name << " scale " << scale << ": pdf " << e.pdf << " for " << ref.pdf;
        EXPECT_TRUE(close(double(e.f.x), double(ref.f.x))) << name << " scale " << scale << ": f " << e.f.x << " for " << ref.f.x;
        EXPECT_TRUE(close(double(fiber.pdf(so, si)), double(ref.pdf))) << name << " scale " << scale;
        const hs::HairSample<T> s = fiber.sample(so, u);
        ASSERT_TRUE(finite3(s.wi)) << name << " scale " << scale;
        EXPECT_TRUE(close(double(s.pdf), double(ref_s.pdf))) << name << " scale " << scale << ": sample pdf " << s.pdf;
        EXPECT_NEAR(double(glm::length(s.wi)), 1.0, 1e-5) << name << " scale " << scale;
    }
    const V3 zero(T(0));
    EXPECT_EQ(fiber.pdf(zero, wi), T(0)) << name;
    EXPECT_EQ(fiber.pdf(wo, zero), T(0)) << name;
    EXPECT_EQ(fiber.eval(wo, zero), V3(T(0))) << name;
    EXPECT_EQ(fiber.sample(zero, u).pdf, T(0)) << name;
    // albedo and lobe_split follow the same rule: a scaled wo gives the unit one's values,
    // a zero or non-finite one no energy (Chiang, the far field and the table returned an
    // albedo of exactly 1 for a NaN wo, and a finite albedo for a zero one).
    const V3 ref_a = fiber.albedo(wo);
    ASSERT_GT(ref_a.x, T(0)) << name;
    const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
    for (T scale : {big / T(3), T(3), T(1e-3)}) {
        const V3 so = wo * (scale / std::max({std::abs(wo.x), std::abs(wo.y), std::abs(wo.z)}));
        EXPECT_TRUE(close(double(fiber.albedo(so).x), double(ref_a.x))) << name << " albedo at scale " << scale;
    }
    for (const V3& bad : {zero, V3(nan, T(0), T(1)), V3(T(0), inf, T(1))}) {
        EXPECT_EQ(fiber.albedo(bad), V3(T(0))) << name << " albedo of (" << bad.x << ", " << bad.y << ", " << bad.z << ")";
        if constexpr (kHasLobeSplit<Fiber>) {
            const auto split = fiber.lobe_split(bad, T(0));
            EXPECT_EQ(hs::split_albedo(split), V3(T(0))) << name << " lobe_split of a bad wo";
        }
    }
}

template <typename T> void every_model_normalises() {
    for_each_model_with_huang<T>(T(0.3), T(0.3), [](const auto& fiber, const char* name) { expect_normalised<T>(fiber, name); });
}

TEST(NonUnit, EveryModelNormalisesFloat) { every_model_normalises<float>(); }
TEST(NonUnit, EveryModelNormalisesDouble) { every_model_normalises<double>(); }

// Under -ffast-math (this file's second build) comparisons with NaN fold away; the checks
// that read the bits still refuse it. Before, ChiangFiber::checked(h = NaN) stopped throwing.
TEST(Validation, CheckedOffsetRefusesNanUnderAnyFlags) {
    const hs::ChiangMaterial<float> m{hs::FiberParams<float>()};
    volatile float nan = quiet_nan<float>();  // (not a constant the compiler could fold)
    EXPECT_THROW(hs::ChiangFiber<float>::checked(m, nan), std::invalid_argument);
    EXPECT_THROW(hs::ChiangFiber<float>::checked(m, -infinity<float>()), std::invalid_argument);
    EXPECT_TRUE(hs::is_finite(hs::ChiangFiber<float>(m, nan).h()));
}

}  // namespace
