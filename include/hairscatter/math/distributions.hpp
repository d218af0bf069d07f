// hairscatter — 1D sampling distributions, each as a family: pdf, cdf, sample, invert.
#pragma once

#include <cmath>

#include "../config.hpp"
#include "constants.hpp"
#include "elementary.hpp"
#include "functions.hpp"

namespace hairscatter {

// The unit-area Gaussian of standard deviation σ on the real line, g(σ; x) in Marschner
// et al. 2003's notation (their longitudinal M_p and caustic lobes).
template <typename T> HAIRSCATTER_HD T gaussian(T sigma, T x) {
    return kInvSqrtTwoPi<T> / sigma * elem::exp(T(-0.5) * sqr(x / sigma));
}

// Logistic distribution with scale s, restricted and renormalised to [-π, π]
// (Chiang et al. 2016 §4.2, the azimuthal detector of their N_p). Everything that depends
// only on s is computed once here; with the interval symmetric the normaliser is
// F(π) - F(-π) = tanh(π / 2s), and the inverse CDF has the closed form
// x = 2s atanh(tanh(π / 2s)(2u - 1)).
template <typename T> class TrimmedLogistic {
  public:
    TrimmedLogistic() = default;
    HAIRSCATTER_HD explicit TrimmedLogistic(T s) : s_(s), inv_s_(T(1) / s) {
        using std::tanh;
        norm_ = tanh(kHalfPi<T> * inv_s_);
        pdf_scale_ = inv_s_ / norm_;
    }

    HAIRSCATTER_HD T scale() const { return s_; }

    // Density on [-π, π]; x outside is a caller error (N_p wraps first).
    HAIRSCATTER_HD T pdf(T x) const {
        using elem::exp;
        // e^(-|x|/s) / (s (1 + e^(-|x|/s))²): the |x| form never overflows.
        const T e = exp(-(x < T(0) ? -x : x) * inv_s_);
        return pdf_scale_ * e / sqr(T(1) + e);
    }

    HAIRSCATTER_HD T cdf(T x) const {
        using std::tanh;
        return T(0.5) * (T(1) + tanh(T(0.5) * x * inv_s_) / norm_);
    }

    // u ∈ [0, 1] → x ∈ [-π, π]; never NaN: the atanh argument is kept inside (-1, 1).
    HAIRSCATTER_HD T sample(T u) const {
        constexpr T lim = T(1) - kEpsilon<T>;
        const T z = clamp(norm_ * (T(2) * u - T(1)), -lim, lim);
        // 2 atanh(z) = log((1 + z)/(1 - z)); the quotient lies in [ε/2, 2/ε], so the log's
        // argument is normal, and x needs absolute (not relative) accuracy near 0.
        const T x = s_ * elem::log((T(1) + z) / (T(1) - z));
        return clamp(x, -kPi<T>, kPi<T>);
    }

    HAIRSCATTER_HD T invert(T x) const { return cdf(x); }

    // Probability of the arc [a, a + len] (0 ≤ len ≤ 2π) when the density is read on the
    // circle (as N_p is, after wrapping φ - Φ): the arc is split where it crosses ±π.
    HAIRSCATTER_HD T arc_mass(T a, T len) const {
        a = wrap_pi(a);
        const T b = a + len;
        if (b <= kPi<T>) return cdf(b) - cdf(a);
        return (T(1) - cdf(a)) + cdf(b - kTwoPi<T>);
    }

  private:
    T s_ = T(1), inv_s_ = T(1), norm_ = T(1), pdf_scale_ = T(1);
};

}  // namespace hairscatter
