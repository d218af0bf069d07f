// hairscatter — the tabulated far-field fiber: eval, pdf and sample over a TabulatedView
// (models/tabulated.hpp). Device-callable; the tables are built by
// models/tabulated/material.hpp.
#pragma once

#include <cstddef>

#include <glm/glm.hpp>

#include "../../config.hpp"
#include "../../fiber/frame.hpp"
#include "../../math/constants.hpp"
#include "../../math/distributions.hpp"
#include "../../math/elementary.hpp"
#include "../../math/functions.hpp"
#include "../contract.hpp"
#include "view.hpp"

namespace hairscatter {

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
// on a fiber bound by at(wo); the stateless eval recomputes the conditioning per call and is
// slower than the exact M_p (docs/performance.md quotes the benchmarks). Its error against
// the exact far-field model (tests/tabulated_test.cpp; docs/tradeoff.md) concentrates at
// grazing θo' (> 70°), where rows interpolate lobes clipped at |sinθi| = 1 at different
// places; narrower lobes (β_m < 0.2) need more rows.
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
        T s[std::size_t(kLobes + 1)];  // interpolated channel sums of the lobe masses (outgoing<true>)
        T total;          // their sum: 3 × mean(albedo) (outgoing<true>)
        T sin_p[std::size_t(kLobes + 1)], cos_p[std::size_t(kLobes + 1)];  // tilted θo' per lobe
        DeonLanes<T, kLobes + 1> m;               // !kTable: the exact M_p at θo', side by side
        int row;
        typename DeonLongitudinalTable<T>::Conditioned mc[std::size_t(kLobes + 1)];  // kTable: M̂_p at θo'
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
    // A non-finite or zero wo gives no energy (so albedo 0); other lengths are normalised.
    HAIRSCATTER_HD LobeSplit lobe_split(V3 wo, T centre = T(0)) const {
        if (!unit_direction(wo)) return empty_lobe_split<T, kLobes>();
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
            auto partial = [&](int k, T x) { return v_->phi_mass(o.row + k, p, x); };
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
    template <bool kW> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE Outgoing outgoing(const V3& wo) const {
        Outgoing o;
        const T sin_o = clamp(wo.x, T(-1), T(1));
        const T cos_o = cos_from_sin(sin_o);
        v_->theta_cell(cos_o, o.row, o.t);
        o.n0 = v_->lobes(o.row);
        o.n1 = v_->lobes(o.row + 1);
        const T* a = v_->row_terms(o.row);
        const T* b = v_->row_terms(o.row + 1);
        if constexpr (kW) {  // the lobe masses: pdf and sample only
            o.total = T(0);
            for (int p = 0; p <= kLobes; ++p) {
                o.s[p] = a[12 + p] + o.t * (b[12 + p] - a[12 + p]);
                o.total += o.s[p];
            }
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
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE HairEvalPdf<T> query(const Outgoing& o, const V3& wo, const V3& wi) const {
        // Finite wo and wi: FiberModel and BoundFiber (models/contract.hpp) check before calling.
        const T sin_i = clamp(wi.x, T(-1), T(1));
        const T phi = relative_azimuth(wo, wi);
        return combine<kPdf>(o, sin_i, cos_from_sin(sin_i), phi);
    }

    // f and (kPdf) pdf at (θi, φ): the four M_p, then the bilinear lobes.
    template <bool kPdf>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE HairEvalPdf<T> combine(const Outgoing& o, T sin_i, T cos_i, T phi) const {
        T m[std::size_t(kLobes + 1)];
        if (v_->longitudinal_tabulated())
            for (int p = 0; p <= kLobes; ++p) m[p] = v_->longitudinal_table(p).eval(o.mc[p], sin_i);
        else
            o.m.eval_all(sin_i, cos_i, m);
        int i;
        T u;
        v_->phi_cell(abs_value(phi), i, u);
        const T* a = o.n0 + i * View::kNodeStride;
        const T* b = o.n1 + i * View::kNodeStride;
        const T w00 = (T(1) - o.t) * (T(1) - u), w01 = (T(1) - o.t) * u, w10 = o.t * (T(1) - u), w11 = o.t * u;
        // The 9 values of a node as a loop of 8 over plain arrays (one AVX vector, two SSE:
        // at -O2 GCC vectorises only loops without a remainder) and the 9th apart, then
        // weighted by M_p.
        constexpr int S = View::kNodeStride, kVec = S & ~3;
        T n[std::size_t(S)];
        for (int k = 0; k < kVec; ++k) n[k] = w00 * a[k] + w01 * a[S + k] + w10 * b[k] + w11 * b[S + k];
        for (int k = kVec; k < S; ++k) n[k] = w00 * a[k] + w01 * a[S + k] + w10 * b[k] + w11 * b[S + k];
        V3 f = m[kLobes] * o.residual;
        for (int p = 0; p < kLobes; ++p) f += m[p] * V3(n[3 * p], n[3 * p + 1], n[3 * p + 2]);
        HairEvalPdf<T> r;
        r.f = f;
        // total ≥ the R lobe's F > 0 without lobe controls; zero gains can make it 0.
        if constexpr (kPdf) r.pdf = o.total > T(0) ? (f.x + f.y + f.z) / o.total : T(0);
        return r;
    }

    HAIRSCATTER_HD HairSample<T> sample_from(const Outgoing& o, const V3& wo, const V4& u) const {
        using std::sqrt;
        if (!all_finite(wo, u)) return HairSample<T>{};  // non-finite input: pdf 0, weight 0
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
            phi = v_->sample_phi(row, p, u.w);
        }

        const V3 wi = direction_from_azimuth(wo, sin_i, phi);
        return make_sample(wi, lobe_tag(p), combine<true>(o, sin_i, cos_i, queried_azimuth(wo, wi, cos_i, phi)));
    }

    const View* v_;
};

static_assert(is_fiber_model_v<TabulatedFiber<float>> && is_fiber_model_v<TabulatedFiber<double>>);

}  // namespace hairscatter
