// hairscatter — the cuticle-scale tilt α, written once for every model that uses it.
#pragma once

#include <cmath>
#include <type_traits>

#include "../config.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"

namespace hairscatter {

// pbrt-v4's convention (docs/theory.md §3.3): lobe p is evaluated with the outgoing
// inclination rotated, θo' = θo - 2α (R), θo + α (TT), θo + 4α (TRT), θo (residual).
// Rotating the conditioning angle keeps ∫ M_p cosθi dθi = 1, so the tilt costs no
// energy. The sines and cosines of the rotations are computed once, here, and stored per
// lobe with the sign folded in, so that rotate() is the same branch-free formula for every
// lobe (the residual's rotation by 0 is exact).
template <typename T> class CuticleTilt {
  public:
    static constexpr int kLobes = 4;  // R, TT, TRT, residual (and every higher order)

    CuticleTilt() = default;
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE explicit CuticleTilt(T alpha) {
        using std::sin;
        // R rotates by -2α, TT by +α, TRT by +4α; the residual by 0. Each array is written
        // whole (elem::store4: one vector store in float): the fibers read sin_ and cos_ as
        // vectors, and a vector load of four scalar stores waits for them to retire (a
        // material built per hit, ChiangMaterial::per_hit, is read at once).
        elem::store4(angle_, T(-2) * alpha, alpha, T(4) * alpha, T(0));
        if (std::is_same<T, float>::value && abs_value(alpha) <= T(0.39269908169872415481)) {
            // Float, |α| ≤ π/8 (every validated tilt), so every angle x within [-π/2, π/2]:
            // sin x and cos x of the four angles side by side (a loop the compilers
            // vectorise), by their Taylor series to x¹³ and x¹⁴ (truncation below 7e-10 and
            // 7e-11 there, far below float's rounding; Estrin's scheme, a short chain). Not
            // sin α and then cos α by a square root and 2α, 4α by two doublings: that chain
            // is what the first θi terms of a material built per hit wait for.
            T sn[kLobes], cs[kLobes];
            HAIRSCATTER_NO_UNROLL  // (a vector loop at GCC -O3 too: config.hpp)
            for (int k = 0; k < kLobes; ++k) {
                const T x = angle_[k], z = x * x;
                sn[k] = x + x * z *
                                detail::estrin(z, T(-1.0 / 6), T(1.0 / 120), T(-1.0 / 5040), T(1.0 / 362880),
                                               T(-1.0 / 39916800), T(1.0 / 6227020800.0));
                cs[k] = T(1) + z * detail::estrin(z, T(-0.5), T(1.0 / 24), T(-1.0 / 720), T(1.0 / 40320),
                                                  T(-1.0 / 3628800), T(1.0 / 479001600), T(-1.0 / 87178291200.0));
            }
            elem::store4(sin_, sn[0], sn[1], sn[2], sn[3]);
            elem::store4(cos_, cs[0], cs[1], cs[2], cs[3]);
            return;
        }
        // Double, or beyond π/8: std::sin of α, cos α from it, and sin/cos of 2α and 4α by
        // the double-angle identities.
        T s[3], c[3];  // sin, cos of α, 2α, 4α
        s[0] = sin(alpha);
        c[0] = safe_sqrt(T(1) - s[0] * s[0]);
        for (int k = 1; k < 3; ++k) {
            s[k] = T(2) * c[k - 1] * s[k - 1];
            c[k] = sqr(c[k - 1]) - sqr(s[k - 1]);
        }
        elem::store4(sin_, -s[1], s[0], s[2], T(0));
        elem::store4(cos_, c[1], c[0], c[2], T(1));
    }

    // Explicit rotations of θo for R, TT and TRT (the residual is not rotated), for models
    // whose paper gives each lobe's shift on its own (Marschner et al. 2003: -α_p).
    HAIRSCATTER_HD CuticleTilt(T angle_r, T angle_tt, T angle_trt) {
        using std::cos;
        using std::sin;
        const T a[3] = {angle_r, angle_tt, angle_trt};
        for (int k = 0; k < 3; ++k) {
            angle_[k] = a[k];
            sin_[k] = sin(a[k]);
            cos_[k] = cos(a[k]);
        }
    }

    // The angle θo is rotated by for lobe p: -2α, α, 4α, 0 for pbrt-v4's tilt α. Lobe p's
    // peak sits at θi = -(θo + angle(p)).
    HAIRSCATTER_HD T angle(int p) const { return angle_[p < kLobes ? p : kLobes - 1]; }

    struct Rotated {
        T sin_theta, cos_theta;
    };

    // (sinθo', cosθo') for lobe p; cosθo' is folded to ≥ 0 (a rotation past the pole
    // is the same inclination seen from the other side).
    HAIRSCATTER_HD Rotated rotate(int p, T sin_o, T cos_o) const {
        const int k = p < kLobes ? p : kLobes - 1;
        const T s = sin_o * cos_[k] + cos_o * sin_[k];
        const T c = cos_o * cos_[k] - sin_o * sin_[k];
        return {s, c < T(0) ? -c : c};
    }

    // The rotation itself, (sin, cos) of angle(p): rotate's constants, for callers that
    // rotate many θo at once (models/chiang_batch.hpp).
    HAIRSCATTER_HD Rotated rotation(int p) const {
        const int k = p < kLobes ? p : kLobes - 1;
        return {sin_[k], cos_[k]};
    }

  private:
    T angle_[kLobes] = {T(0), T(0), T(0), T(0)};
    T sin_[kLobes] = {T(0), T(0), T(0), T(0)}, cos_[kLobes] = {T(1), T(1), T(1), T(1)};
};

}  // namespace hairscatter
