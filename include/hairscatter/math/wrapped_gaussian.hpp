// hairscatter — the wrapped Gaussian on the circle: pdf and sample (d'Eon et al. 2011's
// azimuthal detector D, used by models/deon_farfield.hpp).
#pragma once

#include <cmath>

#include "../config.hpp"
#include "constants.hpp"
#include "elementary.hpp"
#include "functions.hpp"

namespace hairscatter {

// D(x; σ) = Σ_k g(x + 2πk; σ), g the unit-area Gaussian of standard deviation σ, is a
// density on [-π, π]. It is evaluated in whichever of its two exact series converges
// faster (the theta-function duality), both truncated below double rounding:
//   σ ≤ kSplit: the image sum, keeping x and its nearest image x - 2π sign(x). For
//     x ∈ [-π, π] the largest omitted term relative to the kept ones is
//     e^(-2π²/σ²) ≤ 6e-16 at σ = 0.75 (smaller for narrower lobes).
//   σ > kSplit: the Fourier series (1/2π)(1 + 2 Σ_{n=1}^{N} e^(-n²σ²/2) cos nx), N = 12;
//     the first omitted term, 2e^(-169σ²/2) ≤ 5e-21, is below 1e-17 of D's minimum
//     (which is ≥ 1e-3/2π for σ ≥ 0.75). cos nx comes from the Chebyshev recurrence.
// Sampling is Box–Muller wrapped to [-π, π], which is the wrapped Gaussian exactly
// (no truncation), so sample and pdf agree whatever the series' truncation.
template <typename T> class WrappedGaussian {
  public:
    static constexpr T kSplit = T(0.75);
    static constexpr int kFourierTerms = 12;

    WrappedGaussian() = default;
    HAIRSCATTER_HD explicit WrappedGaussian(T sigma) : sigma_(sigma) {
        using std::exp;
        half_inv_var_ = T(0.5) / (sigma * sigma);
        norm_ = kInvSqrtTwoPi<T> / sigma;
        for (int n = 1; n <= kFourierTerms; ++n) rho_[n - 1] = exp(T(-0.5) * T(n * n) * sigma * sigma);
    }

    HAIRSCATTER_HD T sigma() const { return sigma_; }

    // Density at x ∈ [-π, π] (callers wrap first, as N_p does).
    HAIRSCATTER_HD T pdf(T x) const {
        if (sigma_ <= kSplit) {
            const T image = (x < T(0) ? -x : x) - kTwoPi<T>;  // the nearest image, |x| - 2π
            return norm_ * (elem::exp(-x * x * half_inv_var_) + elem::exp(-image * image * half_inv_var_));
        }
        T s, c1;
        elem::sincos(x, s, c1);
        T c_prev = T(1), c = c1, sum = T(0);
        for (int n = 0; n < kFourierTerms; ++n) {
            sum += rho_[n] * c;
            const T next = T(2) * c1 * c - c_prev;  // cos (n+1)x = 2 cos x cos nx - cos (n-1)x
            c_prev = c;
            c = next;
        }
        const T d = kInvTwoPi<T> * (T(1) + T(2) * sum);
        return d > T(0) ? d : T(0);  // ≥ 1e-3/2π analytically; the guard is for rounding only
    }

    // Box–Muller: radius from u_radius (full precision in the tails as u_radius → 0; its
    // log argument is floored at the smallest normal number), angle 2π u_angle; returns
    // σ r cos(2π u_angle) wrapped to [-π, π].
    HAIRSCATTER_HD T sample(T u_radius, T u_angle) const {
        using std::sqrt;
        const T r = sqrt(T(-2) * elem::log(u_radius > kMinNormal<T> ? u_radius : kMinNormal<T>));
        T s, c;
        elem::sincos(kTwoPi<T> * u_angle, s, c);
        return wrap_pi(sigma_ * r * c);
    }

  private:
    T sigma_ = T(1), half_inv_var_ = T(0.5), norm_ = kInvSqrtTwoPi<T>;
    T rho_[kFourierTerms] = {};
};

}  // namespace hairscatter
