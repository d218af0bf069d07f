// hairscatter — the user's fiber parameters, their validation, and σa from pigments or colour.
#pragma once

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../math/constants.hpp"
#include "../math/functions.hpp"

namespace hairscatter {

template <typename T> struct FiberParams {
    T eta = T(1.55);            // index of refraction of the cortex (keratin ≈ 1.55), > 1
    T beta_m = T(0.3);          // longitudinal roughness, [kMinRoughness, 1]
    T beta_n = T(0.3);          // azimuthal roughness, [kMinRoughness, 1]
    T alpha = radians(T(2));    // cuticle-scale tilt in radians, |α| ≤ kMaxCuticleTilt
    glm::vec<3, T> sigma_a{T(0)};  // absorption per unit fiber radius, RGB, ≥ 0 and finite
};

// |α| above π/8 would rotate TRT's θo (by 4α) past the pole; real cuticles tilt 2°–10°.
template <typename T> inline constexpr T kMaxCuticleTilt = kPi<T> / T(8);

// The smallest accepted β_m and β_n (and Marschner's β_R and β_n). Every model stays finite
// in float down to β ≈ 1e-18 (below it the float variance underflows: NaN everywhere) and in
// double below 1e-40 (measured, docs/robustness.md); 1e-3 — a fiber far smoother than any
// hair, whose R lobe is 0.04° wide — leaves that a wide margin, and scripts/stress.sh finds
// no NaN, Inf, negative value or sample/pdf mismatch at it.
template <typename T> inline constexpr T kMinRoughness = T(1e-3);

namespace detail {
// x ∈ [lo, hi] and finite, decided without relying on NaN comparisons (fast-math safe).
template <typename T> bool in_range(T x, T lo, T hi) { return is_finite(x) && x >= lo && x <= hi; }

// The messages of a validate(), joined by "; ": "name = value is outside its range R" or a text.
class Complaints {
  public:
    void add(const std::string& name, double value, const char* range) {
        std::ostringstream m;
        m << name << " = " << value << " is outside its range " << range;
        add_text(m.str());
    }
    void add_text(const std::string& text) { msg_ << (msg_.tellp() > 0 ? "; " : "") << text; }
    std::string str() const { return msg_.str(); }

  private:
    std::ostringstream msg_;
};

// require_valid's body for every parameter struct: throws std::invalid_argument
// "hairscatter: invalid <what>: <message>" unless validate() gave an empty message.
inline void throw_if_invalid(const std::string& message, const char* what) {
    if (!message.empty())
        HAIRSCATTER_THROW(std::invalid_argument(std::string("hairscatter: invalid ") + what + ": " + message));
}
}  // namespace detail

// Checks every field; returns an empty string when the parameters are valid, else one
// message per bad field naming the field, its value and the allowed range. Never throws
// (the check for exception-free programs); finiteness is read from the bits, so it holds
// under -ffast-math too.
template <typename T> std::string validate(const FiberParams<T>& p) {
    using detail::in_range;
    const T inf = std::numeric_limits<T>::max();
    const bool eta_ok = in_range(p.eta, T(1), inf) && p.eta != T(1);
    bool ok = eta_ok && in_range(p.beta_m, kMinRoughness<T>, T(1)) && in_range(p.beta_n, kMinRoughness<T>, T(1)) &&
              in_range(p.alpha, -kMaxCuticleTilt<T>, kMaxCuticleTilt<T>);
    for (int c = 0; c < 3; ++c) ok = ok && in_range(p.sigma_a[c], T(0), inf);
    if (ok) return std::string();  // the common case builds no stream (materials may be made per strand)
    detail::Complaints bad;
    if (!eta_ok) bad.add("eta", double(p.eta), "(1, inf) (finite)");
    if (!in_range(p.beta_m, kMinRoughness<T>, T(1))) bad.add("beta_m", double(p.beta_m), "[1e-3, 1]");
    if (!in_range(p.beta_n, kMinRoughness<T>, T(1))) bad.add("beta_n", double(p.beta_n), "[1e-3, 1]");
    if (!in_range(p.alpha, -kMaxCuticleTilt<T>, kMaxCuticleTilt<T>))
        bad.add("alpha", double(p.alpha), "[-pi/8, pi/8] radians");
    const char* channel[3] = {"sigma_a.r", "sigma_a.g", "sigma_a.b"};
    for (int c = 0; c < 3; ++c)
        if (!in_range(p.sigma_a[c], T(0), inf)) bad.add(channel[c], double(p.sigma_a[c]), "[0, inf) (finite)");
    return bad.str();
}

// Throws std::invalid_argument with validate()'s message when the parameters are bad
// (without exceptions: prints it and aborts, config.hpp's HAIRSCATTER_THROW).
template <typename T> void require_valid(const FiberParams<T>& p) {
    detail::throw_if_invalid(validate(p), "fiber parameters");
}

// The parameters, after require_valid: for a material's member-initialiser list.
template <typename T> const FiberParams<T>& validated(const FiberParams<T>& p) {
    require_valid(p);
    return p;
}

// The parameters moved into their ranges, for parameters that vary per hit (textures,
// strand variation) where a renderer cannot stop for an exception: η into (1, 1e6] (its
// smallest value the float or double just above 1), β_m and β_n into [kMinRoughness, 1],
// α into [-kMaxCuticleTilt, kMaxCuticleTilt], each σa channel into [0, 1e30]; NaN goes to
// the lower end (under -ffast-math, where HAIRSCATTER_ALLOW_FAST_MATH permits it, to one
// of the two ends). Valid parameters come back unchanged, so a material built from them per
// hit (ChiangMaterial::per_hit) is the checked constructor's. Device-callable.
template <typename T> HAIRSCATTER_HD FiberParams<T> clamped_params(const FiberParams<T>& p) {
    const T eta_lo = T(1) + kEpsilon<T>;
    const auto into = [](T x, T lo, T hi) { return x > hi ? hi : (x >= lo ? x : lo); };
    FiberParams<T> q;
    q.eta = into(p.eta, eta_lo, T(1e6));
    q.beta_m = into(p.beta_m, kMinRoughness<T>, T(1));
    q.beta_n = into(p.beta_n, kMinRoughness<T>, T(1));
    q.alpha = into(p.alpha, -kMaxCuticleTilt<T>, kMaxCuticleTilt<T>);
    for (int c = 0; c < 3; ++c) q.sigma_a[c] = into(p.sigma_a[c], T(0), T(1e30));
    // Only a NaN can be left out of range (under -ffast-math, whose compares may let it
    // through): then the sum of the clamped values is not finite (read from the bits), and
    // the NaNs are replaced one by one. One test for all seven in the common case.
    if (!is_finite(q.eta + q.beta_m + q.beta_n + q.alpha + (q.sigma_a[0] + q.sigma_a[1] + q.sigma_a[2]))) {
        const auto or_lo = [](T x, T lo) { return is_finite(x) ? x : lo; };
        q.eta = or_lo(q.eta, eta_lo);
        q.beta_m = or_lo(q.beta_m, kMinRoughness<T>);
        q.beta_n = or_lo(q.beta_n, kMinRoughness<T>);
        q.alpha = or_lo(q.alpha, -kMaxCuticleTilt<T>);
        for (int c = 0; c < 3; ++c) q.sigma_a[c] = or_lo(q.sigma_a[c], T(0));
    }
    return q;
}

// Absorption from eumelanin and pheomelanin concentrations ce, cp ≥ 0 per unit fiber
// radius (pbrt-v4's SigmaAFromConcentration, Mitsuba 3's eumelanin and pheomelanin;
// Chiang et al. 2016 §4.3): σa = ce (0.419, 0.697, 1.37) + cp (0.187, 0.4, 1.05).
// Not a melanin amount in [0, 1]: that is sigma_a_from_melanin_amount (pigments.hpp).
template <typename T>
HAIRSCATTER_HD glm::vec<3, T> sigma_a_from_concentrations(T eumelanin, T pheomelanin) {
    return eumelanin * glm::vec<3, T>(T(0.419), T(0.697), T(1.37)) +
           pheomelanin * glm::vec<3, T>(T(0.187), T(0.4), T(1.05));
}

// The former name of sigma_a_from_concentrations, which hid that it takes concentrations.
template <typename T>
[[deprecated("hairscatter: sigma_a_from_melanin takes concentrations: call sigma_a_from_concentrations")]]
HAIRSCATTER_HD glm::vec<3, T> sigma_a_from_melanin(T eumelanin, T pheomelanin) {
    return sigma_a_from_concentrations(eumelanin, pheomelanin);
}

namespace detail {
// Chiang et al. 2016 eq. 9 for one channel, without checks: σa = (ln c / D(βn))², D the
// quintic in βn below (evaluated by Horner's rule). c ∈ (0, 1], βn ∈ [kMinRoughness, 1].
template <typename T> HAIRSCATTER_HD T absorption_from_reflectance(T c, T beta_n) {
    using std::log;
    const T denom = horner(beta_n, T(5.969), T(-0.215), T(2.532), T(-10.73), T(5.574), T(0.245));
    return sqr(log(c) / denom);
}
}  // namespace detail

// Absorption that gives roughly the diffuse-looking colour c for azimuthal roughness
// β_n (Chiang et al. 2016, eq. 9): σa = (ln c / (5.969 - 0.215βn + 2.532βn² - 10.73βn³
// + 5.574βn⁴ + 0.245βn⁵))². Colour channels must lie in (0, 1].
template <typename T> glm::vec<3, T> sigma_a_from_color(const glm::vec<3, T>& c, T beta_n) {
    for (int i = 0; i < 3; ++i)
        if (!(detail::in_range(c[i], T(0), T(1)) && c[i] > T(0)))
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: sigma_a_from_color: colour channel " +
                                        std::to_string(i) + " = " + std::to_string(double(c[i])) +
                                        " is outside (0, 1]"));
    if (!detail::in_range(beta_n, kMinRoughness<T>, T(1)))
        HAIRSCATTER_THROW(std::invalid_argument("hairscatter: sigma_a_from_color: beta_n = " +
                                    std::to_string(double(beta_n)) + " is outside [1e-3, 1]"));
    glm::vec<3, T> s;
    for (int i = 0; i < 3; ++i) s[i] = detail::absorption_from_reflectance(c[i], beta_n);
    return s;
}

}  // namespace hairscatter
