// Materials built per hit: FiberParamBounds (checked once on the host, clamp() per hit) and
// ChiangMaterial::unchecked, which must give the checked constructor's material bit for bit.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

namespace hs = hairscatter;

namespace {

// Bit-for-bit equality (NaN included), reported with the values.
template <typename T> bool same_bits(T a, T b) { return std::memcmp(&a, &b, sizeof a) == 0; }
template <typename T> bool same_bits(const glm::vec<3, T>& a, const glm::vec<3, T>& b) {
    return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

// A valid parameter set drawn over the whole domain, its ends included (the extremes are
// where an unchecked path that computed anything differently would show it first).
template <typename T> hs::FiberParams<T> random_params(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const auto pick = [&](double lo, double hi) {
        const double r = u(rng);
        return T(r < 0.1 ? lo : r > 0.9 ? hi : lo + (hi - lo) * u(rng));
    };
    hs::FiberParams<T> p;
    p.eta = pick(1.0 + 1e-6, 3.0);
    p.beta_m = pick(1e-3, 1.0);
    p.beta_n = pick(1e-3, 1.0);
    p.alpha = pick(-double(hs::kMaxCuticleTilt<T>), double(hs::kMaxCuticleTilt<T>));
    for (int c = 0; c < 3; ++c) p.sigma_a[c] = pick(0.0, 20.0);
    return p;
}

template <typename T> hs::LobeControls<T> random_controls(std::mt19937& rng) {
    std::uniform_real_distribution<T> u(T(0), T(1));
    hs::LobeControls<T> c;
    for (int p = 0; p < hs::LobeControls<T>::kLobes; ++p) {
        c.gain[p] = T(2) * u(rng);
        c.tint[p] = glm::vec<3, T>(u(rng), u(rng), u(rng));
    }
    c.override_alpha(1, T(0.1) * (u(rng) - T(0.5)));
    return c;
}

template <typename T> glm::vec<3, T> random_direction(std::mt19937& rng) {
    std::normal_distribution<T> n(T(0), T(1));
    for (;;) {
        const glm::vec<3, T> d(n(rng), n(rng), n(rng));
        const T l = glm::length(d);
        if (l > T(1e-3)) return d / l;
    }
}

// Everything the fiber reads from its material, and everything it computes from it at a
// few (h, wo, wi, u): the checked and the unchecked material must agree in every bit.
template <typename T>
void expect_same_material(const hs::ChiangMaterial<T>& a, const hs::ChiangMaterial<T>& b, std::mt19937& rng) {
    static_assert(std::is_trivially_copyable<hs::ChiangMaterial<T>>::value, "copyable to a GPU");
    for (int p = 0; p <= hs::ChiangMaterial<T>::kLobes; ++p) {
        ASSERT_TRUE(same_bits(a.lobe_variance(p), b.lobe_variance(p))) << p;
        ASSERT_TRUE(same_bits(a.lobe_exp_m2_over_v(p), b.lobe_exp_m2_over_v(p))) << p;
        ASSERT_TRUE(same_bits(a.lobe_shift(p), b.lobe_shift(p))) << p;
        ASSERT_TRUE(same_bits(a.lobe_weight(p), b.lobe_weight(p))) << p;
    }
    for (int c = 0; c < hs::kChannelLanes; ++c) ASSERT_TRUE(same_bits(a.sigma_a_lanes()[c], b.sigma_a_lanes()[c]));
    ASSERT_EQ(a.has_lobe_weights(), b.has_lobe_weights());
    ASSERT_TRUE(same_bits(a.azimuthal().scale(), b.azimuthal().scale()));
    std::uniform_real_distribution<T> u(T(0), T(1));
    for (int k = 0; k < 16; ++k) {
        const T h = T(2) * u(rng) - T(1);
        const hs::ChiangFiber<T> fa(a, h), fb(b, h);
        const glm::vec<3, T> wo = random_direction<T>(rng), wi = random_direction<T>(rng);
        const glm::vec<4, T> us(u(rng), u(rng), u(rng), u(rng));
        ASSERT_TRUE(same_bits(fa.eval(wo, wi), fb.eval(wo, wi))) << "h " << h;
        ASSERT_TRUE(same_bits(fa.pdf(wo, wi), fb.pdf(wo, wi))) << "h " << h;
        ASSERT_TRUE(same_bits(fa.albedo(wo), fb.albedo(wo))) << "h " << h;
        const hs::HairSample<T> sa = fa.sample(wo, us), sb = fb.sample(wo, us);
        ASSERT_TRUE(same_bits(sa.wi, sb.wi) && same_bits(sa.weight, sb.weight) && same_bits(sa.pdf, sb.pdf));
        ASSERT_EQ(sa.lobe, sb.lobe);
    }
}

template <typename T> void unchecked_matches_checked() {
    std::mt19937 rng(20261206u);
    for (int i = 0; i < 400; ++i) {
        const hs::FiberParams<T> p = random_params<T>(rng);
        ASSERT_EQ(hs::validate(p), "");
        const hs::LobeControls<T> c = i % 2 == 0 ? hs::LobeControls<T>() : random_controls<T>(rng);
        ASSERT_EQ(hs::validate(c), "");
        const hs::ChiangMaterial<T> checked(p, c);
        const hs::ChiangMaterial<T> unchecked = hs::ChiangMaterial<T>::unchecked(p, c);
        expect_same_material(checked, unchecked, rng);
        if (testing::Test::HasFatalFailure()) return;
        // The per-hit route: bounds checked once, clamp, unchecked. A valid value inside the
        // bounds comes through clamp() unchanged, so the material is again the checked one.
        const hs::FiberParams<T> q = hs::FiberParamBounds<T>().clamp(p);
        ASSERT_TRUE(same_bits(q.eta, p.eta) && same_bits(q.beta_m, p.beta_m) && same_bits(q.beta_n, p.beta_n) &&
                    same_bits(q.alpha, p.alpha) && same_bits(q.sigma_a, p.sigma_a));
        expect_same_material(checked, hs::ChiangMaterial<T>::unchecked(q, c), rng);
        if (testing::Test::HasFatalFailure()) return;
    }
}

// Values a texture or a per-strand formula can produce by mistake.
template <typename T> std::vector<T> extreme_values() {
    const T inf = std::numeric_limits<T>::infinity();
    return {T(0), -T(0), T(1), T(-1), T(1e-3), T(0.999e-3), T(1) + hs::kEpsilon<T>, T(1.0000001),
            std::numeric_limits<T>::denorm_min(), -std::numeric_limits<T>::denorm_min(),
            std::numeric_limits<T>::max(), std::numeric_limits<T>::lowest(), inf, -inf,
            std::numeric_limits<T>::quiet_NaN(), -std::numeric_limits<T>::quiet_NaN(), T(0.4), T(-0.4), T(1e30),
            T(-1e30)};
}

template <typename T> void clamp_gives_valid_params(const hs::FiberParamBounds<T>& bounds) {
    const std::vector<T> x = extreme_values<T>();
    std::mt19937 rng(7u);
    std::uniform_int_distribution<std::size_t> pick(0, x.size() - 1);
    for (int i = 0; i < 4000; ++i) {
        hs::FiberParams<T> p;
        p.eta = x[pick(rng)];
        p.beta_m = x[pick(rng)];
        p.beta_n = x[pick(rng)];
        p.alpha = x[pick(rng)];
        p.sigma_a = glm::vec<3, T>(x[pick(rng)], x[pick(rng)], x[pick(rng)]);
        const hs::FiberParams<T> q = bounds.clamp(p);
        ASSERT_EQ(hs::validate(q), "") << "eta " << p.eta << " beta_m " << p.beta_m << " beta_n " << p.beta_n
                                       << " alpha " << p.alpha;
        // ...inside the bounds, field by field.
        ASSERT_TRUE(q.eta >= bounds.lo().eta && q.eta <= bounds.hi().eta);
        ASSERT_TRUE(q.beta_m >= bounds.lo().beta_m && q.beta_m <= bounds.hi().beta_m);
        ASSERT_TRUE(q.beta_n >= bounds.lo().beta_n && q.beta_n <= bounds.hi().beta_n);
        ASSERT_TRUE(q.alpha >= bounds.lo().alpha && q.alpha <= bounds.hi().alpha);
        for (int c = 0; c < 3; ++c)
            ASSERT_TRUE(q.sigma_a[c] >= bounds.lo().sigma_a[c] && q.sigma_a[c] <= bounds.hi().sigma_a[c]);
        // ...and the material built from it without a check is finite where it is evaluated.
        const auto m = hs::ChiangMaterial<T>::unchecked(q);
        const hs::ChiangFiber<T> f(m, T(0.3));
        const glm::vec<3, T> wo(T(0.3), T(0.2), T(0.9327379)), wi(T(-0.1), T(-0.7), T(0.7071068));
        ASSERT_TRUE(hs::is_finite(f.eval(wo, wi)));
        ASSERT_TRUE(hs::is_finite(f.pdf(wo, wi)));
    }
}

}  // namespace

TEST(PerHitMaterial, UncheckedMatchesCheckedBitForBitFloat) { unchecked_matches_checked<float>(); }
TEST(PerHitMaterial, UncheckedMatchesCheckedBitForBitDouble) { unchecked_matches_checked<double>(); }

TEST(PerHitMaterial, ClampOfTheWholeDomainGivesValidParams) {
    clamp_gives_valid_params(hs::FiberParamBounds<float>());
    clamp_gives_valid_params(hs::FiberParamBounds<double>());
}

TEST(PerHitMaterial, ClampOfCheckedBoundsStaysInside) {
    hs::FiberParams<float> lo, hi;
    lo.eta = 1.5f;
    hi.eta = 1.6f;
    lo.beta_m = 0.2f;
    hi.beta_m = 0.4f;
    lo.beta_n = 0.25f;
    hi.beta_n = 0.5f;
    lo.alpha = hi.alpha = hs::radians(2.0f);  // a fixed field: lo = hi
    lo.sigma_a = hs::sigma_a_from_concentrations(0.0f, 0.0f);
    hi.sigma_a = hs::sigma_a_from_concentrations(8.0f, 2.0f);
    const auto b = hs::FiberParamBounds<float>::checked(lo, hi);
    clamp_gives_valid_params(b);
    // Below, above and non-finite: the ends, NaN and ±Inf to the lower one.
    hs::FiberParams<float> p = lo;
    p.eta = 1.0f;
    p.beta_m = 2.0f;
    p.beta_n = std::numeric_limits<float>::quiet_NaN();
    p.sigma_a = glm::vec3(std::numeric_limits<float>::infinity(), -1.0f, 3.0f);
    const hs::FiberParams<float> q = b.clamp(p);
    EXPECT_EQ(q.eta, 1.5f);
    EXPECT_EQ(q.beta_m, 0.4f);
    EXPECT_EQ(q.beta_n, 0.25f);
    EXPECT_EQ(q.sigma_a.x, 0.0f);
    EXPECT_EQ(q.sigma_a.y, 0.0f);
    EXPECT_EQ(q.sigma_a.z, 3.0f);
}

TEST(PerHitMaterial, CheckedBoundsRejectBadBoxesNamingTheField) {
    hs::FiberParams<double> lo, hi;
    hi.beta_m = 0.2;  // below lo's 0.3
    std::string m = hs::validate(lo, hi);
    EXPECT_NE(m.find("beta_m: lo = 0.3"), std::string::npos) << m;
    EXPECT_THROW(hs::FiberParamBounds<double>::checked(lo, hi), std::invalid_argument);
    hi = lo;
    hi.eta = 1.0;  // an invalid end
    m = hs::validate(lo, hi);
    EXPECT_NE(m.find("hi: eta"), std::string::npos) << m;
    EXPECT_NE(m.find("eta: lo = 1.55"), std::string::npos) << m;
    EXPECT_THROW(hs::FiberParamBounds<double>::checked(lo, hi), std::invalid_argument);
    hi = lo;
    lo.sigma_a.y = std::numeric_limits<double>::quiet_NaN();
    m = hs::validate(lo, hi);
    EXPECT_NE(m.find("lo: sigma_a.g"), std::string::npos) << m;
    EXPECT_EQ(hs::validate(hi, hi), "");
    EXPECT_NO_THROW(hs::FiberParamBounds<double>::checked(hi, hi));
}

TEST(PerHitMaterial, DefaultBoundsAreTheValidDomain) {
    const hs::FiberParamBounds<double> b;
    EXPECT_EQ(hs::validate(b.lo(), b.hi()), "");
    EXPECT_EQ(hs::validate(b.lo()), "");
    EXPECT_EQ(hs::validate(b.hi()), "");
    // One step outside either end is invalid: the box is the whole domain, not less.
    hs::FiberParams<double> p = b.lo();
    p.eta = 1.0;
    EXPECT_NE(hs::validate(p), "");
    p = b.lo();
    p.beta_m = std::nextafter(1e-3, 0.0);
    EXPECT_NE(hs::validate(p), "");
    p = b.hi();
    p.alpha = std::nextafter(hs::kMaxCuticleTilt<double>, 1.0);
    EXPECT_NE(hs::validate(p), "");
}
