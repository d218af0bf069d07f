// hairscatter — Gauss–Legendre quadrature nodes and weights (host side, for precomputation).
#pragma once

#include <cmath>
#include <stdexcept>
#include <vector>

#include "../config.hpp"

namespace hairscatter {

// n-point Gauss–Legendre rule on [-1, 1]: nodes are the roots of P_n, found by Newton's
// method from Tricomi's initial guesses; weights 2 / ((1 - x²) P_n'(x)²). Exact for
// polynomials of degree 2n - 1. Computed in double whatever T is.
template <typename T> struct GaussLegendre {
    std::vector<T> nodes, weights;

    explicit GaussLegendre(int n) {
        if (n < 1 || n > 4096) HAIRSCATTER_THROW(std::invalid_argument("hairscatter: GaussLegendre needs 1 ≤ n ≤ 4096"));
        nodes.resize(std::size_t(n));
        weights.resize(std::size_t(n));
        const double pi = 3.14159265358979323846;
        for (int i = 0; i < (n + 1) / 2; ++i) {
            double x = std::cos(pi * (i + 0.75) / (n + 0.5));
            double dp = 1;
            for (int it = 0; it < 100; ++it) {
                // P_n(x) and P_n'(x) by the three-term recurrence.
                double p0 = 1, p1 = x;
                for (int k = 2; k <= n; ++k) {
                    const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                const double pn = n == 1 ? x : p1, pm = n == 1 ? 1.0 : p0;
                dp = n * (x * pn - pm) / (x * x - 1);
                const double dx = pn / dp;
                x -= dx;
                if (std::abs(dx) < 1e-16) break;
            }
            const double w = 2 / ((1 - x * x) * dp * dp);
            nodes[std::size_t(i)] = T(-x);
            nodes[std::size_t(n - 1 - i)] = T(x);
            weights[std::size_t(i)] = weights[std::size_t(n - 1 - i)] = T(w);
        }
    }
};

// n-point Gauss–Hermite rule for the standard normal density: Σ_k weights[k] f(nodes[k])
// ≈ E[f(Z)], Z ~ N(0, 1), exact for polynomials of degree 2n - 1. The nodes are √2 times
// the roots of the Hermite polynomial H_n, found by bisection between sign changes on a
// grid finer than their spacing, bisected to 1e-15; the orthonormal recurrence
// ψ_k = √(2/k) x ψ_{k-1} - √((k-1)/k) ψ_{k-2} keeps every value finite, and the weights
// are 1/(n ψ_{n-1}(x)²)/√π. Computed in double whatever T is.
template <typename T> struct GaussHermite {
    std::vector<T> nodes, weights;

    explicit GaussHermite(int n) {
        if (n < 1 || n > 64) HAIRSCATTER_THROW(std::invalid_argument("hairscatter: GaussHermite needs 1 ≤ n ≤ 64"));
        const double pi = 3.14159265358979323846;
        // ψ_n(x) and ψ_{n-1}(x), orthonormal for the weight e^(-x²).
        auto psi = [n, pi](double x, double& prev) {
            double p0 = std::pow(pi, -0.25), p1 = std::sqrt(2.0) * x * p0;
            if (n == 1) {
                prev = p0;
                return p1;
            }
            for (int k = 2; k <= n; ++k) {
                const double p2 = std::sqrt(2.0 / k) * x * p1 - std::sqrt(double(k - 1) / k) * p0;
                p0 = p1;
                p1 = p2;
            }
            prev = p0;
            return p1;
        };
        // All roots lie in |x| < √(2n + 1); their spacing is at least π/√(2n + 1) · ½.
        const double lim = std::sqrt(2.0 * n + 1), step = 0.05 / lim;
        std::vector<double> roots;
        double prev_dummy = 0, a = -lim, fa = psi(a, prev_dummy);
        for (double b = a + step; a < lim && int(roots.size()) < n; b += step) {
            const double fb = psi(b, prev_dummy);
            // A root exactly on a grid point (fb == 0) is taken there; the next interval,
            // starting at that zero, must not count it again.
            if (fa != 0 && ((fa < 0) != (fb < 0) || fb == 0)) {
                double lo = a, hi = b, flo = fa;
                for (int it = 0; it < 200 && hi - lo > 1e-15; ++it) {
                    const double mid = 0.5 * (lo + hi), fm = psi(mid, prev_dummy);
                    if ((fm < 0) == (flo < 0)) {
                        lo = mid;
                        flo = fm;
                    } else {
                        hi = mid;
                    }
                }
                roots.push_back(0.5 * (lo + hi));
            }
            a = b;
            fa = fb;
        }
        if (int(roots.size()) != n) HAIRSCATTER_THROW(std::logic_error("hairscatter: GaussHermite lost a root"));
        nodes.resize(std::size_t(n));
        weights.resize(std::size_t(n));
        for (int i = 0; i < n; ++i) {
            // Symmetrise: the i-th root from below mirrors the i-th from above exactly.
            const double x = 0.5 * (roots[std::size_t(i)] - roots[std::size_t(n - 1 - i)]);
            double pm = 0;
            psi(x, pm);
            nodes[std::size_t(i)] = T(std::sqrt(2.0) * x);
            weights[std::size_t(i)] = T(1 / (n * pm * pm) / std::sqrt(pi));
        }
    }
};

}  // namespace hairscatter
