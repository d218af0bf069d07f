// hairscatter — 1D sampling distributions, each as a family: pdf, cdf, sample, invert.
#pragma once

#include <cmath>
#include <type_traits>

#include "../config.hpp"
#include "constants.hpp"
#include "elementary.hpp"
#include "functions.hpp"

namespace hairscatter {

// The unit-area Gaussian of standard deviation σ on the real line, g(σ; x) in Marschner
// et al. 2003's notation (their longitudinal M_p and caustic lobes).
template <typename T> HAIRSCATTER_HD T gaussian(T sigma, T x) {
    return kInvSqrtTwoPi<T> / sigma * elem::exp(T(-0.5) * sqr(x / sigma));
}

// Logistic distribution with scale s, restricted and renormalised to [-π, π]
// (Chiang et al. 2016 §4.2, the azimuthal detector of their N_p). Everything that depends
// only on s is computed once here; with the interval symmetric the normaliser is
// F(π) - F(-π) = tanh(π / 2s), and the inverse CDF has the closed form
// x = 2s atanh(tanh(π / 2s)(2u - 1)).
template <typename T> class TrimmedLogistic {
  public:
    TrimmedLogistic() = default;
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE explicit TrimmedLogistic(T s) : s_(s), inv_s_(T(1) / s) {
        // tanh(x) = -m / (2 + m) with m = e^(-2x) - 1 (x = π/2s > 0): elem::expm1 costs a
        // fraction of std::tanh, which was a quarter of a material's construction (a
        // material may be built per hit: ChiangMaterial::per_hit). Within 3 ulp of tanh;
        // e^(-2x) underflowing to 0 gives exactly 1.
        const T x = -kPi<T> * inv_s_;
        // Where e^x is below half an ulp of 1, expm1(x) rounds to -1 exactly, so norm is 1
        // and pdf_scale 1/s, bit for bit: the expm1 and two divisions are skipped (a material
        // built per hit pays them otherwise). In float that is every s below 0.179 (β_n
        // below 0.39 by Chiang's mapping), in double s below 0.082.
        if (x < kExpm1IsMinusOne) {
            norm_ = T(1);
            pdf_scale_ = inv_s_;
            return;
        }
        const T m = elem::expm1(x);
        norm_ = -m / (T(2) + m);
        pdf_scale_ = inv_s_ / norm_;
    }

    // The same logistic from s, 1/s and m = e^(-π/s) - 1 computed elsewhere (a model that
    // takes several lobes' exps as one vector: FurFiber), without the expm1 and its branch.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE TrimmedLogistic(T s, T inv_s, T m)
        : s_(s), inv_s_(inv_s), norm_(-m / (T(2) + m)), pdf_scale_(inv_s / norm_) {}

    HAIRSCATTER_HD T scale() const { return s_; }

    // Density on [-π, π]; x outside is a caller error (N_p wraps first).
    // e^(-|x|/s) / (s (1 + e^(-|x|/s))²): the |x| form never overflows. Split in two,
    // pdf(x) = density(exp(exponent(x))), so that a model can batch the exps of its lobes.
    HAIRSCATTER_HD T pdf(T x) const { return density(elem::exp(exponent(x))); }
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T exponent(T x) const { return -abs_value(x) * inv_s_; }
    // exponent(wrap_pi_once(d)) for d = φ - Φ with φ, Φ ∈ [-π, π], so d ∈ [-2π, 2π]: minus
    // the distance on the circle, min(|d|, 2π - |d|), over s, bit-identical to the wrap's
    // (2π - |d| is exact for |d| ≥ π, by Sterbenz's lemma; and -0 at |d| = 2π). Written as
    // the larger of the two exponents -|d|/s and -(2π - |d|)/s (rounding is monotonic, so the
    // larger is the one of the shorter distance): both products start as soon as |d| is
    // known, and the choice is one max instruction (a ?: of two values, which GCC vectorises
    // as such) at the end instead of a compare and a select before the product. This sits
    // on the chain from the azimuth to f.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T exponent_of_difference(T d) const {
        return exponent_of_difference(d, -inv_s_);
    }
    // The same with -1/s passed in (a lane may pass -0, for an exponent of -0 whatever d).
    static HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T exponent_of_difference(T d, T minus_inv_s) {
        const T a = abs_value(d);
        const T near = a * minus_inv_s, far = (kTwoPi<T> - a) * minus_inv_s;
        return far > near ? far : near;
    }
    HAIRSCATTER_HD T inv_scale() const { return inv_s_; }
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T density(T e) const { return pdf_scale_ * e / sqr(T(1) + e); }
    // density(e) = density_numerator(e) / density_denominator(e), for callers that multiply
    // the density by other factors before dividing.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T density_numerator(T e) const { return pdf_scale_ * e; }
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T density_denominator(T e) const { return sqr(T(1) + e); }

    HAIRSCATTER_HD T cdf(T x) const {
        using std::tanh;
        return T(0.5) * (T(1) + tanh(T(0.5) * x * inv_s_) / norm_);
    }

    // u ∈ [0, 1] → x ∈ [-π, π]; never NaN: the atanh argument is kept inside (-1, 1).
    HAIRSCATTER_HD T sample(T u) const {
        constexpr T lim = T(1) - kEpsilon<T>;
        const T z = clamp(norm_ * (T(2) * u - T(1)), -lim, lim);
        // 2 atanh(z) = log((1 + z)/(1 - z)); the quotient lies in [ε/2, 2/ε], so the log's
        // argument is normal, and x needs absolute (not relative) accuracy near 0.
        const T x = s_ * elem::log((T(1) + z) / (T(1) - z));
        return clamp(x, -kPi<T>, kPi<T>);
    }

    HAIRSCATTER_HD T invert(T x) const { return cdf(x); }

    // Probability of the arc [a, a + len] (0 ≤ len ≤ 2π) when the density is read on the
    // circle (as N_p is, after wrapping φ - Φ): the arc is split where it crosses ±π.
    HAIRSCATTER_HD T arc_mass(T a, T len) const {
        a = wrap_pi(a);
        const T b = a + len;
        if (b <= kPi<T>) return cdf(b) - cdf(a);
        return (T(1) - cdf(a)) + cdf(b - kTwoPi<T>);
    }

  private:
    // e^x < 2^-25 (float) or 2^-54 (double), half an ulp of 1, below these x, with a margin
    // for exp's own error: ln 2^-25 = -17.33, ln 2^-54 = -37.43.
    static constexpr T kExpm1IsMinusOne = std::is_same<T, float>::value ? T(-17.5) : T(-38);
    T s_ = T(1), inv_s_ = T(1), norm_ = T(1), pdf_scale_ = T(1);
};

// A discrete choice: the entry picked and the leftover of u within its interval,
// rescaled to a fresh uniform number in [0, 1].
template <typename T> struct DiscreteChoice {
    int index;
    T rescaled;
};

// Picks entry i of w[0, n) (weights ≥ 0) with probability w_i / Σw by inverting the
// cumulative sum at u·total, u ∈ [0, 1]. total is Σw summed in index order (the overload
// below) or 1 for weights the caller normalised (u is then compared as is). Entries of
// weight 0 are never picked: u ≈ 1 past the rounded sum falls back to the last entry with
// weight, leftover 1. All weights 0: entry 0, leftover u clamped to [0, 1]. The leftover is
// always in [0, 1], so a u outside it (a caller's error) cannot carry further.
template <typename T>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE DiscreteChoice<T> sample_discrete(const T* w, int n, T u, T total) {
    const T target = u * total;
    T before = T(0), last_before = T(0);
    int last = -1;
    for (int i = 0; i < n; ++i) {
        if (!(w[i] > T(0))) continue;
        if (target < before + w[i]) return {i, clamp((target - before) / w[i], T(0), T(1))};
        last = i;
        last_before = before;
        before += w[i];
    }
    if (last < 0) return {0, clamp(u, T(0), T(1))};
    return {last, clamp((target - last_before) / w[last], T(0), T(1))};
}

// The index sample_discrete(w, N, u, total) picks, given target = u·total (u itself for
// weights the caller normalised), without a branch: the count of cumulative sums at or
// below the target, raised to the first entry with weight (a target below 0) and capped at
// the last one (0 if none has weight). The same index for every u, ties, zero weights and
// u outside [0, 1] included (SampleDiscrete.ChosenIndexMatchesSampleDiscrete). For a
// sampler whose weights come at the end of a long chain (a stateless sample's wo terms): a
// branch on the picked entry is resolved only then, and goes wrong as often as the choice
// is uncertain, discarding the work begun on the guess.
template <int N, typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE int chosen_index(const T* w, T target) {
    T cum = T(0);
    int k = 0, first = N - 1, last = 0;
    for (int i = 0; i < N; ++i) {
        cum += w[i];
        if (i < N - 1) k += int(target >= cum);
        first = w[i] > T(0) && i < first ? i : first;
        last = w[i] > T(0) ? i : last;
    }
    k = k < first ? first : k;
    return k < last ? k : last;
}

template <typename T> HAIRSCATTER_HD DiscreteChoice<T> sample_discrete(const T* w, int n, T u) {
    T total = T(0);
    for (int i = 0; i < n; ++i) total += w[i];
    return sample_discrete(w, n, u, total);
}

// The inverse of the CDF C of a piecewise-linear density on the n ≥ 2 equispaced nodes
// x_k = k h: cdf(k) = C(x_k) (non-decreasing), density(k) = the density at x_k, both
// callables. Returns x = cell·h + offset with C(x) = target: the cell by binary search
// (the last k ≤ n - 2 with C(x_k) ≤ target, or 0), the offset δ ∈ [0, h] as the root of
// the cell's quadratic mass d = a δ + (b - a) δ²/2h in the form without cancellation,
// δ = 2d / (a + sqrt(a² + 2(b - a) d/h)).
template <typename T> struct PiecewiseLinearPoint {
    int cell;
    T offset;
};

template <typename T, typename Cdf, typename Density>
HAIRSCATTER_HD PiecewiseLinearPoint<T> invert_piecewise_linear(const Cdf& cdf, const Density& density, int n,
                                                              T h, T inv_h, T target) {
    using std::sqrt;
    int lo = 0, hi = n - 1;  // C[lo] ≤ target, and target < C[hi] unless hi = n - 1
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        if (cdf(mid) <= target)
            lo = mid;
        else
            hi = mid;
    }
    const T a = density(lo), b = density(lo + 1);
    // d < 0 only for a target below C[0] (rounding): the cell's start.
    const T d0 = target - cdf(lo);
    const T d = d0 > T(0) ? d0 : T(0);
    const T disc = a * a + T(2) * (b - a) * d * inv_h;
    const T den = a + sqrt(disc > T(0) ? disc : T(0));
    return {lo, den > T(0) ? clamp(T(2) * d / den, T(0), h) : T(0)};
}

}  // namespace hairscatter
