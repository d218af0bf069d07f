// hairscatter — the tabulated far-field model's tables, built on the host: validation of the
// parameters and options, the table build from d'Eon's far-field ingredients (the shared
// M_p and tilt of lobes/deon_lobes.hpp, the h rule and node terms of
// lobes/farfield_quadrature.hpp) and ownership of the data (models/tabulated.hpp).
#pragma once

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "../../config.hpp"
#include "../../fiber/params.hpp"
#include "../../lobes/azimuthal.hpp"
#include "../../lobes/deon_lobes.hpp"
#include "../../lobes/farfield_quadrature.hpp"
#include "../../lobes/lobe_controls.hpp"
#include "../../lobes/longitudinal_table.hpp"
#include "../../math/constants.hpp"
#include "../../math/functions.hpp"
#include "../../math/wrapped_gaussian_grid.hpp"
#include "options.hpp"
#include "view.hpp"

namespace hairscatter {

template <typename T> class TabulatedFiber;

// Host side: validates the parameters and options (std::invalid_argument naming the bad
// one), builds the tables and owns them. The table values are the far-field model's
// N_p(φ)·A_p (in double, by lobes/farfield_quadrature.hpp's rule with h_nodes nodes, the
// same terms DeonFarFieldFiber sums) at the grid points, each (row, lobe, channel) rescaled so that its piecewise-linear interpolant
// integrates to the quadrature's ½∫A_p dh exactly (a relative change of the order of the
// interpolation error): bilinear interpolation then keeps Σ_p ∫ N_p A_p dφ = Σ_p A_p, which
// is 1 for σa = 0, so the white furnace is 1 at every resolution.
// Memory: (12·phi_samples + 16)·theta_samples values of T, plus with
// TabulatedLongitudinal::kTable 3·m_rows·2(m_nodes + 2) (R, TT, TRT; the residual shares TRT's
// variance): 354 kB in float for fast().
// The optional lobe controls (lobes/lobe_controls.hpp) go into the build: each A_p(h_j) is
// multiplied by gain_p × tint_p before it is tabulated (the table values, their φ CDFs and
// masses all follow, so sampling stays proportional to eval), and the per-lobe tilts into
// the view's DeonLobes. They cost nothing per query.
template <typename T> class TabulatedMaterial {
  public:
    using View = TabulatedView<T>;
    static constexpr int kLobes = View::kLobes;

    explicit TabulatedMaterial(const FiberParams<T>& params, const TabulatedOptions& options = TabulatedOptions(),
                               const LobeControls<T>& controls = LobeControls<T>())
        : params_(params), options_(options), controls_(controls) {
        require_valid(params);
        check(options);
        require_valid(controls);
        const int n = options.phi_samples, rows = options.theta_samples;

        // M_p and the tilt in T, the same ingredients as the far-field material's.
        static_cast<DeonLobes<T>&>(view_) = DeonLobes<T>(params.beta_m, controls, params.alpha);
        view_.n_phi_ = n;
        view_.n_theta_ = rows;
        view_.phi_step_ = T(kPi<double> / (n - 1));
        view_.phi_scale_ = T((n - 1) / kPi<double>);
        view_.cdf_offset_ = std::size_t(rows) * std::size_t(n) * View::kNodeStride;
        view_.terms_offset_ = view_.cdf_offset_ + std::size_t(rows) * std::size_t(n) * kLobes;
        data_.assign(view_.terms_offset_ + std::size_t(rows) * View::kRowTerms, T(0));
        if (options.longitudinal == TabulatedLongitudinal::kTable) {
            view_.m_tabulated_ = true;
            for (int p = 0; p < kLobes; ++p)
                view_.mt_[p] = DeonLongitudinalTable<T>::build(double(view_.lobe_variance(p)), options.m_rows,
                                                               options.m_nodes, data_);
        }

        // The lobes in double, from the far-field model's h rule and node terms
        // (lobes/farfield_quadrature.hpp).
        FiberParams<double> pd;
        pd.eta = double(params.eta);
        pd.beta_m = double(params.beta_m);
        pd.beta_n = double(params.beta_n);
        // Clamped: a float α validated against the float π/8 can exceed the double one.
        pd.alpha = clamp(double(params.alpha), -kMaxCuticleTilt<double>, kMaxCuticleTilt<double>);
        pd.sigma_a = glm::dvec3(params.sigma_a);
        using Quadrature = FarFieldQuadrature<double>;
        const Quadrature q(options.h_nodes == Quadrature::kAutoNodes ? Quadrature::auto_nodes(pd.beta_n)
                                                                     : options.h_nodes);
        options_.h_nodes = q.nodes();
        detail::WrappedGaussianGrid grid(azimuthal_gaussian_width(pd.beta_n), n);
        const double step = kPi<double> / (n - 1);

        struct Terms {
            glm::dvec3 a[std::size_t(kLobes + 1)];  // A_p(h_j)
            double phi[std::size_t(kLobes)];        // Φ(p, h_j); the mirror node's is -Φ(p, h_j)
        };
        std::vector<Terms> terms(std::size_t(q.half_nodes()));
        for (int r = 0; r < rows; ++r) {
            const double cos_o = tabulated_row_cos(double(r) / (rows - 1));
            const double sin_o = std::sqrt((1 - cos_o) * (1 + cos_o));
            const FiberRefraction<double> refraction(sin_o, cos_o, pd.eta);
            glm::dvec3 mass[std::size_t(kLobes + 1)] = {};
            for (int j = 0; j < q.half_nodes(); ++j) {
                const FarFieldNode<double, kLobes> nd = far_field_node<kLobes>(q, j, refraction, cos_o, pd);
                for (int p = 0; p <= kLobes; ++p) terms[std::size_t(j)].a[p] = nd.att.a[p];
                if (controls.has_weights())  // the lobe controls: gain × tint on A_p
                    for (int p = 0; p <= kLobes; ++p) terms[std::size_t(j)].a[p] *= glm::dvec3(controls.weight(p));
                for (int p = 0; p < kLobes; ++p) terms[std::size_t(j)].phi[p] = exit_azimuth(p, q.node_gamma(j), nd.gamma_t);
                const double w = q.node_weight(j) * (q.node_mirrored(j) ? 2 : 1);
                for (int p = 0; p <= kLobes; ++p) mass[p] += w * terms[std::size_t(j)].a[p];
            }
            T* lobes = data_.data() + std::size_t(r) * std::size_t(n) * View::kNodeStride;
            T* row_terms = data_.data() + view_.terms_offset_ + std::size_t(r) * View::kRowTerms;
            for (int p = 0; p < kLobes; ++p) {
                grid.clear();
                for (int j = 0; j < q.half_nodes(); ++j) {
                    const Terms& t = terms[std::size_t(j)];
                    const glm::dvec3 w = q.node_weight(j) * t.a[p];
                    grid.add(t.phi[p], w);
                    if (q.node_mirrored(j)) grid.add(-t.phi[p], w);
                }
                const std::vector<glm::dvec3>& v = grid.values();
                // ∫_{-π}^{π} of the interpolant = 2 × the trapezoidal rule over [0, π].
                glm::dvec3 trap = -0.5 * (v.front() + v.back());
                for (const glm::dvec3& x : v) trap += x;
                trap *= 2 * step;
                for (int c = 0; c < 3; ++c) {
                    // A lobe narrower than the grid can fall between every node (β_n → 0):
                    // it is then spread uniformly, which keeps its energy.
                    const bool resolved = trap[c] > 1e-300 && trap[c] > 1e-12 * mass[p][c];
                    const double scale = resolved ? mass[p][c] / trap[c] : 0.0;
                    for (int i = 0; i < n; ++i)
                        lobes[std::size_t(i) * View::kNodeStride + std::size_t(3 * p + c)] =
                            T(resolved ? v[std::size_t(i)][c] * scale : mass[p][c] * kInvTwoPi<double>);
                }
                // The sampling CDF and the lobe's mass from the stored (rounded) values, so
                // that sample() and pdf() describe the same distribution to rounding.
                T* cdf = data_.data() + view_.cdf_offset_ + std::size_t(r * kLobes + p) * std::size_t(n);
                double acc = 0, prev = 0;
                glm::dvec3 stored(0.0);
                for (int i = 0; i < n; ++i) {
                    const T* node = lobes + std::size_t(i) * View::kNodeStride + 3 * p;
                    const double cur = double(node[0] + node[1] + node[2]);
                    if (i > 0) acc += 0.5 * step * (prev + cur);
                    cdf[i] = T(acc);
                    prev = cur;
                    const double wt = (i == 0 || i == n - 1) ? step : 2 * step;  // 2 × trapezoid weight
                    stored += wt * glm::dvec3(double(node[0]), double(node[1]), double(node[2]));
                }
                for (int c = 0; c < 3; ++c) row_terms[3 * p + c] = T(stored[c]);
                row_terms[12 + p] = T(2 * double(cdf[n - 1]));
            }
            for (int c = 0; c < 3; ++c) row_terms[3 * kLobes + c] = T(mass[kLobes][c]);
            row_terms[12 + kLobes] = row_terms[3 * kLobes] + row_terms[3 * kLobes + 1] + row_terms[3 * kLobes + 2];
        }
        view_.data_ = data_.data();
    }

    const FiberParams<T>& params() const { return params_; }
    const TabulatedOptions& options() const { return options_; }
    const LobeControls<T>& controls() const { return controls_; }

    // A copy keeps its own tables (and its view points at them).
    TabulatedMaterial(const TabulatedMaterial& o)
        : params_(o.params_), options_(o.options_), controls_(o.controls_), view_(o.view_), data_(o.data_) {
        view_.data_ = data_.data();
    }
    TabulatedMaterial& operator=(const TabulatedMaterial& o) {
        params_ = o.params_, options_ = o.options_, controls_ = o.controls_, view_ = o.view_, data_ = o.data_;
        view_.data_ = data_.data();
        return *this;
    }
    TabulatedMaterial(TabulatedMaterial&&) = default;  // the vector's buffer moves with the view
    TabulatedMaterial& operator=(TabulatedMaterial&&) = default;

    // The tables over this material's own data (valid while it lives), or over a copy of
    // data() elsewhere, e.g. in device memory.
    View view() const& { return view_; }
    View view() const&& = delete;
    View view(const T* data) const { return view_.with_data(data); }
    const std::vector<T>& data() const { return data_; }
    std::size_t bytes() const { return data_.size() * sizeof(T); }

    // As the other materials: lobe p peaks at θi = lobe_shift(p) - θo, with variance v_p.
    T lobe_shift(int p) const { return view_.lobe_shift(p); }
    T lobe_variance(int p) const { return view_.lobe_variance(p); }

  private:
    static void check(const TabulatedOptions& o) {
        auto bad = [](const char* name, int value, int lo, int hi) {
            HAIRSCATTER_THROW(std::invalid_argument(std::string("hairscatter: TabulatedOptions::") + name + " = " +
                                        std::to_string(value) + " is outside its range [" + std::to_string(lo) +
                                        ", " + std::to_string(hi) + "]"));
        };
        if (!(o.phi_samples >= 2 && o.phi_samples <= TabulatedOptions::kMaxPhiSamples))
            bad("phi_samples", o.phi_samples, 2, TabulatedOptions::kMaxPhiSamples);
        if (!(o.theta_samples >= 2 && o.theta_samples <= TabulatedOptions::kMaxThetaSamples))
            bad("theta_samples", o.theta_samples, 2, TabulatedOptions::kMaxThetaSamples);
        // 0 = kAutoNodes.
        if (!(o.h_nodes >= 0 && o.h_nodes <= FarFieldQuadrature<double>::kMaxNodes))
            bad("h_nodes", o.h_nodes, 0, FarFieldQuadrature<double>::kMaxNodes);
        if (o.longitudinal != TabulatedLongitudinal::kExact && o.longitudinal != TabulatedLongitudinal::kTable)
            bad("longitudinal", int(o.longitudinal), 0, 1);
        // Checked in kExact mode too, where no M table is built: an option is valid or not
        // whatever the mode (0 or 1e9 passed there while fast() refused them).
        if (!(o.m_rows >= 2 && o.m_rows <= TabulatedOptions::kMaxLongitudinalRows))
            bad("m_rows", o.m_rows, 2, TabulatedOptions::kMaxLongitudinalRows);
        if (!(o.m_nodes >= 2 && o.m_nodes <= TabulatedOptions::kMaxLongitudinalNodes))
            bad("m_nodes", o.m_nodes, 2, TabulatedOptions::kMaxLongitudinalNodes);
    }

    FiberParams<T> params_;
    TabulatedOptions options_;
    LobeControls<T> controls_;
    friend class TabulatedFiber<T>;
    View view_;  // over data_ (set once the tables are built: building appends to data_)
    std::vector<T> data_;
};

}  // namespace hairscatter
