// hairscatter — d'Eon et al. 2011's longitudinal lobe M_p (lobes/longitudinal.hpp) as a
// table: a piecewise-linear density in sinθi per row of the (tilted) conditioning angle θo',
// renormalised per θo' so that it integrates to 1 exactly and sampled by inverting the same
// piecewise-linear density. Used by models/tabulated.hpp's TabulatedLongitudinal::kTable.
//
// Coordinates. With s = sinθi, ∫ M cosθi dθi = ∫ M ds, so M itself is the density in s. Its
// peak sits at the mirror s = -sinθo' with width √v cosθo' away from grazing and v at
// grazing, so each row stores it over
//   x = (s + sinθo') / w,   w = √(v (cos²θo' + v)),
// in which the lobe has a fixed place (x ≈ 0) and a width of order 1 at every θo' (a
// Gaussian of σ ≈ 1 at normal incidence, e^(-x) at grazing): rows interpolated at fixed x
// blend two lobes that sit on top of each other. M(s | θo') = M(-s | -θo'), so rows cover
// θ = |θo'| ∈ [0, π/2] uniformly and negative θo' flip s.
//
// Window. x ∈ [max(-6, -1/√(v(1 + v))), min(14, 2/v)]: the lobe's tails beyond are below
// e^(-14) (the lower bound of -6σ, and the e^(-x) tail at grazing), and ±1/√(v(1+v)), 2/v are
// the extreme physical values of x (|s| ≤ 1), reached at θo' = 0 and π/2 — so rough lobes
// (v ≫ 1, nearly uniform in s) spend every node on the physical range. A node outside its
// row's physical range |s| ≤ 1 holds the value at s = ±1 (a smooth continuation for the
// neighbouring row's query, which clips at its own range); one zero node pads each end.
//
// Node values. g(x) = w M is sampled at the nodes and corrected by -h²g''/12 (the second
// difference / 12): the linear interpolant of point samples is biased by ξ(1 - ξ)h²g''/2
// inside a cell, and the correction removes its mean, which cuts the L1 error about 2.5×.
//
// At θo' (between rows r, r+1 with weight t) the density in x is the mixture
// g̃ = (1 - t) g_r + t g_{r+1}, piecewise linear on the common nodes; its CDF C̃ is exact
// from each row's stored trapezoid sums. Clipped to the physical range x ∈ [L, U] =
// [(sinθo' - 1)/w, (sinθo' + 1)/w] and normalised by Z = C̃(U) - C̃(L):
//   M̂(s | θo') = g̃(x(s)) / (w Z),   ∫_{-1}^{1} M̂ ds = 1 exactly (to rounding),
// whatever the resolution; sample() inverts C̃ (binary search, then the cell's quadratic).
// The error against M is that of the interpolation (measured in tests/tabulated_test.cpp):
// the x step h against the lobe's width in x (≈ 1 for v ≲ 1) and the θ step against
// the change of shape near grazing, which happens over Δθ ≈ √v (narrow lobes, β_m < 0.2,
// need more rows there).
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "../config.hpp"
#include "../math/constants.hpp"
#include "../math/distributions.hpp"
#include "../math/functions.hpp"
#include "longitudinal.hpp"

namespace hairscatter {

// One lobe's table over data it does not own (offset into a shared array). Each row is
// [nodes values g][nodes CDF values], rows after each other.
template <typename T> class DeonLongitudinalTable {
  public:
    static constexpr double kLowX = -6, kHighX = 14;
    static constexpr double kRowK = 1;

    DeonLongitudinalTable() = default;

    // Host side: appends rows × (nodes + 2) × 2 values to data and returns the table
    // (offset = where it starts). rows ≥ 2, nodes ≥ 2 (interior nodes, without the pads).
    static DeonLongitudinalTable build(double v, int rows, int nodes, std::vector<T>& data) {
        DeonLongitudinalTable tab;
        const int k2 = nodes + 2;
        tab.v_ = T(v);
        tab.rows_ = rows;
        tab.nodes_ = k2;
        tab.offset_ = data.size();
        tab.row_scale_ = T((rows - 1) / (1 + kRowK));
        const double x0 = std::fmax(kLowX, -1 / std::sqrt(v * (1 + v))), x1 = std::fmin(kHighX, 2 / v);
        const double h = (x1 - x0) / (nodes - 1), xs = x0 - h;
        tab.h_ = T(h);
        tab.inv_h_ = T(1 / h);
        tab.xs_ = T(xs);
        // M in T: float's exponential is several times faster than double's, and its
        // relative error (~1e-6) is far below the interpolation error.
        const DeonLongitudinal<T> m{T(v)};
        data.resize(tab.offset_ + std::size_t(rows) * std::size_t(2 * k2), T(0));
        std::vector<double> g(std::size_t(k2 + 2));
        for (int r = 0; r < rows; ++r) {
            const double y = double(r) / (rows - 1);
            const double theta = kHalfPi<double> * (std::sqrt(1 + 4 * kRowK * (1 + kRowK) * y) - 1) / (2 * kRowK);
            const double sin_o = r == rows - 1 ? 1.0 : std::sin(theta), cos_o = r == rows - 1 ? 0.0 : std::cos(theta);
            const double w = std::sqrt(v * (cos_o * cos_o + v));
            // g at the interior nodes 1 … nodes, and one more on each side for the second
            // differences (the zero pads themselves are not corrected).
            for (int j = 0; j < k2 + 2; ++j) {
                const double x = xs + (j - 1) * h;
                const double s = clamp(x * w - sin_o, -1.0, 1.0);
                g[std::size_t(j)] = w * double(m.eval(T(s), T(std::sqrt((1 - s) * (1 + s))), T(sin_o), T(cos_o)));
            }
            T* vals = data.data() + tab.offset_ + std::size_t(r) * std::size_t(2 * k2);
            T* cdf = vals + k2;
            for (int j = 1; j + 1 < k2; ++j) {
                const double* c = g.data() + j + 1;  // g of node j
                vals[j] = T(std::fmax(c[0] - (c[1] - 2 * c[0] + c[-1]) / 12, 0.0));
            }
            double acc = 0;
            cdf[0] = T(0);
            for (int j = 1; j < k2; ++j) {
                acc += 0.5 * h * (double(vals[j - 1]) + double(vals[j]));
                cdf[j] = T(acc);
            }
        }
        return tab;
    }

    // The lobe conditioned on θo' (its angle folded into [-π/2, π/2], and its sine and
    // cosine, as CuticleTilt::rotate gives them): everything eval and sample need.
    struct Conditioned {
        const T* row;  // row r; row r + 1 follows at 2 × nodes
        T t;           // weight of row r + 1
        T a, b;        // node coordinate of s: a s + b
        T scale;       // 1 / (w Z)
        T sign, sin_abs, w;
        T c_lo, z;     // C̃(L) and Z
    };

    HAIRSCATTER_HD Conditioned condition(const T* data, T theta, T sin_o, T cos_o) const {
        using std::sqrt;
        Conditioned c;
        c.sign = theta < T(0) ? T(-1) : T(1);
        c.sin_abs = sin_o < T(0) ? -sin_o : sin_o;
        const T th = (theta < T(0) ? -theta : theta) * T(1 / kHalfPi<double>);
        const T y = clamp(th * (T(1) + T(kRowK) * th) * row_scale_, T(0), T(rows_ - 1));
        const int r = table_cell(y, rows_ - 2);  // NaN-safe (v underflow, non-finite θo)
        c.t = y - T(r);
        c.row = data + offset_ + std::size_t(r) * std::size_t(2 * nodes_);
        c.w = sqrt(v_ * (cos_o * cos_o + v_));
        const T inv_w = T(1) / c.w;
        c.a = c.sign * inv_w * inv_h_;
        c.b = (c.sin_abs * inv_w - xs_) * inv_h_;
        c.c_lo = mix_cdf(c, (c.sin_abs - T(1)) * inv_w);
        c.z = mix_cdf(c, (c.sin_abs + T(1)) * inv_w) - c.c_lo;
        // Z ≥ the mass near the peak x ≈ 0, which is inside [L, U] and the window.
        c.scale = c.z > T(0) ? inv_w / c.z : T(0);
        return c;
    }

    // M̂(sinθi | θo').
    HAIRSCATTER_HD T eval(const Conditioned& c, T sin_i) const {
        const T xi = clamp(c.a * sin_i + c.b, T(0), T(nodes_ - 1));
        const int j = table_cell(xi, nodes_ - 2);
        const T f = xi - T(j);
        const T* r0 = c.row + j;
        const T* r1 = r0 + 2 * nodes_;
        const T g0 = r0[0] + c.t * (r1[0] - r0[0]), g1 = r0[1] + c.t * (r1[1] - r0[1]);
        return c.scale * (g0 + f * (g1 - g0));
    }

    // sinθi distributed as M̂(· | θo') from one uniform number: the interpolated row's
    // piecewise-linear density inverted exactly.
    HAIRSCATTER_HD T sample_sin_theta(const Conditioned& c, T u) const {
        const T* c0 = c.row + nodes_;
        const T* c1 = c0 + 2 * nodes_;
        const T* g0 = c.row;
        const T* g1 = g0 + 2 * nodes_;
        const PiecewiseLinearPoint<T> x = invert_piecewise_linear(
            [&](int k) { return c0[k] + c.t * (c1[k] - c0[k]); }, [&](int k) { return g0[k] + c.t * (g1[k] - g0[k]); },
            nodes_, h_, inv_h_, c.c_lo + u * c.z);
        return clamp(c.sign * ((xs_ + T(x.cell) * h_ + x.offset) * c.w - c.sin_abs), T(-1), T(1));
    }

    HAIRSCATTER_HD T variance() const { return v_; }
    HAIRSCATTER_HD int rows() const { return rows_; }
    HAIRSCATTER_HD int nodes() const { return nodes_; }
    HAIRSCATTER_HD std::size_t offset() const { return offset_; }

  private:
    // C̃(x), clamped to the padded window.
    HAIRSCATTER_HD T mix_cdf(const Conditioned& c, T x) const {
        const T xi = clamp((x - xs_) * inv_h_, T(0), T(nodes_ - 1));
        const int j = table_cell(xi, nodes_ - 2);
        const T f = xi - T(j);
        const T* r0 = c.row + j;
        const T* r1 = r0 + 2 * nodes_;
        const T g0 = r0[0] + c.t * (r1[0] - r0[0]), g1 = r0[1] + c.t * (r1[1] - r0[1]);
        const T c0 = r0[nodes_] + c.t * (r1[nodes_] - r0[nodes_]);
        return c0 + h_ * f * (g0 + T(0.5) * f * (g1 - g0));
    }

    T v_ = T(1), row_scale_ = T(0), xs_ = T(0), h_ = T(1), inv_h_ = T(1);
    int rows_ = 2, nodes_ = 4;
    std::size_t offset_ = 0;
};

}  // namespace hairscatter
