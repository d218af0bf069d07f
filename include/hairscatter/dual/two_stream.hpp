// hairscatter — two-stream dual scattering at the arrival direction (docs/dual.md,
// docs/theory.md §5.6): an energy-conserving reading of Zinke et al. 2008's global and
// local multiple scattering, evaluated where the light arrives rather than where it left.
//
// A renderer samples the direction a from which light arrives at a hair point x (the
// fiber's own sampler) and asks how much hair lies along it: n fibers toward a and m
// beyond x toward -a. Each fiber is a layer that passes a_f and returns a_b of the light
// (the tables' albedos at θa), and the two stacks on either side of x give, by the 1D
// adding formula (tables.hpp), the light that arrives along a:
//
//     D(a) = c_f L̃_f + c_b L̃_b,   c_f = T_n / (1 - R_n R_m),   c_b = R_n T_m / (1 - R_n R_m)
//
// L̃_f is the light that enters the hair on a's side, spread by its passage (the source
// kernel K_f below), L̃_b the light entering on the far side, which the n fibers return (K_b).
// Lossless layers have T_k + R_k = 1, so c_f + c_b = 1: under a uniform environment every
// arrival direction carries the environment's radiance, and a fiber that integrates to 1
// returns it, whatever the geometry (the white furnace). With n = 0 the direction is
// unobstructed: c_f = 1, c_b = 0, and the light is the source's own, unspread.
//
// The kernels are densities over the direction s the light came from (fiber frame of x):
//     K_f(s | a) = M(v_f; θs around θa) · [|φs − φa| < π/2] / π
//     K_b(s | a) = M(v_b; θs around θa) · [|φs − φa − π| < π/2] / π
// M is d'Eon et al. 2011's normalised longitudinal lobe. Scattering by a fiber keeps the
// component of the light's travel along the fiber, so θ is kept and spread; a transmitted
// path stays on a's side of the circle of azimuths, a returned one comes from the other
// half (Zinke et al. 2008 spread forward-scattered light uniformly over a half-circle).
// The variances come from the stacks themselves, nothing fitted: a path of the stack
// passes k_f forward and k_b backward events on average, k_f = a_f ∂ln X/∂a_f and
// k_b = a_b ∂ln X/∂a_b for X = T_n or R_n (and T_m for the far side's passage), and each
// event adds its lobe's mean variance β̄²_f or β̄²_b (tables.hpp).
#pragma once

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../fiber/frame.hpp"
#include "../lobes/longitudinal.hpp"
#include "../math/constants.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"
#include "tables.hpp"

namespace hairscatter {

// What the hair along one arrival direction does to the light (per RGB channel).
template <typename T> struct DualStreams {
    glm::vec<3, T> forward{T(1)};  // c_f: share of the light entering on a's side that arrives along a
    glm::vec<3, T> back{T(0)};     // c_b: share of the light entering on the far side that arrives along a
    T spread_f = T(0), spread_b = T(0);  // variances v_f, v_b of the source kernels (rad², channel mean)
};

// The smallest and largest kernel variance used: below, M is sharper than any table can
// resolve (and n = 0 needs no kernel); above, M is uniform in θ to rounding.
template <typename T> inline constexpr T kMinSourceSpread = T(1e-4);
template <typename T> inline constexpr T kMaxSourceSpread = T(1e4);

// The deepest stack used: 10,000 fibers pass less than 1e-3 of the light even when lossless,
// and deeper stacks on both sides of a point would leave 1 - R_n R_m to rounding (in float,
// 0: the light would vanish instead of splitting evenly between the two sides).
template <typename T> inline constexpr T kDeepStack = T(1e4);
// A count of fibers as a stack depth: NaN or negative → 0, above kDeepStack (+Inf,
// kUnbounded) → kDeepStack.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T dual_stack_depth(T count) {
    return count > T(0) ? (count < kDeepStack<T> ? count : kDeepStack<T>) : T(0);
}

// The depth beyond which more fibers change no stack by more than `tolerance`: T_N below it
// and R_N within it of R_∞, in every channel of the entry (a renderer counting a ray's fibers
// can stop there). For N ≫ 1, T_N → a_f (1 − e^{−2κ}) e^{−(N−1)κ} / (1 − a_f e^{−κ}) (the
// closed form of tables.hpp), and R_N − R_∞ falls as e^{−2Nκ}, faster. Lossless channels
// (κ = 0) fall only as 1/N: kDeepStack.
template <typename T> HAIRSCATTER_HD T dual_count_limit(const DualScatteringEntry<T>& e, T tolerance) {
    const T tol = tolerance > T(1e-12) ? (tolerance < T(0.5) ? tolerance : T(0.5)) : T(1e-12);
    LayerLanes<T, 4> c;
    elem::store4(c.a_f, e.a_f.x, e.a_f.y, e.a_f.z, T(0));
    elem::store4(c.a_b, e.a_b.x, e.a_b.y, e.a_b.z, T(0));
    layer_lanes(c);
    T limit = T(1);
    for (int k = 0; k < 3; ++k) {
        const T kappa = c.kappa[k];
        if (!(c.a_f[k] > T(0))) continue;  // opaque: the first fiber stops everything
        if (!(kappa > T(1e-6))) return kDeepStack<T>;
        const T den = T(1) - c.a_f[k] * c.e_k[k];
        const T scale = den > T(0) ? c.a_f[k] * c.q[k] / den : T(1);
        const T n = T(1) + elem::log(scale > tol ? scale / tol : T(1)) / kappa;
        limit = n > limit ? n : limit;
    }
    limit = limit + T(1);  // one layer's margin over the asymptote
    return limit < kDeepStack<T> ? limit : kDeepStack<T>;
}

// One count drawn from a Poisson distribution of mean `mean` (conditioned on at least one
// fiber when given_hit: the ray along a was found blocked), by inversion of its CDF with
// the uniform number u. A density source reports an expectation; the stacks' T_N and R_N
// are far from linear in N, and E[T_N] ≥ T_{E[N]} (Jensen), so a renderer with a density
// grid draws a count per arrival instead of using the mean. Counts are Poisson for fibers
// placed independently; real hair is more clustered, which only an exact count captures.
// Means above 64 use the normal approximation.
template <typename T> HAIRSCATTER_HD T poisson_fiber_count(T mean, T u, bool given_hit) {
    const T mu = is_finite(mean) ? (mean > T(0) ? mean : T(0)) : (mean > T(0) ? T(1e12) : T(0));
    const T v = is_finite(u) ? clamp(u, T(0), T(1)) : T(0.5);
    if (!(mu > T(0))) return given_hit ? T(1) : T(0);
    using std::sqrt;
    if (mu > T(64)) {
        // The logistic approximation of the normal quantile, z = ln(v / (1 - v)) √3 / π: off
        // by a few hundredths of σ, a fraction of one fiber at this mean.
        const T w = clamp(v, T(1e-6), T(1) - T(1e-6));
        const T k = mu + elem::log(w / (T(1) - w)) * T(0.5513288954217921) * sqrt(mu);
        return k > T(1) ? T(int(k + T(0.5))) : T(1);
    }
    const T p0 = elem::exp(-mu);
    // Conditioned on N ≥ 1: skip k = 0 by rescaling u over the rest of the mass.
    const T target = given_hit ? p0 + v * (T(1) - p0) : v;
    // The tail beyond μ + 12√μ + 12 holds less than rounding: the walk stops there.
    const T last = mu + T(12) * sqrt(mu) + T(12);
    T k = T(0), pk = p0, cdf = p0;
    while (cdf < target && k < last) {
        k += T(1);
        pk *= mu / k;
        cdf += pk;
    }
    return given_hit && k < T(1) ? T(1) : k;
}

namespace detail {
// ln(x / y) / ln(1 - ε): the mean number of events of a kind, from a stack made with that
// kind's albedo scaled by (1 - ε); 0 where either stack is empty.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T mean_events(T scaled, T base, T inv_log) {
    return scaled > T(0) && base > T(0) ? elem::log(scaled / base) * inv_log : T(0);
}
}  // namespace detail

// c_f, c_b and the kernel variances for n fibers along a and m beyond the point, from the
// table entry at θa (DualTablesView::lookup(sin θa)). n and m are fiber counts: exact counts
// of one ray each (then an average over samples is an average over the counts'
// distribution), or expectations. NaN counts count as 0, +Inf as a deep volume.
template <typename T>
HAIRSCATTER_HD DualStreams<T> dual_streams(const DualScatteringEntry<T>& e, T n_fibers, T m_fibers) {
    DualStreams<T> s;
    const T n = dual_stack_depth(n_fibers), m = dual_stack_depth(m_fibers);
    // Lanes 0–2: the channels; lane 3: the channel mean, whose albedos give the events below.
    // The same four layers n deep (lanes 0–3) and m deep (4–7), as one batch.
    const T af = (e.a_f.x + e.a_f.y + e.a_f.z) * T(1.0 / 3.0), ab = (e.a_b.x + e.a_b.y + e.a_b.z) * T(1.0 / 3.0);
    LayerLanes<T, 4> layer;
    elem::store4(layer.a_f, e.a_f.x, e.a_f.y, e.a_f.z, af);
    elem::store4(layer.a_b, e.a_b.x, e.a_b.y, e.a_b.z, ab);
    layer_lanes(layer);
    LayerLanes<T, 8> c;
    repeat_lanes(layer, c);
    const T depth[8] = {n, n, n, n, m, m, m, m};
    T R[8], T_[8];
    layered_stacks(c, depth, R, T_);
    for (int k = 0; k < 3; ++k) {
        const T den = T(1) - R[k] * R[4 + k];
        s.forward[k] = den > T(0) ? clamp(T_[k] / den, T(0), T(1)) : T(0);
        s.back[k] = den > T(0) ? clamp(R[k] * T_[4 + k] / den, T(0), T(1)) : T(0);
    }
    // The events, from the mean channel's stacks with a_f, then a_b, scaled by 1 - ε.
    constexpr T eps = sizeof(T) < 8 ? T(1e-3) : T(1e-6);
    const T inv_log = T(1) / elem::log1p(-eps);
    LayerLanes<T, 4> d;
    const T depth_d[4] = {n, n, m, m};
    d.a_f[0] = af * (T(1) - eps), d.a_b[0] = ab;
    d.a_f[1] = af, d.a_b[1] = ab * (T(1) - eps);
    d.a_f[2] = af * (T(1) - eps), d.a_b[2] = ab;
    d.a_f[3] = af, d.a_b[3] = ab * (T(1) - eps);
    layer_lanes(d);
    T Rd[4], Td[4];
    layered_stacks(d, depth_d, Rd, Td);
    const T bf = (e.beta2_f.x + e.beta2_f.y + e.beta2_f.z) * T(1.0 / 3.0);
    const T bb = (e.beta2_b.x + e.beta2_b.y + e.beta2_b.z) * T(1.0 / 3.0);
    using detail::mean_events;
    const T far_side = mean_events(Td[2], T_[7], inv_log) * bf + mean_events(Td[3], T_[7], inv_log) * bb;
    const T vf = mean_events(Td[0], T_[3], inv_log) * bf + mean_events(Td[1], T_[3], inv_log) * bb;
    const T vb = mean_events(Rd[0], R[3], inv_log) * bf + mean_events(Rd[1], R[3], inv_log) * bb + far_side;
    s.spread_f = clamp(is_finite(vf) ? vf : T(0), kMinSourceSpread<T>, kMaxSourceSpread<T>);
    s.spread_b = clamp(is_finite(vb) ? vb : T(0), kMinSourceSpread<T>, kMaxSourceSpread<T>);
    return s;
}
template <typename T>
HAIRSCATTER_HD DualStreams<T> dual_streams(const DualTablesView<T>& tables, T sin_theta_a, T n_fibers, T m_fibers) {
    return dual_streams(tables.lookup(sin_theta_a), n_fibers, m_fibers);
}

// The share of L(s) that reaches a stack's far face from direction s when `count` more
// fibers lie between that face and the outside along s (docs/theory.md §5.7, "sources beyond
// the exit"): T_N + R_N of that stack at the entry's θ. The face receives the light the
// N fibers transmit, T_N L(s), and their reflection of the light on the face's own side,
// R_N L_in, with L_in taken as L(s): exact in a furnace (a lossless stack gives 1 to
// rounding), and no brighter than the source wherever the hair is dimmer than it. NaN or
// negative counts give 1 (no fibers), +Inf a deep stack.
template <typename T> HAIRSCATTER_HD glm::vec<3, T> dual_source_gain(const DualScatteringEntry<T>& e, T count) {
    const T n = dual_stack_depth(count);
    if (!(n > T(0))) return glm::vec<3, T>(T(1));
    LayerLanes<T, 4> layer;
    elem::store4(layer.a_f, e.a_f.x, e.a_f.y, e.a_f.z, T(0));
    elem::store4(layer.a_b, e.a_b.x, e.a_b.y, e.a_b.z, T(0));
    layer_lanes(layer);
    const T depth[4] = {n, n, n, n};
    T R[4], T_[4];
    layered_stacks(layer, depth, R, T_);
    glm::vec<3, T> g;
    for (int k = 0; k < 3; ++k) {
        const T v = R[k] + T_[k];
        g[k] = is_finite(v) ? clamp(v, T(0), T(1)) : T(0);
    }
    return g;
}

// Where the fibers along a ray end, for a density source (density_source.hpp: anything with
// fibers_crossed(origin, direction, max_distance)): the distance t in [0, max_distance] past
// which less than min(1/2, C/2) of the C fibers expected on [0, max_distance] remain, by
// bisection to 1/256 of max_distance (8 queries). The two-stream estimator reads a stack's
// sources beyond this point. max_distance must be finite (clip it to the source's box);
// non-finite or non-positive input gives 0.
template <typename T, class Source>
HAIRSCATTER_HD T dual_stack_end(const Source& source, const glm::vec<3, T>& origin, const glm::vec<3, T>& direction,
                                T max_distance) {
    if (!(max_distance > T(0)) || !is_finite(max_distance) || !is_finite(origin) || !is_finite(direction)) return T(0);
    const T all = source.fibers_crossed(origin, direction, max_distance);
    if (!(all > T(0)) || !is_finite(all)) return T(0);
    const T rest = all * T(0.5) < T(0.5) ? all * T(0.5) : T(0.5);
    T lo = T(0), hi = max_distance;
    for (int i = 0; i < 8; ++i) {
        const T mid = T(0.5) * (lo + hi);
        if (all - source.fibers_crossed(origin, direction, mid) > rest) lo = mid;
        else hi = mid;
    }
    return hi;
}

// The source of the light arriving along a: the mixture c_f K_f + c_b K_b over the direction
// s the light came from (fiber frame), with eval (per channel, 1/sr), the mixture's pdf and a
// sampler. A renderer estimates L̃ = ∫ eval(s) L(s) ds by light sampling, by sample(), or by
// both with MIS, where L(s) is what lies outside the hair along s (a light, the
// environment, another surface's radiance). eval_pdf and the sample's f save the second
// evaluation of the kernels that separate eval and pdf calls would make.
template <typename T> class DualSourceKernel {
  public:
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;

    struct Sample {
        V3 s{T(0)};
        T pdf = T(0);  // 0: no sample
        V3 f{T(0)};    // eval(s), computed with the pdf (no second evaluation needed)
    };
    struct EvalPdf {
        V3 f{T(0)};
        T pdf = T(0);
    };

    HAIRSCATTER_HD DualSourceKernel(const V3& a, const DualStreams<T>& streams)
        : a_(a), c_f_(streams.forward), c_b_(streams.back), m_f_(streams.spread_f), m_b_(streams.spread_b) {
        valid_ = is_finite(a) && is_finite(c_f_) && is_finite(c_b_);
        const T sa = clamp(a.x, T(-1), T(1));
        sin_a_ = is_finite(sa) ? sa : T(0);
        cos_a_ = cos_from_sin(sin_a_);
        const T wf = (c_f_.x + c_f_.y + c_f_.z), wb = (c_b_.x + c_b_.y + c_b_.z);
        p_f_ = valid_ && wf + wb > T(0) ? wf / (wf + wb) : T(0);
        p_b_ = valid_ && wf + wb > T(0) ? T(1) - p_f_ : T(0);
    }

    // c_f K_f(s | a) + c_b K_b(s | a).
    HAIRSCATTER_HD V3 eval(const V3& s) const {
        T kf, kb;
        if (!densities(s, kf, kb)) return V3(T(0));
        return c_f_ * kf + c_b_ * kb;
    }
    HAIRSCATTER_HD T pdf(const V3& s) const {
        T kf, kb;
        if (!densities(s, kf, kb)) return T(0);
        return p_f_ * kf + p_b_ * kb;
    }
    // eval(s) and pdf(s) from one evaluation of the kernels (a light sample needs both).
    HAIRSCATTER_HD EvalPdf eval_pdf(const V3& s) const {
        EvalPdf r;
        T kf, kb;
        if (!densities(s, kf, kb)) return r;
        r.f = c_f_ * kf + c_b_ * kb;
        r.pdf = p_f_ * kf + p_b_ * kb;
        return r;
    }
    // u.x picks the side, (u.y, u.z) θs, u.w the azimuth within the half-circle.
    HAIRSCATTER_HD Sample sample(const V4& u) const {
        Sample r;
        if (!(p_f_ + p_b_ > T(0)) || !is_finite(u)) return r;
        const bool forward = clamp(u.x, T(0), T(1)) < p_f_;
        const DeonLongitudinal<T>& lobe = forward ? m_f_ : m_b_;
        // Conditioned on θo = -θa, M peaks at θs = θa.
        const T sin_s = lobe.sample_sin_theta(-sin_a_, cos_a_, clamp(u.y, T(0), T(1)), clamp(u.z, T(0), T(1)));
        const T half = kPi<T> * (clamp(u.w, T(0), T(1)) - T(0.5));
        const T psi = forward ? half : (half >= T(0) ? kPi<T> - half : -kPi<T> - half);
        r.s = direction_from_azimuth(a_, clamp(sin_s, T(-1), T(1)), psi);
        const EvalPdf ep = eval_pdf(r.s);
        r.pdf = ep.pdf > T(0) ? ep.pdf : T(0);
        r.f = r.pdf > T(0) ? ep.f : V3(T(0));
        return r;
    }
    HAIRSCATTER_HD const V3& arrival() const { return a_; }

  private:
    HAIRSCATTER_HD bool densities(const V3& s, T& kf, T& kb) const {
        kf = kb = T(0);
        if (!(valid_ && is_finite(s))) return false;
        const T sin_s = clamp(s.x, T(-1), T(1)), cos_s = cos_from_sin(sin_s);
        const bool near_half = abs_value(relative_azimuth(a_, s)) < kHalfPi<T>;
        if (near_half) kf = m_f_.eval(sin_s, cos_s, -sin_a_, cos_a_) * kInvPi<T>;
        else kb = m_b_.eval(sin_s, cos_s, -sin_a_, cos_a_) * kInvPi<T>;
        return true;
    }

    V3 a_;
    V3 c_f_, c_b_;
    DeonLongitudinal<T> m_f_, m_b_;
    T sin_a_ = T(0), cos_a_ = T(1);
    T p_f_ = T(0), p_b_ = T(0);
    bool valid_ = false;
};

}  // namespace hairscatter
