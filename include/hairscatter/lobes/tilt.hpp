// hairscatter — the cuticle-scale tilt α, written once for every model that uses it.
#pragma once

#include <cmath>

#include "../config.hpp"
#include "../math/functions.hpp"

namespace hairscatter {

// pbrt-v4's convention (theory.md §3.3): lobe p is evaluated with the outgoing
// inclination rotated, θo' = θo - 2α (R), θo + α (TT), θo + 4α (TRT), θo (residual).
// Rotating the conditioning angle keeps ∫ M_p cosθi dθi = 1, so the tilt costs no
// energy. sin/cos of 2α and 4α come from double-angle identities once, here.
template <typename T> class CuticleTilt {
  public:
    CuticleTilt() = default;
    HAIRSCATTER_HD explicit CuticleTilt(T alpha) {
        using std::sin;
        sin_[0] = sin(alpha);
        cos_[0] = safe_sqrt(T(1) - sin_[0] * sin_[0]);
        for (int k = 1; k < 3; ++k) {
            sin_[k] = T(2) * cos_[k - 1] * sin_[k - 1];
            cos_[k] = sqr(cos_[k - 1]) - sqr(sin_[k - 1]);
        }
    }

    struct Rotated {
        T sin_theta, cos_theta;
    };

    // (sinθo', cosθo') for lobe p; cosθo' is folded to ≥ 0 (a rotation past the pole
    // is the same inclination seen from the other side).
    HAIRSCATTER_HD Rotated rotate(int p, T sin_o, T cos_o) const {
        // R rotates by -2α = -(2^1 α); TT by +α (2^0 α); TRT by +4α (2^2 α).
        if (p > 2) return {sin_o, cos_o};
        const int k = p == 0 ? 1 : (p == 1 ? 0 : 2);
        const T sgn = p == 0 ? T(-1) : T(1);
        const T s = sin_o * cos_[k] + sgn * cos_o * sin_[k];
        const T c = cos_o * cos_[k] - sgn * sin_o * sin_[k];
        return {s, c < T(0) ? -c : c};
    }

  private:
    T sin_[3] = {T(0), T(0), T(0)}, cos_[3] = {T(1), T(1), T(1)};
};

}  // namespace hairscatter
