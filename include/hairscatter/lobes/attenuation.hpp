// hairscatter — Fresnel reflectance and the per-lobe attenuation A_p.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstring>
#include <type_traits>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../math/constants.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"

namespace hairscatter {

namespace detail {

// Reflectance of each polarisation at an interface into relative index n, given the
// cosines of the incident and refracted angles (Fresnel; Marschner et al. 2003 app. B):
// perpendicular (s) r = (cos_i - n cos_t)/(cos_i + n cos_t), parallel (p)
// r = (n cos_i - cos_t)/(n cos_i + cos_t).
template <typename T> HAIRSCATTER_HD T fresnel_perpendicular(T cos_i, T cos_t, T n) {
    return sqr((cos_i - n * cos_t) / (cos_i + n * cos_t));
}
template <typename T> HAIRSCATTER_HD T fresnel_parallel(T cos_i, T cos_t, T n) {
    return sqr((n * cos_i - cos_t) / (n * cos_i + cos_t));
}

// cosγt of the ray refracted into relative index n, or -1 on total internal reflection
// (n < 1 and sin²γi ≥ n²; compared without dividing, so n = 0 is TIR, not NaN).
template <typename T> HAIRSCATTER_HD T refracted_cos(T cos_i, T n) {
    const T sin2_i = (T(1) - cos_i) * (T(1) + cos_i);
    return sin2_i >= n * n ? T(-1) : safe_sqrt(T(1) - sin2_i / (n * n));
}

}  // namespace detail

// Unpolarised Fresnel reflectance of a dielectric interface from index 1 to η > 1, for
// the cosine of the incident angle. No total internal reflection on this side, and the
// denominators stay positive for η > 1 even at grazing incidence (cos_i = 0 gives F = 1).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T fresnel_dielectric(T cos_i, T eta) {
    cos_i = clamp(cos_i, T(0), T(1));
    const T inv_eta2 = T(1) / (eta * eta);  // depends on η alone: off the direction's chain
    const T cos_t = safe_sqrt(T(1) - (T(1) - cos_i * cos_i) * inv_eta2);
    // (Two divisions, not one of the product of the denominators: that product overflows
    // for an η near the top of the float range, which validation accepts.)
    return T(0.5) * (detail::fresnel_parallel(cos_i, cos_t, eta) + detail::fresnel_perpendicular(cos_i, cos_t, eta));
}

// Marschner et al. 2003's Fresnel factor F(η', η'', γ) (their appendix B): the
// perpendicular polarisation sees the Bravais index η', the parallel one η'' (docs/theory.md
// §3.1), each refracting by its own Snell law. Either index may be below 1 (the internal
// reflection F(1/η', 1/η'', γt), or η'' → 0 at grazing θ): total internal reflection
// reflects that polarisation fully.
template <typename T> HAIRSCATTER_HD T fresnel_bravais(T cos_i, T eta_perp, T eta_par) {
    cos_i = clamp(cos_i, T(0), T(1));
    const T ct_perp = detail::refracted_cos(cos_i, eta_perp), ct_par = detail::refracted_cos(cos_i, eta_par);
    const T f_perp = ct_perp < T(0) ? T(1) : detail::fresnel_perpendicular(cos_i, ct_perp, eta_perp);
    const T f_par = ct_par < T(0) ? T(1) : detail::fresnel_parallel(cos_i, ct_par, eta_par);
    // 0/0 only at cos_i = 0 with an index of exactly 1 (grazing, no interface): reflects.
    return T(0.5) * ((f_perp == f_perp ? f_perp : T(1)) + (f_par == f_par ? f_par : T(1)));
}

// The attenuations of the lobes p = 0 … P (P the residual), Chiang et al. 2016 eqs. 3–4:
//   A_0 = F,  A_1 = (1 - F)² T,  A_p = A_{p-1} T F,  A_P = A_{P-1} T F / (1 - T F),
// with F at cos = cosθo cosγo and T the transmittance of one chord through the fiber,
// per channel c of C, every step one loop over the channels (vectorised for C = 4).
// f_internal is the reflectance at the inner surface; Chiang et al. use the entry
// reflectance (equal for one index by reciprocity), Marschner et al. 2003 their
// F(1/η', 1/η'', γt), which differs when η' ≠ η''.
template <typename T, int P, int C>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void attenuation_channels(T fresnel, T fresnel_internal,
                                                                  const T (&transmittance)[std::size_t(C)],
                                                                  T (&a)[std::size_t(P + 1)][std::size_t(C)]) {
    static_assert(P >= 1, "at least the R lobe and the residual");
    const T f = fresnel, fi = fresnel_internal, entry = sqr(T(1) - f);
#if HAIRSCATTER_HAS_VECTOR_EXT && defined(__clang__)
    // Float channel lanes (C = 4) under Clang: each row one vector of the vector extensions,
    // stored whole; the same operations in the same order as the loops below. Clang left
    // those loops partly scalar (40 to 50 instructions more per bound Chiang query, counted
    // with callgrind); GCC vectorises them as they are and does a little worse (+8) with
    // this form, so it keeps the loops.
    if constexpr (std::is_same<T, float>::value && C == 4 && P >= 2) {
        using V = elem::detail::F32x4;
        using I = elem::detail::I32x4;
        V t;
        std::memcpy(&t, transmittance, sizeof t);
        V row = elem::detail::splat<V>(f);
        std::memcpy(a[0], &row, sizeof row);
        row = entry * t;
        std::memcpy(a[1], &row, sizeof row);
        for (int p = 2; p < P; ++p) {
            row = row * t * fi;
            std::memcpy(a[p], &row, sizeof row);
        }
        const V tf = t * fi, denom = elem::detail::splat<V>(1.0f) - tf, floor = elem::detail::splat<V>(kMinNormal<float>);
        row = row * tf / elem::detail::select_lanes<V, I>(denom > floor, denom, floor);
        std::memcpy(a[P], &row, sizeof row);
        return;
    }
#endif
    for (int c = 0; c < C; ++c) a[0][c] = f;
    if (P == 1) {
        // Everything but R is one residual: (1 - F)² T / (1 - T F), summed geometric series.
        for (int c = 0; c < C; ++c) {
            const T denom = T(1) - transmittance[c] * fi;
            a[1][c] = denom > T(0) ? entry * transmittance[c] / denom : T(0);
        }
        return;
    }
    for (int c = 0; c < C; ++c) a[1][c] = entry * transmittance[c];
    for (int p = 2; p < P; ++p)
        for (int c = 0; c < C; ++c) a[p][c] = a[p - 1][c] * transmittance[c] * fi;
    // 1 - T F = 0 only when F = 1 (grazing h) and T = 1, where A_{P-1} carries (1 - F)² = 0:
    // flooring the denominator at the smallest normal number (1 - T F is otherwise at least
    // one ulp of 1) gives 0 there without a branch per channel.
    for (int c = 0; c < C; ++c) {
        const T tf = transmittance[c] * fi, denom = T(1) - tf;
        a[P][c] = a[P - 1][c] * tf / (denom > kMinNormal<T> ? denom : kMinNormal<T>);
    }
}

// The same as colours: A_p as RGB vectors.
template <typename T, int P> struct Attenuation {
    static_assert(P >= 1, "at least the R lobe and the residual");
    glm::vec<3, T> a[std::size_t(P + 1)];
};

template <typename T, int P>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE Attenuation<T, P> attenuation(T fresnel, T fresnel_internal, const glm::vec<3, T>& transmittance) {
    const T t[3] = {transmittance.x, transmittance.y, transmittance.z};
    T a[std::size_t(P + 1)][3];
    attenuation_channels<T, P, 3>(fresnel, fresnel_internal, t, a);
    Attenuation<T, P> r;
    for (int p = 0; p <= P; ++p) r.a[p] = glm::vec<3, T>(a[p][0], a[p][1], a[p][2]);
    return r;
}

template <typename T, int P>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE Attenuation<T, P> attenuation(T fresnel, const glm::vec<3, T>& transmittance) {
    return attenuation<T, P>(fresnel, fresnel, transmittance);
}

// The refracted path of a ray leaving toward wo from offset h (docs/theory.md §3.1–3.2), split
// into the part that depends on θo alone (once per wo) and the part per h:
//   sinγt = h / η' = h cosθo / sqrt(η² - sin²θo)   (no division by cosθo: finite at ±90°)
//   T = exp(-σa · 2 cosγt / cosθt)                  (one chord through the fiber, in radii)
template <typename T> struct FiberRefraction {
    T gamma_t_scale = T(0);  // sinγt = h · gamma_t_scale
    T chord_scale = T(2);    // chord = chord_scale · cosγt

    FiberRefraction() = default;
    // One square root and one division serve both: with x = sinθo / η (1/η depends on η
    // alone, off the direction's chain), cosθt = √((1 - x)(1 + x)), chord_scale = 2 / cosθt
    // and gamma_t_scale = cosθo / (η cosθt). Nothing overflows for any η > 1 (η² would).
    HAIRSCATTER_HD FiberRefraction(T sin_o, T cos_o, T eta) {
        const T inv_eta = T(1) / eta;
        // (floored: for η within an ulp of 1 at θo = ±90°, x rounds to 1 and cosθt to 0)
        const T cos_t = cos_from_sin(sin_o * inv_eta);
        const T inv_cos_t = T(1) / (cos_t > kMinNormal<T> ? cos_t : kMinNormal<T>);
        gamma_t_scale = cos_o * inv_eta * inv_cos_t;
        chord_scale = T(2) * inv_cos_t;
    }

    struct AtOffset {
        T gamma_t;
        glm::vec<3, T> transmittance;
    };
    // sinγt at offset h and the chord length 2 cosγt / cosθt.
    struct Path {
        T sin_gamma_t, chord;
    };
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE Path path(T h) const {
        const T sin_gamma_t = h * gamma_t_scale;
        return {sin_gamma_t, chord_scale * cos_from_sin(sin_gamma_t)};
    }
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE AtOffset at(T h, const glm::vec<3, T>& sigma_a) const {
        const Path q = path(h);
        return {elem::asin(q.sin_gamma_t), glm::vec<3, T>(elem::exp(-sigma_a.x * q.chord), elem::exp(-sigma_a.y * q.chord),
                                                           elem::exp(-sigma_a.z * q.chord))};
    }

    // The same per channel lane (kChannelLanes) from σa per lane (the padding lane's σa is
    // 0, so its transmittance is 1): in float the three exps and the padding lane's are one
    // vectorised batch (elem::exp_each), about the cost of one scalar exp; in double three
    // of the standard library's.
    struct AtOffsetChannels {
        T gamma_t;
        T transmittance[kChannelLanes];
    };
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE AtOffsetChannels at_channels(T h, const T (&sigma_a)[kChannelLanes]) const {
        const Path q = path(h);
        AtOffsetChannels r;
        r.gamma_t = elem::asin(q.sin_gamma_t);
        for (int c = 0; c < kChannelLanes; ++c) r.transmittance[c] = -sigma_a[c] * q.chord;
        if constexpr (std::is_same<T, float>::value) {
            elem::exp_each_nonpositive(r.transmittance);  // (σa ≥ 0)
        } else {  // one libm exp per colour channel; the padding's e^0 is 1
            for (int c = 0; c < 3; ++c) r.transmittance[c] = elem::exp(r.transmittance[c]);
            for (int c = 3; c < kChannelLanes; ++c) r.transmittance[c] = T(1);
        }
        return r;
    }
};

}  // namespace hairscatter
