// hairscatter — d'Eon et al. 2011's far-field fiber with the azimuthal lobes tabulated:
// N_p·A_p, integrated over h exactly as models/deon_farfield.hpp does, is computed once per
// material on a grid over (|φ|, cosθo) and interpolated bilinearly; M_p is the exact
// energy-conserving lobe (lobes/longitudinal.hpp) with the cuticle tilt on θo (docs/theory.md
// §3.3). For renderers that shade many fibers with shared parameters: the per-call cost no
// longer grows with the number of h nodes.
#pragma once

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../fiber/frame.hpp"
#include "../fiber/params.hpp"
#include "../lobes/deon_lobes.hpp"
#include "../lobes/longitudinal_table.hpp"
#include "../math/constants.hpp"
#include "../math/distributions.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"
#include "../math/wrapped_gaussian.hpp"
#include "contract.hpp"
#include "deon_farfield.hpp"  // the exact far field the tables are built from (host side)

namespace hairscatter {

// The table's resolution, fixed at construction.
//   phi_samples:   nodes over |φ| ∈ [0, π], equispaced (N_p is even in φ: the h rule is
//                  symmetric);
//   theta_samples: rows over cosθo ∈ [0, 1] (N_p·A_p depends on θo through η', the
//                  Fresnel cosine and the chord: smooth in cosθo and even in θo), placed at
//                  cosθo = y(1 + 2y)/3 for equispaced y, five times denser at grazing, where
//                  the curvature of Fresnel's F → 1 dominates the interpolation error, than
//                  at normal incidence (halves the error of equispaced rows);
//   h_nodes:       Gauss–Legendre nodes in γ of each row's h integral (DeonFarFieldMaterial),
//                  or kAutoNodes (0, the default) for DeonFarFieldMaterial::auto_nodes(β_n):
//                  34 at β_n = 0.3 (the default table builds in 0.47 ms in float), 24 for
//                  β_n ≥ 0.4, more for narrower detectors; options() reports the count used.
// The default keeps the relative L1 error against the exact far-field model (64 h nodes)
// near 5e-4 for β_n ≥ 0.3 (tests/tabulated_test.cpp states the figures per resolution);
// narrower azimuthal lobes need proportionally more φ samples (the automatic h node count
// grows with them, as the exact model's does).
// How M_p is evaluated: kExact, d'Eon's formula per call (lobes/longitudinal.hpp); kTable,
// lobes/longitudinal_table.hpp's table of m_rows rows over |θo'| ∈ [0, π/2] and m_nodes
// nodes per row, renormalised per θo' so that the furnace stays exactly 1 and sampled by
// inverting the same piecewise-linear density (faster: no exponential or Bessel function
// per call; see TabulatedFiber for the cost and the accuracy).
enum class TabulatedLongitudinal { kExact, kTable };

struct TabulatedOptions {
    static constexpr int kMaxPhiSamples = 4096;
    static constexpr int kMaxThetaSamples = 1024;
    static constexpr int kMaxLongitudinalRows = 1024;
    static constexpr int kMaxLongitudinalNodes = 8192;

    static constexpr int kAutoNodes = DeonFarFieldMaterial<double>::kAutoNodes;

    int phi_samples = 96;
    int theta_samples = 28;
    int h_nodes = kAutoNodes;
    TabulatedLongitudinal longitudinal = TabulatedLongitudinal::kExact;
    int m_rows = 48;
    int m_nodes = 192;

    // The shipped resolutions besides the default: a quarter of its memory (and the fewest
    // h nodes auto_nodes ever picks, for the cheapest build), and four times it (h nodes
    // fixed at the accuracy tests' reference count).
    static constexpr TabulatedOptions coarse() { return {48, 16, 24}; }
    static constexpr TabulatedOptions fine() { return {192, 56, 64}; }
    // The speed preset: the default azimuthal table with M_p tabulated.
    static constexpr TabulatedOptions fast() { return {96, 28, kAutoNodes, TabulatedLongitudinal::kTable, 48, 192}; }
};

// Row y ∈ [0, 1] of the table ↔ cosθo (see theta_samples above).
HAIRSCATTER_HD inline double tabulated_row_cos(double y) { return y * (1 + 2 * y) / 3; }

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

template <typename T> class TabulatedMaterial;
template <typename T> class TabulatedFiber;

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

  private:
    friend class TabulatedMaterial<T>;
    const T* data_ = nullptr;
    int n_phi_ = 2, n_theta_ = 2;
    std::size_t cdf_offset_ = 0, terms_offset_ = 0;
    T phi_scale_ = T(0), phi_step_ = T(0);
    bool m_tabulated_ = false;
    DeonLongitudinalTable<T> mt_[kLobes];
};

// Host side: validates the parameters and options (std::invalid_argument naming the bad
// one), builds the tables and owns them. The table values are the far-field model's
// N_p(φ)·A_p (DeonFarFieldFiber<double> with h_nodes nodes, through its node_terms) at the
// grid points, each (row, lobe, channel) rescaled so that its piecewise-linear interpolant
// integrates to the quadrature's ½∫A_p dh exactly (a relative change of the order of the
// interpolation error): bilinear interpolation then keeps Σ_p ∫ N_p A_p dφ = Σ_p A_p, which
// is 1 for σa = 0, so the white furnace is 1 at every resolution.
// Memory: (12·phi_samples + 16)·theta_samples values of T, plus with
// TabulatedLongitudinal::kTable 3·m_rows·2(m_nodes + 2) (R, TT, TRT; the residual shares TRT's
// variance): 354 kB in float for fast().
template <typename T> class TabulatedMaterial {
  public:
    using View = TabulatedView<T>;
    static constexpr int kLobes = View::kLobes;

    explicit TabulatedMaterial(const FiberParams<T>& params, const TabulatedOptions& options = TabulatedOptions())
        : params_(params), options_(options) {
        require_valid(params);
        check(options);
        const int n = options.phi_samples, rows = options.theta_samples;

        // M_p and the tilt in T, the same ingredients as the far-field material's.
        static_cast<DeonLobes<T>&>(view_) = DeonLobes<T>(params.beta_m, params.alpha);
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

        // The lobes in double, from the far-field fiber's own quadrature terms.
        FiberParams<double> pd;
        pd.eta = double(params.eta);
        pd.beta_m = double(params.beta_m);
        pd.beta_n = double(params.beta_n);
        // Clamped: a float α validated against the float π/8 can exceed the double one.
        pd.alpha = clamp(double(params.alpha), -kMaxCuticleTilt<double>, kMaxCuticleTilt<double>);
        pd.sigma_a = glm::dvec3(params.sigma_a);
        const DeonFarFieldMaterial<double> md(pd, options.h_nodes);
        options_.h_nodes = md.nodes();
        const DeonFarFieldFiber<double> fd(md);
        detail::WrappedGaussianGrid grid(md.azimuthal().sigma(), n);
        const double step = kPi<double> / (n - 1);

        using Terms = typename DeonFarFieldFiber<double>::NodeTerms;
        std::vector<Terms> terms(std::size_t(md.half_nodes()));
        for (int r = 0; r < rows; ++r) {
            const double cos_o = tabulated_row_cos(double(r) / (rows - 1));
            const double sin_o = std::sqrt((1 - cos_o) * (1 + cos_o));
            const glm::dvec3 wo(sin_o, cos_o, 0.0);
            glm::dvec3 mass[kLobes + 1] = {};
            for (int j = 0; j < md.half_nodes(); ++j) {
                terms[std::size_t(j)] = fd.node_terms(wo, j);
                const double w = md.node_weight(j) * (md.node_mirrored(j) ? 2 : 1);
                for (int p = 0; p <= kLobes; ++p) mass[p] += w * terms[std::size_t(j)].a[p];
            }
            T* lobes = data_.data() + std::size_t(r) * std::size_t(n) * View::kNodeStride;
            T* row_terms = data_.data() + view_.terms_offset_ + std::size_t(r) * View::kRowTerms;
            for (int p = 0; p < kLobes; ++p) {
                grid.clear();
                for (int j = 0; j < md.half_nodes(); ++j) {
                    const Terms& t = terms[std::size_t(j)];
                    const glm::dvec3 w = md.node_weight(j) * t.a[p];
                    grid.add(t.phi[p], w);
                    if (md.node_mirrored(j)) grid.add(-t.phi[p], w);
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

    // A copy keeps its own tables (and its view points at them).
    TabulatedMaterial(const TabulatedMaterial& o)
        : params_(o.params_), options_(o.options_), view_(o.view_), data_(o.data_) {
        view_.data_ = data_.data();
    }
    TabulatedMaterial& operator=(const TabulatedMaterial& o) {
        params_ = o.params_, options_ = o.options_, view_ = o.view_, data_ = o.data_;
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
        if (!(o.h_nodes >= 0 && o.h_nodes <= DeonFarFieldMaterial<double>::kMaxNodes))
            bad("h_nodes", o.h_nodes, 0, DeonFarFieldMaterial<double>::kMaxNodes);
        if (o.longitudinal != TabulatedLongitudinal::kExact && o.longitudinal != TabulatedLongitudinal::kTable)
            bad("longitudinal", int(o.longitudinal), 0, 1);
        if (o.longitudinal == TabulatedLongitudinal::kTable) {
            if (!(o.m_rows >= 2 && o.m_rows <= TabulatedOptions::kMaxLongitudinalRows))
                bad("m_rows", o.m_rows, 2, TabulatedOptions::kMaxLongitudinalRows);
            if (!(o.m_nodes >= 2 && o.m_nodes <= TabulatedOptions::kMaxLongitudinalNodes))
                bad("m_nodes", o.m_nodes, 2, TabulatedOptions::kMaxLongitudinalNodes);
        }
    }

    FiberParams<T> params_;
    TabulatedOptions options_;
    friend class TabulatedFiber<T>;
    View view_;  // over data_ (set once the tables are built: building appends to data_)
    std::vector<T> data_;
};

// The tabulated far-field fiber. Same frame and convention as the other models: unit
// vectors in the fiber frame (x = tangent), wo toward the viewer, wi toward the light, eval
// with the cosine inside (∫ eval dωi = 1 for σa = 0, exactly at every resolution).
//
//   f(wo, wi) = Σ_{p<3} M_p(θi | θo'_p) Ñ_p(|φ|, cosθo) + M_3(θi | θo) Ã_3(cosθo) / 2π,
//
// Ñ_p the bilinear interpolant of the table (RGB), Ã_3 the linear one of the residual.
// sample picks lobe p with probability ∝ the interpolated channel sum of ∫Ñ_p (Ã_3 for the
// residual), θi from M_p (d'Eon, Marschner & Hanika 2013), and φ by inverting Ñ_p exactly:
// Ñ_p = (1 - t) N_p,row + t N_p,row+1 is a mixture, so a row is picked with probability ∝
// its weighted mass and |φ| drawn from that row's piecewise-linear density by its CDF (a
// quadratic within the cell), the sign of φ with even odds. The density of all this is
// mean(f) / mean(albedo), computed in the same loop as f, so pdf() and sample's pdf agree
// to rounding.
//
// TabulatedLongitudinal::kTable replaces each M_p by lobes/longitudinal_table.hpp's M̂_p,
// conditioned once per wo (θo = asin(wo.x), θo' = θo + angle_p, the row pair and the window
// mass Z: a few table reads per lobe) and read with one bilinear lookup per lobe per wi; the
// furnace stays exactly 1 and sample inverts M̂_p exactly (it uses u.y, not u.z). It pays off
// on a fiber bound by at(wo) (eval ≈ 1.1 u against 1.4 u with exact M_p, bench/
// tabulated_bench.cpp); the stateless eval recomputes the conditioning per call and is slower
// than the exact M_p. Accuracy (fast(), tests/tabulated_test.cpp): relative L1 7.6e-4 against
// the exact far-field model for β_m ∈ [0.2, 1], β_n ≥ 0.3 (4.5e-4 of it is the azimuthal
// table's); the M̂ error concentrates at grazing θo' (> 70°), where rows interpolate lobes
// clipped at |sinθi| = 1 at different places; narrower lobes (β_m < 0.2) need more rows.
//
// Refers to the tables' view by pointer: the material's own (the material must outlive the
// fiber; a temporary is rejected at compile time) or, on a GPU, a view over a device copy
// of the data (material.view(device_copy)) that itself lives in device memory or in the
// kernel's parameters, and outlives the fiber.
template <typename T> class TabulatedFiber : public FiberModel<TabulatedFiber<T>, T> {
  public:
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    using Material = TabulatedMaterial<T>;
    using View = TabulatedView<T>;
    static constexpr int kLobes = View::kLobes;
    using LobeSplit = hairscatter::LobeSplit<T, kLobes>;

    explicit TabulatedFiber(const Material& material) : v_(&material.view_) {}
    TabulatedFiber(const Material&&) = delete;
    HAIRSCATTER_HD explicit TabulatedFiber(const View& view) : v_(&view) {}
    TabulatedFiber(const View&&) = delete;

    HAIRSCATTER_HD const View& view() const { return *v_; }

  private:
    friend class FiberModel<TabulatedFiber, T>;
    friend class BoundFiber<TabulatedFiber>;

    // The terms that depend on wo only.
    struct Outgoing {
        const T* n0;      // the two rows' lobe tables
        const T* n1;
        V3 residual;      // Ã_3 / 2π
        T t;              // weight of the second row
        T s[kLobes + 1];  // interpolated channel sums of the lobe masses
        T total;          // their sum: 3 × mean(albedo)
        T sin_p[kLobes + 1], cos_p[kLobes + 1];  // tilted θo' per lobe
        DeonLanes<T, kLobes + 1> m;               // !kTable: the exact M_p at θo', side by side
        int row;
        typename DeonLongitudinalTable<T>::Conditioned mc[kLobes + 1];  // kTable: M̂_p at θo'
    };

  public:
    // u.x picks the lobe and then the row (its leftover rescaled), (u.y, u.z) sample θi from
    // M_p, u.w samples φ (its sign from u.w < ½). at(wo) computes the row, its weights and
    // the tilted θo' once.

    // Σ_p Ã_p(wo): the directional albedo of the tabulated fiber (its ∫ eval dωi).
    HAIRSCATTER_HD V3 albedo(const V3& wo) const { return split_albedo(lobe_split(wo)); }

    // Per lobe: Ã_p(wo) and the part of the interpolated Ñ_p in |φ - centre| < π/2 (centre 0:
    // the backward half), from each row's φ CDF (exact for the piecewise-linear table: a
    // quadratic within the cell). The table holds |φ| ∈ [0, π] of a density symmetric in φ.
    HAIRSCATTER_HD LobeSplit lobe_split(const V3& wo, T centre = T(0)) const {
        const Outgoing o = outgoing<false>(wo);
        const T* a = v_->row_terms(o.row);
        const T* b = v_->row_terms(o.row + 1);
        LobeSplit r;
        const T c = clamp(centre < T(0) ? -centre : centre, T(0), kPi<T>);  // by symmetry
        const T lo = c - kHalfPi<T>, hi = c + kHalfPi<T>;
        for (int p = 0; p <= kLobes; ++p) {
            for (int ch = 0; ch < 3; ++ch) r.a[p][ch] = a[3 * p + ch] + o.t * (b[3 * p + ch] - a[3 * p + ch]);
            if (p == kLobes) {
                r.backward[p] = T(0.5);  // the residual is uniform in φ
                continue;
            }
            // ∫_0^x of each row's channel sum (x ∈ [0, π]); the row's total is cdf[n - 1].
            auto partial = [&](int k, T x) {
                int i;
                T u;
                v_->phi_cell(x, i, u);
                const T* cdf = v_->cdf(o.row + k, p);
                const T* node = v_->lobes(o.row + k) + 3 * p + i * View::kNodeStride;
                const T n0 = node[0] + node[1] + node[2];
                const T n1 = node[View::kNodeStride] + node[View::kNodeStride + 1] + node[View::kNodeStride + 2];
                return cdf[i] + v_->phi_step() * u * (n0 + T(0.5) * u * (n1 - n0));
            };
            // The arc [lo, hi] in |φ|: [0, -lo] and [0, hi] when lo < 0 (then hi < π); else
            // [lo, min(hi, π)] and, past π, [2π - hi, π]; each |φ| range holds half its mass.
            T half[2], whole[2];
            for (int k = 0; k < 2; ++k) {
                whole[k] = v_->cdf(o.row + k, p)[v_->phi_samples() - 1];
                if (lo < T(0)) {
                    half[k] = T(0.5) * (partial(k, -lo) + partial(k, hi));
                } else {
                    T m = partial(k, hi < kPi<T> ? hi : kPi<T>) - partial(k, lo);
                    if (hi > kPi<T>) m += whole[k] - partial(k, kTwoPi<T> - hi);
                    half[k] = T(0.5) * m;
                }
            }
            const T total = (T(1) - o.t) * whole[0] + o.t * whole[1];
            r.backward[p] = total > T(0) ? ((T(1) - o.t) * half[0] + o.t * half[1]) / total : T(0.5);
        }
        return r;
    }

  private:
    // The same terms serve eval, pdf and sample (pdf = mean(f) / Σ s_p in one loop).
    template <bool kW> HAIRSCATTER_HD Outgoing outgoing(const V3& wo) const {
        Outgoing o;
        const T sin_o = clamp(wo.x, T(-1), T(1));
        const T cos_o = cos_from_sin(sin_o);
        v_->theta_cell(cos_o, o.row, o.t);
        o.n0 = v_->lobes(o.row);
        o.n1 = v_->lobes(o.row + 1);
        const T* a = v_->row_terms(o.row);
        const T* b = v_->row_terms(o.row + 1);
        o.total = T(0);
        for (int p = 0; p <= kLobes; ++p) {
            o.s[p] = a[12 + p] + o.t * (b[12 + p] - a[12 + p]);
            o.total += o.s[p];
        }
        v_->tilt_all(sin_o, cos_o, o.sin_p, o.cos_p);
        if (v_->longitudinal_tabulated()) {
            // The rows are over the angle θo' = θo + angle_p, folded past the poles as
            // rotate() folds cosθo' ≥ 0: one asin per wo.
            const T theta_o = elem::asin(sin_o);
            for (int p = 0; p <= kLobes; ++p) {
                T th = theta_o + v_->tilt().angle(p);
                th = th > kHalfPi<T> ? kPi<T> - th : (th < -kHalfPi<T> ? -kPi<T> - th : th);
                o.mc[p] = v_->longitudinal_table(p).condition(v_->data(), th, o.sin_p[p], o.cos_p[p]);
            }
        } else {
            v_->template condition<LobeSet::kAll>(o.m, sin_o, cos_o);
        }
        for (int c = 0; c < 3; ++c) o.residual[c] = kInvTwoPi<T> * (a[9 + c] + o.t * (b[9 + c] - a[9 + c]));
        return o;
    }

    template <bool kF, bool kPdf>
    HAIRSCATTER_HD HairEvalPdf<T> query(const Outgoing& o, const V3& wo, const V3& wi) const {
        if (!(is_finite(wo) && is_finite(wi))) return HairEvalPdf<T>{};  // non-finite input: 0 (see HairSample)
        const T sin_i = clamp(wi.x, T(-1), T(1));
        const T phi = relative_azimuth(wo, wi);
        return combine(o, sin_i, cos_from_sin(sin_i), phi);
    }

    // f and pdf at (θi, φ): the four M_p, then the bilinear lobes.
    HAIRSCATTER_HD HairEvalPdf<T> combine(const Outgoing& o, T sin_i, T cos_i, T phi) const {
        T m[kLobes + 1];
        if (v_->longitudinal_tabulated())
            for (int p = 0; p <= kLobes; ++p) m[p] = v_->longitudinal_table(p).eval(o.mc[p], sin_i);
        else
            o.m.eval_all(sin_i, cos_i, m);
        int i;
        T u;
        v_->phi_cell(phi < T(0) ? -phi : phi, i, u);
        const T* a = o.n0 + i * View::kNodeStride;
        const T* b = o.n1 + i * View::kNodeStride;
        const T w00 = (T(1) - o.t) * (T(1) - u), w01 = (T(1) - o.t) * u, w10 = o.t * (T(1) - u), w11 = o.t * u;
        V3 f = m[kLobes] * o.residual;
        for (int p = 0; p < kLobes; ++p) {
            V3 n;
            for (int c = 0; c < 3; ++c) {
                const int k = 3 * p + c;
                n[c] = w00 * a[k] + w01 * a[View::kNodeStride + k] + w10 * b[k] + w11 * b[View::kNodeStride + k];
            }
            f += m[p] * n;
        }
        HairEvalPdf<T> r;
        r.f = f;
        // total ≥ the R lobe's F > 0 in every channel, so the division is safe.
        r.pdf = (f.x + f.y + f.z) / o.total;
        return r;
    }

    HAIRSCATTER_HD HairSample<T> sample_from(const Outgoing& o, const V3& wo, const V4& u) const {
        using std::sqrt;
        if (!(is_finite(wo) && is_finite(u))) return HairSample<T>{};  // non-finite input: pdf 0, weight 0
        // Lobe ∝ s_p; the leftover of u.x picks the row below.
        const DiscreteChoice<T> lobe = sample_discrete(o.s, kLobes + 1, u.x, o.total);
        const int p = lobe.index;
        const T v = lobe.rescaled;

        const T sin_i = v_->longitudinal_tabulated()
                            ? v_->longitudinal_table(p).sample_sin_theta(o.mc[p], u.y)
                            : v_->longitudinal(p).sample_sin_theta(o.sin_p[p], o.cos_p[p], u.y, u.z);
        const T cos_i = cos_from_sin(sin_i);
        T phi;
        if (p == kLobes) {
            phi = kTwoPi<T> * u.w - kPi<T>;  // the residual is uniform in φ
        } else {
            // The row, with probability ∝ its interpolation weight × its mass of lobe p.
            const T first = (T(1) - o.t) * v_->row_terms(o.row)[12 + p];
            const T second_mass = o.t * v_->row_terms(o.row + 1)[12 + p];
            const int row = o.row + ((second_mass > T(0) && !(v * o.s[p] < first)) ? 1 : 0);
            phi = sample_phi(row, p, u.w);
        }

        return make_sample(direction_from_azimuth(wo, sin_i, phi), lobe_tag(p), combine(o, sin_i, cos_i, phi));
    }

    // φ from row's lobe p: |φ| by inverting its piecewise-linear CDF, the sign from which
    // half of [0, 1) u falls in.
    HAIRSCATTER_HD T sample_phi(int row, int p, T u) const {
        const int n = v_->phi_samples();
        const T* cdf = v_->cdf(row, p);
        const T* node = v_->lobes(row) + 3 * p;
        const T w = T(2) * u - T(1);
        const T sign = w < T(0) ? T(-1) : T(1);
        const T step = v_->phi_step();
        const PiecewiseLinearPoint<T> x = invert_piecewise_linear(
            [&](int k) { return cdf[k]; },
            [&](int k) {
                const T* c = node + k * View::kNodeStride;
                return c[0] + c[1] + c[2];
            },
            n, step, v_->phi_scale(), (w < T(0) ? -w : w) * cdf[n - 1]);
        return sign * clamp(T(x.cell) * step + x.offset, T(0), kPi<T>);
    }

    const View* v_;
};

static_assert(is_fiber_model_v<TabulatedFiber<float>> && is_fiber_model_v<TabulatedFiber<double>>);

}  // namespace hairscatter
