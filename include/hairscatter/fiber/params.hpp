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

// The largest finite value: the upper end of η's and σa's ranges (device-callable, unlike
// std::numeric_limits<T>::max() without nvcc's --expt-relaxed-constexpr).
template <typename T> inline constexpr T kMaxFinite = T(0);
template <> inline constexpr float kMaxFinite<float> = 3.40282346638528859811704183484516925e+38f;
template <> inline constexpr double kMaxFinite<double> = 1.79769313486231570814527423731704357e+308;

namespace detail {
// x ∈ [lo, hi] and finite, decided without relying on NaN comparisons (fast-math safe).
template <typename T> HAIRSCATTER_HD bool in_range(T x, T lo, T hi) { return is_finite(x) && x >= lo && x <= hi; }

// Every field of p inside its range (validate()'s test, without the message; device-callable).
template <typename T> HAIRSCATTER_HD bool params_in_range(const FiberParams<T>& p) {
    bool ok = in_range(p.eta, T(1), kMaxFinite<T>) && p.eta != T(1) && in_range(p.beta_m, kMinRoughness<T>, T(1)) &&
              in_range(p.beta_n, kMinRoughness<T>, T(1)) && in_range(p.alpha, -kMaxCuticleTilt<T>, kMaxCuticleTilt<T>);
    for (int c = 0; c < 3; ++c) ok = ok && in_range(p.sigma_a[c], T(0), kMaxFinite<T>);
    return ok;
}

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
    const T inf = kMaxFinite<T>;
    if (detail::params_in_range(p)) return std::string();  // the common case builds no stream (materials may be made per strand)
    const bool eta_ok = in_range(p.eta, T(1), inf) && p.eta != T(1);
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

// The ranges a renderer's per-hit parameters come from (textured melanin or roughness,
// per-strand variation), checked once on the host, and clamp(), which puts any per-hit
// value into them on the host or the device. Every FiberParams that clamp() returns passes
// validate(), so a material may be built from it without a check
// (ChiangMaterial<T>::unchecked, models/chiang.hpp).
//   FiberParamBounds<T>()              every valid value (η in (1, max], β in [1e-3, 1],
//                                      |α| ≤ π/8, σa in [0, max]): clamp() only repairs
//   FiberParamBounds<T>::checked(lo, hi)  per field [lo, hi]; both valid parameter sets and
//                                      lo ≤ hi field by field, else std::invalid_argument
//                                      naming the field (validate(lo, hi): the message only)
// clamp() maps a value below a range to its lower end, above to its upper end, and a
// non-finite one (NaN, ±Inf, read from the bits: -ffast-math safe) to its lower end.
// Trivially copyable: pass it to a kernel by value.
template <typename T> class FiberParamBounds {
  public:
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE FiberParamBounds() {
        lo_.eta = T(1) + kEpsilon<T>;  // the smallest η above 1
        hi_.eta = kMaxFinite<T>;
        lo_.beta_m = lo_.beta_n = kMinRoughness<T>;
        hi_.beta_m = hi_.beta_n = T(1);
        lo_.alpha = -kMaxCuticleTilt<T>;
        hi_.alpha = kMaxCuticleTilt<T>;
        lo_.sigma_a = glm::vec<3, T>(T(0));
        hi_.sigma_a = glm::vec<3, T>(kMaxFinite<T>);
    }
    static FiberParamBounds checked(const FiberParams<T>& lo, const FiberParams<T>& hi);

    HAIRSCATTER_HD const FiberParams<T>& lo() const { return lo_; }
    HAIRSCATTER_HD const FiberParams<T>& hi() const { return hi_; }

    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE FiberParams<T> clamp(const FiberParams<T>& p) const {
        FiberParams<T> r;
        r.eta = clamp_field(p.eta, lo_.eta, hi_.eta);
        r.beta_m = clamp_field(p.beta_m, lo_.beta_m, hi_.beta_m);
        r.beta_n = clamp_field(p.beta_n, lo_.beta_n, hi_.beta_n);
        r.alpha = clamp_field(p.alpha, lo_.alpha, hi_.alpha);
        for (int c = 0; c < 3; ++c) r.sigma_a[c] = clamp_field(p.sigma_a[c], lo_.sigma_a[c], hi_.sigma_a[c]);
        return r;
    }

  private:
    static HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T clamp_field(T x, T lo, T hi) {
        if (!is_finite(x)) return lo;
        return x < lo ? lo : (x > hi ? hi : x);
    }
    FiberParams<T> lo_, hi_;
};

// Empty when [lo, hi] is a valid bounds box (both valid, lo ≤ hi per field), else the
// messages: validate()'s of lo and hi, prefixed "lo: " / "hi: ", and each field whose lo
// exceeds its hi. Never throws.
template <typename T> std::string validate(const FiberParams<T>& lo, const FiberParams<T>& hi) {
    detail::Complaints bad;
    const std::string lo_msg = validate(lo), hi_msg = validate(hi);
    if (!lo_msg.empty()) bad.add_text("lo: " + lo_msg);
    if (!hi_msg.empty()) bad.add_text("hi: " + hi_msg);
    const auto order = [&](const char* name, T l, T h) {
        if (!(l <= h)) bad.add_text(std::string(name) + ": lo = " + std::to_string(double(l)) + " exceeds hi = " +
                                    std::to_string(double(h)));
    };
    order("eta", lo.eta, hi.eta);
    order("beta_m", lo.beta_m, hi.beta_m);
    order("beta_n", lo.beta_n, hi.beta_n);
    order("alpha", lo.alpha, hi.alpha);
    const char* channel[3] = {"sigma_a.r", "sigma_a.g", "sigma_a.b"};
    for (int c = 0; c < 3; ++c) order(channel[c], lo.sigma_a[c], hi.sigma_a[c]);
    return bad.str();
}

template <typename T>
FiberParamBounds<T> FiberParamBounds<T>::checked(const FiberParams<T>& lo, const FiberParams<T>& hi) {
    detail::throw_if_invalid(validate(lo, hi), "fiber parameter bounds");
    FiberParamBounds b;
    b.lo_ = lo;
    b.hi_ = hi;
    return b;
}

// The parameters moved into every valid range (FiberParamBounds<T>()'s clamp), for
// parameters that vary per hit where a renderer cannot stop for an exception
// (ChiangMaterial::per_hit). Valid parameters come back unchanged. Device-callable.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE FiberParams<T> clamped_params(const FiberParams<T>& p) {
    return FiberParamBounds<T>().clamp(p);
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
