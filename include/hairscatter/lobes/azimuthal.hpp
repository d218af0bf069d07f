// hairscatter — azimuthal scattering: the exit azimuth Φ(p, h) and Chiang's N_p.
#pragma once

#include <cmath>

#include "../config.hpp"
#include "../math/constants.hpp"
#include "../math/distributions.hpp"
#include "../math/functions.hpp"

namespace hairscatter {

// Logistic scale s of the azimuthal lobes from the user's roughness β_n ∈ (0, 1]
// (Chiang et al. 2016, eq. 8).
template <typename T> HAIRSCATTER_HD T logistic_scale(T beta_n) {
    const T b2 = beta_n * beta_n, b4 = b2 * b2, b8 = b4 * b4, b16 = b8 * b8;
    return kSqrtPiOver8<T> * (T(0.265) * beta_n + T(1.194) * b2 + T(5.372) * b16 * b4 * b2);
}

// Standard deviation σ of the azimuthal Gaussian from β_n: the variance of Chiang et al.
// 2016's logistic of scale s(β_n) (eq. 8), π²s²/3, so σ = π s / √3. d'Eon et al. 2011 use
// β_n itself as the Gaussian's width; matching Chiang's variance instead makes the same
// FiberParams give the same azimuthal spread in both models (β_n is tuned, and perceptually
// linearised, for Chiang's mapping), so switching model does not change a groom's look.
template <typename T> HAIRSCATTER_HD T azimuthal_gaussian_width(T beta_n) {
    return T(1.81379936423421785059) * logistic_scale(beta_n);  // π/√3
}

// Exit azimuth of the path that reflects p - 1 times inside the fiber, relative to the
// incoming one: Φ(p, h) = 2p γt - 2γo + pπ (Marschner et al. 2003, eq. 3 with d'Eon's
// sign convention as in pbrt).
template <typename T> HAIRSCATTER_HD T exit_azimuth(int p, T gamma_o, T gamma_t) {
    return T(2 * p) * gamma_t - T(2) * gamma_o + T(p) * kPi<T>;
}

// Φ(p, h) wrapped to [-π, π], without floor: with pπ taken modulo 2π first, the angle lies
// within [-3π, 3π] (|γo|, |γt| ≤ π/2, p ≤ 2), one turn from the range at most.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T exit_azimuth_wrapped(int p, T gamma_o, T gamma_t) {
    return wrap_pi_once(T(2 * p) * gamma_t - T(2) * gamma_o + T(p & 1) * kPi<T>);
}

// Chiang et al. 2016 eq. 6: N_p(φ) is the trimmed logistic of φ - Φ(p, h), wrapped.
template <typename T>
HAIRSCATTER_HD T azimuthal_logistic(const TrimmedLogistic<T>& d, T phi, T phi_p) {
    return d.pdf(wrap_pi(phi - phi_p));
}

// The mass of the wrapped Gaussian of width σ centred on μ that falls in the backward half
// |φ| < π/2: Σ_k ½[erf((π/2 - μ + 2πk)/σ√2) - erf((-π/2 - μ + 2πk)/σ√2)], k = -3 … 3 (the
// images beyond lie ≥ 5π from the half, over 8σ for every σ that β_n ≤ 1 maps to).
template <typename T> HAIRSCATTER_HD T wrapped_gaussian_backward_mass(T sigma, T mu) {
    using std::erf;
    const T scale = T(0.70710678118654752440) / sigma;
    const T c = wrap_pi(mu);
    T mass = T(0);
    for (int k = -3; k <= 3; ++k) {
        const T shift = T(k) * kTwoPi<T> - c;
        mass += erf((kHalfPi<T> + shift) * scale) - erf((-kHalfPi<T> + shift) * scale);
    }
    return T(0.5) * mass;
}

}  // namespace hairscatter
