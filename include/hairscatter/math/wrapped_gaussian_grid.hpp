// hairscatter — a sum of wrapped Gaussians evaluated on an equispaced grid over [0, π], the
// host-side kernel of the tabulated model's table build (models/tabulated/material.hpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "constants.hpp"
#include "functions.hpp"
#include "wrapped_gaussian.hpp"

namespace hairscatter {

namespace detail {

// Σ_k w_k D(φ_i - μ_k) for RGB weights w_k on the grid φ_i = iΔ, Δ = π/(n - 1), where D is
// the wrapped Gaussian of math/wrapped_gaussian.hpp (host side, double; the table build).
// WrappedGaussian::pdf per node and grid point costs two exponentials each; here:
//   σ ≤ 0.75: each image μ + 2πk within 10σ of [0, π] (the rest is below e^-50 of the
//     peak) is walked outward from its nearest grid point by the exact recurrence
//     g(x + Δ) = g(x) r, r(x + Δ) = r(x) e^(-Δ²/σ²), r(x) = e^(-(2xΔ + Δ²)/2σ²):
//     four exponentials per image and 32 grid points instead of one per point;
//   σ > 0.75: D's Fourier series (1/2π)(1 + 2 Σ_n e^(-n²σ²/2) cos n(φ - μ)), summed over
//     the nodes first (coefficients Σ_k w_k cos nμ_k, Σ_k w_k sin nμ_k), then evaluated
//     once per grid point; terms up to e^(-n²σ²/2) < 1e-17.
class WrappedGaussianGrid {
  public:
    WrappedGaussianGrid(double sigma, int n)
        : sigma_(sigma), step_(kPi<double> / (n - 1)), half_inv_var_(0.5 / (sigma * sigma)), n_(n),
          values_(std::size_t(n)) {
        fourier_ = sigma > WrappedGaussian<double>::kSplit;
        if (fourier_) {
            terms_ = int(std::ceil(8.85 / sigma));  // e^(-n²σ²/2) < 1e-17 beyond
            cos_.resize(std::size_t(terms_ + 1));
            sin_.resize(std::size_t(terms_ + 1));
            for (int k = 0; k <= terms_; ++k) rho_.push_back(std::exp(-0.5 * k * k * sigma * sigma));
        }
        clear();
    }

    void clear() {
        for (auto& v : values_) v = glm::dvec3(0.0);
        for (auto& c : cos_) c = glm::dvec3(0.0);
        for (auto& s : sin_) s = glm::dvec3(0.0);
    }

    void add(double mu, const glm::dvec3& w) {
        mu = wrap_pi(mu);
        if (fourier_) {
            const double c1 = std::cos(mu), s1 = std::sin(mu);
            double c = 1, s = 0;
            for (int k = 0; k <= terms_; ++k) {
                cos_[std::size_t(k)] += c * w;
                sin_[std::size_t(k)] += s * w;
                const double cn = c * c1 - s * s1;  // angle addition: (k + 1)μ
                s = s * c1 + c * s1;
                c = cn;
            }
            return;
        }
        const double reach = 10 * sigma_, norm = kInvSqrtTwoPi<double> / sigma_;
        const double q = std::exp(-2 * step_ * step_ * half_inv_var_);
        for (int k = -2; k <= 2; ++k) {
            const double c = mu + kTwoPi<double> * k;
            const int lo = std::max(0, int(std::ceil((c - reach) / step_)));
            const int hi = std::min(n_ - 1, int(std::floor((c + reach) / step_)));
            if (c + reach < 0 || c - reach > kPi<double> || lo > hi) continue;
            const int start = std::min(hi, std::max(lo, int(std::lround(c / step_))));
            // Outward from the grid point nearest the centre, so that g only decreases and
            // neither g nor the ratio can overflow; restarted from the exact values every
            // kRestart steps (the recurrence's rounding grows with the square of the steps).
            const double dir_step[2] = {step_, -step_};
            for (int side = 0; side < 2; ++side) {
                const double d = dir_step[side];
                const int first = side == 0 ? start : start - 1, last = side == 0 ? hi : lo;
                double g = 0, r = 0;
                for (int i = first, s = 0; side == 0 ? i <= last : i >= last; i += side == 0 ? 1 : -1, ++s) {
                    if (s % kRestart == 0) {
                        const double x = i * step_ - c;
                        g = norm * std::exp(-x * x * half_inv_var_);
                        r = std::exp(-(2 * x * d + step_ * step_) * half_inv_var_);
                    }
                    if (!(g > 1e-300)) break;  // the rest underflows
                    values_[std::size_t(i)] += g * w;
                    g *= r;
                    r *= q;
                }
            }
        }
    }

    // The sums at the grid points (after the last add).
    const std::vector<glm::dvec3>& values() {
        if (fourier_) {
            for (int i = 0; i < n_; ++i) {
                const double phi = i * step_, c1 = std::cos(phi), s1 = std::sin(phi);
                double c = 1, s = 0;
                glm::dvec3 sum = cos_[0];
                for (int k = 1; k <= terms_; ++k) {
                    const double cn = c * c1 - s * s1;
                    s = s * c1 + c * s1;
                    c = cn;
                    sum += (2 * rho_[std::size_t(k)]) * (c * cos_[std::size_t(k)] + s * sin_[std::size_t(k)]);
                }
                values_[std::size_t(i)] = glm::max(kInvTwoPi<double> * sum, glm::dvec3(0.0));  // ≥ 1e-3/2π analytically
            }
        }
        return values_;
    }

  private:
    static constexpr int kRestart = 32;
    double sigma_, step_, half_inv_var_;
    int n_, terms_ = 0;
    bool fourier_ = false;
    std::vector<glm::dvec3> values_, cos_, sin_;
    std::vector<double> rho_;
};

}  // namespace detail

}  // namespace hairscatter
