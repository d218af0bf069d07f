// hairscatter — the user's fiber parameters, their validation, and σa from pigments or colour.
#pragma once

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../math/constants.hpp"

namespace hairscatter {

template <typename T> struct FiberParams {
    T eta = T(1.55);            // index of refraction of the cortex (keratin ≈ 1.55), > 1
    T beta_m = T(0.3);          // longitudinal roughness, (0, 1]
    T beta_n = T(0.3);          // azimuthal roughness, (0, 1]
    T alpha = radians(T(2));    // cuticle-scale tilt in radians, |α| ≤ kMaxCuticleTilt
    glm::vec<3, T> sigma_a{T(0)};  // absorption per unit fiber radius, RGB, ≥ 0 and finite
};

// |α| above π/8 would rotate TRT's θo (by 4α) past the pole; real cuticles tilt 2°–10°.
template <typename T> inline constexpr T kMaxCuticleTilt = kPi<T> / T(8);

// Checks every field; returns an empty string when the parameters are valid, else one
// message per bad field naming the field, its value and the allowed range.
template <typename T> std::string validate(const FiberParams<T>& p) {
    bool ok = p.eta > T(1) && std::isfinite(p.eta) && p.beta_m > T(0) && p.beta_m <= T(1) && p.beta_n > T(0) &&
              p.beta_n <= T(1) && std::abs(p.alpha) <= kMaxCuticleTilt<T>;
    for (int c = 0; c < 3; ++c) ok = ok && p.sigma_a[c] >= T(0) && std::isfinite(p.sigma_a[c]);
    if (ok) return std::string();  // the common case builds no stream (materials may be made per strand)
    std::ostringstream msg;
    auto bad = [&](const char* name, double value, const char* range) {
        if (msg.tellp() > 0) msg << "; ";
        msg << name << " = " << value << " is outside its range " << range;
    };
    if (!(p.eta > T(1)) || !std::isfinite(p.eta)) bad("eta", double(p.eta), "(1, inf) (finite)");
    if (!(p.beta_m > T(0) && p.beta_m <= T(1))) bad("beta_m", double(p.beta_m), "(0, 1]");
    if (!(p.beta_n > T(0) && p.beta_n <= T(1))) bad("beta_n", double(p.beta_n), "(0, 1]");
    if (!(std::abs(p.alpha) <= kMaxCuticleTilt<T>))
        bad("alpha", double(p.alpha), "[-pi/8, pi/8] radians");
    const char* channel[3] = {"sigma_a.r", "sigma_a.g", "sigma_a.b"};
    for (int c = 0; c < 3; ++c)
        if (!(p.sigma_a[c] >= T(0)) || !std::isfinite(p.sigma_a[c]))
            bad(channel[c], double(p.sigma_a[c]), "[0, inf) (finite)");
    return msg.str();
}

// Throws std::invalid_argument with validate()'s message when the parameters are bad.
template <typename T> void require_valid(const FiberParams<T>& p) {
    const std::string m = validate(p);
    if (!m.empty()) throw std::invalid_argument("hairscatter: invalid fiber parameters: " + m);
}

// The parameters, after require_valid: for a material's member-initialiser list.
template <typename T> const FiberParams<T>& validated(const FiberParams<T>& p) {
    require_valid(p);
    return p;
}

// Absorption from eumelanin and pheomelanin concentrations (Chiang et al. 2016 §4.3,
// the coefficients pbrt uses): σa = ce (0.419, 0.697, 1.37) + cp (0.187, 0.4, 1.05).
template <typename T>
HAIRSCATTER_HD glm::vec<3, T> sigma_a_from_melanin(T eumelanin, T pheomelanin) {
    return eumelanin * glm::vec<3, T>(T(0.419), T(0.697), T(1.37)) +
           pheomelanin * glm::vec<3, T>(T(0.187), T(0.4), T(1.05));
}

// Absorption that gives roughly the diffuse-looking colour c for azimuthal roughness
// β_n (Chiang et al. 2016, eq. 9): σa = (ln c / (5.969 - 0.215βn + 2.532βn² - 10.73βn³
// + 5.574βn⁴ + 0.245βn⁵))². Colour channels must lie in (0, 1].
template <typename T> glm::vec<3, T> sigma_a_from_color(const glm::vec<3, T>& c, T beta_n) {
    for (int i = 0; i < 3; ++i)
        if (!(c[i] > T(0) && c[i] <= T(1)))
            throw std::invalid_argument("hairscatter: sigma_a_from_color: colour channel " +
                                        std::to_string(i) + " = " + std::to_string(double(c[i])) +
                                        " is outside (0, 1]");
    if (!(beta_n > T(0) && beta_n <= T(1)))
        throw std::invalid_argument("hairscatter: sigma_a_from_color: beta_n = " +
                                    std::to_string(double(beta_n)) + " is outside (0, 1]");
    const T b = beta_n;
    const T denom = T(5.969) - T(0.215) * b + T(2.532) * b * b - T(10.73) * b * b * b +
                    T(5.574) * b * b * b * b + T(0.245) * b * b * b * b * b;
    glm::vec<3, T> s;
    for (int i = 0; i < 3; ++i) s[i] = std::pow(std::log(c[i]) / denom, T(2));
    return s;
}

}  // namespace hairscatter
