// hairscatter — the tabulated far-field model's tables as a device-side view: the data
// layout, the interpolation cells and the φ CDF lookups and inversion (models/tabulated.hpp).
#pragma once

#include <cstddef>

#include "../../config.hpp"
#include "../../lobes/deon_lobes.hpp"
#include "../../lobes/longitudinal_table.hpp"
#include "../../math/constants.hpp"
#include "../../math/distributions.hpp"
#include "../../math/functions.hpp"

namespace hairscatter {

template <typename T> class TabulatedMaterial;

// The tables of a TabulatedMaterial over data it does not own: trivially copyable, so it can
// be passed by value to a GPU kernel once the data are copied to device memory
// (material.view(device_pointer)). Every query is HAIRSCATTER_HD and check-free.
//
// Layout of the data (all of type T), n = phi_samples, rows = theta_samples:
//   lobes: [row][i][3p + c]   N_p(φ_i)·A_p for p = R, TT, TRT, channel c (9 per node);
//   cdf:   [row][p][i]        ∫_0^φ_i of the channel sum of lobe p, trapezoidal (exact
//                             for the piecewise-linear interpolant);
//   terms: [row][16]          [3p + c] = ∫_{-π}^{π} N_p A_p dφ (p = 0…3, 3 the residual),
//                             [12 + p] = its channel sum.
// Its d'Eon ingredients (longitudinal(p), tilt(), lobe_shift(p), lobe_variance(p)) are
// DeonLobes'.
template <typename T> class TabulatedView : public DeonLobes<T> {
  public:
    static constexpr int kLobes = DeonLobes<T>::kLobes;  // R, TT, TRT tabulated; index 3 is the φ-uniform residual
    static constexpr int kNodeStride = 3 * kLobes;
    static constexpr int kRowTerms = 16;

    // No tables: assign one from TabulatedMaterial::view() before querying.
    TabulatedView() = default;

    // The same tables over a copy of the data elsewhere (e.g. in device memory).
    HAIRSCATTER_HD TabulatedView with_data(const T* data) const {
        TabulatedView v = *this;
        v.data_ = data;
        return v;
    }

    HAIRSCATTER_HD int phi_samples() const { return n_phi_; }
    HAIRSCATTER_HD int theta_samples() const { return n_theta_; }
    HAIRSCATTER_HD T phi_step() const { return phi_step_; }
    HAIRSCATTER_HD T phi_scale() const { return phi_scale_; }  // 1 / phi_step()
    HAIRSCATTER_HD const T* data() const { return data_; }
    HAIRSCATTER_HD const T* lobes(int row) const { return data_ + std::size_t(row) * std::size_t(n_phi_ * kNodeStride); }
    HAIRSCATTER_HD const T* cdf(int row, int p) const {
        return data_ + cdf_offset_ + std::size_t(row * kLobes + p) * std::size_t(n_phi_);
    }
    HAIRSCATTER_HD const T* row_terms(int row) const { return data_ + terms_offset_ + std::size_t(row) * kRowTerms; }
    // TabulatedLongitudinal::kTable: lobe p's M_p table (the residual shares TRT's: same v).
    HAIRSCATTER_HD bool longitudinal_tabulated() const { return m_tabulated_; }
    HAIRSCATTER_HD const DeonLongitudinalTable<T>& longitudinal_table(int p) const { return mt_[p < kLobes ? p : kLobes - 1]; }

    // The interpolation coordinates: |φ| ∈ [0, π] → (node i ≤ n - 2, fraction), cosθo → (row
    // ≤ rows - 2, fraction). Clamped, so rounding never extrapolates.
    HAIRSCATTER_HD void phi_cell(T abs_phi, int& i, T& frac) const {
        const T x = clamp(abs_phi * phi_scale_, T(0), T(n_phi_ - 1));
        i = table_cell(x, n_phi_ - 2);  // NaN-safe: cell 0
        frac = x - T(i);
    }
    HAIRSCATTER_HD void theta_cell(T cos_o, int& row, T& frac) const {
        using std::sqrt;
        // y = the root of y(1 + 2y)/3 = cosθo in [0, 1] (tabulated_row_cos).
        const T y = clamp((sqrt(T(1) + T(24) * cos_o) - T(1)) * T(0.25) * T(n_theta_ - 1), T(0), T(n_theta_ - 1));
        row = table_cell(y, n_theta_ - 2);
        frac = y - T(row);
    }

    // ∫_0^x of row's channel sum of lobe p, x ∈ [0, π]: the row's φ CDF, exact for the
    // piecewise-linear table (a quadratic within the cell); the row's total is cdf[n - 1].
    HAIRSCATTER_HD T phi_mass(int row, int p, T x) const {
        int i;
        T u;
        phi_cell(x, i, u);
        const T* node = lobes(row) + 3 * p + i * kNodeStride;
        const T n0 = node[0] + node[1] + node[2];
        const T n1 = node[kNodeStride] + node[kNodeStride + 1] + node[kNodeStride + 2];
        return cdf(row, p)[i] + phi_step_ * u * (n0 + T(0.5) * u * (n1 - n0));
    }

    // φ from row's lobe p: |φ| by inverting its piecewise-linear CDF, the sign from which
    // half of [0, 1) u falls in.
    HAIRSCATTER_HD T sample_phi(int row, int p, T u) const {
        const T* c = cdf(row, p);
        const T* node = lobes(row) + 3 * p;
        const T w = T(2) * u - T(1);
        const T sign = w < T(0) ? T(-1) : T(1);
        const PiecewiseLinearPoint<T> x = invert_piecewise_linear(
            [&](int k) { return c[k]; },
            [&](int k) {
                const T* nk = node + k * kNodeStride;
                return nk[0] + nk[1] + nk[2];
            },
            n_phi_, phi_step_, phi_scale_, abs_value(w) * c[n_phi_ - 1]);
        return sign * clamp(T(x.cell) * phi_step_ + x.offset, T(0), kPi<T>);
    }

  private:
    friend class TabulatedMaterial<T>;
    const T* data_ = nullptr;
    int n_phi_ = 2, n_theta_ = 2;
    std::size_t cdf_offset_ = 0, terms_offset_ = 0;
    T phi_scale_ = T(0), phi_step_ = T(0);
    bool m_tabulated_ = false;
    DeonLongitudinalTable<T> mt_[std::size_t(kLobes)];
};

}  // namespace hairscatter
