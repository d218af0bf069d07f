// The production-shader controls: melanin with redness and a dye (fiber/pigments.hpp),
// per-strand variation by hashing (fiber/strand_variation.hpp), and per-lobe gains, tints
// and tilts (lobes/lobe_controls.hpp) on every model that takes them (Chiang, d'Eon's far
// field, tabulated, Marschner). The contract suite runs over each with controls
// (chi-square with a zero gain included; tests/support/controls_specs.hpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <boost/math/distributions/chi_squared.hpp>
#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

#include "support/contract_suite.hpp"
#include "support/controls_specs.hpp"
#include "support/model_specs.hpp"

namespace hs = hairscatter;
using glm::dvec3;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = contract::kPi;

void expect_names(const std::string& message, const std::string& field) {
    EXPECT_NE(message.find(field), std::string::npos) << "message '" << message << "' does not name " << field;
}

// A default S changed by change(s) is rejected by validate (naming field) and require_valid;
// returns it for further checks.
template <typename S, typename Change> S expect_rejected(Change change, const char* field) {
    S s;
    change(s);
    expect_names(hs::validate(s), field);
    EXPECT_THROW(hs::require_valid(s), std::invalid_argument);
    return s;
}

// ---- pigments ---------------------------------------------------------------------------

// Cycles' mapping written out independently: c = -ln(max(1 - m, 1e-4)), split by r.
TEST(Pigments, MelaninAmountMapsToConcentrations) {
    const auto zero = hs::melanin_concentrations(0.0, 0.7);
    EXPECT_EQ(zero.eumelanin, 0.0);
    EXPECT_EQ(zero.pheomelanin, 0.0);
    EXPECT_FALSE(std::signbit(zero.eumelanin));  // +0: σa = 0 exactly for white hair
    const auto half = hs::melanin_concentrations(0.5, 0.25);
    EXPECT_NEAR(half.eumelanin, std::log(2.0) * 0.75, 1e-15);
    EXPECT_NEAR(half.pheomelanin, std::log(2.0) * 0.25, 1e-15);
    // m = 1 meets the floor: c = ln 1e4, finite.
    const auto black = hs::melanin_concentrations(1.0, 0.0);
    EXPECT_NEAR(black.eumelanin, std::log(1e4), 1e-12);
    EXPECT_EQ(black.pheomelanin, 0.0);
    // σa is sigma_a_from_concentrations of the concentrations.
    const dvec3 s = hs::sigma_a_from_melanin_amount(0.6, 0.3);
    const auto c = hs::melanin_concentrations(0.6, 0.3);
    EXPECT_EQ(s, hs::sigma_a_from_concentrations(c.eumelanin, c.pheomelanin));
}

// The former names, deprecated, still compile and give the new names' values to the bit:
// sigma_a_from_melanin took concentrations, sigma_a_from_melanin_redness an amount.
#if defined(_MSC_VER)
#pragma warning(push)
#pragma warning(disable : 4996)
#else
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#endif
TEST(Pigments, FormerNamesGiveTheSameValues) {
    for (double ce : {0.0, 0.3, 1.3, 8.0})
        for (double cp : {0.0, 0.2, 2.0}) {
            EXPECT_EQ(hs::sigma_a_from_melanin(ce, cp), hs::sigma_a_from_concentrations(ce, cp));
            EXPECT_EQ(hs::sigma_a_from_melanin(float(ce), float(cp)),
                      hs::sigma_a_from_concentrations(float(ce), float(cp)));
        }
    for (double m : {0.0, 0.25, 0.6, 1.0})
        for (double r : {0.0, 0.3, 1.0}) {
            EXPECT_EQ(hs::sigma_a_from_melanin_redness(m, r), hs::sigma_a_from_melanin_amount(m, r));
            EXPECT_EQ(hs::sigma_a_from_melanin_redness(float(m), float(r)),
                      hs::sigma_a_from_melanin_amount(float(m), float(r)));
        }
}
#if defined(_MSC_VER)
#pragma warning(pop)
#else
#pragma GCC diagnostic pop
#endif

TEST(Pigments, MoreMelaninIsDarkerAndRednessShiftsTheHue) {
    double prev = -1;
    for (double m = 0; m <= 1.0; m += 0.05) {
        const dvec3 s = hs::sigma_a_from_melanin_amount(m, 0.5);
        EXPECT_GT(s.b, prev);
        prev = s.b;
    }
    // Pheomelanin absorbs relatively less red than eumelanin: red hair has the lower σa.r/σa.b.
    const dvec3 eu = hs::sigma_a_from_melanin_amount(0.5, 0.0), ph = hs::sigma_a_from_melanin_amount(0.5, 1.0);
    EXPECT_LT(ph.r / ph.b, eu.r / eu.b);
}

TEST(Pigments, DyeIsTheColourMapping) {
    EXPECT_EQ(hs::sigma_a_from_dye(dvec3(1.0), 0.3), dvec3(0.0));
    for (double bn : {1e-3, 0.3, 1.0}) {
        const dvec3 d(0.8, 0.4, 0.05);
        EXPECT_EQ(hs::sigma_a_from_dye(d, bn), hs::sigma_a_from_color(d, bn));
    }
    hs::HairPigments<double> p;
    p.melanin = 0.4;
    p.redness = 0.2;
    p.dye = dvec3(0.9, 0.5, 0.7);
    EXPECT_EQ(hs::sigma_a_from_pigments(p, 0.25),
              hs::sigma_a_from_melanin_amount(0.4, 0.2) + hs::sigma_a_from_color(p.dye, 0.25));
}

TEST(Pigments, ValidationNamesTheField) {
    EXPECT_EQ(hs::validate(hs::HairPigments<double>{}), "");
    EXPECT_EQ(hs::validate(hs::HairPigments<float>{}), "");
    using P = hs::HairPigments<double>;
    for (double m : {-0.01, 1.01, kNaN, kInf}) {
        expect_rejected<P>([m](P& p) { p.melanin = m; }, "melanin");
        expect_rejected<P>([m](P& p) { p.redness = m; }, "redness");
    }
    for (double d : {0.0, -0.5, 1.5, kNaN}) expect_rejected<P>([d](P& p) { p.dye.g = d; }, "dye.g");
    hs::HairPigments<double> edge;
    edge.melanin = 1.0, edge.redness = 1.0, edge.dye = dvec3(1e-300, 1.0, 1.0);
    EXPECT_EQ(hs::validate(edge), "");
}

// Every valid input, at the edges too, gives a finite σa ≥ 0 that FiberParams accepts.
template <typename T> void pigment_sweep() {
    using V3 = glm::vec<3, T>;
    const T tiny = std::numeric_limits<T>::denorm_min(), small = std::numeric_limits<T>::min();
    long checked = 0;
    for (T m : {T(0), tiny, T(0.5), T(0.9999), T(1)})
        for (T r : {T(0), T(0.5), T(1)})
            for (T d : {small, T(1e-3), T(0.5), T(1)})
                for (T bn : {hs::kMinRoughness<T>, T(0.3), T(1)}) {
                    hs::HairPigments<T> p;
                    p.melanin = m, p.redness = r, p.dye = V3(d, T(1), d);
                    ASSERT_EQ(hs::validate(p), "");
                    hs::FiberParams<T> f;
                    f.beta_n = bn;
                    f.sigma_a = hs::sigma_a_from_pigments(p, bn);
                    ASSERT_EQ(hs::validate(f), "") << double(m) << " " << double(r) << " " << double(d);
                    ++checked;
                }
    std::printf("[ sweep    ] %ld pigment sets give valid sigma_a\n", checked);
}
TEST(Pigments, ExtremesGiveValidAbsorption) {
    pigment_sweep<float>();
    pigment_sweep<double>();
}

// ---- per-strand variation -----------------------------------------------------------------

// p-value of Pearson's statistic over equiprobable bins.
double uniform_p_value(const std::vector<long>& counts) {
    long n = 0;
    for (long c : counts) n += c;
    const double expected = double(n) / double(counts.size());
    double stat = 0;
    for (long c : counts) stat += (double(c) - expected) * (double(c) - expected) / expected;
    return boost::math::cdf(boost::math::complement(boost::math::chi_squared(double(counts.size() - 1)), stat));
}

// Uniformity of u(strand) over consecutive strands 0 … n-1 (the realistic ids) in `bins` bins.
double uniformity(const std::function<double(std::uint32_t)>& u, std::uint32_t n, int bins) {
    std::vector<long> counts(std::size_t(bins), 0);
    for (std::uint32_t s = 0; s < n; ++s) ++counts[std::size_t(std::min(bins - 1, int(u(s) * bins)))];
    return uniform_p_value(counts);
}

// Joint uniformity of (u(strand), v(strand)) in bins × bins cells: independence.
double joint_uniformity(const std::function<double(std::uint32_t)>& u, const std::function<double(std::uint32_t)>& v,
                        std::uint32_t n, int bins) {
    std::vector<long> counts(std::size_t(bins * bins), 0);
    for (std::uint32_t s = 0; s < n; ++s) {
        const int i = std::min(bins - 1, int(u(s) * bins)), j = std::min(bins - 1, int(v(s) * bins));
        ++counts[std::size_t(i * bins + j)];
    }
    return uniform_p_value(counts);
}

TEST(StrandVariation, IsDeterministicAndStateless) {
    hs::StrandVariation<double> v;
    v.seed = 42;
    v.melanin = {0.2, 0.9};
    v.redness = {0.0, 0.6};
    v.roughness_scale = {0.5, 1.5};
    const hs::StrandVariation<double> copy = v;
    for (std::uint32_t s : {0u, 1u, 77u, 123456u, 0xffffffffu}) {
        const auto a = v.at(s), b = copy.at(s);
        EXPECT_EQ(a.melanin, b.melanin);
        EXPECT_EQ(a.redness, b.redness);
        EXPECT_EQ(a.roughness_scale, b.roughness_scale);
    }
    // The same uniform number in float and double (24 bits): the precisions agree.
    for (std::uint32_t s = 0; s < 1000; ++s) {
        const std::uint32_t h = hs::strand_hash(s, 9u, 0u);
        EXPECT_EQ(double(hs::hash_to_unit<float>(h)), hs::hash_to_unit<double>(h));
    }
    // A constant expression: usable in tables built at compile time.
    static_assert(hs::pcg_hash(0u) != hs::pcg_hash(1u));
    // Another seed, other values; a strand's three quantities are drawn apart.
    int same_seed = 0, same_stream = 0;
    for (std::uint32_t s = 0; s < 1000; ++s) {
        same_seed += hs::strand_hash(s, 1u, 0u) == hs::strand_hash(s, 2u, 0u);
        same_stream += hs::strand_hash(s, 1u, 0u) == hs::strand_hash(s, 1u, 1u);
    }
    EXPECT_LE(same_seed, 1);
    EXPECT_LE(same_stream, 1);
}

TEST(StrandVariation, StaysInItsIntervals) {
    hs::StrandVariation<float> v;
    v.seed = 7;
    v.melanin = {0.1f, 0.35f};
    v.redness = {0.5f, 0.5f};  // fixed
    v.roughness_scale = {0.8f, 1.25f};
    ASSERT_EQ(hs::validate(v), "");
    float lo = 1, hi = 0;
    for (std::uint32_t s = 0; s < 200000; ++s) {
        const auto t = v.at(s);
        ASSERT_GE(t.melanin, 0.1f);
        ASSERT_LE(t.melanin, 0.35f);
        ASSERT_EQ(t.redness, 0.5f);
        ASSERT_GE(t.roughness_scale, 0.8f);
        ASSERT_LE(t.roughness_scale, 1.25f);
        lo = std::min(lo, t.melanin), hi = std::max(hi, t.melanin);
    }
    // The draws fill the interval (200000 draws leave gaps of ~1e-6 at the ends).
    EXPECT_LT(lo, 0.1f + 1e-4f);
    EXPECT_GT(hi, 0.35f - 1e-4f);
    // An interval whose rounding would overshoot: the draw stays ≤ hi.
    hs::StrandVariation<float> w;
    w.melanin = {0.1f, std::nextafter(0.1f, 1.0f)};
    for (std::uint32_t s = 0; s < 10000; ++s) ASSERT_LE(w.at(s).melanin, w.melanin.hi);
}

// Pearson's chi-square over 64 equiprobable bins of 10⁶ consecutive strands, for three
// seeds and each stream, then joint 16 × 16 cells of two streams (independence) and of
// neighbouring strands (no serial correlation). 12 tests at a family-wise 1 %: each must
// reach p > 0.01/12. Negative controls: an unmixed hash (the id itself), a biased map (u²)
// and two identical streams must be rejected.
TEST(StrandVariation, HashedValuesAreUniformChi2) {
    const std::uint32_t n = 1000000;
    const double threshold = 0.01 / 12;
    double min_p = 1;
    for (std::uint32_t seed : {0u, 1u, 0xdeadbeefu})
        for (std::uint32_t stream : {0u, 1u, 2u}) {
            if (stream == 2u && seed != 0u) continue;  // 7 marginal tests
            const double p = uniformity(
                [&](std::uint32_t s) { return hs::hash_to_unit<double>(hs::strand_hash(s, seed, stream)); }, n, 64);
            EXPECT_GT(p, threshold) << "seed " << seed << " stream " << stream;
            min_p = std::min(min_p, p);
        }
    for (std::uint32_t seed : {0u, 5u, 0xdeadbeefu}) {  // 3 independence tests
        const double p = joint_uniformity([&](std::uint32_t s) { return hs::hash_to_unit<double>(hs::strand_hash(s, seed, 0u)); },
                                          [&](std::uint32_t s) { return hs::hash_to_unit<double>(hs::strand_hash(s, seed, 1u)); },
                                          n, 16);
        EXPECT_GT(p, threshold) << "streams 0 and 1, seed " << seed;
        min_p = std::min(min_p, p);
    }
    for (std::uint32_t seed : {3u, 11u}) {  // 2 serial tests
        const double p = joint_uniformity([&](std::uint32_t s) { return hs::hash_to_unit<double>(hs::strand_hash(s, seed, 2u)); },
                                          [&](std::uint32_t s) { return hs::hash_to_unit<double>(hs::strand_hash(s + 1, seed, 2u)); },
                                          n, 16);
        EXPECT_GT(p, threshold) << "neighbouring strands, seed " << seed;
        min_p = std::min(min_p, p);
    }
    std::printf("[ chi2     ] strand hash: 12 tests, smallest p-value %.3g (threshold %.3g)\n", min_p, threshold);

    // Negative controls.
    EXPECT_LT(uniformity([](std::uint32_t s) { return hs::hash_to_unit<double>(s); }, n, 64), threshold);
    EXPECT_LT(uniformity([](std::uint32_t s) {
                  const double u = hs::hash_to_unit<double>(hs::strand_hash(s, 0u, 0u));
                  return u * u;
              }, n, 64),
              threshold);
    EXPECT_LT(joint_uniformity([](std::uint32_t s) { return hs::hash_to_unit<double>(hs::strand_hash(s, 4u, 0u)); },
                               [](std::uint32_t s) { return hs::hash_to_unit<double>(hs::strand_hash(s, 4u, 0u)); }, n,
                               16),
              threshold);
}

TEST(StrandVariation, ValidationNamesTheInterval) {
    EXPECT_EQ(hs::validate(hs::StrandVariation<double>{}), "");
    using V = hs::StrandVariation<double>;
    auto bad = [](auto change, const char* field) { expect_rejected<V>(change, field); };
    bad([](V& v) { v.melanin = {0.5, 0.4}; }, "melanin");
    bad([](V& v) { v.melanin = {-0.1, 0.4}; }, "melanin");
    bad([](V& v) { v.melanin = {0.1, 1.1}; }, "melanin");
    bad([](V& v) { v.redness = {kNaN, 0.4}; }, "redness");
    bad([](V& v) { v.redness = {0.0, kInf}; }, "redness");
    bad([](V& v) { v.roughness_scale = {0.0, 1.0}; }, "roughness_scale");
    bad([](V& v) { v.roughness_scale = {1.0, 1e4}; }, "roughness_scale");
    bad([](V& v) { v.roughness_scale = {2.0, 1.0}; }, "roughness_scale");
}

// Every strand of a valid variation gets valid fiber parameters, at extreme scales too.
TEST(StrandVariation, StrandParamsAreValid) {
    hs::FiberParams<float> base;
    base.beta_m = 0.9f, base.beta_n = 2e-3f;
    hs::StrandVariation<float> v;
    v.melanin = {0.0f, 1.0f};
    v.redness = {0.0f, 1.0f};
    v.roughness_scale = {1e-3f, 1000.0f};
    ASSERT_EQ(hs::validate(v), "");
    for (std::uint32_t s = 0; s < 20000; ++s) {
        const hs::StrandTraits<float> t = v.at(s);
        const hs::FiberParams<float> p = hs::strand_params(base, t, glm::vec3(0.3f, 1.0f, 1e-30f));
        ASSERT_EQ(hs::validate(p), "") << "strand " << s;
    }
    // With scale 1 and no dye the strand's σa is the pigments' own.
    const hs::StrandTraits<float> t{0.5f, 0.2f, 1.0f};
    const hs::FiberParams<float> p = hs::strand_params(base, t);
    EXPECT_EQ(p.beta_m, base.beta_m);
    EXPECT_EQ(p.sigma_a, hs::sigma_a_from_melanin_amount(0.5f, 0.2f));
}

// ---- lobe controls --------------------------------------------------------------------------

hs::LobeControls<double> some_controls() {
    hs::LobeControls<double> c;
    c.gain[0] = 2.0, c.gain[1] = 0.5, c.gain[2] = 1.5, c.gain[3] = 0.25;
    c.tint[1] = dvec3(1.0, 0.6, 0.3);
    c.tint[2] = dvec3(0.9, 1.2, 1.0);
    return c;
}

hs::FiberParams<double> test_params(double sigma) {
    hs::FiberParams<double> p;
    p.beta_m = 0.25, p.beta_n = 0.35;
    p.sigma_a = dvec3(sigma, 0.6 * sigma, 0.3 * sigma);
    return p;
}

TEST(LobeControls, ValidationNamesTheField) {
    EXPECT_EQ(hs::validate(hs::LobeControls<double>{}), "");
    using C = hs::LobeControls<double>;
    auto bad = [](auto change, const char* field) {
        const C c = expect_rejected<C>(change, field);
        EXPECT_THROW(hs::ChiangMaterial<double>(hs::FiberParams<double>(), c), std::invalid_argument);
    };
    bad([](C& c) { c.gain[0] = -1; }, "gain_r");
    bad([](C& c) { c.gain[1] = kNaN; }, "gain_tt");
    bad([](C& c) { c.gain[2] = kInf; }, "gain_trt");
    bad([](C& c) { c.gain[3] = 2e6; }, "gain_residual");
    bad([](C& c) { c.tint[1].b = -0.1; }, "tint_tt.b");
    bad([](C& c) { c.tint[3].r = kNaN; }, "tint_residual.r");
    bad([](C& c) { c.override_alpha(2, 0.5); }, "alpha_trt");
    bad([](C& c) { c.override_alpha(0, kNaN); }, "alpha_r");
    bad([](C& c) { c.alpha_override = 8u; }, "alpha_override");
    // An alpha that is not overridden is not read.
    hs::LobeControls<double> unused;
    unused.alpha[1] = 5.0;
    EXPECT_EQ(hs::validate(unused), "");
    hs::LobeControls<double> zero;
    for (double& g : zero.gain) g = 0;
    EXPECT_EQ(hs::validate(zero), "");
}

// albedo(wo) with controls is Σ_p gain_p tint_p A_p of the plain model's lobe split, and eval
// is Σ_p gain_p tint_p f_p over the one-lobe fibers.
TEST(LobeControls, GainsScaleEachLobe) {
    const hs::FiberParams<double> params = test_params(0.4);
    const hs::LobeControls<double> c = some_controls();
    const hs::ChiangMaterial<double> plain(params), controlled(params, c);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> uni(0, 1);
    for (int k = 0; k < 50; ++k) {
        const double h = -1 + 2 * uni(rng);
        const dvec3 wo = contract::dir(std::asin(-1 + 2 * uni(rng)), 2 * kPi * uni(rng));
        const dvec3 wi = contract::dir(std::asin(-1 + 2 * uni(rng)), 2 * kPi * uni(rng));
        const hs::ChiangFiber<double> a(plain, h), b(controlled, h);
        const auto split = a.lobe_split(wo);
        dvec3 expected(0.0);
        for (int p = 0; p <= 3; ++p) expected += c.weight(p) * split.a[p];
        const dvec3 got = b.albedo(wo);
        for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(got[ch], expected[ch], 1e-14 * expected[ch]);

        const dvec3 f_lobes = c.weight(0) * hs::BasicChiangFiber<double, hs::LobeSet::kR>(plain, h).eval(wo, wi) +
                              c.weight(1) * hs::BasicChiangFiber<double, hs::LobeSet::kTT>(plain, h).eval(wo, wi) +
                              c.weight(2) * hs::BasicChiangFiber<double, hs::LobeSet::kTRT>(plain, h).eval(wo, wi) +
                              c.weight(3) * hs::BasicChiangFiber<double, hs::LobeSet::kResidual>(plain, h).eval(wo, wi);
        const dvec3 f = b.eval(wo, wi);
        for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(f[ch], f_lobes[ch], 1e-12 * f_lobes[ch] + 1e-300);
    }
}

// Default controls change nothing; an override equal to the global α changes nothing but
// rounding; an override of R's α moves the R lobe as a global α would and leaves TT alone.
TEST(LobeControls, AlphaOverridesMoveOnlyTheirLobe) {
    const hs::FiberParams<double> params = test_params(0.2);
    const hs::ChiangMaterial<double> plain(params), defaults(params, hs::LobeControls<double>{});
    hs::LobeControls<double> same;
    same.override_alpha(0, params.alpha).override_alpha(1, params.alpha).override_alpha(2, params.alpha);
    const hs::ChiangMaterial<double> same_alpha(params, same);
    hs::LobeControls<double> r_only;
    r_only.override_alpha(0, hs::radians(7.0));
    const hs::ChiangMaterial<double> moved(params, r_only);
    hs::FiberParams<double> global7 = params;
    global7.alpha = hs::radians(7.0);
    const hs::ChiangMaterial<double> all_moved(global7);
    for (double theta : {-1.2, -0.3, 0.0, 0.5, 1.4}) {
        const dvec3 wo = contract::dir(theta, 0.2);
        for (double ti : {-1.0, -0.2, 0.4})
            for (double phi : {0.1, 1.5, 3.0}) {
                const dvec3 wi = contract::dir(ti, phi);
                EXPECT_EQ(hs::ChiangFiber<double>(plain, 0.3).eval(wo, wi), hs::ChiangFiber<double>(defaults, 0.3).eval(wo, wi));
                const dvec3 a = hs::ChiangFiber<double>(plain, 0.3).eval(wo, wi);
                const dvec3 b = hs::ChiangFiber<double>(same_alpha, 0.3).eval(wo, wi);
                for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(a[ch], b[ch], 1e-12 * a[ch] + 1e-300);
                using R = hs::BasicChiangFiber<double, hs::LobeSet::kR>;
                using TT = hs::BasicChiangFiber<double, hs::LobeSet::kTT>;
                const dvec3 r_moved = R(moved, -0.4).eval(wo, wi), r_global = R(all_moved, -0.4).eval(wo, wi);
                for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(r_moved[ch], r_global[ch], 1e-12 * r_global[ch] + 1e-300);
                const dvec3 tt_moved = TT(moved, -0.4).eval(wo, wi), tt_plain = TT(plain, -0.4).eval(wo, wi);
                // TT's rotation is rebuilt from sin/cos of α instead of the double-angle ladder: rounding.
                for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(tt_moved[ch], tt_plain[ch], 1e-12 * tt_plain[ch] + 1e-300);
            }
    }
    EXPECT_NEAR(moved.lobe_shift(0), 2 * hs::radians(7.0), 1e-15);
    EXPECT_EQ(moved.lobe_shift(1), plain.lobe_shift(1));
}

// ---- lobe controls on every model --------------------------------------------------------

// Calls f(adapter) for every model that takes lobe controls (tests/support/controls_specs.hpp).
template <typename T, typename F> void for_each_model(F f) {
    f(specs::ChiangControls<T>{});
    f(specs::FarFieldControls<T>{});
    f(specs::TabulatedControls<T>{});
    f(specs::MarschnerControls<T>{});
}

// The d'Eon-family test parameters in each model's terms.
template <typename A> typename A::Params model_params(double sigma) {
    return A::params(0.25, 0.35, 2, dvec3(sigma, 0.6 * sigma, 0.3 * sigma));
}

// Controls with every lobe weighted (the residual where the model has one).
template <typename A> hs::LobeControls<typename A::Fiber::Real> weighted_controls() {
    using T = typename A::Fiber::Real;
    const hs::LobeControls<double> d = some_controls();
    hs::LobeControls<T> c;
    for (int p = 0; p < (A::kResidual ? 4 : 3); ++p) {
        c.gain[p] = T(d.gain[p]);
        c.tint[p] = glm::vec<3, T>(d.tint[p]);
    }
    return c;
}

// Default controls (and default-constructed ones passed explicitly) change nothing, bit for
// bit: eval, pdf, sample and albedo equal the plain material's exactly, in float and double;
// the tabulated tables are identical.
template <typename T> void default_controls_change_nothing() {
    using V3 = glm::vec<3, T>;
    for_each_model<T>([](auto a) {
        using A = decltype(a);
        std::mt19937_64 rng(11);
        std::uniform_real_distribution<double> uni(0, 1);
        const hs::LobeControls<T> none;
        for (int k = 0; k < 4; ++k) {
            const typename A::Params p = A::random_params(rng, k);
            const auto plain = A::material(p, nullptr, k), controlled = A::material(p, &none, k);
            if constexpr (std::is_same<typename A::Material, hs::TabulatedMaterial<T>>::value) {
                EXPECT_TRUE(plain->data() == controlled->data()) << A::kName;
            }
            const double h = -1 + 2 * uni(rng);
            const auto fa = A::fiber(*plain, h), fb = A::fiber(*controlled, h);
            for (int j = 0; j < 25; ++j) {
                const V3 wo(contract::dir(std::asin(-1 + 2 * uni(rng)), 2 * kPi * uni(rng)));
                const V3 wi(contract::dir(std::asin(-1 + 2 * uni(rng)), 2 * kPi * uni(rng)));
                const double u0 = uni(rng), u1 = uni(rng), u2 = uni(rng), u3 = uni(rng);
                const glm::vec<4, T> u{T(u0), T(u1), T(u2), T(u3)};
                ASSERT_EQ(fa.eval(wo, wi), fb.eval(wo, wi)) << A::kName;
                ASSERT_EQ(fa.pdf(wo, wi), fb.pdf(wo, wi)) << A::kName;
                const auto sa = fa.sample(wo, u), sb = fb.sample(wo, u);
                ASSERT_EQ(sa.wi, sb.wi) << A::kName;
                ASSERT_EQ(sa.pdf, sb.pdf) << A::kName;
                ASSERT_EQ(sa.weight, sb.weight) << A::kName;
                ASSERT_EQ(sa.lobe, sb.lobe) << A::kName;
                if (j % 8 == 0) {  // Marschner's albedo is 4096 samples
                    ASSERT_EQ(fa.albedo(wo), fb.albedo(wo)) << A::kName;
                }
            }
        }
    });
}
TEST(LobeControls, DefaultControlsChangeNothingOnEveryModel) {
    default_controls_change_nothing<float>();
    default_controls_change_nothing<double>();
}

// eval with controls is Σ_p gain_p tint_p f_p, f_p the same model with lobe p alone (gain 1,
// the others 0), on every model; for the models with a lobe split (Chiang, far field,
// tabulated) albedo(wo) is Σ_p gain_p tint_p A_p of the plain material's split. A TT tilt
// override rides along in every material. Double; tolerance: rounding of the sums.
TEST(LobeControls, GainsScaleEachLobeOnEveryModel) {
    for_each_model<double>([](auto a) {
        using A = decltype(a);
        hs::LobeControls<double> c = weighted_controls<A>();
        c.override_alpha(1, hs::radians(6.0));
        const typename A::Params p = model_params<A>(0.4);
        const auto plain = A::material(p, nullptr, 0), controlled = A::material(p, &c, 0);
        std::shared_ptr<const typename A::Material> alone[4];
        const int lobes = A::kResidual ? 4 : 3;
        for (int q = 0; q < lobes; ++q) {
            hs::LobeControls<double> only;
            only.override_alpha(1, hs::radians(6.0));
            for (int p2 = 0; p2 < lobes; ++p2) only.gain[p2] = p2 == q ? 1.0 : 0.0;
            alone[q] = A::material(p, &only, 0);
        }
        std::mt19937_64 rng(3);
        std::uniform_real_distribution<double> uni(0, 1);
        for (int k = 0; k < 30; ++k) {
            const double h = -1 + 2 * uni(rng);
            const dvec3 wo = contract::dir(std::asin(-1 + 2 * uni(rng)), 2 * kPi * uni(rng));
            const dvec3 wi = contract::dir(std::asin(-1 + 2 * uni(rng)), 2 * kPi * uni(rng));
            dvec3 f_lobes(0.0);
            for (int q = 0; q < lobes; ++q) f_lobes += c.weight(q) * A::fiber(*alone[q], h).eval(wo, wi);
            const dvec3 f = A::fiber(*controlled, h).eval(wo, wi);
            for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(f[ch], f_lobes[ch], 1e-12 * f_lobes[ch] + 1e-300) << A::kName;
            if constexpr (hs::has_lobe_split_v<typename A::Fiber>) {
                hs::LobeControls<double> tilt_only;
                tilt_only.override_alpha(1, hs::radians(6.0));
                const auto split = A::fiber(*A::material(p, &tilt_only, 0), h).lobe_split(wo);
                dvec3 expected(0.0);
                for (int q = 0; q < lobes; ++q) expected += c.weight(q) * split.a[q];
                const dvec3 got = A::fiber(*controlled, h).albedo(wo);
                for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(got[ch], expected[ch], 1e-12 * expected[ch]) << A::kName;
            }
        }
    });
}

// A tilt override of R moves the R lobe exactly as the model's own tilt would (the d'Eon
// family: FiberParams::alpha; Marschner: α_R = -2α) and leaves TT where it was; each lobe is
// isolated by zero gains on the others. Tolerance: the rotations are rebuilt from sin/cos of
// each lobe's α instead of the double-angle ladder (rounding).
TEST(LobeControls, AlphaOverrideMovesOnlyItsLobeOnEveryModel) {
    for_each_model<double>([](auto a) {
        using A = decltype(a);
        auto lobe_alone = [](int q) {
            hs::LobeControls<double> c;
            for (int p = 0; p < (A::kResidual ? 4 : 3); ++p) c.gain[p] = p == q ? 1.0 : 0.0;
            return c;
        };
        const typename A::Params base = A::params(0.25, 0.35, 2, dvec3(0.2)), tilted = A::params(0.25, 0.35, 7, dvec3(0.2));
        hs::LobeControls<double> r_moved = lobe_alone(0), tt_moved = lobe_alone(1);
        r_moved.override_alpha(0, hs::radians(7.0));
        tt_moved.override_alpha(0, hs::radians(7.0));
        const hs::LobeControls<double> r_alone = lobe_alone(0), tt_alone = lobe_alone(1);
        const auto r_override = A::material(base, &r_moved, 0), r_global = A::material(tilted, &r_alone, 0);
        const auto tt_override = A::material(base, &tt_moved, 0), tt_plain = A::material(base, &tt_alone, 0);
        for (double theta : {-1.2, -0.3, 0.0, 0.5, 1.4})
            for (double ti : {-1.0, -0.2, 0.4})
                for (double phi : {0.1, 1.5, 3.0}) {
                    const dvec3 wo = contract::dir(theta, 0.2), wi = contract::dir(ti, phi);
                    const dvec3 r1 = A::fiber(*r_override, -0.4).eval(wo, wi), r2 = A::fiber(*r_global, -0.4).eval(wo, wi);
                    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(r1[ch], r2[ch], 1e-12 * r2[ch] + 1e-300) << A::kName;
                    const dvec3 t1 = A::fiber(*tt_override, -0.4).eval(wo, wi), t2 = A::fiber(*tt_plain, -0.4).eval(wo, wi);
                    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(t1[ch], t2[ch], 1e-12 * t2[ch] + 1e-300) << A::kName;
                }
    });
}

// The furnace with gains on the models whose albedo is exact (Chiang, far field,
// tabulated): ∫ eval dω (cubature) equals albedo(wo) = Σ_p gain_p A_p, and the energy the
// gains add or remove is Σ_p (gain_p - 1) A_p (printed). σa = 0, so the plain model's albedo
// is 1.
TEST(LobeControls, FurnaceReportsTheEnergyChange) {
    hs::LobeControls<double> c;
    c.gain[0] = 2.0, c.gain[1] = 0.5, c.gain[2] = 1.5, c.gain[3] = 0.0;
    for_each_model<double>([&c](auto a) {
        using A = decltype(a);
        if constexpr (hs::has_lobe_split_v<typename A::Fiber>) {
            const typename A::Params params = model_params<A>(0.0);
            const auto plain = A::material(params, nullptr, 0), controlled = A::material(params, &c, 0);
            for (double h : {-0.7, 0.2})
                for (double theta_o : {-60.0, 0.0, 30.0}) {
                    const dvec3 wo = contract::dir(theta_o * kPi / 180, 0.3);
                    const auto fiber = A::fiber(*controlled, h);
                    const chi2::CellIntegrator integrate(
                        [&](double x, double phi) {
                            const double cs = std::sqrt(std::max(0.0, 1 - x * x));
                            return fiber.eval(wo, dvec3(x, cs * std::cos(phi), cs * std::sin(phi))).g;
                        },
                        2, 5);
                    double total = 0;
                    for (int i = 0; i < 8; ++i)
                        for (int j = 0; j < 16; ++j)
                            total += integrate.integrate(-1 + i * 0.25, -1 + (i + 1) * 0.25, -kPi + j * kPi / 8,
                                                         -kPi + (j + 1) * kPi / 8);
                    const auto split = A::fiber(*plain, h).lobe_split(wo);
                    double change = 0, plain_total = 0;
                    for (int p = 0; p <= 3; ++p) change += (c.gain[p] - 1) * split.a[p].g, plain_total += split.a[p].g;
                    const double albedo = fiber.albedo(wo).g;
                    std::printf("[ furnace  ] %s, gains R 2, TT 0.5, TRT 1.5, residual 0; h %.1f θo %.0f°: "
                                "∫ f dω = %.6f, albedo %.6f, energy change %+.6f (plain %.6f)\n",
                                A::kName, h, theta_o, total, albedo, change, plain_total);
                    EXPECT_NEAR(plain_total, 1.0, 1e-12) << A::kName;
                    EXPECT_NEAR(total, albedo, 1e-5) << A::kName;
                    EXPECT_NEAR(albedo - 1.0, change, 1e-12) << A::kName;
                }
        }
    });
}

// A zero gain removes its lobe from sampling on every model: it is never drawn, the others
// are, and every sample has a positive pdf. All gains 0: f and pdf are 0 and a sample carries
// no weight (no NaN).
template <typename T> void zero_gain_is_never_sampled() {
    using V3 = glm::vec<3, T>;
    for_each_model<T>([](auto a) {
        using A = decltype(a);
        hs::LobeControls<T> c;
        c.gain[1] = T(0);  // no TT
        const auto m = A::material(model_params<A>(0.1), &c, 0);
        const auto fiber = A::fiber(*m, 0.1);
        std::mt19937_64 rng(5);
        std::uniform_real_distribution<double> uni(0, 1);
        int drawn[4] = {};
        for (int k = 0; k < 4000; ++k) {
            const V3 wo(contract::dir(std::asin(-1 + 2 * uni(rng)), 0.0));
            const double u0 = uni(rng), u1 = uni(rng), u2 = uni(rng), u3 = uni(rng);
            const auto s = fiber.sample(wo, glm::vec<4, T>(T(u0), T(u1), T(u2), T(u3)));
            ASSERT_GT(s.pdf, T(0)) << A::kName;
            ++drawn[hs::lobe_index(s.lobe)];
        }
        EXPECT_EQ(drawn[1], 0) << A::kName;
        EXPECT_GT(drawn[0], 0) << A::kName;
        EXPECT_GT(drawn[2], 0) << A::kName;
        if (A::kResidual) {
            EXPECT_GT(drawn[3], 0) << A::kName;
        }
        hs::LobeControls<T> none;
        for (int p = 0; p < (A::kResidual ? 4 : 3); ++p) none.gain[p] = T(0);
        const auto dark = A::material(model_params<A>(0.1), &none, 0);
        const auto df = A::fiber(*dark, 0.1);
        for (double theta : {-1.0, 0.3, 1.2}) {
            const V3 wo(contract::dir(theta, 0.0)), wi(contract::dir(-0.2, 2.0));
            const auto s = df.sample(wo, glm::vec<4, T>(T(0.3), T(0.5), T(0.5), T(0.5)));
            EXPECT_EQ(s.pdf, T(0)) << A::kName;
            EXPECT_EQ(s.weight, V3(T(0))) << A::kName;
            EXPECT_TRUE(hs::is_finite(s.wi)) << A::kName;
            EXPECT_EQ(df.eval(wo, wi), V3(T(0))) << A::kName;
            EXPECT_EQ(df.pdf(wo, wi), T(0)) << A::kName;
        }
    });
}
TEST(LobeControls, ZeroGainLobeIsNeverSampledOnEveryModel) {
    zero_gain_is_never_sampled<float>();
    zero_gain_is_never_sampled<double>();
}

// Subnormal gains (every lobe at min()/1000, float and double): the selection weights'
// total is subnormal, where 1 / total overflows; eval, pdf and sample stay finite and
// non-negative, and a sample's pdf is the pdf of its direction (relative 1e-4: the weights
// are quotients of subnormals, which keep fewer digits). A fuzzer found the NaN this guards.
template <typename T> void subnormal_gains_stay_finite() {
    using V3 = glm::vec<3, T>;
    for_each_model<T>([](auto a) {
        using A = decltype(a);
        hs::LobeControls<T> c;
        for (int p = 0; p < (A::kResidual ? 4 : 3); ++p) c.gain[p] = std::numeric_limits<T>::min() / T(1000);
        const auto m = A::material(model_params<A>(0.1), &c, 0);
        const auto fiber = A::fiber(*m, 0.1);
        for (double theta : {-1.0, 0.3, 1.2}) {
            const V3 wo(contract::dir(theta, 0.0)), wi(contract::dir(-0.2, 2.0));
            const V3 f = fiber.eval(wo, wi);
            const T pdf = fiber.pdf(wo, wi);
            EXPECT_TRUE(hs::is_finite(f) && f.x >= T(0) && f.y >= T(0) && f.z >= T(0)) << A::kName;
            EXPECT_TRUE(hs::is_finite(pdf) && pdf >= T(0)) << A::kName << " pdf " << double(pdf);
            for (double u0 : {0.1, 0.5, 0.9}) {
                const auto s = fiber.sample(wo, glm::vec<4, T>(T(u0), T(0.4), T(0.6), T(0.3)));
                ASSERT_TRUE(hs::is_finite(s.pdf) && s.pdf >= T(0) && hs::is_finite(s.weight) && hs::is_finite(s.wi))
                    << A::kName << " theta " << theta << " u0 " << u0 << " pdf " << double(s.pdf);
                EXPECT_TRUE(s.weight.x >= T(0) && s.weight.y >= T(0) && s.weight.z >= T(0)) << A::kName;
                if (s.pdf > T(0)) {
                    EXPECT_NEAR(double(fiber.pdf(wo, s.wi)), double(s.pdf), 1e-4 * double(s.pdf)) << A::kName;
                }
            }
        }
    });
}
TEST(LobeControls, SubnormalGainsStayFiniteOnEveryModel) {
    subnormal_gains_stay_finite<float>();
    subnormal_gains_stay_finite<double>();
}

// Negative control for the contract suite's chi-square with controls, per model: the sampler
// of a material with gains tested against the pdf of the same material without them (lobe
// selection by the unscaled weights) must be rejected, so the test sees whether the gains
// reach the sampler; against its own pdf it passes (the model's chi-square options).
TEST(LobeControls, Chi2RejectsUnscaledSelectionOnEveryModel) {
    for_each_model<double>([](auto a) {
        using A = decltype(a);
        hs::LobeControls<double> c;
        c.gain[0] = 3.0, c.gain[1] = 0.0;
        const typename A::Params params = model_params<A>(0.3);
        const auto plain = A::material(params, nullptr, 0), controlled = A::material(params, &c, 0);
        const auto fa = A::fiber(*plain, 0.2), fb = A::fiber(*controlled, 0.2);
        const dvec3 wo = contract::dir(0.5, 0.7);
        chi2::Options o = A::Base::chi2_options();
        o.num_tests = 4;  // the four models
        // One histogram of the controlled sampler for both pdfs.
        const chi2::Histogram hist = chi2::histogram([&](const glm::dvec4& u) { return fb.sample(wo, u).wi; }, o);
        const chi2::Result good =
            chi2::compare(hist, chi2::expected_counts([&](const dvec3& wi) { return fb.pdf(wo, wi); }, o), o);
        EXPECT_TRUE(good.passed) << A::kName << "\n" << good.report;
        const chi2::Result bad =
            chi2::compare(hist, chi2::expected_counts([&](const dvec3& wi) { return fa.pdf(wo, wi); }, o), o);
        EXPECT_FALSE(bad.passed) << A::kName << ": the unscaled pdf was accepted (p = " << bad.p_value << ")";
        std::printf("[ chi2     ] %s with gains R 3, TT 0: p = %.3g against its pdf, %.3g against the plain pdf\n",
                    A::kName, good.p_value, bad.p_value);
    });
}

// Marschner's model has no residual lobe: a residual gain or tint is refused, naming the
// field and the reason; R, TT and TRT controls are accepted.
TEST(LobeControls, MarschnerRefusesResidualControls) {
    const hs::MarschnerParams<double> p;
    hs::LobeControls<double> c;
    c.gain[3] = 0.5;
    try {
        const hs::MarschnerMaterial<double> m(p, c);
        ADD_FAILURE() << "a residual gain was accepted";
    } catch (const std::invalid_argument& e) {
        expect_names(e.what(), "gain_residual");
        expect_names(e.what(), "no residual lobe");
    }
    hs::LobeControls<double> t;
    t.tint[3] = dvec3(1.0, 0.5, 1.0);
    EXPECT_THROW(hs::MarschnerMaterial<double>(p, t), std::invalid_argument);
    const hs::LobeControls<double> ok = weighted_controls<specs::MarschnerControls<double>>();
    EXPECT_NO_THROW(hs::MarschnerMaterial<double>(p, ok));
    // The models built from FiberParams name the bad control through the shared validation.
    hs::LobeControls<double> bad;
    bad.tint[1].g = -1;
    const hs::FiberParams<double> fp;
    for (auto build : {std::function<void()>([&] { hs::DeonFarFieldMaterial<double>(fp, bad); }),
                       std::function<void()>([&] { hs::TabulatedMaterial<double>(fp, hs::TabulatedOptions(), bad); }),
                       std::function<void()>([&] { hs::MarschnerMaterial<double>(p, bad); })}) {
        try {
            build();
            ADD_FAILURE() << "a negative tint was accepted";
        } catch (const std::invalid_argument& e) {
            expect_names(e.what(), "tint_tt.g");
        }
    }
}

}  // namespace

// The contract suite over every model with controls: tests/contract/*.cpp (the suites
// named <Model>WithControls).
