// hairscatter — the longitudinal ingredients every d'Eon-based model shares (Chiang's near
// field, d'Eon's far field, the tabulated far field), written once: the variance ladder
// from β_m, one energy-conserving M_p per lobe and the cuticle tilt of θo per lobe.
#pragma once

#include <type_traits>

#include "../config.hpp"
#include "../math/distributions.hpp"
#include "../math/elementary.hpp"
#include "lobe_controls.hpp"
#include "lobe_set.hpp"
#include "longitudinal.hpp"
#include "tilt.hpp"

namespace hairscatter {

// Lobes p = 0 (R), 1 (TT), 2 (TRT) and kLobes = 3, the residual (every order p ≥ 3).
//   v_p: v, v/4, 4v, 4v with v = longitudinal_variance(β_m) (Chiang et al. 2016 eq. 7 and §4.1);
//   M_p: d'Eon et al. 2011's lobe of variance v_p (lobes/longitudinal.hpp);
//   tilt: θo' = θo - 2α, θo + α, θo + 4α, θo (pbrt-v4's, lobes/tilt.hpp).
// Trivially copyable and device-callable once built; a material holds one by value.
template <typename T> class DeonLobes {
  public:
    static constexpr int kLobes = 3;

    DeonLobes() = default;
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE DeonLobes(T beta_m, T alpha) : DeonLobes(beta_m, LobeControls<T>(), alpha) {}
    // With per-lobe tilts of their own (LobeControls::cuticle_tilt of the fiber's α).
    // The tilt is built in place, from the controls (not passed in built): a tilt built
    // first and then copied in was, at GCC -O3, two 16-byte stores read back by one 32-byte
    // load, which waits for the stores to retire (a store-forwarding stall, on the chain of
    // a material built per hit: ChiangMaterial::per_hit).
    // The four lobes' constants as DeonLongitudinal(v_p) computes them, bit for bit, but
    // as lanes: one division (1/(v/4) = 4 (1/v) exactly, the factors being powers of two)
    // and one vector of exps in float, the expm1s taken from them, so that a material is
    // cheap enough to build per hit (ChiangMaterial::per_hit). In double, where each exp and
    // expm1 is a libm call, the residual's, whose variance is TRT's, are TRT's copied.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE DeonLobes(T beta_m, const LobeControls<T>& controls, T alpha)
        : tilt_(controls.cuticle_tilt(alpha)) {
        const T v0 = longitudinal_variance(beta_m);
        const T inv_v0 = T(1) / v0;
        const T scale[kLobes + 1] = {T(1), T(0.25), T(4), T(4)}, inv_scale[kLobes + 1] = {T(1), T(4), T(0.25), T(0.25)};
        constexpr int kExps = std::is_same<T, float>::value ? kLobes + 1 : kLobes;  // (float: a whole vector)
        T e[std::size_t(kExps)], m[std::size_t(kExps)];
        HAIRSCATTER_NO_UNROLL
        for (int p = 0; p <= kLobes; ++p) {
            v_[p] = scale[p] * v0;
            inv_v_[p] = inv_v0 * inv_scale[p];  // (exact)
        }
        // -2/v_p straight from 1/v0, the same value (every factor a power of two: exact), one
        // product sooner on the chain from β_m to norm_, which a material built per hit waits on.
        HAIRSCATTER_NO_UNROLL
        for (int p = 0; p < kExps; ++p) e[p] = m[p] = inv_v0 * (T(-2) * inv_scale[p]);
        elem::exp_each_nonpositive(e);  // (-2/v < 0) underflows to 0 for v < 0.02 in float: harmless
        elem::expm1_each_given_exp(m, e);
        HAIRSCATTER_NO_UNROLL
        for (int p = 0; p <= kLobes; ++p) {
            const int q = p < kExps ? p : kLobes - 1;  // (the residual: TRT's, v_3 = v_2)
            exp_m2_over_v_[p] = e[q];
            norm_[p] = inv_v_[p] / -m[q];
        }
    }

    HAIRSCATTER_HD DeonLongitudinal<T> longitudinal(int p) const {
        DeonLongitudinal<T> m;
        m.v_ = v_[p];
        m.inv_v_ = inv_v_[p];
        m.exp_m2_over_v_ = exp_m2_over_v_[p];
        m.norm_ = norm_[p];
        return m;
    }
    HAIRSCATTER_HD const CuticleTilt<T>& tilt() const { return tilt_; }

    // The longitudinal shift of lobe p's peak in θi + θo (Marschner's α_p in d'Eon's
    // corrected 2θh form): the lobe peaks at θi = α_p - θo. pbrt-v4's tilt gives 2α (R),
    // -α (TT), -4α (TRT), 0 (residual).
    HAIRSCATTER_HD T lobe_shift(int p) const { return -tilt_.angle(p); }
    // The longitudinal variance v_p of lobe p (β_p² of the dual-scattering tables).
    HAIRSCATTER_HD T lobe_variance(int p) const { return v_[p]; }
    // e^(-2/v_p), the constant of lobe p's sampler (DeonLongitudinal::sample_sin_theta).
    HAIRSCATTER_HD T lobe_exp_m2_over_v(int p) const { return exp_m2_over_v_[p]; }

    // (sinθo'_p, cosθo'_p) of every lobe p whose bit is set in `keep` (bit p), into the
    // arrays sin_p[0 … kLobes], cos_p[0 … kLobes]; the others are left untouched.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void tilt_all(T sin_o, T cos_o, T* sin_p, T* cos_p,
                                                    unsigned keep = (1u << (kLobes + 1)) - 1u) const {
        for (int p = 0; p <= kLobes; ++p) {
            if (((keep >> p) & 1u) == 0u) continue;
            const typename CuticleTilt<T>::Rotated r = tilt_.rotate(p, sin_o, cos_o);
            sin_p[p] = r.sin_theta;
            cos_p[p] = r.cos_theta;
        }
    }

    // The lobes of kSet conditioned on θo, each tilted (lane k: lobe lane_lobe(kSet, k),
    // lobes/lobe_set.hpp), for their per-θi evaluation side by side (DeonLanes). kRoots false
    // leaves lanes.take_roots() to a caller that conditions a lane again first (FurFiber).
    template <LobeSet kSet, int N, bool kRoots = true>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void condition(DeonLanes<T, N>& lanes, T sin_o, T cos_o) const {
        static_assert(N >= lobe_count(kSet), "a lane per lobe of the set");
        for (int k = lobe_count(kSet); k < N; ++k) {  // padding: M = 0
            lanes.sin_o[k] = lanes.cos_o[k] = lanes.a_scale[k] = lanes.half_inv_v[k] = lanes.norm[k] = T(0);
        }
        for (int k = 0; k < lobe_count(kSet); ++k) {
            const int p = lane_lobe(kSet, k);
            const typename CuticleTilt<T>::Rotated r = tilt_.rotate(p, sin_o, cos_o);
            lanes.sin_o[k] = r.sin_theta;
            lanes.cos_o[k] = r.cos_theta;
            lanes.a_scale[k] = r.cos_theta * inv_v_[p];
            lanes.half_inv_v[k] = T(0.5) * inv_v_[p];
            lanes.norm[k] = norm_[p];
        }
        if constexpr (kRoots) lanes.take_roots();
    }

  private:
    // The constants of the four DeonLongitudinal lobes, one array each, so that the lanes
    // read them as vectors.
    T v_[kLobes + 1], inv_v_[kLobes + 1], exp_m2_over_v_[kLobes + 1], norm_[kLobes + 1];
    CuticleTilt<T> tilt_;
};

// The azimuthal widths the lanes of deon_logistic_densities read: every explicit lane the
// one trimmed logistic n (Chiang's N_p, one β_n for every lobe) ...
template <typename T> struct SharedLogistic {
    const TrimmedLogistic<T>& n;
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T minus_inv_scale(int) const { return -n.inv_scale(); }
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T numerator(int) const { return n.density_numerator(T(1)); }
};
// ... or a trimmed logistic per lane, for a model whose lobes have azimuthal widths of their
// own (FurFiber on the rough cortex): lane k's -1/s and density_numerator(1), one array each
// (read as vectors).
template <typename T, int N> struct LaneLogistics {
    T minus_inv_s[std::size_t(N)], scale[std::size_t(N)];
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void set(int k, const TrimmedLogistic<T>& n) {
        minus_inv_s[k] = -n.inv_scale();
        scale[k] = n.density_numerator(T(1));
    }
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T minus_inv_scale(int k) const { return minus_inv_s[k]; }
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T numerator(int k) const { return scale[k]; }
};

// M_p N_p of every lane at (sinθi, cosθi, φ): lane k's M_p conditioned in m (DeonLobes::
// condition), its N_p Chiang et al. 2016's trimmed logistic about Φ(p, h) = phi_p[k]
// (eq. 6), of lane k's width in widths (SharedLogistic: the one n), for the kExplicit
// explicit lobes, 1/2π for the residual. The exponents of N_p
// and M_p go into one array whose exps are one vectorised loop in float, then the lanes
// are multiplied out. kAzimuthal lanes take N's arithmetic (every lane in float, where the
// residual's is part of a whole vector; the explicit ones only in double, one libm exp
// each); the kept lanes past it are residual lanes. Shared by every model built on these
// lobes side by side (ChiangFiber, FurFiber).
template <int kKeptLanes, int kExplicit, int kAzimuthal, typename T, int N, class Widths>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void deon_logistic_densities(const DeonLanes<T, N>& m, const T (&phi_p)[std::size_t(N)],
                                                                    const Widths& widths, T sin_i, T cos_i, T phi,
                                                                    T (&mn)[std::size_t(N)]) {
    using std::sqrt;
    constexpr int kM = kAzimuthal;  // where the M_p exponents start in e
    T e[std::size_t(kAzimuthal + N)], m_factor[std::size_t(N)];
    // The residual's lane (float: part of the vector) gets the exponent -0, so e = 1,
    // and its density is then 1/2π through the same arithmetic as N's (e·scale over
    // (1 + e·0)², bit for bit as a select after it): no select on the chain.
    for (int k = 0; k < kAzimuthal; ++k)
        e[k] = TrimmedLogistic<T>::exponent_of_difference(phi - phi_p[k],
                                                          select(k < kExplicit, widths.minus_inv_scale(k), T(-0.0)));
    const T sqrt_cos_i = sqrt(cos_i);
    for (int k = 0; k < N; ++k) m.terms(k, sin_i, cos_i, sqrt_cos_i, e[kM + k], m_factor[k]);
    elem::exp_each_nonpositive(e);  // (every exponent ≤ 0) in float whole vectors (math/elementary.hpp)
    // The residual lumps all orders: uniform in φ. Where its lane's N is computed with
    // the others (float), by the same arithmetic, so that mn is written as one vector.
    // N's density e/(1 + e)² (times its scale) as one quotient with M in the numerator,
    // so that the division waits only for the denominator: the chain from the exps to f
    // is one multiplication shorter. The residual's lane (e = 1) has the scale 1/2π and
    // the denominator (1 + 1·0)² = 1.
    for (int k = 0; k < kAzimuthal; ++k) {
        const T scale = select(k < kExplicit, widths.numerator(k), kInvTwoPi<T>);
        const T onto = select(k < kExplicit, T(1), T(0));
        mn[k] = (m_factor[k] * e[kM + k]) * (e[k] * scale) / sqr(T(1) + e[k] * onto);
    }
    for (int k = kAzimuthal; k < kKeptLanes; ++k) mn[k] = m_factor[k] * e[kM + k] * kInvTwoPi<T>;
}
template <int kKeptLanes, int kExplicit, int kAzimuthal, typename T, int N>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void deon_logistic_densities(const DeonLanes<T, N>& m, const T (&phi_p)[std::size_t(N)],
                                                                    const TrimmedLogistic<T>& n, T sin_i, T cos_i, T phi,
                                                                    T (&mn)[std::size_t(N)]) {
    deon_logistic_densities<kKeptLanes, kExplicit, kAzimuthal>(m, phi_p, SharedLogistic<T>{n}, sin_i, cos_i, phi, mn);
}

}  // namespace hairscatter
