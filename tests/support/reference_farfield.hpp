// An independent double-precision reference of d'Eon et al. 2011's far-field fiber, for
// tests and the speed/accuracy study (bench/tradeoff.cpp): Boost's adaptive Gauss–Kronrod
// over h of the reference transcription's A_p and Φ (reference_chiang.hpp), with a
// brute-force wrapped Gaussian. Slow (one f costs ~10⁵ model evaluations) and exact to
// ~1e-10.
#pragma once

#include <cmath>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <glm/glm.hpp>

#include "reference_chiang.hpp"

namespace ref {

// The wrapped Gaussian by brute force: every image within 12σ + 2π of x (no truncation
// that matters in double), independent of the library's two-series evaluation.
inline double wrapped_gaussian_ref(double x, double sigma) {
    const int kmax = int(std::ceil((12 * sigma + std::abs(x)) / (2 * kPi))) + 2;
    double s = 0;
    for (int k = -kmax; k <= kmax; ++k) {
        const double y = x + 2 * kPi * k;
        s += std::exp(-0.5 * y * y / (sigma * sigma));
    }
    return s / (sigma * std::sqrt(2 * kPi));
}

// The far-field f assembled independently: M_p from the reference transcription
// (tests/support/reference_chiang.hpp), and N_p(φ) = ½ ∫ A_p(h) D(φ - Φ(p, h)) dh with A_p
// and Φ from the reference model at each h, D by brute force with σ = π s/√3, integrated
// over h (not γ) by adaptive Gauss–Kronrod to 1e-11.
struct FarFieldReference {
    ref::Params p;

    double sigma() const { return kPi / std::sqrt(3.0) * ref::Model{p, 0.0}.s(); }

    // ½ ∫ A_p(h)[c] (D(φ - Φ(p, h)) or 1/2π for the residual) dh.
    double np(int l, int c, double theta_o, double phi) const {
        using GK = boost::math::quadrature::gauss_kronrod<double, 31>;
        const double s = sigma();
        auto g = [&](double h) {
            const ref::Model m{p, h};
            const double a = m.Ap(theta_o)[std::size_t(l)][c];
            return l < 3 ? a * wrapped_gaussian_ref(phi - m.Phi(l, theta_o), s) : a / (2 * kPi);
        };
        return 0.5 * GK::integrate(g, -1.0, 1.0, 18, 1e-11);
    }

    glm::dvec3 f(const glm::dvec3& wo, const glm::dvec3& wi) const {
        const ref::Model m{p, 0.0};
        const double theta_o = std::asin(wo.x), theta_i = std::asin(wi.x);
        const double phi = std::atan2(wi.z, wi.y) - std::atan2(wo.z, wo.y);
        glm::dvec3 r(0.0);
        for (int l = 0; l < 4; ++l) {
            const double to = m.theta_o_tilted(l, theta_o);
            const double mp = ref::mp(m.v(l), std::sin(theta_i), std::cos(theta_i), std::sin(to), std::abs(std::cos(to)));
            for (int c = 0; c < 3; ++c) r[c] += mp * np(l, c, theta_o, phi);
        }
        return r;
    }
};

}  // namespace ref
