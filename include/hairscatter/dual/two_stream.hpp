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
//     K_f(s | a) = M(v_f; θs around θa) · G(u_f; φs − φa)
//     K_b(s | a) = M(v_b; θs around θa) · [|φs − φa − π| < π/2] / π
// M is d'Eon et al. 2011's normalised longitudinal lobe, G(u; ·) the Gaussian of variance u
// restricted to the half-circle |φs − φa| < π/2. Scattering by a fiber keeps the
// component of the light's travel along the fiber, so θ is kept and spread; a transmitted
// path stays on a's side of the circle of azimuths, a returned one comes from the other
// half (Zinke et al. 2008 spread forward-scattered light uniformly over a half-circle; K_b
// still does). Each event also turns the light around the fiber by an angle of mean cosine
// μ_f or μ_b (the tables' mu_f, mu_b), so K_f narrows to the forward lobe's turn after one
// fiber and widens toward the uniform half-circle as the events add up, and the stacks are
// as deep as the fibers the turning light crosses (dual_turned_depth; docs/theory.md §5.7).
// The variances come from the stacks themselves, nothing fitted: a path of the stack
// passes k_f forward and k_b backward events on average, k_f = a_f ∂ln X/∂a_f and
// k_b = a_b ∂ln X/∂a_b for X = T_n or R_n (and T_m for the far side's passage), and each
// event adds its lobe's mean variance β̄²_f or β̄²_b (tables.hpp), and to u_f the variance
// −2 ln μ of its turn.
#pragma once

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../fiber/frame.hpp"
#include "../lobes/longitudinal.hpp"
#include "../math/constants.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"
#include "density_grid_view.hpp"
#include "tables.hpp"

namespace hairscatter {

// What the hair along one arrival direction does to the light (per RGB channel).
template <typename T> struct DualStreams {
    glm::vec<3, T> forward{T(1)};  // c_f: share of the light entering on a's side that arrives along a
    glm::vec<3, T> back{T(0)};     // c_b: share of the light entering on the far side that arrives along a
    T spread_f = T(0), spread_b = T(0);  // variances v_f, v_b of the source kernels (rad², channel mean)
    // Variance of K_f's azimuth around a (rad², channel mean): the turns of the events the
    // transmitted light passed. The default is wide enough to be uniform over the half-circle.
    T turn_f = T(1e4);
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

// A stack inclined to its fibers (docs/theory.md §5.7, "Stacks inclined to the fibers"):
// the entry whose layers return only the share rho_b of their backscatter, the share whose
// travel runs back along the stack (a fiber keeps the component of the light's travel along
// its axis), and pass the rest on with the forward light. a_f + a_b is kept, so a lossless
// stack still passes or returns everything. dual_streams, dual_source_stack and
// dual_count_limit use an entry's a_f and a_b as they are: the 1D stack of Zinke et al. 2008,
// where every backward event returns, unless the caller passes them this entry instead
// (the example renderer does by default, --dual-stacks inclined; planar keeps the 1D
// stack: docs/dual.md).
// rho_b is clamped to [0, 1]; NaN gives 1.
template <typename T> HAIRSCATTER_HD DualScatteringEntry<T> dual_stack_entry(const DualScatteringEntry<T>& e) {
    DualScatteringEntry<T> r = e;
    for (int k = 0; k < 3; ++k) {
        const T rho = e.rho_b[k] >= T(0) ? (e.rho_b[k] < T(1) ? e.rho_b[k] : T(1)) : (e.rho_b[k] < T(0) ? T(0) : T(1));
        r.a_b[k] = e.a_b[k] * rho;
        r.a_f[k] = e.a_f[k] + (e.a_b[k] - r.a_b[k]);
        r.rho_b[k] = T(1);
    }
    return r;
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
        using std::floor;
        return k > T(1) ? floor(k + T(0.5)) : T(1);  // floor, not int: means up to 1e12 and beyond
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

// The variance of the Gaussian whose mean cosine is μ, −2 ln μ: one event's azimuthal turn.
// μ ≤ 1e-6 (no preferred direction, or a NaN) gives 27.6, which spreads K_f evenly.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T dual_turn_variance(T mu) {
    return T(-2) * elem::log(mu > T(1e-6) ? (mu < T(1) ? mu : T(1)) : T(1e-6));
}

// The inverse error function: Giles 2010 ("Approximating the erfinv function", GPU Computing
// Gems Jade, the single-precision rational-free form), then one Newton step on erf, which
// brings double to a few ulp. |y| is kept below 1.
template <typename T> HAIRSCATTER_HD T erf_inverse(T y) {
    using std::erf;
    using std::sqrt;
    constexpr T lim = T(1) - T(4) * kEpsilon<T>;
    const T x = clamp(y, -lim, lim);
    T w = -elem::log((T(1) - x) * (T(1) + x)), p;
    if (w < T(5)) {
        w -= T(2.5);
        p = T(2.81022636e-08);
        p = T(3.43273939e-07) + p * w;
        p = T(-3.5233877e-06) + p * w;
        p = T(-4.39150654e-06) + p * w;
        p = T(0.00021858087) + p * w;
        p = T(-0.00125372503) + p * w;
        p = T(-0.00417768164) + p * w;
        p = T(0.246640727) + p * w;
        p = T(1.50140941) + p * w;
    } else {
        w = sqrt(w) - T(3);
        p = T(-0.000200214257);
        p = T(0.000100950558) + p * w;
        p = T(0.00134934322) + p * w;
        p = T(-0.00367342844) + p * w;
        p = T(0.00573950773) + p * w;
        p = T(-0.0076224613) + p * w;
        p = T(0.00943887047) + p * w;
        p = T(1.00167406) + p * w;
        p = T(2.83297682) + p * w;
    }
    T r = p * x;
    // Newton on erf(r) = x: erf'(r) = 2/√π e^{−r²}.
    const T slope = T(1.1283791670955126) * elem::exp(-r * r);
    if (slope > T(0)) r -= (erf(r) - x) / slope;
    return r;
}

// The Gaussian of variance v restricted and renormalised to the half-circle [−π/2, π/2]:
// K_f's azimuth around a. One fiber's forward turn, averaged over h, is close to a Gaussian
// of the same mean cosine (for Chiang's fiber at θ = 0, η = 1.55, β_n = 0.3: density 0.688
// against 0.685 at the peak, 0.468 against 0.475 at 0.5 rad), and Gaussians compose: the
// turns of k events are the Gaussian of k times the variance. Large v tends to the uniform
// half-circle of Zinke et al. 2008.
template <typename T> class HalfCircleGaussian {
  public:
    HalfCircleGaussian() = default;
    HAIRSCATTER_HD explicit HalfCircleGaussian(T variance) {
        using std::erf;
        using std::sqrt;
        const T v = is_finite(variance) ? clamp(variance, kMinSourceSpread<T>, kMaxSourceSpread<T>) : kMaxSourceSpread<T>;
        root_2v_ = sqrt(T(2) * v);
        inv_2v_ = T(0.5) / v;
        mass_ = erf(kHalfPi<T> / root_2v_);  // of [−π/2, π/2]
        scale_ = T(0.56418958354775628695) / (root_2v_ * mass_);  // 1 / (√π √(2v) mass)
    }
    // Density on [−π/2, π/2] (0 outside).
    HAIRSCATTER_HD T pdf(T x) const {
        if (!(abs_value(x) <= kHalfPi<T>)) return T(0);
        return scale_ * elem::exp(-x * x * inv_2v_);
    }
    // u ∈ [0, 1] → x ∈ [−π/2, π/2].
    HAIRSCATTER_HD T sample(T u) const {
        const T y = mass_ * (T(2) * clamp(u, T(0), T(1)) - T(1));
        return clamp(root_2v_ * erf_inverse(y), -kHalfPi<T>, kHalfPi<T>);
    }

  private:
    T root_2v_ = T(1), inv_2v_ = T(1), mass_ = T(1), scale_ = T(1);
};

// The fibers that light crosses to come n fibers deep along a when every fiber it passes
// turns it (docs/theory.md §5.7, "Turning light"). The 1D stack lets light run straight along
// a; each forward event turns it by an angle of mean cosine μ_f, so after j events its
// direction makes an angle φ_j with a, and it crosses 1/E[cos φ_j] fibers per fiber of
// progress along a (the flux's diffusivity). E[cos φ_j] runs from 1 (j = 0: the last
// fiber before the point is crossed along a) to 2/π, the uniform half-circle's (the 2D
// diffusivity π/2), through the Gaussian turn of variance −2 j ln μ_f:
//     c_j = 2/π + (1 − 2/π) exp(−v_j / (2 (1 − 2/π))),   v_j = −2 j ln μ_f,
// which has the Gaussian's slope at v = 0 and the half-circle's limit (within 4.5 % of the
// truncated Gaussian's own mean cosine everywhere). The depth is Σ_{j<n} 1/c_j, with the
// fraction of the last fiber counted as such; n ≤ 1 is unchanged (one fiber is crossed
// along a). Lossless stacks still pass or return everything at any depth. n comes from
// dual_stack_depth (finite, ≥ 0); μ_f is clamped to [1e-6, 1].
//
// `limit` replaces the slab's 2/π by what the hair's own shape gives (dual_turn_limit): in
// a volume of finite width light that turns leaves through the sides sooner, and the
// fibers it crosses are fewer. The turns' rate stays the Gaussian's. limit is clamped to
// [kMinTurnLimit, kMaxTurnLimit]; NaN gives the slab's.
template <typename T> inline constexpr T kSlabTurnLimit = T(0.63661977236758134308);  // 2/π
template <typename T> inline constexpr T kMinTurnLimit = T(0.3);
template <typename T> inline constexpr T kMaxTurnLimit = T(3);
// The turned depth and the part of it that the light crosses before it is spread: the sum
// of e_j / c_j with e_j = e^{−λ j}, the share of the light at the j-th fiber still in the
// Gaussian's narrow part (c_j = limit + (1 − limit) e_j). The diffuse transport of
// dual_streams keeps that part at each end of a stack as it is and spreads the rest.
template <typename T> struct DualTurnedDepth {
    T total = T(0);      // Σ 1/c_j: dual_turned_depth
    T ballistic = T(0);  // Σ e_j/c_j ≤ total
};
template <typename T> HAIRSCATTER_HD DualTurnedDepth<T> dual_turned_depths(T n, T mu_f, T limit = kSlabTurnLimit<T>) {
    DualTurnedDepth<T> r;
    if (!(n > T(1))) {
        r.total = r.ballistic = n;
        return r;
    }
    const T lim = limit == limit ? clamp(limit, kMinTurnLimit<T>, kMaxTurnLimit<T>) : kSlabTurnLimit<T>;
    const T w = T(1) - lim;
    const T mu = mu_f > T(1e-6) ? (mu_f < T(1) ? mu_f : T(1)) : T(1e-6);
    // The rate at which the turns spread the light is the Gaussian's (slope −1/2 at v = 0),
    // whatever the limit the geometry sets.
    const T lambda = -elem::log(mu) / (T(1) - kSlabTurnLimit<T>);
    const T q = elem::exp(-lambda);
    // The first fibers one by one; past 32 (fibers that turn light very little), the rest as
    // the integral of the same summand over [j − ½, n − ½], the midpoint rule's span:
    //     ∫ dx / (2/π + w e^{−λx}) = (x + ln(2/π + w e^{−λx}) / λ) / (2/π),
    // and for the ballistic part ∫ e^{−λx} dx / (lim + w e^{−λx}) = −ln(lim + w e^{−λx}) / (λ w).
    constexpr int kTerms = 32;
    T depth = T(0), ballistic = T(0), qj = T(1);
    int j = 0;
    for (; T(j + 1) <= n && j < kTerms; ++j) {
        const T inv_c = T(1) / (lim + w * qj);
        depth += inv_c;
        ballistic += qj * inv_c;
        qj *= q;
    }
    const T rest = n - T(j);  // fibers left, the last perhaps a fraction
    if (rest <= T(1) || !(lambda > T(1e-6))) {
        const T c = lim + w * qj;
        r.total = depth + rest / c;
        r.ballistic = ballistic + rest * qj / c;
        return r;
    }
    const T e0 = qj * elem::exp(T(0.5) * lambda), e1 = qj * elem::exp(-(rest - T(0.5)) * lambda);  // e^{−λx} at both ends
    const T span = elem::log((lim + w * e1) / (lim + w * e0));
    r.total = depth + (rest + span / lambda) / lim;
    const T tail = abs_value(w) > T(1e-6) ? -span / (lambda * w) : (e0 - e1) / (lambda * lim);
    r.ballistic = ballistic + clamp(tail, T(0), r.total - ballistic);
    return r;
}
template <typename T> HAIRSCATTER_HD T dual_turned_depth(T n, T mu_f, T limit = kSlabTurnLimit<T>) {
    return dual_turned_depths(n, mu_f, limit).total;
}

// How light crosses a stack past its first fibers (dual_streams; docs/theory.md §5.7,
// "Spread light in the stacks").
//  kTurned: every fiber passes a_f and returns a_b of the light, as for the light along a;
//    only the depth grows with the turns (dual_turned_depth).
//  kDiffuse: the same where the light is still narrow about the stack's axis, at both ends
//    (the arrival along a, and the source's beam entering beyond the far face); in between,
//    where it is spread over its half-circle, a fiber's turn also carries some of it across
//    to the other half-circle: forward events send back, and backward ones on, the shares
//    dual_crossover(μ_f) and dual_crossover(μ_b) (the two-stream's hemispheric-mean
//    exchange for light spread evenly over its half-circle, as in Meador and Weaver 1980).
//    a_f + a_b is kept. Closer to explicit slabs than kTurned, not to every scene.
enum class DualStackTransport : int { kTurned = 0, kDiffuse = 1 };

// The share of light spread evenly over a half-circle of azimuths that one event's turn, of
// mean cosine mu, carries across to the other half: E|δ| / π for the turn δ (a Gaussian of
// variance −2 ln μ, whose E|δ| = σ √(2/π)), at most ½ (a turn uniform over the circle).
// Light that turns along the fiber's normal plane by δ from φ crosses ±π/2 where
// |φ + δ| > π/2, and over φ uniform in [−π/2, π/2] that happens with probability E|δ|/π.
// mu is clamped to [1e-6, 1]; NaN gives ½.
template <typename T> HAIRSCATTER_HD T dual_crossover(T mu) {
    using std::sqrt;
    if (!(mu == mu)) return T(0.5);
    const T m = mu > T(1e-6) ? (mu < T(1) ? mu : T(1)) : T(1e-6);
    // σ √(2/π) / π = 2 √(−ln μ / π) / π
    const T x = T(0.63661977236758134308) * sqrt(-elem::log(m) * T(0.31830988618379067154));
    return x < T(0.5) ? x : T(0.5);
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
// misalignment ∈ [0, 1] (clamped; NaN as 0): the mean sin² of the angle between the fibers
// around the point and its own axis (0 for combed or straight hair; 2/3 for fibers in every
// direction), which widens both kernels in θ (below); 0 leaves every result unchanged.
template <typename T>
HAIRSCATTER_HD DualStreams<T> dual_streams(const DualScatteringEntry<T>& e, T n_fibers, T m_fibers,
                                           T limit_n = kSlabTurnLimit<T>, T limit_m = kSlabTurnLimit<T>,
                                           DualStackTransport transport = DualStackTransport::kTurned,
                                           T misalignment = T(0)) {
    DualStreams<T> s;
    const T mf = (e.mu_f.x + e.mu_f.y + e.mu_f.z) * T(1.0 / 3.0), mb = (e.mu_b.x + e.mu_b.y + e.mu_b.z) * T(1.0 / 3.0);
    // The stacks' depths as the fibers the turning light crosses (at most kDeepStack).
    const DualTurnedDepth<T> dn = dual_turned_depths(dual_stack_depth(n_fibers), mf, limit_n);
    const DualTurnedDepth<T> dm = dual_turned_depths(dual_stack_depth(m_fibers), mf, limit_m);
    const T n = dual_stack_depth(dn.total), m = dual_stack_depth(dm.total);
    const bool diffuse = transport == DualStackTransport::kDiffuse;
    // Lanes 0–2: the channels; lane 3: the channel mean, whose albedos give the events below.
    // The same four layers n deep (lanes 0–3) and m deep (4–7), as one batch. With diffuse
    // transport these are the stacks' narrow ends (each at most half the stack), and a second
    // batch holds the spread middles.
    const T af = (e.a_f.x + e.a_f.y + e.a_f.z) * T(1.0 / 3.0), ab = (e.a_b.x + e.a_b.y + e.a_b.z) * T(1.0 / 3.0);
    LayerLanes<T, 4> layer;
    elem::store4(layer.a_f, e.a_f.x, e.a_f.y, e.a_f.z, af);
    elem::store4(layer.a_b, e.a_b.x, e.a_b.y, e.a_b.z, ab);
    layer_lanes(layer);
    LayerLanes<T, 8> c;
    repeat_lanes(layer, c);
    // A stack whose narrow ends meet (the light still narrow halfway through) has no middle
    // and stays one stack, as with turned transport.
    const T end_n = diffuse && dn.ballistic < T(0.5) * n ? dn.ballistic : n;
    const T end_m = diffuse && dm.ballistic < T(0.5) * m ? dm.ballistic : m;
    const T mid_n = end_n < n ? n - T(2) * end_n : T(0), mid_m = end_m < m ? m - T(2) * end_m : T(0);
    const T depth[8] = {end_n, end_n, end_n, end_n, end_m, end_m, end_m, end_m};
    T R[8], T_[8];
    layered_stacks(c, depth, R, T_);
    if (mid_n > T(0) || mid_m > T(0)) {
        const T cf = dual_crossover(mf), cb = dual_crossover(mb);
        LayerLanes<T, 4> spread;
        for (int k = 0; k < 4; ++k) {
            spread.a_f[k] = layer.a_f[k] * (T(1) - cf) + layer.a_b[k] * cb;
            spread.a_b[k] = layer.a_b[k] * (T(1) - cb) + layer.a_f[k] * cf;
        }
        layer_lanes(spread);
        LayerLanes<T, 8> c2;
        repeat_lanes(spread, c2);
        const T middle[8] = {mid_n, mid_n, mid_n, mid_n, mid_m, mid_m, mid_m, mid_m};
        T R2[8], T2[8];
        layered_stacks(c2, middle, R2, T2);
        // The adding formula for layers alike from both sides: the middle and the far end,
        // then the near end before them (R seen from the shading point).
        for (int k = 0; k < 8; ++k) {
            if (!((k < 4 ? mid_n : mid_m) > T(0))) continue;  // one stack, already whole
            const T d1 = T(1) - R2[k] * R[k];
            const T r_far = d1 > T(0) ? R2[k] + T2[k] * T2[k] * R[k] / d1 : T(1);
            const T t_far = d1 > T(0) ? T2[k] * T_[k] / d1 : T(0);
            const T d2 = T(1) - R[k] * r_far;
            const T r = d2 > T(0) ? R[k] + T_[k] * T_[k] * r_far / d2 : T(1);
            T_[k] = d2 > T(0) ? T_[k] * t_far / d2 : T(0);
            R[k] = r;
        }
    }
    for (int k = 0; k < 3; ++k) {
        const T den = T(1) - R[k] * R[4 + k];
        s.forward[k] = den > T(0) ? clamp(T_[k] / den, T(0), T(1)) : T(0);
        s.back[k] = den > T(0) ? clamp(R[k] * T_[4 + k] / den, T(0), T(1)) : T(0);
    }
    // The events, from the mean channel's stacks with a_f, then a_b, scaled by 1 - ε: in
    // double whatever T is (a float quotient of two stacks 1e-3 apart loses the events of
    // deep stacks: 40 % in v_f at 15 fibers, 80° off normal), with the unscaled stacks
    // recomputed beside them (lanes 4 and 5).
    constexpr double eps = 1e-6;
    const double inv_log = 1.0 / elem::log1p(-eps);
    LayerLanes<double, 8> d;
    const double nd = double(n), md = double(m), afd = double(af), abd = double(ab);
    const double depth_d[8] = {nd, nd, md, md, nd, md, 0.0, 0.0};
    d.a_f[0] = afd * (1 - eps), d.a_b[0] = abd;
    d.a_f[1] = afd, d.a_b[1] = abd * (1 - eps);
    d.a_f[2] = afd * (1 - eps), d.a_b[2] = abd;
    d.a_f[3] = afd, d.a_b[3] = abd * (1 - eps);
    for (int k = 4; k < 8; ++k) d.a_f[k] = afd, d.a_b[k] = abd;
    layer_lanes(d);
    double Rd[8], Td[8];
    layered_stacks(d, depth_d, Rd, Td);
    using detail::mean_events;
    const T events_f = T(mean_events(Td[0], Td[4], inv_log)), events_b = T(mean_events(Td[1], Td[4], inv_log));
    const T returned_f = T(mean_events(Rd[0], Rd[4], inv_log)), returned_b = T(mean_events(Rd[1], Rd[4], inv_log));
    const T far_f = T(mean_events(Td[2], Td[5], inv_log)), far_b = T(mean_events(Td[3], Td[5], inv_log));
    const T bf = (e.beta2_f.x + e.beta2_f.y + e.beta2_f.z) * T(1.0 / 3.0);
    const T bb = (e.beta2_b.x + e.beta2_b.y + e.beta2_b.z) * T(1.0 / 3.0);
    // Fibers around the point that are not parallel to it (`misalignment`, the mean sin² of
    // their angle δ to its axis: dual_misalignment) move the light's longitudinal angle at
    // every event too. A fiber tilted by δ keeps the travel along its own axis, which moves
    // the component along the point's axis by δ (d_in − d_out)·v (v the tilt's direction
    // across the axis, uniform): a variance of E[δ²] (1 + cos φ) in θ for a turn φ of wi from
    // wo, so E[δ²] (1 − μ_f) per forward event and E[δ²] (1 + μ_b) per backward one. Straight
    // through (φ = π) is not deviated; straight back by a mirror tilted by δ, by 2δ.
    const T tilt = misalignment > T(0) ? (misalignment < T(1) ? misalignment : T(1)) : T(0);
    const T tf = tilt * (T(1) - mf), tb = tilt * (T(1) + mb);
    const T vf = events_f * (bf + tf) + events_b * (bb + tb);
    const T vb = (returned_f + far_f) * (bf + tf) + (returned_b + far_b) * (bb + tb);
    s.spread_f = clamp(is_finite(vf) ? vf : T(0), kMinSourceSpread<T>, kMaxSourceSpread<T>);
    s.spread_b = clamp(is_finite(vb) ? vb : T(0), kMinSourceSpread<T>, kMaxSourceSpread<T>);
    // Each event turns the light around the fiber by an angle whose mean cosine is μ (the
    // entry's mu_f, mu_b). Mean cosines of independent turns multiply, so the variance of the
    // equivalent Gaussian, −2 ln μ per event, adds over the events like the θ spreads.
    const T turn = events_f * dual_turn_variance(mf) + events_b * dual_turn_variance(mb);
    s.turn_f = clamp(is_finite(turn) ? turn : T(0), kMinSourceSpread<T>, kMaxSourceSpread<T>);
    return s;
}
template <typename T>
HAIRSCATTER_HD DualStreams<T> dual_streams(const DualTablesView<T>& tables, T sin_theta_a, T n_fibers, T m_fibers) {
    return dual_streams(tables.lookup(sin_theta_a), n_fibers, m_fibers);
}

template <typename T> struct DualSourceStack {
    glm::vec<3, T> t{T(1)}, r{T(0)};  // T_N' and R_N' per channel
};

// The stack of N' fibers beyond a stack's face along a source direction, apart: what it
// transmits of L(s) (t = T_N') and what it reflects of the light on the face's own side
// (r = R_N'); each in [0, 1], t + r = dual_source_gain. NaN or negative counts give no
// fibers (t = 1, r = 0), +Inf a deep stack.
template <typename T>
HAIRSCATTER_HD DualSourceStack<T> dual_source_stack(const DualScatteringEntry<T>& e, T count) {
    DualSourceStack<T> st;
    const T n = dual_stack_depth(count);
    if (!(n > T(0))) return st;
    LayerLanes<T, 4> layer;
    elem::store4(layer.a_f, e.a_f.x, e.a_f.y, e.a_f.z, T(0));
    elem::store4(layer.a_b, e.a_b.x, e.a_b.y, e.a_b.z, T(0));
    layer_lanes(layer);
    const T depth[4] = {n, n, n, n};
    T R[4], T_[4];
    layered_stacks(layer, depth, R, T_);
    for (int k = 0; k < 3; ++k) {
        st.t[k] = is_finite(T_[k]) ? clamp(T_[k], T(0), T(1)) : T(0);
        st.r[k] = is_finite(R[k]) ? clamp(R[k], T(0), T(1) - st.t[k]) : T(0);
    }
    return st;
}

// Where the renderer knows the light around the face (its hair's mean radiance L̄ there, as
// the example renderer's glow volume holds it), the hair along s is better read as a
// medium of albedo a_f + a_b lit by L̄: the face receives t L(s) + h L̄ with
// h = (1 − t)(a_f + a_b) per channel (docs/theory.md §5.7, "The hair along a source
// direction"). Exact in a furnace (lossless: a_f + a_b = 1 and L̄ = L).
template <typename T>
HAIRSCATTER_HD glm::vec<3, T> dual_source_hair(const DualScatteringEntry<T>& e, const DualSourceStack<T>& st) {
    glm::vec<3, T> h;
    for (int k = 0; k < 3; ++k) {
        const T v = (T(1) - st.t[k]) * (e.a_f[k] + e.a_b[k]);
        h[k] = is_finite(v) ? clamp(v, T(0), T(1)) : T(0);
    }
    return h;
}

// The misalignment of dual_streams at a point from the hair's length tensor there (the
// density grid's DensityGridView::tensor_density, or any Σ ℓ t tᵀ): 1 − axisᵀ M axis / tr M,
// the length-weighted mean sin² of the angle between the hair and the unit `axis`. 0 where
// there is no hair or the input is not finite.
template <typename T>
HAIRSCATTER_HD T dual_misalignment(const HairLengthTensor<T>& m, const glm::vec<3, T>& axis) {
    const T len = m.length();
    if (!(len > T(0)) || !is_finite(len) || !is_finite(axis)) return T(0);
    const T v = T(1) - m.along(axis) / len;
    return is_finite(v) ? clamp(v, T(0), T(1)) : T(0);
}

// The share of L(s) that reaches a stack's far face from direction s when `count` more
// fibers lie between that face and the outside along s (docs/theory.md §5.7, "sources beyond
// the exit"): T_N + R_N of that stack at the entry's θ. The face receives the light the
// N fibers transmit, T_N L(s), and their reflection of the light on the face's own side,
// R_N L_in, with L_in taken as L(s): exact in a furnace (a lossless stack gives 1 to
// rounding), and no brighter than the source wherever the hair is dimmer than it. NaN or
// negative counts give 1 (no fibers), +Inf a deep stack.
template <typename T> HAIRSCATTER_HD glm::vec<3, T> dual_source_gain(const DualScatteringEntry<T>& e, T count) {
    const DualSourceStack<T> st = dual_source_stack(e, count);
    return st.t + st.r;
}

// The limit of dual_turned_depth for a stack along d from origin, from the hair's own
// shape (docs/theory.md §5.7, "The hair's shape sets the diffusivity"): light spread evenly
// over the half-circle of directions around d (turned about the fiber's axis) crosses
// 1/E[cos φ] fibers per fiber of progress in a slab, where the count along the turned
// direction is C(φ) = C(0)/cos φ. So C(0) · E[1/C(φ)] is 2/π deep in a slab across d, and
// larger where turned light leaves the hair sooner (a volume of finite width, a face).
// E over the half-circle by its six-point midpoint rule; counts below one fiber count as
// one (the fiber a ray along d meets). Any density source (fibers_crossed); d and axis unit
// vectors; max_distance as for fibers_crossed, and the same bound for all seven directions:
// pass kUnbounded (to the source's edge) rather than a distance measured along d, which cuts
// the turned directions short (they cross more of a layer than d does, so a thin layer would
// read as one its light leaves sideways). Non-finite input gives the slab's 2/π.
template <typename T, class Source>
HAIRSCATTER_HD T dual_turn_limit(const Source& source, const glm::vec<3, T>& origin, const glm::vec<3, T>& axis,
                                 const glm::vec<3, T>& d, T max_distance) {
    using V3 = glm::vec<3, T>;
    if (!(is_finite(origin) && is_finite(axis) && is_finite(d))) return kSlabTurnLimit<T>;
    const auto count = [&](const V3& dir) {
        const T c = source.fibers_crossed(origin, dir, max_distance);
        return c > T(1) ? c : T(1);  // also NaN → 1
    };
    // cos and sin of (k + ½) π/6 − π/2, k = 0..2 (the other three are their mirrors).
    constexpr T cs[3] = {T(0.25881904510252076), T(0.70710678118654752), T(0.96592582628906829)};
    constexpr T sn[3] = {T(0.96592582628906829), T(0.70710678118654752), T(0.25881904510252076)};
    const V3 along = axis * glm::dot(axis, d), across = d - along, side = glm::cross(axis, d);
    T inv = T(0);
    for (int k = 0; k < 3; ++k)
        for (int sign = -1; sign <= 1; sign += 2)
            inv += T(1) / count(glm::normalize(along + across * cs[k] + side * (T(sign) * sn[k])));
    const T limit = count(d) * inv / T(6);
    return is_finite(limit) ? clamp(limit, kMinTurnLimit<T>, kMaxTurnLimit<T>) : kSlabTurnLimit<T>;
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
        : a_(a), c_f_(streams.forward), c_b_(streams.back), m_f_(streams.spread_f), m_b_(streams.spread_b),
          turn_f_(streams.turn_f) {
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
    // u.x picks the side, (u.y, u.z) θs, u.w the azimuth within the half-circle (K_f's
    // Gaussian, K_b's uniform).
    HAIRSCATTER_HD Sample sample(const V4& u) const {
        Sample r;
        if (!(p_f_ + p_b_ > T(0)) || !is_finite(u)) return r;
        const bool forward = clamp(u.x, T(0), T(1)) < p_f_;
        const DeonLongitudinal<T>& lobe = forward ? m_f_ : m_b_;
        // Conditioned on θo = -θa, M peaks at θs = θa.
        const T sin_s = lobe.sample_sin_theta(-sin_a_, cos_a_, clamp(u.y, T(0), T(1)), clamp(u.z, T(0), T(1)));
        const T half = kPi<T> * (clamp(u.w, T(0), T(1)) - T(0.5));
        const T psi = forward ? turn_f_.sample(u.w) : (half >= T(0) ? kPi<T> - half : -kPi<T> - half);
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
        const T turn = relative_azimuth(a_, s);
        if (abs_value(turn) < kHalfPi<T>) kf = m_f_.eval(sin_s, cos_s, -sin_a_, cos_a_) * turn_f_.pdf(turn);
        else kb = m_b_.eval(sin_s, cos_s, -sin_a_, cos_a_) * kInvPi<T>;
        return true;
    }

    V3 a_;
    V3 c_f_, c_b_;
    DeonLongitudinal<T> m_f_, m_b_;
    HalfCircleGaussian<T> turn_f_;
    T sin_a_ = T(0), cos_a_ = T(1);
    T p_f_ = T(0), p_b_ = T(0);
    bool valid_ = false;
};

}  // namespace hairscatter
