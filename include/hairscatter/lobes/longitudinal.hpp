// hairscatter — longitudinal scattering functions M_p.
#pragma once

#include <cmath>

#include "../config.hpp"
#include "../math/constants.hpp"
#include "../math/distributions.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"

namespace hairscatter {

// Longitudinal variance v of the R lobe from the user's roughness β_m ∈ (0, 1]
// (Chiang et al. 2016, eq. 7); TT uses v/4 and TRT and higher 4v (ibid.).
template <typename T> HAIRSCATTER_HD T longitudinal_variance(T beta_m) {
    const T b2 = beta_m * beta_m, b4 = b2 * b2, b8 = b4 * b4, b16 = b8 * b8;
    return sqr(T(0.726) * beta_m + T(0.812) * b2 + T(3.7) * b16 * b4);
}

// d'Eon et al. 2011's energy-conserving longitudinal lobe (eq. 7 of their paper),
//   M(v, θi, θo) = csch(1/v)/(2v) · exp(-sinθi sinθo / v) · I0(cosθi cosθo / v),
// with ∫ M cosθi dθi = 1. It is the θ-marginal of a von Mises–Fisher lobe of
// concentration 1/v around the mirror direction (-θo), which gives a form that is finite
// for every v without a log-space switch:
//   M = exp(-d²/2v) · e^(-a) I0(a) / (v (1 - e^(-2/v))),   a = cosθi cosθo / v,
//   d² = (cosθi - cosθo)² + (sinθi + sinθo)² = 2 - 2 cos(θi + θo),
// because a - b - 1/v = -d²/2v exactly. d² is a sum of squares, so it has no
// cancellation near the peak, and the exponent is never positive.
template <typename T> class DeonLongitudinal {
  public:
    DeonLongitudinal() = default;
    HAIRSCATTER_HD explicit DeonLongitudinal(T v) : v_(v), inv_v_(T(1) / v) {
        // (made per call where the variance depends on the light, as in dual scattering)
        exp_m2_over_v_ = elem::exp(T(-2) * inv_v_);  // underflows to 0 for v < 0.02 in float: harmless
        norm_ = inv_v_ / -elem::expm1(T(-2) * inv_v_);
    }

    HAIRSCATTER_HD T variance() const { return v_; }

    HAIRSCATTER_HD HAIRSCATTER_INLINE T eval(T sin_i, T cos_i, T sin_o, T cos_o) const {
        using elem::exp;
        using std::sqrt;
        const T d2 = sqr(cos_i - cos_o) + sqr(sin_i + sin_o);
        const T half_inv_v = T(0.5) * inv_v_;
        const T a = cos_i * cos_o * inv_v_;
        if (a <= T(detail::kI0SmallSplit))
            return norm_ * exp(-d2 * half_inv_v - a) * (T(1) + detail::i0_small_minus_one(a));
        const T inv_a = T(1) / a;  // e^(-a) I0(a) = Q(6/a) · sqrt(1/a)
        return norm_ * exp(-d2 * half_inv_v) * detail::i0_large_scaled_sqrt_t(T(detail::kI0SmallSplit) * inv_a) *
               sqrt(inv_a);
    }

    // Samples sinθi for the lobe conditioned on θo (d'Eon, Marschner & Hanika 2013): the
    // cosine of the angle to the mirror direction, c = 1 + v ln(u1 + (1 - u1) e^(-2/v)),
    // as 1 - c so that sharp lobes keep their precision, and an azimuth 2π u2 around it.
    // The log argument is floored at the smallest normal number instead of clamping u1,
    // so the distribution is exact wherever e^(-2/v) does not underflow.
    HAIRSCATTER_HD HAIRSCATTER_INLINE T sample_sin_theta(T sin_o, T cos_o, T u1, T u2) const {
        const T arg = u1 + (T(1) - u1) * exp_m2_over_v_;
        const T one_minus_c = clamp(-v_ * elem::log(arg > kMinNormal<T> ? arg : kMinNormal<T>), T(0), T(2));
        const T c = T(1) - one_minus_c;
        const T s = safe_sqrt(one_minus_c * (T(2) - one_minus_c));
        T sin_az, cos_az;
        elem::sincos(kTwoPi<T> * u2, sin_az, cos_az);
        return clamp(-c * sin_o + s * cos_az * cos_o, T(-1), T(1));
    }

  private:
    T v_ = T(1), inv_v_ = T(1), exp_m2_over_v_ = T(0), norm_ = T(1);
};

// Marschner et al. 2003's longitudinal lobe with d'Eon et al. 2011's correction of the
// half angle (docs/theory.md §3.3): M_p(θh) = g(β_p; 2θh - α_p) = g(β_p; θi + θo - α_p), a
// unit-area Gaussian in radians. Marschner's own shift convention: lobe p peaks at
// θi = α_p - θo (with α_R < 0 the R highlight sits at θi + θo = α_R). Unlike
// DeonLongitudinal it is not normalised on the sphere (it is a density in θi over the
// whole real line, and the model divides by cos²θd): the energy it loses or gains is
// Marschner's, reported by the furnace test, not corrected.
template <typename T> class MarschnerLongitudinal {
  public:
    MarschnerLongitudinal() = default;
    HAIRSCATTER_HD MarschnerLongitudinal(T beta, T alpha) : beta_(beta), alpha_(alpha) {}

    HAIRSCATTER_HD T beta() const { return beta_; }
    HAIRSCATTER_HD T alpha() const { return alpha_; }
    HAIRSCATTER_HD T eval(T theta_i, T theta_o) const { return gaussian(beta_, theta_i + theta_o - alpha_); }

  private:
    T beta_ = T(1), alpha_ = T(0);
};

}  // namespace hairscatter
