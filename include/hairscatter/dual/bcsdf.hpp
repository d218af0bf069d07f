// hairscatter — the dual-scattering BCSDF at a shading point (Zinke et al. 2008 §4; the
// improved formulation of docs/dual.md) over any single-fiber model, with eval, pdf and
// sample, and importance sampling of the whole BCSDF as one mixture of its lobes (the
// origin study's contribution) whose density does not depend on the light state: a
// renderer samples a direction first and learns whether hair shadows it afterwards.
#pragma once

#include <cmath>
#include <cstddef>
#include <type_traits>
#include <utility>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../fiber/frame.hpp"
#include "../lobes/longitudinal.hpp"
#include "../math/constants.hpp"
#include "../math/distributions.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"
#include "../models/contract.hpp"
#include "settings.hpp"
#include "tables.hpp"

namespace hairscatter {

// Which component of the dual BCSDF's mixture drew a sample (kSingle: the fiber model's
// own sampler; the model's lobe is not reported).
enum class DualComponent : int { kSingle = 0, kBack = 1, kGlobal = 2, kGlobalBack = 3, kUniform = 4 };

template <typename T> struct DualSample {
    glm::vec<3, T> wi{T(0)};
    T pdf = T(0);  // solid-angle density of the mixture; 0: no sample
    DualComponent component = DualComponent::kSingle;
    // Filled by the samplers that take the light state (sample(u, light), sample_with(u,
    // light_of)): f = eval(wi, light) and the path's throughput factor weight = f / pdf, as
    // HairSample::weight; 0 from sample(u) alone, which cannot know the light state.
    glm::vec<3, T> f{T(0)};
    glm::vec<3, T> weight{T(0)};
};

// The light that reaches a shadowed point, and its spread σ̄²_f, from the count n toward the
// light. The density source's n is an unconditional expectation, and a shadow ray that hit
// hair says at least one fiber lies in the way: for a Poisson count of mean n,
// E[N | N ≥ 1] = n / (1 - e^{-n}) (→ 1 as n → 0). Improved: the direct forward-scattered
// light is attenuated by a_f^{E[N | N ≥ 1]} and spread by E[N | N ≥ 1] β̄²_f; the hair below
// the point is driven by the downward flux of the 1D adding model of the layers above and
// below, T_n / (1 - R_n R_{m+1}), which also counts the light the hair below sends back up
// and the layers above return (lossless hair: the flux stays 1 at every depth).
// Zinke 2008 eq. 6: a_f^n with the unconditional n for both.
// The largest forward spread σ̄²_f used (a variance in rad²): M with a variance this wide is
// uniform in θ to rounding, and an infinite one (a renderer's Σ β̄²_f over unbounded hair)
// would turn M into ∞ · 0.
template <typename T> inline constexpr T kMaxForwardSpread = T(1e6);

template <typename T> struct DualForward {
    glm::vec<3, T> transmittance{T(1)};
    glm::vec<3, T> flux{T(1)};  // improved: the downward flux T_n / (1 - R_n R_{m+1}) that drives f_back^G
    T spread = T(0);  // σ̄²_f, channel mean
};
// The layer coefficients of an entry's three channels (κ and friends, tables.hpp), shared
// by every stack the BCSDF builds at one lookup: lanes 0–2 the channels, lane 3 an opaque
// padding layer (four lanes, one SSE vector in float).
template <typename T> struct DualLayers {
    static constexpr int kLanes = 4;
    LayerLanes<T, kLanes> c;
    // R_N and T_N of the three channels at one depth.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void stacks(T layers, glm::vec<3, T>& R, glm::vec<3, T>& T_) const {
        const T depth[kLanes] = {layers, layers, layers, layers};
        T r[kLanes], t[kLanes];
        layered_stacks(c, depth, r, t);
        R = glm::vec<3, T>(r[0], r[1], r[2]);
        T_ = glm::vec<3, T>(t[0], t[1], t[2]);
    }
    // The same at two depths a and b as one batch of eight lanes where that is one vector
    // (float with AVX; elsewhere, where eight lanes cost twice four, two batches of four):
    // the lanes do what two calls of stacks() would, so the results are the same.
#if defined(__AVX__) && !defined(__CUDA_ARCH__)
    static constexpr bool kTwoDepthBatch = std::is_same<T, float>::value;
#else
    static constexpr bool kTwoDepthBatch = false;
#endif
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void stacks(T a, T b, glm::vec<3, T>& R_a, glm::vec<3, T>& T_a,
                                                        glm::vec<3, T>& R_b) const {
        if constexpr (!kTwoDepthBatch) {
            glm::vec<3, T> T_b;
            stacks(a, R_a, T_a);
            stacks(b, R_b, T_b);
            return;
        }
        LayerLanes<T, 2 * kLanes> c2;
        repeat_lanes(c, c2);
        T depth[2 * kLanes], r[2 * kLanes], t[2 * kLanes];
        elem::store8(depth, a, a, a, a, b, b, b, b);
        layered_stacks(c2, depth, r, t);
        R_a = glm::vec<3, T>(r[0], r[1], r[2]);
        T_a = glm::vec<3, T>(t[0], t[1], t[2]);
        R_b = glm::vec<3, T>(r[4], r[5], r[6]);
    }
};
// R and T of the layers above a shadowed point (dual_forward's, when its caller made them).
template <typename T> struct DualAbove {
    glm::vec<3, T> R, T_;
};
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE DualLayers<T> dual_layers(const DualScatteringEntry<T>& e) {
    DualLayers<T> l;
    elem::store4(l.c.a_f, e.a_f.x, e.a_f.y, e.a_f.z, T(0));  // whole (elem::store4)
    elem::store4(l.c.a_b, e.a_b.x, e.a_b.y, e.a_b.z, T(0));
    layer_lanes(l.c);
    return l;
}
// The depth of the stack below a point, m + 1, from the fibers beyond it (NaN → m = 0).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T dual_below_depth(T beyond) {
    const T m = is_finite(beyond) ? (beyond > T(0) ? beyond : T(0)) : (beyond > T(0) ? T(1e12) : T(0));
    return m + T(1);
}
template <typename T>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE glm::vec<3, T> dual_below_reflectance(const DualLayers<T>& l, T beyond) {
    glm::vec<3, T> R, T_;
    l.stacks(dual_below_depth(beyond), R, T_);
    return R;
}
// The light's fiber count n, clamped: NaN → 0; beyond a million fibers nothing gets
// through, and the spread stays finite.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T dual_count(const DualScatteringLight<T>& light) {
    return !is_finite(light.n) ? (light.n > T(0) ? T(1e6) : T(0)) : clamp(light.n, T(0), T(1e6));
}
// E[N | N ≥ 1] = n / (1 - e^{-n}) of a Poisson count of mean n ≥ 0 (1 as n → 0).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T dual_count_given_hit(T n) {
    const T q = -elem::expm1(-n);  // P(N ≥ 1)
    return q > T(1e-6) ? n / q : T(1);
}
// The count of fibers in front of a shadowed point that the improved formulation uses: an
// expectation conditioned on the blocked shadow ray, or an exact count as it is (at least 1:
// the ray was blocked).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T dual_shadowed_count(const DualScatteringLight<T>& light) {
    const T n = dual_count(light);
    return light.exact_count ? (n > T(1) ? n : T(1)) : dual_count_given_hit(n);
}
template <typename T>
HAIRSCATTER_HD glm::vec<3, T> dual_below_reflectance(const DualScatteringEntry<T>& e, T beyond) {
    return dual_below_reflectance(dual_layers(e), beyond);
}
// below_R: R_{m+1} of dual_below_reflectance (improved only; computed here if negative);
// layers: the entry's dual_layers (computed here if null); above: the stack of depth
// dual_shadowed_count(light) of those layers (computed here if null).
template <typename T>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE DualForward<T>
dual_forward(const DualScatteringLight<T>& light, const DualScatteringEntry<T>& e, DualFormulation formulation,
             glm::vec<3, T> below_R = glm::vec<3, T>(T(-1)), const DualLayers<T>* layers = nullptr,
             const DualAbove<T>* above = nullptr) {
    using std::pow;
    DualForward<T> r;
    const T beta2 = (e.beta2_f.x + e.beta2_f.y + e.beta2_f.z) * T(1.0 / 3.0);
    if (light.use_transmittance) {
        // A NaN transmittance lets nothing through, as a NaN count does below.
        for (int c = 0; c < 3; ++c) r.transmittance[c] = is_finite(light.T_f[c]) ? clamp(light.T_f[c], T(0), T(1))
                                                                               : (light.T_f[c] > T(0) ? T(1) : T(0));
        r.spread = light.sigma2_f > T(0) ? (light.sigma2_f < kMaxForwardSpread<T> ? light.sigma2_f : kMaxForwardSpread<T>)
                                         : T(0);
        return r;
    }
    const T n0 = dual_count(light);
    if (formulation == DualFormulation::kZinke2008) {
        for (int c = 0; c < 3; ++c) r.transmittance[c] = pow(e.a_f[c], n0);
        r.spread = n0 * beta2;
        return r;
    }
    const T n = dual_shadowed_count(light);
    glm::vec<3, T> above_R, above_T;
    if (above && below_R.x >= T(0)) {
        above_R = above->R;
        above_T = above->T_;
    } else {
        const DualLayers<T> l = layers ? *layers : dual_layers(e);
        if (below_R.x < T(0)) below_R = dual_below_reflectance(l, light.beyond);
        l.stacks(n, above_R, above_T);
    }
    T a_f[4];
    elem::store4(a_f, e.a_f.x, e.a_f.y, e.a_f.z, T(1));
    elem::pow_each(a_f, n);  // n ≥ 1
    for (int c = 0; c < 3; ++c) {
        const T den = T(1) - above_R[c] * below_R[c];
        r.flux[c] = den > T(0) ? clamp(above_T[c] / den, T(0), T(1)) : T(1);
        r.transmittance[c] = a_f[c];
    }
    r.spread = n * beta2;
    return r;
}

// The local backscattering amplitude at a point with `beyond` fibers behind it along the
// light's direction of travel. Zinke 2008 eqs. 13–14: A_b = A_1 + A_3 of a deep volume.
// Improved: the same A_b scaled by the 1D adding formula's finite-depth factor
// (R_{m+1} - a_b) / (R_∞ - a_b), the share of a deep volume's multiple backscattering that
// the point's layer and the m layers after it return. below_R is R_{m+1}.
template <typename T>
HAIRSCATTER_HD glm::vec<3, T> dual_backscatter_scaled(const DualScatteringEntry<T>& e, const DualLayers<T>& l,
                                                      const glm::vec<3, T>& below_R) {
    glm::vec<3, T> r;
    for (int c = 0; c < 3; ++c) {
        const T deep = deep_reflectance(l.c.a_f[c], l.c.a_b[c], l.c.e_k[c]) - e.a_b[c];
        const T here = below_R[c] - e.a_b[c];
        r[c] = deep > T(1e-12) && here > T(0) ? e.A_b[c] * clamp(here / deep, T(0), T(1)) : T(0);
    }
    return r;
}
template <typename T>
HAIRSCATTER_HD glm::vec<3, T> dual_backscatter_scaled(const DualScatteringEntry<T>& e, const glm::vec<3, T>& below_R) {
    return dual_backscatter_scaled(e, dual_layers(e), below_R);
}
template <typename T>
HAIRSCATTER_HD glm::vec<3, T> dual_backscatter(const DualScatteringEntry<T>& e, T beyond, DualFormulation formulation) {
    if (formulation == DualFormulation::kZinke2008) return e.A_b;
    return dual_backscatter_scaled(e, dual_below_reflectance(e, beyond));
}

// The dual-scattering BCSDF of one hit, in the library's convention (cosine inside:
// Lo = ∫ eval Li dωi). With df the direct fraction, s = the tables' settings:
//   F = df (f_s + d_b f_back) + (1 - df) d_f (T_f f_s^G + D d_b f_back^G)       (improved)
//   F = df (f_s + d_b f_back) + max(0, T_f - df) d_f (f_s^G + π d_b f_back^G)  (Zinke 2008)
//   f_back   = k A_b M(σ_b²; θi, θo - Δ_b) / π                  on |ψ| < π/2
//              (A_b = A_1 + A_3; improved: k = 2 and A_b scaled by (R_{m+1} - a_b)/(R_∞ - a_b);
//               Zinke: k = 1, the normalised reading of f_back)
//   f_s^G    = Σ_p M(v_p + σ̄²_f; θi, θo'_p) W_p(θo, ψ)          improved: every ψ
//            = Σ_p M(v_p + σ̄²_f; θi, θo'_p) W_p(θo, π)          Zinke: |ψ| > π/2 only
//   f_back^G = k A_b M(σ_b² + σ̄²_f; θi, θo - Δ_b) (π - |ψ|) / π² improved (f_back's half-
//              circle convolved with the half-circle the forward light is spread over)
//            = A_b M(σ_b² + σ̄²_f; θi, θo - Δ_b) / π on |ψ| < π/2 Zinke
// where ψ is the relative azimuth of wi, A_b, Δ_b, σ_b, a_f, β̄²_f are read at θi and W_p at
// θo. The longitudinal lobes are d'Eon et al. 2011's normalised M (so f_back integrates to
// A_b), and the widening variances are the channel mean.
//
// The fiber is held by value (models keep a pointer to their material); the tables' arrays
// must outlive this object (a view of them is held: tables are per material).
template <typename Fiber> class DualScatteringBcsdf {
  public:
    using V3 = typename Fiber::V3;
    using T = typename V3::value_type;
    using V4 = glm::vec<4, T>;
    using Entry = DualScatteringEntry<T>;
    using View = DualTablesView<T>;
    using FiberAt = decltype(std::declval<const Fiber&>().at(std::declval<const V3&>()));
    static constexpr int kMaxLobes = View::kMaxLobes;
    // The lanes of the longitudinal lobes (At::lobe_lanes): the global lobes, then f_back's
    // and f_back^G's, padded to a whole vector in float.
    static constexpr int kBackLane = kMaxLobes, kGlobalBackLane = kMaxLobes + 1;
    static constexpr int kLanes = elem::exp_batch<T>(kMaxLobes + 2);
    using Lanes = DeonLanes<T, kLanes>;
    // Zinke et al. 2008 eq. 14 writes f_back = 2 A_b g(…) / (π cos²θd): the factor 2 is kept in
    // the improved formulation, where with d'Eon's normalised M it doubles the backscattered
    // energy — measured against path-traced slabs of explicit fibers (tests/dual_slab_test.cpp)
    // the lit points' multiple scattering is otherwise half of what the path tracer finds.
    // The Zinke formulation keeps this library's earlier normalised reading (factor 1).

    HAIRSCATTER_HD DualScatteringBcsdf(const Fiber& fiber, const View& tables) : fiber_(fiber), tables_(tables) {}
    DualScatteringBcsdf(const Fiber& fiber, const DualScatteringTables<T>& tables) : fiber_(fiber), tables_(tables.view()) {}

    // Everything that depends on wo, computed once per hit. spread is the forward variance
    // σ̄²_f the sampler widens its global lobes by (a hint such as n β̄²_f toward the main
    // light; 0 if unknown): it shapes the density, never the value.
    class At {
      public:
        // Non-finite or zero directions (or such a wo) give 0, never NaN or an out-of-table
        // read; finite ones of any other length are normalised, as the models do.
        HAIRSCATTER_HD V3 eval(V3 wi, const DualScatteringLight<T>& light) const {
            if (!(valid_ && unit_direction(wi))) return V3(T(0));
            return value(wi, relative_azimuth(wo_, wi), light, single_.eval(wi));
        }
        HAIRSCATTER_HD T pdf(V3 wi) const {
            if (!(valid_ && unit_direction(wi))) return T(0);
            return density(wi, relative_azimuth(wo_, wi), single_.pdf(wi));
        }
        HAIRSCATTER_HD const V3& wo() const { return wo_; }

        // The sample with its value and weight under a known light state (a path that
        // continues along it): one call instead of sample, then eval.
        HAIRSCATTER_HD DualSample<T> sample(const V4& u, const DualScatteringLight<T>& light) const {
            return weighted(sample(u), light);
        }
        // The same where the light state depends on the sampled direction: light_of(wi)
        // returns it for wi in the fiber frame (e.g. dual_light(grid, x, frame.to_world(wi),
        // direct_fraction), with the renderer's shadow ray along wi for direct_fraction).
        // Called once, and only when there is a sample.
#if defined(__NVCC__)
#pragma nv_exec_check_disable
#endif
        template <typename LightOf> HAIRSCATTER_HD DualSample<T> sample_with(const V4& u, LightOf&& light_of) const {
            DualSample<T> r = sample(u);
            if (!(r.pdf > T(0))) return r;
            return weighted(r, light_of(r.wi));
        }

        // u.x picks the component and, rescaled, the lobe inside it; (u.y, u.z) sample θi,
        // u.w the azimuth (and, rescaled, its sign).
        // Non-finite u (or wo) gives no sample (pdf 0).
        HAIRSCATTER_HD DualSample<T> sample(const V4& u) const {
            DualSample<T> r;
            if (!(valid_ && is_finite(u))) return r;
            const DiscreteChoice<T> c = sample_discrete(w_, 5, clamp(u.x, T(0), T(1)), T(1));
            r.component = DualComponent(c.index);
            T sin_i, phi;
            if (c.index == 4) {
                sin_i = T(1) - T(2) * clamp(u.y, T(0), T(1));
                phi = kTwoPi<T> * clamp(u.z, T(0), T(1)) - kPi<T>;
            } else if (c.index == 0) {
                // The model's own sample: its pdf is the mixture's single-fiber term.
                const auto s = single_.sample(V4(c.rescaled, u.y, u.z, u.w));
                if (!(s.pdf > T(0) && finite(s.wi))) return r;
                r.wi = s.wi;
                r.pdf = density(r.wi, relative_azimuth(wo_, r.wi), s.pdf);
                if (!(r.pdf > T(0))) r.pdf = T(0);
                return r;
            } else if (c.index == 2) {
                const DiscreteChoice<T> l = sample_discrete(g_, kMaxLobes, c.rescaled, T(1));
                const int p = l.index;
                sin_i = DeonLongitudinal<T>(t_.lobe_variance[p] + s2_spread_).sample_sin_theta(sin_l_[p], cos_l_[p], u.y, u.z);
                if (improved()) {
                    // |ψ| from the row's piecewise-linear W̄_p, the sign from u.w's first half.
                    const bool negative = u.w < T(0.5);
                    const T v = clamp(negative ? T(2) * u.w : T(2) * u.w - T(1), T(0), T(1));
                    const T h = kPi<T> / T(t_.n_psi - 1);
                    const std::size_t base = t_.window_index(row_, p, 0);
                    const auto pt = invert_piecewise_linear<T>(
                        [&](int k) { return t_.window_cdf[base + std::size_t(k)]; },
                        [&](int k) {
                            const V3& w = t_.window[base + std::size_t(k)];
                            return (w.x + w.y + w.z) * T(1.0 / 3.0);
                        },
                        t_.n_psi, h, T(1) / h, v * total_[p]);
                    const T a = clamp(T(pt.cell) * h + pt.offset, T(0), kPi<T>);
                    phi = negative ? -a : a;
                } else {
                    const T half = kPi<T> * (u.w - T(0.5));  // uniform over the forward half
                    phi = half >= T(0) ? kPi<T> - half : -kPi<T> - half;
                }
            } else {
                const T var = c.index == 1 ? s2_back_ : s2_back_ + s2_spread_;
                sin_i = DeonLongitudinal<T>(var).sample_sin_theta(sin_back_, cos_back_, u.y, u.z);
                if (c.index == 3 && improved()) {
                    // the triangle (π - |ψ|)/π² on [-π, π], by inversion
                    const T w = clamp(u.w, T(0), T(1));
                    phi = w < T(0.5) ? kPi<T> * (safe_sqrt(T(2) * w) - T(1)) : kPi<T> * (T(1) - safe_sqrt(T(2) - T(2) * w));
                } else {
                    phi = kPi<T> * (u.w - T(0.5));  // uniform over the backward half
                }
            }
            r.wi = direction_from_azimuth(wo_, clamp(sin_i, T(-1), T(1)), phi);
            r.pdf = pdf(r.wi);
            if (!(r.pdf > T(0))) r.pdf = T(0);
            return r;
        }

      private:
        friend class DualScatteringBcsdf;
        HAIRSCATTER_HD DualSample<T> weighted(DualSample<T> r, const DualScatteringLight<T>& light) const {
            if (!(r.pdf > T(0))) return r;
            r.f = eval(r.wi, light);
            r.weight = r.f / r.pdf;
            if (!finite(r.weight)) r.f = r.weight = V3(T(0));
            return r;
        }
        HAIRSCATTER_HD bool improved() const { return t_.settings.formulation == DualFormulation::kImproved; }
        static HAIRSCATTER_HD T mean(const V3& v) { return (v.x + v.y + v.z) * T(1.0 / 3.0); }
        // Read from the bits (math/functions.hpp), so that -ffast-math cannot fold it away.
        static HAIRSCATTER_HD bool finite(const V3& v) { return is_finite(v); }

        // with_mixture: also the sampler's mixture (pdf and sample need it, eval not).
        HAIRSCATTER_HD At(const DualScatteringBcsdf& d, const V3& wo, T spread, bool with_mixture = true)
            : t_(d.tables_), single_(d.fiber_.at(wo)), wo_(single_.wo()), valid_(single_.valid()) {
            const T so = clamp(wo_.x, T(-1), T(1));
            sin_o_ = is_finite(so) ? so : T(0);
            cos_o_ = cos_from_sin(sin_o_);
            theta_o_ = elem::asin(sin_o_);
            node_o_ = t_.node_of_angle(theta_o_);
            cell_o_ = t_.cell_of_node(node_o_);
            row_ = cell_o_.t < T(0.5) ? cell_o_.i : cell_o_.i + 1;
            for (int p = 0; p < kMaxLobes; ++p) t_.rotate(p, sin_o_, cos_o_, sin_l_[p], cos_l_[p]);
            if (with_mixture) mixture(single_.albedo(), spread);  // from the bound terms
        }

        HAIRSCATTER_HD void mixture(const V3& albedo, T spread) {
            const DualScatteringSettings<T>& s = t_.settings;

            // The backscattering lobe's shape at the specular cone θi = -θo, where the light
            // that returns toward wo is concentrated.
            const typename View::Cell ce = t_.cell_of_node(-node_o_);  // θ = -θo
            T sb, cb;
            elem::sincos(theta_o_ - mean(t_.lookup_field(ce, Entry::kFieldDelta_b)), sb, cb);
            sin_back_ = sb;
            cos_back_ = cb < T(0) ? -cb : cb;
            const T s2b = mean(t_.lookup_field(ce, Entry::kFieldSigma2_b));
            s2_back_ = s2b > T(1e-6) ? s2b : T(1e-6);
            s2_spread_ = spread > T(0) ? (spread < kMaxForwardSpread<T> ? spread : kMaxForwardSpread<T>) : T(0);
            // A deep volume's A_b (the finite-depth factor is 1): the table value.
            const T ab = (improved() ? T(2) : T(1)) * mean(t_.lookup_field(ce, Entry::kFieldA_b));

            T gsum = T(0);
            const std::size_t last = t_.window_index(row_, 0, t_.n_psi - 1);  // lobe p's: last + p n_psi
            for (int p = 0; p < kMaxLobes; ++p) {
                const std::size_t at_pi = last + std::size_t(p) * std::size_t(t_.n_psi);
                total_[p] = p < t_.lobes ? t_.window_cdf[at_pi] : T(0);
                // improved: the lobe's mass over every ψ; Zinke: the forward half at W_p(π).
                g_[p] = p >= t_.lobes ? T(0) : improved() ? total_[p] : kHalfPi<T> * mean(t_.window[at_pi]);
                gsum += g_[p];
            }
            for (int p = 0; p < kMaxLobes; ++p) g_[p] = gsum > T(0) ? g_[p] / gsum : T(p == 0);

            // Half the samples as for a directly lit point, half as for a shadowed one, after a
            // small uniform share that bounds the weight where the hint's lobes are too narrow.
            const T lit[2] = {mean(albedo), s.d_b * ab};
            const T shadow[2] = {gsum, s.d_b * ab * (improved() ? T(1) : kPi<T>)};
            const T lit_sum = lit[0] + lit[1], shadow_sum = shadow[0] + shadow[1];
            const T half_lit = (shadow_sum > T(0) ? T(0.5) : T(1)) * (T(1) - kUniformShare);
            for (int k = 0; k < 2; ++k) {
                w_[k] = lit_sum > T(0) ? half_lit * lit[k] / lit_sum : (k == 0 ? half_lit : T(0));
                w_[2 + k] = shadow_sum > T(0) ? (T(1) - kUniformShare - half_lit) * shadow[k] / shadow_sum : T(0);
            }
            w_[4] = kUniformShare;
            lobe_lanes(pdf_lanes_, s2_spread_, s2_back_, sin_back_, cos_back_);
        }

        // Every longitudinal lobe of the BCSDF as one set of lanes, evaluated per θi in one
        // batch: lane p < kMaxLobes the global lobe p (variance v_p + spread, at θo'_p),
        // kBackLane f_back's (σ_b², at θo - Δ_b), kGlobalBackLane f_back^G's (σ_b² + spread,
        // there); the lanes of absent lobes and the padding hold a unit lobe nothing reads.
        HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void lobe_lanes(Lanes& m, T spread, T s2b, T sb, T cb) const {
            static_assert(kMaxLobes == 4 && kBackLane == 4 && kGlobalBackLane == 5 && (kLanes == 6 || kLanes == 8),
                          "the lane layout below");
            // Each array written whole (elem::store4, store8): set() reads them as vectors.
            T v[std::size_t(kLanes)], s[std::size_t(kLanes)], c[std::size_t(kLanes)];
            const auto lobe = [&](int p, T value, T unit) { return p < t_.lobes ? value : unit; };
            const T v0 = lobe(0, t_.lobe_variance[0] + spread, T(1)), v1 = lobe(1, t_.lobe_variance[1] + spread, T(1)),
                    v2 = lobe(2, t_.lobe_variance[2] + spread, T(1)), v3 = lobe(3, t_.lobe_variance[3] + spread, T(1));
            const T s0 = lobe(0, sin_l_[0], T(0)), s1 = lobe(1, sin_l_[1], T(0)), s2 = lobe(2, sin_l_[2], T(0)),
                    s3 = lobe(3, sin_l_[3], T(0));
            const T c0 = lobe(0, cos_l_[0], T(1)), c1 = lobe(1, cos_l_[1], T(1)), c2 = lobe(2, cos_l_[2], T(1)),
                    c3 = lobe(3, cos_l_[3], T(1));
            if constexpr (kLanes == 8) {
                elem::store8(v, v0, v1, v2, v3, s2b, s2b + spread, T(1), T(1));
                elem::store8(s, s0, s1, s2, s3, sb, sb, T(0), T(0));
                elem::store8(c, c0, c1, c2, c3, cb, cb, T(1), T(1));
            } else {
                elem::store4(v, v0, v1, v2, v3);
                elem::store4(s, s0, s1, s2, s3);
                elem::store4(c, c0, c1, c2, c3);
                v[kBackLane] = s2b;
                v[kGlobalBackLane] = s2b + spread;
                s[kBackLane] = s[kGlobalBackLane] = sb;
                c[kBackLane] = c[kGlobalBackLane] = cb;
            }
            m.set(v, s, c);
        }

        // Σ_p g_p m[p] × the global lobe p's density over ψ ∈ [-π, π] (the sampler's row of
        // W̄_p, normalised), with the ψ cell and the row found once for every lobe.
        HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T window_pdf_sum(T abs_psi, const T* m) const {
            const typename View::Cell q = t_.psi_cell(abs_psi);
            const V3* w = t_.window + t_.window_index(row_, 0, q.i);
            T g = T(0);
            for (int p = 0; p < t_.lobes; ++p, w += t_.n_psi) {
                if (!(g_[p] > T(0) && total_[p] > T(0))) continue;
                const T a = mean(w[0]), b = mean(w[1]);
                const T az = T(0.5) * (a + q.t * (b - a)) / total_[p];
                if (az > T(0)) g += g_[p] * az * m[p];
            }
            return g;
        }

        HAIRSCATTER_HD T density(const V3& wi, T psi, T pdf_single) const {
            const T sin_i = clamp(wi.x, T(-1), T(1)), cos_i = cos_from_sin(sin_i);
            const T a = abs_value(psi);
            const bool backward = a < kHalfPi<T>;
            T m[std::size_t(kLanes)];
            pdf_lanes_.eval_all(sin_i, cos_i, m);
            T pdf = w_[4] * T(0.25) * kInvPi<T> + w_[0] * pdf_single;
            if (w_[1] > T(0) && backward) pdf += w_[1] * m[kBackLane] * kInvPi<T>;
            if (w_[2] > T(0)) {
                T g = T(0);
                if (improved()) {
                    g = window_pdf_sum(a, m);
                } else if (!backward) {  // Zinke: uniform over the forward half
                    for (int p = 0; p < t_.lobes; ++p)
                        if (g_[p] > T(0)) g += g_[p] * kInvPi<T> * m[p];
                }
                pdf += w_[2] * g;
            }
            if (w_[3] > T(0)) {
                const T az = improved() ? (kPi<T> - a) * kInvPi<T> * kInvPi<T> : (backward ? kInvPi<T> : T(0));
                if (az > T(0)) pdf += w_[3] * az * m[kGlobalBackLane];
            }
            return pdf;
        }

        // Not inlined (config.hpp): inlined, GCC de-vectorises its loops in the caller.
        HAIRSCATTER_HD HAIRSCATTER_NOINLINE V3 value(const V3& wi, T psi, const DualScatteringLight<T>& light, const V3& f_single) const {
            const DualScatteringSettings<T>& s = t_.settings;
            const T kBack = improved() ? T(2) : T(1);
            const T sin_i = clamp(wi.x, T(-1), T(1)), cos_i = cos_from_sin(sin_i);
            const T a = abs_value(psi);
            const bool backward = a < kHalfPi<T>;
            const T df = is_finite(light.direct_fraction) ? clamp(light.direct_fraction, T(0), T(1)) : T(0);
            const Entry ei = t_.lookup(sin_i);
            T sb, cb;
            elem::sincos(theta_o_ - mean(ei.delta_b), sb, cb);
            cb = cb < T(0) ? -cb : cb;
            const T s2b = mean(ei.sigma2_b) > T(1e-6) ? mean(ei.sigma2_b) : T(1e-6);
            const bool lit_back = df > T(0) && backward;
            const bool shadowed = df < T(1);
            if (!(lit_back || shadowed)) return df * f_single;
            // A_b: Zinke's table value, scaled by the depth of hair beyond (R_{m+1} shared with D).
            V3 below_R(T(-1)), ab = ei.A_b;
            DualLayers<T> layers;
            DualAbove<T> above;
            bool have_above = false;
            if (improved()) {
                layers = dual_layers(ei);
                if (shadowed && !light.use_transmittance) {
                    // The stacks above (dual_forward's) and below as one batch.
                    layers.stacks(dual_shadowed_count(light), dual_below_depth(light.beyond), above.R,
                                  above.T_, below_R);
                    have_above = true;
                } else {
                    below_R = dual_below_reflectance(layers, light.beyond);
                }
                ab = dual_backscatter_scaled(ei, layers, below_R);
            }

            // The global terms' scales (0 when lit: then only f_back is evaluated).
            DualForward<T> fw;
            V3 scale(T(0)), scale_back(T(0));
            if (shadowed) {
                fw = dual_forward(light, ei, s.formulation, below_R, improved() ? &layers : nullptr,
                                  have_above ? &above : nullptr);
                if (improved()) {
                    scale = (T(1) - df) * s.d_f * fw.transmittance;
                    scale_back = (T(1) - df) * s.d_f * fw.flux;
                } else {
                    for (int c = 0; c < 3; ++c)
                        scale[c] = fw.transmittance[c] > df ? (fw.transmittance[c] - df) * s.d_f : T(0);
                    scale_back = scale;
                }
            }
            const bool global = scale_back.x > T(0) || scale_back.y > T(0) || scale_back.z > T(0);
            V3 f = df * f_single;
            if (!global) {
                // Lit (or no global light left): f_back's one lobe, not the whole batch.
                if (lit_back)
                    f += kBack * df * s.d_b * ab * (DeonLongitudinal<T>(s2b).eval(sin_i, cos_i, sb, cb) * kInvPi<T>);
                return f;
            }

            // Every M at θi in one batch (f_back's, the global lobes', f_back^G's).
            Lanes lanes;
            lobe_lanes(lanes, fw.spread, s2b, sb, cb);
            T m[std::size_t(kLanes)];
            lanes.eval_all(sin_i, cos_i, m);
            if (lit_back) f += kBack * df * s.d_b * ab * (m[kBackLane] * kInvPi<T>);

            V3 g(T(0));
            if (improved() || !backward) g = t_.window_sum(cell_o_, improved() ? a : kPi<T>, m);
            const T az = improved() ? (kPi<T> - a) * kInvPi<T> * kInvPi<T> : (backward ? T(1) : T(0));
            V3 gb(T(0));
            if (az > T(0)) gb = kBack * s.d_b * az * ab * m[kGlobalBackLane];
            return f + scale * g + scale_back * gb;
        }

        View t_;
        FiberAt single_;
        V3 wo_;
        bool valid_ = true;
        T sin_o_ = T(0), cos_o_ = T(1), theta_o_ = T(0), node_o_ = T(0);
        typename View::Cell cell_o_{0, T(0)};
        int row_ = 0;  // the θ row the sampler's window CDFs are read from (nearest to θo)
        T sin_l_[std::size_t(kMaxLobes)] = {}, cos_l_[std::size_t(kMaxLobes)] = {};
        static constexpr T kUniformShare = T(0.05);
        T w_[5] = {};              // mixture weights: single, back, global, global back, uniform
        T g_[std::size_t(kMaxLobes)] = {};      // lobe probabilities inside the global component
        T total_[std::size_t(kMaxLobes)] = {};  // each lobe's row total ∫_0^π W̄_p
        T s2_back_ = T(1e-6), s2_spread_ = T(0);
        T sin_back_ = T(0), cos_back_ = T(1);  // θo - Δ_b at the specular cone
        // The sampler's lobes (lobe_lanes), for density(): set by mixture(), left unset (not
        // zeroed, 192 bytes in float) in the At that eval() makes, which never reads them.
        Lanes pdf_lanes_;
    };

    HAIRSCATTER_HD At at(const V3& wo, T spread = T(0)) const { return At(*this, wo, spread); }
    HAIRSCATTER_HD V3 eval(const V3& wo, const V3& wi, const DualScatteringLight<T>& light) const {
        return At(*this, wo, T(0), false).eval(wi, light);
    }
    HAIRSCATTER_HD T pdf(const V3& wo, const V3& wi) const { return at(wo).pdf(wi); }
    HAIRSCATTER_HD DualSample<T> sample(const V3& wo, const V4& u) const { return at(wo).sample(u); }
    HAIRSCATTER_HD DualSample<T> sample(const V3& wo, const V4& u, const DualScatteringLight<T>& light) const {
        return at(wo).sample(u, light);
    }
    HAIRSCATTER_HD const Fiber& fiber() const { return fiber_; }
    HAIRSCATTER_HD const View& tables() const { return tables_; }

  private:
    Fiber fiber_;
    View tables_;
};

// A uniform direction on the sphere and its density 1/4π, for the uniform baseline of the
// dual BCSDF (whose value needs the light state, so no weight is computed here).
template <typename T> HAIRSCATTER_HD DualSample<T> uniform_sphere_sample(T u1, T u2) {
    DualSample<T> out;
    const T z = T(1) - T(2) * u1;
    const T r = cos_from_sin(z);
    T s, c;
    elem::sincos(kTwoPi<T> * u2, s, c);
    out.wi = glm::vec<3, T>(z, r * c, r * s);
    out.pdf = T(0.25) * kInvPi<T>;
    return out;
}
}  // namespace hairscatter
