// hairscatter — Fresnel reflectance and the per-lobe attenuation A_p.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../math/constants.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"

namespace hairscatter {

// Unpolarised Fresnel reflectance of a dielectric interface from index 1 to η > 1, for
// the cosine of the incident angle. No total internal reflection on this side, and the
// denominators stay positive for η > 1 even at grazing incidence (cos_i = 0 gives F = 1).
template <typename T> HAIRSCATTER_HD T fresnel_dielectric(T cos_i, T eta) {
    cos_i = clamp(cos_i, T(0), T(1));
    const T sin2_t = (T(1) - cos_i * cos_i) / (eta * eta);
    const T cos_t = safe_sqrt(T(1) - sin2_t);
    const T r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const T r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return T(0.5) * (r_parl * r_parl + r_perp * r_perp);
}

// The attenuations of the lobes p = 0 … P (P the residual), Chiang et al. 2016 eqs. 3–4:
//   A_0 = F,  A_1 = (1 - F)² T,  A_p = A_{p-1} T F,  A_P = A_{P-1} T F / (1 - T F),
// with F at cos = cosθo cosγo and T the transmittance of one chord through the fiber.
template <typename T, int P> struct Attenuation {
    static_assert(P >= 1, "at least the R lobe and the residual");
    glm::vec<3, T> a[P + 1];
};

template <typename T, int P>
HAIRSCATTER_HD Attenuation<T, P> attenuation(T fresnel, const glm::vec<3, T>& transmittance) {
    using V = glm::vec<3, T>;
    Attenuation<T, P> r;
    const T f = fresnel;
    r.a[0] = V(f);
    if (P == 1) {
        // Everything but R is one residual: (1 - F)² T / (1 - T F), summed geometric series.
        const V tf = transmittance * f;
        const V denom = V(1) - tf;
        for (int c = 0; c < 3; ++c)
            r.a[1][c] = denom[c] > T(0) ? sqr(T(1) - f) * transmittance[c] / denom[c] : T(0);
        return r;
    }
    r.a[1] = sqr(T(1) - f) * transmittance;
    for (int p = 2; p < P; ++p) r.a[p] = r.a[p - 1] * transmittance * f;
    // 1 - T F = 0 only when F = 1 (grazing h) and T = 1, where A_{P-1} carries (1 - F)² = 0:
    // flooring the denominator at the smallest normal number (1 - T F is otherwise at least
    // one ulp of 1) gives 0 there without a branch per channel.
    const V tf = transmittance * f;
    r.a[P] = r.a[P - 1] * tf / glm::max(V(1) - tf, V(kMinNormal<T>));
    return r;
}

// The refracted path of a ray leaving toward wo from offset h (theory.md §3.1–3.2), split
// into the part that depends on θo alone (once per wo) and the part per h:
//   sinγt = h / η' = h cosθo / sqrt(η² - sin²θo)   (no division by cosθo: finite at ±90°)
//   T = exp(-σa · 2 cosγt / cosθt)                  (one chord through the fiber, in radii)
template <typename T> struct FiberRefraction {
    T gamma_t_scale = T(0);  // sinγt = h · gamma_t_scale
    T chord_scale = T(2);    // chord = chord_scale · cosγt

    FiberRefraction() = default;
    HAIRSCATTER_HD FiberRefraction(T sin_o, T cos_o, T eta) {
        using std::sqrt;
        gamma_t_scale = cos_o / sqrt(eta * eta - sin_o * sin_o);
        chord_scale = T(2) / cos_from_sin(sin_o / eta);
    }

    struct AtOffset {
        T gamma_t;
        glm::vec<3, T> transmittance;
    };
    HAIRSCATTER_HD AtOffset at(T h, const glm::vec<3, T>& sigma_a) const {
        const T sin_gamma_t = h * gamma_t_scale;
        const T chord = chord_scale * cos_from_sin(sin_gamma_t);
        return {elem::asin(sin_gamma_t), glm::vec<3, T>(elem::exp(-sigma_a.x * chord), elem::exp(-sigma_a.y * chord),
                                                         elem::exp(-sigma_a.z * chord))};
    }
};

}  // namespace hairscatter
