// hairscatter — longitudinal scattering functions M_p.
#pragma once

#include <cmath>
#include <cstddef>

#include "../config.hpp"
#include "../math/constants.hpp"
#include "../math/distributions.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"

namespace hairscatter {

// Longitudinal variance v of the R lobe from the user's roughness β_m ∈ (0, 1]
// (Chiang et al. 2016, eq. 7); TT uses v/4 and TRT and higher 4v (ibid.).
template <typename T> HAIRSCATTER_HD T longitudinal_variance(T beta_m) {
    const T b2 = beta_m * beta_m, b4 = b2 * b2, b8 = b4 * b4, b16 = b8 * b8;
    return sqr(T(0.726) * beta_m + T(0.812) * b2 + T(3.7) * b16 * b4);
}

// d'Eon et al. 2011's energy-conserving longitudinal lobe (eq. 7 of their paper),
//   M(v, θi, θo) = csch(1/v)/(2v) · exp(-sinθi sinθo / v) · I0(cosθi cosθo / v),
// with ∫ M cosθi dθi = 1. It is the θ-marginal of a von Mises–Fisher lobe of
// concentration 1/v around the mirror direction (-θo), which gives a form that is finite
// for every v without a log-space switch:
//   M = exp(-d²/2v) · e^(-a) I0(a) / (v (1 - e^(-2/v))),   a = cosθi cosθo / v,
//   d² = (cosθi - cosθo)² + (sinθi + sinθo)² = 2 - 2 cos(θi + θo),
// because a - b - 1/v = -d²/2v exactly. d² is a sum of squares, so it has no
// cancellation near the peak, and the exponent is never positive.
//
// DeonLanes holds N such lobes conditioned on their θo (lane k: one lobe, its tilted θo'),
// as a structure of arrays: the per-θi work of all lanes is then one loop that GCC and
// Clang vectorise (and nvcc runs as scalar code). terms() splits M = factor · exp(exponent)
// so that a model can take the exps of all its lobe terms in one batch. The I0 split at
// a = 6 is a select, not a branch (both forms are computed, each on an argument kept in
// its own range so that the unused one stays finite): which side a lobe falls on depends
// on θi and is not predictable.
template <typename T, int N> struct DeonLanes {
    T sin_o[std::size_t(N)], cos_o[std::size_t(N)];  // θo' per lane (cos folded ≥ 0)
    T a_scale[std::size_t(N)];          // cosθo' / v: a = cosθi · a_scale
    T sqrt_a_scale[std::size_t(N)];     // its square root: 1/√a = 1/(√cosθi √a_scale), no sqrt per lane
    T half_inv_v[std::size_t(N)], norm[std::size_t(N)];

    // sqrt_a_scale from a_scale, after the lanes are conditioned: a step of its own, since
    // a sqrt (which may set errno) keeps the compilers from vectorising a loop it is in
    // (elem::sqrt_each: one vector square root on x86).
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void take_roots() {
        for (int k = 0; k < N; ++k) sqrt_a_scale[k] = a_scale[k];
        elem::sqrt_each(sqrt_a_scale);
    }

    // Lane k of M at (sinθi, cosθi), with sqrt_cos_i = √cosθi.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void terms(int k, T sin_i, T cos_i, T sqrt_cos_i, T& exponent,
                                                       T& factor) const {
        constexpr T split = T(detail::kI0SmallSplit);
        const T d2 = sqr(cos_i - cos_o[k]) + sqr(sin_i + sin_o[k]);
        const T a = cos_i * a_scale[k];
        const bool small = a <= split;
        // a ≤ 6: e^(-a) I0(a), the e^(-a) folded into the exponent.
        const T series = T(1) + detail::i0_small_minus_one(select(small, a, split));
        // a > 6: e^(-a) I0(a) = Q(6/a) · 1/√a.
        const T inv_sqrt_a = select(small, T(0.40824829046386301637), T(1) / (sqrt_cos_i * sqrt_a_scale[k]));
        const T asymptotic = detail::i0_large_scaled_sqrt_t(split * sqr(inv_sqrt_a)) * inv_sqrt_a;
        exponent = -d2 * half_inv_v[k] - select(small, a, T(0));
        factor = norm[k] * select(small, series, asymptotic);
    }

    // The same where a ≤ 6 for every θi (a_scale[k] ≤ 6: a wide lobe, or θo' near grazing):
    // the series alone, no square root and no division.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void terms_small(int k, T sin_i, T cos_i, T& exponent, T& factor) const {
        const T d2 = sqr(cos_i - cos_o[k]) + sqr(sin_i + sin_o[k]);
        const T a = cos_i * a_scale[k];
        exponent = -d2 * half_inv_v[k] - a;
        factor = norm[k] * (T(1) + detail::i0_small_minus_one(a));
    }

    // Every lane k as the lobe of variance v[k] conditioned on θo' = (s[k], c[k]), for lanes
    // whose variance changes per call (dual scattering widens its lobes by the light's
    // spread): DeonLongitudinal's constants, each as one loop over the lanes.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void set(const T (&v)[std::size_t(N)], const T (&s)[std::size_t(N)],
                                                     const T (&c)[std::size_t(N)]) {
        T e[std::size_t(N)];
        for (int k = 0; k < N; ++k) {
            const T inv_v = T(1) / v[k];
            sin_o[k] = s[k];
            cos_o[k] = c[k];
            a_scale[k] = c[k] * inv_v;
            half_inv_v[k] = T(0.5) * inv_v;
            e[k] = T(-2) * inv_v;
        }
        elem::expm1_each(e);
        for (int k = 0; k < N; ++k) norm[k] = T(2) * half_inv_v[k] / -e[k];  // 1 / (v (1 - e^(-2/v)))
        take_roots();
    }

    // M of every lane at (sinθi, cosθi): the terms, then their exps as one batch.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void eval_all(T sin_i, T cos_i, T (&m)[std::size_t(N)]) const {
        using std::sqrt;
        const T sqrt_cos_i = sqrt(cos_i);
        T e[std::size_t(elem::exp_batch<T>(N))] = {}, factor[std::size_t(N)];
        for (int k = 0; k < N; ++k) terms(k, sin_i, cos_i, sqrt_cos_i, e[k], factor[k]);
        elem::exp_each_nonpositive(e);  // (the exponents are ≤ 0)
        for (int k = 0; k < N; ++k) m[k] = factor[k] * e[k];
    }
};

template <typename T> class DeonLobes;

template <typename T> class DeonLongitudinal {
  public:
    DeonLongitudinal() = default;
    HAIRSCATTER_HD explicit DeonLongitudinal(T v) : v_(v), inv_v_(T(1) / v) {
        // (made per call where the variance depends on the light, as in dual scattering)
        exp_m2_over_v_ = elem::exp(T(-2) * inv_v_);  // underflows to 0 for v < 0.02 in float: harmless
        norm_ = inv_v_ / -elem::expm1(T(-2) * inv_v_);
    }

    // The same lobe from v, 1/v, e^(-2/v) and its expm1 computed elsewhere (several lobes' exps
    // as one vector: FurFiber).
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE DeonLongitudinal(T v, T inv_v, T exp_m2_over_v, T expm1_m2_over_v)
        : v_(v), inv_v_(inv_v), exp_m2_over_v_(exp_m2_over_v), norm_(inv_v / -expm1_m2_over_v) {}

    HAIRSCATTER_HD T variance() const { return v_; }

    // Writes this lobe, conditioned on θo', into lane k of `lanes` (then lanes.take_roots()).
    template <int N>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void condition(DeonLanes<T, N>& lanes, int k, T sin_o, T cos_o) const {
        lanes.sin_o[k] = sin_o;
        lanes.cos_o[k] = cos_o;
        lanes.a_scale[k] = cos_o * inv_v_;
        lanes.half_inv_v[k] = T(0.5) * inv_v_;
        lanes.norm[k] = norm_;
    }

    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T eval(T sin_i, T cos_i, T sin_o, T cos_o) const {
        using std::sqrt;
        DeonLanes<T, 1> lane;
        condition(lane, 0, sin_o, cos_o);
        lane.take_roots();
        T exponent, factor;
        lane.terms(0, sin_i, cos_i, sqrt(cos_i), exponent, factor);
        return factor * elem::exp(exponent);
    }

    // Samples sinθi for the lobe conditioned on θo (d'Eon, Marschner & Hanika 2013): the
    // cosine of the angle to the mirror direction, c = 1 + v ln(u1 + (1 - u1) e^(-2/v)),
    // as 1 - c so that sharp lobes keep their precision, and an azimuth 2π u2 around it.
    // The log argument is floored at the smallest normal number instead of clamping u1,
    // so the distribution is exact wherever e^(-2/v) does not underflow.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T sample_sin_theta(T sin_o, T cos_o, T u1, T u2) const {
        const T v[1] = {v_}, e[1] = {exp_m2_over_v_};
        T out[1];
        sample_sin_theta_each(v, e, &sin_o, &cos_o, u1, u2, out);
        return out[0];
    }
    // The same for N lobes from one (u1, u2): lobe j of variance v[j] (e^(-2/v) in
    // exp_m2_over_v[j]) conditioned on θo'_j = (sin_o[j], cos_o[j]), its sinθi into out[j];
    // the logs and square roots of the lobes one vector each in float (a sampler that draws
    // θi for every lobe before it knows which lobe it picked). Lane j is bit for bit the
    // one-lobe call's.
    template <std::size_t N>
    static HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void sample_sin_theta_each(const T (&v)[N], const T (&exp_m2_over_v)[N],
                                                                           const T* sin_o, const T* cos_o, T u1, T u2,
                                                                           T (&out)[N]) {
        T arg[N], omc[N], s[N];
        for (int j = 0; j < int(N); ++j) {
            const T a = u1 + (T(1) - u1) * exp_m2_over_v[j];
            arg[j] = a > kMinNormal<T> ? a : kMinNormal<T>;
        }
        elem::log_each(arg);
        for (int j = 0; j < int(N); ++j) {
            omc[j] = clamp(-v[j] * arg[j], T(0), T(2));  // 1 - c
            s[j] = omc[j] * (T(2) - omc[j]);            // ≥ 0
        }
        elem::sqrt_each(s);
        T sin_az, cos_az;
        elem::sincos(kTwoPi<T> * u2, sin_az, cos_az);
        for (int j = 0; j < int(N); ++j)
            out[j] = clamp(-(T(1) - omc[j]) * sin_o[j] + s[j] * cos_az * cos_o[j], T(-1), T(1));
    }

  private:
    friend class DeonLobes<T>;  // stores the constants of its four lobes per lane

    T v_ = T(1), inv_v_ = T(1), exp_m2_over_v_ = T(0), norm_ = T(1);
};

// Marschner et al. 2003's longitudinal lobe with d'Eon et al. 2011's correction of the
// half angle (docs/theory.md §3.3): M_p(θh) = g(β_p; 2θh - α_p) = g(β_p; θi + θo - α_p), a
// unit-area Gaussian in radians. Marschner's own shift convention: lobe p peaks at
// θi = α_p - θo (with α_R < 0 the R highlight sits at θi + θo = α_R). Unlike
// DeonLongitudinal it is not normalised on the sphere (it is a density in θi over the
// whole real line, and the model divides by cos²θd): the energy it loses or gains is
// Marschner's, reported by the furnace test, not corrected.
template <typename T> class MarschnerLongitudinal {
  public:
    MarschnerLongitudinal() = default;
    HAIRSCATTER_HD MarschnerLongitudinal(T beta, T alpha) : beta_(beta), alpha_(alpha) {}

    HAIRSCATTER_HD T beta() const { return beta_; }
    HAIRSCATTER_HD T alpha() const { return alpha_; }
    HAIRSCATTER_HD T eval(T theta_i, T theta_o) const { return gaussian(beta_, theta_i + theta_o - alpha_); }

  private:
    T beta_ = T(1), alpha_ = T(0);
};

}  // namespace hairscatter
