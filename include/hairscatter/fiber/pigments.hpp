// hairscatter — hair colour as production hair shaders parameterise it: a melanin amount
// with its redness, and a dye colour, each mapped to the absorption σa of FiberParams
// (docs/controls.md). The mappings are pure math and device-callable; HairPigments is
// validated on the host like FiberParams (validate / require_valid).
#pragma once

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../math/functions.hpp"
#include "params.hpp"

namespace hairscatter {

// Eumelanin and pheomelanin concentrations (per unit fiber radius), what
// sigma_a_from_concentrations takes.
template <typename T> struct MelaninConcentrations {
    T eumelanin, pheomelanin;
};

// The floor of 1 - m in the melanin mapping below: m = 1 gives a finite concentration,
// -ln 1e-4 ≈ 9.21 (Cycles' principled hair uses the same floor).
template <typename T> inline constexpr T kMelaninRemainderFloor = T(1e-4);

// The perceptually even melanin amount m ∈ [0, 1] and redness r ∈ [0, 1] of Cycles'
// principled hair as concentrations: the total c = -ln(max(1 - m, 1e-4)) (m → 1 is black
// hair, c unbounded but floored), split by r as Bitterli's remapping does: eumelanin
// c (1 - r), pheomelanin c r. Inputs outside [0, 1] are the caller's to refuse
// (validate(HairPigments)); here m > 1 meets the floor and stays finite.
template <typename T> HAIRSCATTER_HD MelaninConcentrations<T> melanin_concentrations(T melanin, T redness) {
    using std::log;
    const T rest = T(1) - melanin;
    // 0 - ln(…) rather than -ln(…): m = 0 gives +0, not -0.
    const T c = T(0) - log(rest > kMelaninRemainderFloor<T> ? rest : kMelaninRemainderFloor<T>);
    return {c * (T(1) - redness), c * redness};
}

// σa of Cycles' melanin amount m ∈ [0, 1] and redness r ∈ [0, 1] (its Principled Hair
// "Melanin" and "Melanin Redness"): melanin_concentrations, then
// sigma_a_from_concentrations' coefficients (Chiang et al. 2016 §4.3, pbrt-v4's).
template <typename T> HAIRSCATTER_HD glm::vec<3, T> sigma_a_from_melanin_amount(T melanin, T redness) {
    const MelaninConcentrations<T> c = melanin_concentrations(melanin, redness);
    return sigma_a_from_concentrations(c.eumelanin, c.pheomelanin);
}

// The former name of sigma_a_from_melanin_amount.
template <typename T>
[[deprecated("hairscatter: sigma_a_from_melanin_redness takes an amount in [0, 1]: call sigma_a_from_melanin_amount")]]
HAIRSCATTER_HD glm::vec<3, T> sigma_a_from_melanin_redness(T melanin, T redness) {
    return sigma_a_from_melanin_amount(melanin, redness);
}

// σa of a dye colour d (each channel in (0, 1]; white adds nothing) for azimuthal
// roughness β_n ∈ [kMinRoughness, 1]: Chiang et al. 2016 eq. 9, the mapping of
// sigma_a_from_color, without its checks (device-callable; validate(HairPigments) checks d).
// Cycles adds this to the melanin's σa for its "Tint".
template <typename T> HAIRSCATTER_HD glm::vec<3, T> sigma_a_from_dye(const glm::vec<3, T>& dye, T beta_n) {
    return glm::vec<3, T>(detail::absorption_from_reflectance(dye.x, beta_n),
                          detail::absorption_from_reflectance(dye.y, beta_n),
                          detail::absorption_from_reflectance(dye.z, beta_n));
}

// Hair colour as melanin amount, redness and a dye.
template <typename T> struct HairPigments {
    T melanin = T(0.8);             // amount, [0, 1]: 0 white, ~0.5 blond to brown, 1 black
    T redness = T(0);               // pheomelanin fraction, [0, 1]: 0 eumelanin only, 1 red
    glm::vec<3, T> dye{T(1)};       // dye colour, each channel in (0, 1]; white adds no absorption
};

// Empty when the pigments are valid, else one message per bad field naming it, its value
// and the allowed range. Never throws.
template <typename T> std::string validate(const HairPigments<T>& p) {
    using detail::in_range;
    auto dye_ok = [&](int c) { return in_range(p.dye[c], T(0), T(1)) && p.dye[c] > T(0); };
    const bool ok = in_range(p.melanin, T(0), T(1)) && in_range(p.redness, T(0), T(1)) && dye_ok(0) && dye_ok(1) &&
                    dye_ok(2);
    if (ok) return std::string();
    detail::Complaints bad;
    if (!in_range(p.melanin, T(0), T(1))) bad.add("melanin", double(p.melanin), "[0, 1]");
    if (!in_range(p.redness, T(0), T(1))) bad.add("redness", double(p.redness), "[0, 1]");
    const char* channel[3] = {"dye.r", "dye.g", "dye.b"};
    for (int c = 0; c < 3; ++c)
        if (!dye_ok(c)) bad.add(channel[c], double(p.dye[c]), "(0, 1]");
    return bad.str();
}

// Throws std::invalid_argument with validate()'s message when the pigments are bad
// (without exceptions: prints it and aborts).
template <typename T> void require_valid(const HairPigments<T>& p) { detail::throw_if_invalid(validate(p), "hair pigments"); }

// σa of valid pigments at azimuthal roughness β_n: the melanin's and the dye's, added
// (the dye's depends on β_n through eq. 9).
template <typename T> HAIRSCATTER_HD glm::vec<3, T> sigma_a_from_pigments(const HairPigments<T>& p, T beta_n) {
    return sigma_a_from_melanin_amount(p.melanin, p.redness) + sigma_a_from_dye(p.dye, beta_n);
}

}  // namespace hairscatter
