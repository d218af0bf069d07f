// hairscatter — Gauss–Legendre quadrature nodes and weights (host side, for precomputation).
#pragma once

#include <cmath>
#include <stdexcept>
#include <vector>

namespace hairscatter {

// n-point Gauss–Legendre rule on [-1, 1]: nodes are the roots of P_n, found by Newton's
// method from Tricomi's initial guesses; weights 2 / ((1 - x²) P_n'(x)²). Exact for
// polynomials of degree 2n - 1. Computed in double whatever T is.
template <typename T> struct GaussLegendre {
    std::vector<T> nodes, weights;

    explicit GaussLegendre(int n) {
        if (n < 1 || n > 4096) throw std::invalid_argument("hairscatter: GaussLegendre needs 1 ≤ n ≤ 4096");
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

}  // namespace hairscatter
