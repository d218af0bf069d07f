// hairscatter — domain-safe scalar helpers and the modified Bessel function I0.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "constants.hpp"

namespace hairscatter {

template <typename T> HAIRSCATTER_HD constexpr T sqr(T x) { return x * x; }

// x[0] + … + x[N-1] as a balanced tree, (x0 + x1) + (x2 + x3): a chain of ⌈log2 N⌉
// dependent additions instead of the loop's N - 1 (and no leading 0 + x0, which the
// compilers must keep for x0 = -0). Rounds differently from the loop in the last bits.
template <int N, typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T pairwise_sum(const T* x) {
    static_assert(N >= 1, "at least one term");
    if constexpr (N == 1) {
        return x[0];
    } else {
        constexpr int kHalf = (N + 1) / 2;
        return pairwise_sum<kHalf>(x) + pairwise_sum<N - kHalf>(x + kHalf);
    }
}

// Two separate selects, each the form of one max / min instruction (x86 SSE, CUDA): the
// compilers emit no branch for it. NaN stays NaN.
template <typename T> HAIRSCATTER_HD constexpr T clamp(T x, T lo, T hi) {
    const T above = x < lo ? lo : x;
    return above > hi ? hi : above;
}

// |x| as one bit operation (fabs). Written as x < 0 ? -x : x, GCC compiles it to a branch
// in some callers, mispredicted half the time where the sign is random (an azimuth).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T abs_value(T x) {
    using std::fabs;
    return fabs(x);
}

// clamp for a table coordinate: the same two selects, written so that a NaN x fails both
// comparisons and gives lo (a cell index made from it stays inside the table).
template <typename T> HAIRSCATTER_HD constexpr T clamp_nan_to_lo(T x, T lo, T hi) {
    const T above = x > lo ? x : lo;
    return above < hi ? above : hi;
}

// x is neither NaN nor ±Inf, read from the exponent bits: -ffast-math (-ffinite-math-only)
// folds std::isfinite and x == x to true, this test it cannot fold.
HAIRSCATTER_HD inline bool is_finite(float x) {
    std::uint32_t b;
    std::memcpy(&b, &x, sizeof b);
    return (b & 0x7f800000u) != 0x7f800000u;
}
HAIRSCATTER_HD inline bool is_finite(double x) {
    std::uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    return (b & 0x7ff0000000000000ull) != 0x7ff0000000000000ull;
}
namespace detail {
template <typename T> struct FiniteBits;
template <> struct FiniteBits<float> {
    using U = std::uint32_t;
    static constexpr U kAbs = 0x7fffffffu, kInf = 0x7f800000u;
};
template <> struct FiniteBits<double> {
    using U = std::uint64_t;
    static constexpr U kAbs = 0x7fffffffffffffffull, kInf = 0x7ff0000000000000ull;
};
template <int N, typename T>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE typename FiniteBits<T>::U max_magnitude_bits(const glm::vec<N, T>& v,
                                                                                     typename FiniteBits<T>::U m) {
    using B = FiniteBits<T>;
    for (int i = 0; i < N; ++i) {
        typename B::U b;
        std::memcpy(&b, &v[i], sizeof b);
        b &= B::kAbs;
        m = b > m ? b : m;
    }
    return m;
}
}  // namespace detail
template <int N, typename T> HAIRSCATTER_HD bool is_finite(const glm::vec<N, T>& v) {
    bool ok = true;
    for (int i = 0; i < N; ++i) ok &= is_finite(v[i]);  // & not &&: no branch per component
    return ok;
}
// Both vectors finite: the largest magnitude's bits below those of +Inf (NaN's are above),
// one comparison and one branch for the six or seven components the stateless calls test.
template <int N, int M, typename T>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE bool all_finite(const glm::vec<N, T>& a, const glm::vec<M, T>& b) {
    using U = typename detail::FiniteBits<T>::U;
    return detail::max_magnitude_bits(b, detail::max_magnitude_bits(a, U(0))) < detail::FiniteBits<T>::kInf;
}

// Directions as the models read them: unit vectors. A finite direction of another length
// (one a renderer forgot to normalise, or with components up to the largest float) is
// rescaled, by its largest component first so that no square overflows or underflows; a
// zero vector has no direction (false). A renderer's normalised vectors (|w|² within a few
// ulps of 1) pass as they are: one dot product and one predictable branch.
namespace detail {
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE bool to_unit(glm::vec<3, T>& w) {
    using std::abs;
    using std::sqrt;
    const T l2 = w.x * w.x + w.y * w.y + w.z * w.z;
    if (abs(l2 - T(1)) <= T(1e-5)) return true;
    const T ax = abs(w.x), ay = abs(w.y), az = abs(w.z);
    const T m = ax > ay ? (ax > az ? ax : az) : (ay > az ? ay : az);
    if (!(m > T(0))) return false;
    // w / m, the largest component then ±1, so that its square neither overflows nor
    // underflows. Written as w · (1/m), which is what -ffast-math makes of it anyway: 1/m is
    // subnormal (flushed to 0 under fast-math) for m above 1/FLT_MIN and infinite for a
    // subnormal m, so m is first brought toward 1 by 2^∓64 (exact).
    constexpr T kDown = T(5.42101086242752217e-20), kUp = T(18446744073709551616.0);  // 2^-64, 2^64
    T k = m;
    if (m > kUp) w *= kDown, k *= kDown;
    if (m < kDown) w *= kUp, k *= kUp;
    w *= T(1) / k;
    w /= sqrt(w.x * w.x + w.y * w.y + w.z * w.z);
    return true;
}
}  // namespace detail
// Finite, non-zero w, made unit in place (see detail::to_unit).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE bool unit_direction(glm::vec<3, T>& w) {
    return is_finite(w) && detail::to_unit(w);
}
// Finite, non-zero a and b, made unit in place (see detail::to_unit).
template <typename T>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE bool unit_directions(glm::vec<3, T>& a, glm::vec<3, T>& b) {
    if (!all_finite(a, b)) return false;
    const bool ok_a = detail::to_unit(a), ok_b = detail::to_unit(b);
    return ok_a && ok_b;
}
// Finite u, clamped into [0, 1] in place: a sampler's numbers slightly outside it, or far,
// give the nearest valid sample, in every model.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE bool unit_numbers(glm::vec<4, T>& u) {
    if (!is_finite(u)) return false;
    for (int k = 0; k < 4; ++k) u[k] = u[k] < T(0) ? T(0) : (u[k] > T(1) ? T(1) : u[k]);
    return true;
}
// Finite, non-zero w made unit and finite u clamped, in place.
template <typename T>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE bool unit_direction_and_numbers(glm::vec<3, T>& w, glm::vec<4, T>& u) {
    if (!all_finite(w, u)) return false;
    unit_numbers(u);
    return detail::to_unit(w);
}

// c ? a : b without a branch, for the loops over lobes that the compilers vectorise: GCC
// (under the default -ftrapping-math) does not if-convert a floating-point `c ? a : b`
// whose arms it would have to speculate, and leaves the whole loop scalar; selecting the
// bits with an integer mask it does vectorise (to a blend). Both arms are evaluated.
namespace detail {
template <typename T, typename Bits> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T select_bits(bool c, T a, T b) {
    static_assert(sizeof(T) == sizeof(Bits), "an unsigned integer of the real's width");
    Bits ba, bb;
    std::memcpy(&ba, &a, sizeof ba);
    std::memcpy(&bb, &b, sizeof bb);
    const Bits m = c ? ~Bits(0) : Bits(0);
    const Bits r = (ba & m) | (bb & ~m);
    T out;
    std::memcpy(&out, &r, sizeof out);
    return out;
}
}  // namespace detail
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE float select(bool c, float a, float b) {
    return detail::select_bits<float, std::uint32_t>(c, a, b);
}
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE double select(bool c, double a, double b) {
    return detail::select_bits<double, std::uint64_t>(c, a, b);
}

// The cell of a table coordinate x ∈ [0, last + 1], in [0, last]: NaN and values below 0
// give 0 and values past the end give last, so a bad coordinate never indexes outside.
template <typename T> HAIRSCATTER_HD int table_cell(T x, int last) {
    if (!(x > T(0))) return 0;  // also NaN
    if (!(x < T(last))) return last;
    return int(x);
}

// sqrt that tolerates arguments rounded slightly below zero (e.g. 1 - sin² at θ = ±90°).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T safe_sqrt(T x) {
    HAIRSCATTER_DCHECK(!(x < T(-1e-3)));  // NaN passes: non-finite input is the models' to zero
    using std::sqrt;
    return sqrt(x > T(0) ? x : T(0));
}

// asin that tolerates |x| rounded slightly above one.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T safe_asin(T x) {
    HAIRSCATTER_DCHECK(!(x < T(-1.0001) || x > T(1.0001)));  // NaN passes, as in safe_sqrt
    using std::asin;
    return asin(clamp(x, T(-1), T(1)));
}

// cos θ from sin θ, accurate near θ = ±90° where 1 - s² cancels: (1 - s)(1 + s).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T cos_from_sin(T s) { return safe_sqrt((T(1) - s) * (T(1) + s)); }

// Wraps a finite angle to [-π, π] (differences of azimuths and Φ(p, h) reach ±4π).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T wrap_pi(T x) {
    using std::floor;
    x -= kTwoPi<T> * floor((x + kPi<T>) * kInvTwoPi<T>);
    return clamp(x, -kPi<T>, kPi<T>);  // rounding can leave it a hair outside
}

// Wraps x ∈ [-3π, 3π] (the difference of two angles in [-π, π]) to [-π, π] by at most one
// turn, without floor or a branch: the form the lane loops vectorise (on SSE2 as well).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T wrap_pi_once(T x) {
    x = select(x > kPi<T>, x - kTwoPi<T>, select(x < -kPi<T>, x + kTwoPi<T>, x));
    return clamp(x, -kPi<T>, kPi<T>);
}

namespace detail {

// Horner evaluation, lowest order first. The coefficients are passed as literals converted
// to T at the call site, so they fold to constants of the evaluation type.
template <typename T> HAIRSCATTER_HD constexpr T horner(T, T c0) { return c0; }
template <typename T, typename... Cs> HAIRSCATTER_HD constexpr T horner(T x, T c0, Cs... cs) {
    return c0 + x * horner(x, cs...);
}

// The same polynomial by Estrin's scheme, for the hot paths: c_0 … c_{M-1} + x^M · (the
// rest), M the largest power of two below the count, recursively. The FMA chain is
// log₂(n) deep instead of n - 1 (evaluated on its own, a polynomial is latency-bound), at
// the price of a few multiplications; the rounding error is of the same order.
template <int M, typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T power_of_two_power(T x) {
    if constexpr (M == 1) return x;
    else return sqr(power_of_two_power<M / 2>(x));
}
template <int N, typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T estrin_array(T x, const T* c) {
    if constexpr (N == 1) {
        return c[0];
    } else {
        constexpr int M = N > 8 ? 8 : N > 4 ? 4 : N > 2 ? 2 : 1;
        return estrin_array<M>(x, c) + power_of_two_power<M>(x) * estrin_array<N - M>(x, c + M);
    }
}
template <typename T, typename... Cs> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T estrin(T x, Cs... cs) {
    static_assert(sizeof...(Cs) <= 16, "up to degree 15");
    const T c[] = {T(cs)...};
    return estrin_array<int(sizeof...(Cs))>(x, c);
}

// Modified Bessel function I0, split at x = 6 (fitted for this library by Chebyshev
// interpolation against mpmath at 40 digits; see tests/math_test.cpp for the check against
// Boost.Math):
//   x ≤ 6: I0(x) = 1 + y·P(y), y = x²/4 — P is the power series Σ y^k/((k+1)!)² refitted on
//          y ∈ [0, 9]; relative error 1.5e-10, and I0 - 1 keeps its relative accuracy
//          for tiny x (log I0 needs it).
//   x > 6: √x e^(-x) I0(x) = Q(6/x) — relative error 1.7e-9 (Q(0) = 1/√(2π) is the
//          asymptotic limit, so no slow path exists for any argument).
// pbrt's 10-term series is off by 1.5 % at large x and runs into subnormals; this is not.
constexpr double kI0SmallSplit = 6.0;

template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T i0_small_minus_one(T x) {
    const T y = T(0.25) * x * x;
    return y * (T(1.0000000003133483716) + y * estrin(y, T(0.249999994362186269057),
                      T(0.027777794445482060956), T(0.00173609217789404810854),
                      T(0.0000694551895274435695843), T(0.00000192560003122220105341),
                      T(4.00000626509952145251e-8), T(5.47656410364662669124e-10),
                      T(1.1352864748412762681e-11)));
}

// Takes t = 6/x ∈ (0, 1].
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T i0_large_scaled_sqrt_t(T t) {
    return T(0.398942279781196684609) + t * estrin(t, T(0.00831139763790257582454),
                  T(0.000776561216222653930921), T(0.000161276754668690157394),
                  T(-0.0000915198354603106014836), T(0.000342097117170683312368),
                  T(-0.000471667343606663586999), T(0.000354470865047110757867),
                  T(-0.0000992243858736370222398));
}
template <typename T> HAIRSCATTER_HD T i0_large_scaled_sqrt(T x) {
    return i0_large_scaled_sqrt_t(T(kI0SmallSplit) / x);
}

}  // namespace detail

// I0(x), the modified Bessel function of the first kind, order 0. Overflows (like
// I0 itself) beyond x ≈ 89 in float and ≈ 713 in double: use i0e or log_i0 there.
template <typename T> HAIRSCATTER_HD T i0(T x) {
    using std::exp;
    using std::sqrt;
    x = x < T(0) ? -x : x;
    if (x <= T(detail::kI0SmallSplit)) return T(1) + detail::i0_small_minus_one(x);
    // e^x split in two halves so that it does not overflow before the 1/√x factor.
    const T e = exp(T(0.5) * x);
    return (detail::i0_large_scaled_sqrt(x) * e / sqrt(x)) * e;
}

// e^(-|x|) I0(x), the exponentially scaled I0: finite and accurate for every x.
template <typename T> HAIRSCATTER_HD T i0e(T x) {
    using std::exp;
    using std::sqrt;
    x = x < T(0) ? -x : x;
    if (x <= T(detail::kI0SmallSplit)) return exp(-x) * (T(1) + detail::i0_small_minus_one(x));
    return detail::i0_large_scaled_sqrt(x) / sqrt(x);
}

// log I0(x), accurate in relative terms for every x (log1p keeps x²/4 for tiny x).
template <typename T> HAIRSCATTER_HD T log_i0(T x) {
    using std::log;
    using std::log1p;
    using std::sqrt;
    x = x < T(0) ? -x : x;
    if (x <= T(detail::kI0SmallSplit)) return log1p(detail::i0_small_minus_one(x));
    return x + log(detail::i0_large_scaled_sqrt(x) / sqrt(x));
}

}  // namespace hairscatter
