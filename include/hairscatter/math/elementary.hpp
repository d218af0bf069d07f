// hairscatter — exp, atan2 and asin for the hot paths. double uses the standard library;
// float on the host uses the inline versions below, accurate to a few ulp (tested against
// the standard library in tests/math_test.cpp) but free of libm's call overhead and
// special-case handling, which dominate the cost of a hair evaluation; on a GPU, CUDA's
// own device functions.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "../config.hpp"

// x86 host code (SSE is part of x86-64): sqrt_each's SQRTPS. Not in CUDA device code.
#if !defined(__CUDA_ARCH__) && (defined(__SSE__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 1))
#include <xmmintrin.h>
#define HAIRSCATTER_HAS_SSE_SQRT 1
#else
#define HAIRSCATTER_HAS_SSE_SQRT 0
#endif
// And SSE2's SQRTPD for doubles (part of x86-64 too).
#if !defined(__CUDA_ARCH__) && (defined(__SSE2__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2))
#include <emmintrin.h>
#define HAIRSCATTER_HAS_SSE2_SQRT 1
#else
#define HAIRSCATTER_HAS_SSE2_SQRT 0
#endif
// And AVX's eight floats or four doubles to one VSQRTPS / VSQRTPD (where the target has AVX).
#if HAIRSCATTER_HAS_SSE2_SQRT && defined(__AVX__)
#include <immintrin.h>
#define HAIRSCATTER_HAS_AVX_SQRT 1
#else
#define HAIRSCATTER_HAS_AVX_SQRT 0
#endif
// GCC's and Clang's vector extensions (exp_each's groups of four): host code only, and not
// under nvcc, whose front end need not know __builtin_convertvector.
#if !defined(__CUDACC__) && (defined(__GNUC__) || defined(__clang__))
#define HAIRSCATTER_HAS_VECTOR_EXT 1
#else
#define HAIRSCATTER_HAS_VECTOR_EXT 0
#endif
#include "constants.hpp"
#include "functions.hpp"

namespace hairscatter {
namespace elem {

namespace detail {

// The float exp rounds x log2 e with the shifter 1.5·2²³ (an addition and a subtraction)
// rather than a truncating conversion after adding ±1/2 and converting back (a chain twice as
// long). Reassociating flags (-ffast-math, -fassociative-math) would fold (y + s) - s to y,
// so under them it keeps the conversions (round_to_int).
#if defined(__FAST_MATH__) || defined(__ASSOCIATIVE_MATH__)
#define HAIRSCATTER_EXP_SHIFTER 0
#else
#define HAIRSCATTER_EXP_SHIFTER 1
#endif

// Rounds y (|y| < 2^30) to the nearest integer, halves away from zero, through a
// float → int conversion. The classic (y + 1.5·2^23) - 1.5·2^23 trick is folded to y by
// -ffast-math (-fassociative-math); a conversion cannot be.
HAIRSCATTER_FORCE_INLINE std::int32_t round_to_int(float y) { return std::int32_t(y + std::copysign(0.5f, y)); }

// The polynomials below take a float or a lane vector F (GCC's and Clang's vector
// extensions, exp_each and friends), so that the scalar and the lane forms share one set of
// coefficients and the same operations in the same order (bit-identical results).
// Horner's scheme with float coefficients, lowest order first (hairscatter::detail::horner's
// nesting; a coefficient is broadcast to the lanes).
template <typename F> HAIRSCATTER_FORCE_INLINE F horner_f(F x, float c0, float c1) { return c0 + x * c1; }
template <typename F, typename... Cs> HAIRSCATTER_FORCE_INLINE F horner_f(F x, float c0, float c1, Cs... cs) {
    return c0 + x * horner_f(x, c1, cs...);
}
// expm1 near 0 (|x| < 1/2): its Taylor series to x¹⁰, truncation 5e-10 relative.
template <typename F> HAIRSCATTER_FORCE_INLINE F expm1_series(F x) {
    return x * horner_f(x, 1.0f, 0.5f, 1.0f / 6, 1.0f / 24, 1.0f / 120, 1.0f / 720, 1.0f / 5040, 1.0f / 40320,
                        1.0f / 362880);
}
// 2 atanh s = ln((1 + s) / (1 - s)) by its series to s⁹ (|s| ≤ 0.172: truncation 1e-9
// relative): the logarithms' common tail.
template <typename F> HAIRSCATTER_FORCE_INLINE F atanh2_series(F s) {
    const F z = s * s;
    return s * horner_f(z, 2.0f, 2.0f / 3, 2.0f / 5, 2.0f / 7, 2.0f / 9);
}
// log1p near 0 (x ∈ [-0.29, 0.41]): 2 atanh(x / (2 + x)), truncation 2e-9 relative.
template <typename F> HAIRSCATTER_FORCE_INLINE F log1p_series(F x) { return atanh2_series(x / (2.0f + x)); }

// e^x for x ≤ 88 (callers pass x ≤ 0): Cody–Waite reduction x = n ln2 + r, |r| ≤ ln2/2,
// the degree-7 Taylor polynomial of e^r (truncation 5e-9 relative), and 2^n written into
// the exponent bits. Below -87.3 (where e^x is subnormal) it returns 0; NaN returns NaN
// (the clamp sends it to -87.3 first, so no NaN is ever converted to an integer).
// kLanes: the two range selects as integer masks (math/functions.hpp: select), the form in
// which a loop of exps vectorises (exp_each); a single scalar exp uses plain conditionals,
// because the masks move the value between float and integer registers (measured: eval
// 28 % slower with the mask form in its scalar exps).
template <bool kLanes> HAIRSCATTER_FORCE_INLINE float exp_float(float x) {
    const float xc = kLanes ? select(x > -87.3f, select(x < 88.0f, x, 88.0f), -87.3f)
                            : (x > -87.3f ? (x < 88.0f ? x : 88.0f) : -87.3f);
#if HAIRSCATTER_EXP_SHIFTER
    // n = round(x log2 e) by the shifter: 1.5·2²³ + y has unit spacing, so the sum holds the
    // rounded y in its low mantissa bits (read as an integer) and minus the shifter is n.
    const float t = xc * 1.44269504088896341f + 12582912.0f;
    const float n = t - 12582912.0f;
    std::int32_t ni;
    std::memcpy(&ni, &t, sizeof ni);
    ni -= 0x4B400000;
#else
    const std::int32_t ni = round_to_int(xc * 1.44269504088896341f);
    const float n = float(ni);
#endif
    const float r = (xc - n * 0.693145751953125f) - n * 1.42860682030941723212e-6f;
    // The terms from r² on by Estrin's scheme (a short FMA chain), the last two steps as in
    // Horner's, so that the rounding of the result stays that of Horner's scheme.
    const float q = hairscatter::detail::estrin(r, 0.5f, 1.0f / 6, 1.0f / 24, 1.0f / 120, 1.0f / 720, 1.0f / 5040);
    const float p = 1.0f + r * (1.0f + r * q);
    const std::int32_t bits = (ni + 127) * (1 << 23);
    float scale;
    std::memcpy(&scale, &bits, sizeof scale);
    if (kLanes) return p * select(x > -87.3f, scale, select(x <= -87.3f, 0.0f, x));  // (as in exp_float_lanes)
    return x > -87.3f ? p * scale : (x <= -87.3f ? 0.0f : x);
}

#if HAIRSCATTER_HAS_VECTOR_EXT
// exp_float<true> of four (or, with AVX, eight) lanes as one vector of GCC's and Clang's
// vector extensions: the same operations in the same order. A loop of exp_float<true> is
// left to the compilers' vectorisers, and Clang's leaves a batch of four scalar (its loop
// vectoriser skips loops that short; what the SLP vectoriser makes of the unrolled copies
// depends on the code around them: it left the Chiang batches scalar when the N and M exps
// became two batches of four). exp_each uses it for whole groups of lanes.
typedef float F32x4 __attribute__((vector_size(16)));
typedef std::int32_t I32x4 __attribute__((vector_size(16)));
typedef float F32x8 __attribute__((vector_size(32)));
typedef std::int32_t I32x8 __attribute__((vector_size(32)));
template <typename V, typename S> HAIRSCATTER_FORCE_INLINE V splat(S v) {
    return V{} + v;  // a scalar operand is broadcast to every lane
}
// m ? a : b per lane, m a comparison's all-ones / zero mask.
template <typename F, typename I> HAIRSCATTER_FORCE_INLINE F select_lanes(I m, F a, F b) {
    return reinterpret_cast<F>((m & reinterpret_cast<I>(a)) | (~m & reinterpret_cast<I>(b)));
}
// kClampHigh false: for x ≤ 88 only (callers whose exponents are ≤ 0), without the clamp
// at 88, a compare and a select less at the head of the chain; above 88 and at +Inf the
// result is unspecified. Equal to the clamped form wherever both are defined.
template <typename F, typename I, bool kClampHigh = true> HAIRSCATTER_FORCE_INLINE F exp_float_lanes(F x) {
    const F lo = splat<F>(-87.3f);
    const I in_range = x > lo;
    const F xc = kClampHigh ? select_lanes<F, I>(in_range, select_lanes<F, I>(x < splat<F>(88.0f), x, splat<F>(88.0f)), lo)
                            : select_lanes<F, I>(in_range, x, lo);
#if HAIRSCATTER_EXP_SHIFTER
    const F t = xc * splat<F>(1.44269504088896341f) + splat<F>(12582912.0f);
    const F n = t - splat<F>(12582912.0f);
    const I ni = reinterpret_cast<I>(t) - splat<I>(std::int32_t(0x4B400000));
#else
    // round_to_int: y + copysign(0.5, y), truncated
    const F y = xc * splat<F>(1.44269504088896341f);
    const I sign = reinterpret_cast<I>(y) & splat<I>(std::int32_t(0x80000000u));
    const I ni = __builtin_convertvector(y + reinterpret_cast<F>(sign | reinterpret_cast<I>(splat<F>(0.5f))), I);
    const F n = __builtin_convertvector(ni, F);
#endif
    const F r = (xc - n * splat<F>(0.693145751953125f)) - n * splat<F>(1.42860682030941723212e-6f);
    // estrin(r, 1/2, 1/6, 1/24, 1/120, 1/720, 1/5040), as hairscatter::detail::estrin groups it
    const F r2 = r * r;
    const F q = ((splat<F>(0.5f) + r * splat<F>(1.0f / 6)) + r2 * (splat<F>(1.0f / 24) + r * splat<F>(1.0f / 120))) +
                (r2 * r2) * (splat<F>(1.0f / 720) + r * splat<F>(1.0f / 5040));
    const F p = splat<F>(1.0f) + r * (splat<F>(1.0f) + r * q);
    const F scale = reinterpret_cast<F>((ni + splat<I>(std::int32_t(127))) * splat<I>(std::int32_t(1 << 23)));
    const I below = x <= lo;  // (NaN: neither, and stays NaN)
    // The ranges are selected in the factor, which is ready long before p: 2^n in range,
    // 0 below (p > 0), x itself for NaN. The polynomial's result then needs one product.
    return p * select_lanes<F, I>(in_range, scale, select_lanes<F, I>(below, splat<F>(0.0f), x));
}

// e^x of two or four doubles (F64x2, F64x4; I the integer vector) for x ≤ 0 (NaN and -Inf allowed), the form of exp_float_lanes in
// double: x = n ln2 + r with ln2 in two parts (the high one's 21 trailing zero bits keep
// n·ln2_hi exact), |r| ≤ ln2/2, the Taylor polynomial of e^r to r¹³ (truncation 4e-18
// relative) and 2^n written into the exponent bits. Below -708.39 it returns 0, as exp<double>
// does (the results would be subnormal), NaN stays NaN. Within 2 ulp of libm's exp
// (tests/math_test.cpp); reassociating flags (-ffast-math) may fold the two-part reduction
// into one product, which costs about |x|·3e-17 relative (2e-14 at x = -674, measured).
typedef double F64x2 __attribute__((vector_size(16)));
typedef std::int64_t I64x2 __attribute__((vector_size(16)));
typedef double F64x4 __attribute__((vector_size(32)));
typedef std::int64_t I64x4 __attribute__((vector_size(32)));
template <typename F64x4, typename I64x4> HAIRSCATTER_FORCE_INLINE F64x4 exp_double_lanes(F64x4 x) {
    const F64x4 lo = splat<F64x4>(-708.39);
    const I64x4 in_range = x > lo;
    const F64x4 xc = select_lanes<F64x4, I64x4>(in_range, x, lo);
#if HAIRSCATTER_EXP_SHIFTER
    // n = round(x log2 e) by the shifter 1.5·2⁵², as exp_float_lanes
    const F64x4 t = xc * splat<F64x4>(1.4426950408889634074) + splat<F64x4>(6755399441055744.0);
    const F64x4 n = t - splat<F64x4>(6755399441055744.0);
    const I64x4 ni = reinterpret_cast<I64x4>(t) - splat<I64x4>(std::int64_t(0x4338000000000000));
#else
    const F64x4 y = xc * splat<F64x4>(1.4426950408889634074);
    const I64x4 sign = reinterpret_cast<I64x4>(y) & splat<I64x4>(std::int64_t(0x8000000000000000u));
    const I64x4 ni = __builtin_convertvector(y + reinterpret_cast<F64x4>(sign | reinterpret_cast<I64x4>(splat<F64x4>(0.5))), I64x4);
    const F64x4 n = __builtin_convertvector(ni, F64x4);
#endif
    const F64x4 r = (xc - n * splat<F64x4>(0.693147180369123816490)) - n * splat<F64x4>(1.90821492927058770002e-10);
    // 1 + r + r²/2 + … + r¹³/13!: the terms from r² on by Estrin's scheme, the last two
    // steps as Horner's
    const F64x4 r2 = r * r, r4 = r2 * r2;
    const F64x4 c0 = splat<F64x4>(1.0 / 2) + r * splat<F64x4>(1.0 / 6);
    const F64x4 c1 = splat<F64x4>(1.0 / 24) + r * splat<F64x4>(1.0 / 120);
    const F64x4 c2 = splat<F64x4>(1.0 / 720) + r * splat<F64x4>(1.0 / 5040);
    const F64x4 c3 = splat<F64x4>(1.0 / 40320) + r * splat<F64x4>(1.0 / 362880);
    const F64x4 c4 = splat<F64x4>(1.0 / 3628800) + r * splat<F64x4>(1.0 / 39916800);
    const F64x4 c5 = splat<F64x4>(1.0 / 479001600) + r * splat<F64x4>(1.0 / 6227020800);
    const F64x4 q = (c0 + r2 * c1) + r4 * ((c2 + r2 * c3) + r4 * (c4 + r2 * c5));
    const F64x4 p = splat<F64x4>(1.0) + r * (splat<F64x4>(1.0) + r * q);
    const F64x4 scale = reinterpret_cast<F64x4>((ni + splat<I64x4>(std::int64_t(1023))) << 52);
    const I64x4 below = x <= lo;  // (NaN: neither, and stays NaN)
    return p * select_lanes<F64x4, I64x4>(in_range, scale, select_lanes<F64x4, I64x4>(below, splat<F64x4>(0.0), x));
}

// The other lane functions the same way: each the scalar lane form's operations in the same
// order on a vector F (F32x4 or F32x8) with its integer vector I (LaneInt), so that the
// results are bit-identical to the scalar loops they replace. The loops stay scalar under
// Clang (its loop vectoriser skips trip counts this short, and its SLP vectoriser leaves
// bodies this long alone): the dual-scattering BCSDF's lanes cost Clang about 40 % more
// instructions than GCC before.
template <typename F> struct LaneInt;
template <> struct LaneInt<F32x4> {
    using type = I32x4;
};
template <> struct LaneInt<F32x8> {
    using type = I32x8;
};
template <typename F, typename I> HAIRSCATTER_FORCE_INLINE F abs_lanes(F x) {
    return reinterpret_cast<F>(reinterpret_cast<I>(x) & splat<I>(std::int32_t(0x7fffffff)));
}
// expm1_each's lane form: the series below |x| = 1/2, exp - 1 beyond.
template <typename F, typename I> HAIRSCATTER_FORCE_INLINE F expm1_lanes(F x) {
    return select_lanes<F, I>(abs_lanes<F, I>(x) < splat<F>(0.5f), expm1_series(x), exp_float_lanes<F, I>(x) - 1.0f);
}
// log_float (positive normal x).
template <typename F, typename I> HAIRSCATTER_FORCE_INLINE F log_lanes(F x) {
    I bits = reinterpret_cast<I>(x);
    I e = ((bits >> 23) & splat<I>(std::int32_t(0xff))) - splat<I>(std::int32_t(127));
    bits = (bits & splat<I>(std::int32_t(0x007fffff))) | splat<I>(std::int32_t(0x3f800000));
    F m = reinterpret_cast<F>(bits);
    const I high = m > splat<F>(1.41421356f);
    m = select_lanes<F, I>(high, 0.5f * m, m);
    e -= high;  // (a true comparison is -1)
    const F f = m - 1.0f;  // exact (Sterbenz)
    const F log_m = atanh2_series(f / (2.0f + f));
    const F ef = __builtin_convertvector(e, F);
    return (ef * 1.42860682030941723212e-6f + log_m) + ef * 0.693145751953125f;
}
// log1p_each's lane form (x ≥ 0, +Inf or NaN).
template <typename F, typename I> HAIRSCATTER_FORCE_INLINE F log1p_lanes(F x) {
    const I near0 = (x > splat<F>(-0.29f)) & (x < splat<F>(0.41f));
    const F r = select_lanes<F, I>(near0, log1p_series(x), log_lanes<F, I>(1.0f + x));
    return select_lanes<F, I>(x <= splat<F>(3.0e38f), r, x);  // +Inf stays +Inf, NaN NaN
}

// The lane functions as function objects for each_group (generic over the vector type).
template <typename F> using LaneIntOf = typename LaneInt<F>::type;
template <bool kClampHigh = true> struct ExpLanes {
    template <typename F> HAIRSCATTER_FORCE_INLINE F operator()(F v) const {
        return exp_float_lanes<F, LaneIntOf<F>, kClampHigh>(v);
    }
};
struct Expm1Lanes {
    template <typename F> HAIRSCATTER_FORCE_INLINE F operator()(F v) const { return expm1_lanes<F, LaneIntOf<F>>(v); }
};
struct Log1pLanes {
    template <typename F> HAIRSCATTER_FORCE_INLINE F operator()(F v) const { return log1p_lanes<F, LaneIntOf<F>>(v); }
};
struct LogLanes {
    template <typename F> HAIRSCATTER_FORCE_INLINE F operator()(F v) const { return log_lanes<F, LaneIntOf<F>>(v); }
};
struct PowLanes {  // v^y as e^(y ln v), pow_each's form
    float y;
    template <typename F> HAIRSCATTER_FORCE_INLINE F operator()(F v) const {
        return exp_float_lanes<F, LaneIntOf<F>>(y * log_lanes<F, LaneIntOf<F>>(v));
    }
};

// Applies op (a function of one lane vector, generic over F32x4 and F32x8) to x in groups
// of eight floats where AVX gives 8-lane registers, else of four; false (nothing done) when
// N is not a multiple of four. A group of eight is read as two halves of four: callers write
// their lanes in groups of four (the Chiang N and M exponents), and one 32-byte load of two
// 16-byte stores cannot take its data from the store buffer (it waits for the stores to
// reach the cache: measured, it ate the whole saving of the wider exp).
template <std::size_t N, typename Op> HAIRSCATTER_FORCE_INLINE bool each_group(float (&x)[N], Op op) {
#if defined(__AVX__)
    if constexpr (N % 8 == 0) {
        for (int k = 0; k < int(N); k += 8) {
            F32x4 lo, hi;
            std::memcpy(&lo, x + k, sizeof lo);
            std::memcpy(&hi, x + k + 4, sizeof hi);
#if defined(__clang__)
            __asm__("" : "+x"(hi));  // else Clang merges the two loads into the one that stalls
#endif
            F32x8 v = {lo[0], lo[1], lo[2], lo[3], hi[0], hi[1], hi[2], hi[3]};
            v = op(v);
            std::memcpy(x + k, &v, sizeof v);
        }
        return true;
    }
#endif
    if constexpr (N % 4 == 0) {
        for (int k = 0; k < int(N); k += 4) {
            F32x4 v;
            std::memcpy(&v, x + k, sizeof v);
            v = op(v);
            std::memcpy(x + k, &v, sizeof v);
        }
        return true;
    }
    return false;
}
#endif

// atan(a) = a·P(a²) for a ∈ [0, 1], P fitted for this library (Chebyshev interpolation
// against mpmath): absolute error 1e-8. This returns P(a²); the caller multiplies.
HAIRSCATTER_FORCE_INLINE float atan_unit_factor(float a) {
    const float z = a * a;
    // c0 + z·Q(z), Q by Estrin's scheme, as in exp_float.
    return 0.99999998178865573f + z * hairscatter::detail::estrin(z, -0.33333036709286276f, 0.19991872029109072f,
                                                                -0.14197797794085123f, 0.10618370636953849f,
                                                                -0.074568548260045474f, 0.042137623589193041f,
                                                                -0.015731249122183653f, 0.002766283501762026f);
}
HAIRSCATTER_FORCE_INLINE float atan_unit(float a) { return a * atan_unit_factor(a); }

// asin(x) for x ∈ [0, 0.7] as x + x³Q(x²) with one polynomial Q of eight terms, fitted for
// this library (Chebyshev fit against mpmath on x ≤ 0.7): relative error 7e-9 with the
// coefficients rounded to float.
HAIRSCATTER_FORCE_INLINE float asin_small_poly(float x) {
    const float z = x * x;
    return x + x * z *
                   hairscatter::detail::estrin(z, 0.1666666567325592f, 0.07500207424163818f, 0.04455553740262985f,
                                               0.031760264188051224f, 0.011921180412173271f, 0.05892248451709747f,
                                               -0.07186254858970642f, 0.0897582471370697f);
}

// log x for positive normal x: x = m·2^e with m ∈ [√½, √2), log m = 2 atanh(s),
// s = (m - 1)/(m + 1), |s| ≤ 0.172, by its series to s⁹ (truncation 1e-9 relative).
// The mantissa's halving is a select (bit masks), not a branch: whether m > √2 is a coin
// toss for the random numbers a sampler passes (a mispredicted branch per log), and it is
// also the form in which a loop of logs vectorises (log1p_each, pow_each).
HAIRSCATTER_FORCE_INLINE float log_float(float x) {
    std::int32_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    std::int32_t e = ((bits >> 23) & 0xff) - 127;
    bits = (bits & 0x007fffff) | 0x3f800000;
    float m;
    std::memcpy(&m, &bits, sizeof m);
    const bool high = m > 1.41421356f;
    m = select(high, 0.5f * m, m);
    e += std::int32_t(high);
    const float f = m - 1.0f;  // exact (Sterbenz)
    const float log_m = atanh2_series(f / (2.0f + f));
    const float ef = float(e);
    return (ef * 1.42860682030941723212e-6f + log_m) + ef * 0.693145751953125f;
}

// sin and cos of |x| ≤ 8192: x = qπ/2 + r with |r| ≤ π/4 (three-part Cody–Waite), then the
// Taylor series of sin r to r⁹ and cos r to r¹⁰ (truncation below 2e-9), rotated by q.
// No branch: the form in which a loop of them vectorises (ChiangBatch's sampled azimuths).
HAIRSCATTER_FORCE_INLINE void sincos_float_reduced(float x, float& s, float& c) {
    const std::int32_t qi = round_to_int(x * 0.636619772367581343f);
    const float q = float(qi);
    const float r = ((x - q * 1.5703125f) - q * 4.83751296997070312e-4f) - q * 7.54978995489188216e-8f;
    const float z = r * r;
    const float sr = r + r * z * hairscatter::detail::horner(z, -1.0f / 6, 1.0f / 120, -1.0f / 5040, 1.0f / 362880);
    const float cr = 1.0f + z * hairscatter::detail::horner(z, -0.5f, 1.0f / 24, -1.0f / 720, 1.0f / 40320,
                                                            -1.0f / 3628800);
    // Rotated by the quadrant q mod 4 without a branch (a switch on it mispredicts about
    // half the time for the angles of a sampler): odd q swaps sr and cr, and the sign bit
    // of s flips where bit 1 of q is set, that of c where bit 1 of q + 1 is.
    //   q = 0: (sr, cr)   1: (cr, -sr)   2: (-sr, -cr)   3: (-cr, sr)
    const bool odd = (qi & 1) != 0;
    const float s0 = select(odd, cr, sr), c0 = select(odd, sr, cr);
    std::uint32_t bs, bc;
    std::memcpy(&bs, &s0, sizeof bs);
    std::memcpy(&bc, &c0, sizeof bc);
    bs ^= std::uint32_t(qi & 2) << 30;
    bc ^= std::uint32_t((qi + 1) & 2) << 30;
    std::memcpy(&s, &bs, sizeof s);
    std::memcpy(&c, &bc, sizeof c);
}
// The same for any x: |x| > 8192, ±Inf and NaN go to the standard library (NaN results for
// the last two).
HAIRSCATTER_FORCE_INLINE void sincos_float(float x, float& s, float& c) {
    if (!(std::fabs(x) <= 8192.0f)) {
        s = std::sin(x);
        c = std::cos(x);
        return;
    }
    sincos_float_reduced(x, s, c);
}

}  // namespace detail

// Results that would be subnormal are flushed to 0 (e^-708 for double): libm's
// underflow path is many times slower, and lobes far from their peak land there.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T exp(T x) {
    using std::exp;
    return x > T(-708.39) ? exp(x) : T(0);
}
template <> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE float exp(float x) {
#if defined(__CUDA_ARCH__)
    return ::expf(x);
#else
    return detail::exp_float<false>(x);
#endif
}

template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T atan2(T y, T x) {
    using std::atan2;
    return atan2(y, x);
}
template <> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE float atan2(float y, float x) {
#if defined(__CUDA_ARCH__)
    return ::atan2f(y, x);
#else
    // Octant reduction to r = atan(min/max) ∈ [0, π/4], then the octant and quadrant from
    // the signs, all without a conditional: the octant of a random direction is
    // unpredictable, and GCC compiles conditional expressions here to branches (one
    // mispredicted branch per call cost more than the whole polynomial). With d = ax - ay
    // (d < 0: steep) the angle in the upper half-plane is
    //   x ≥ 0, d ≥ 0:  r          x ≥ 0, d < 0:  π/2 - r
    //   x < 0, d ≥ 0:  π - r      x < 0, d < 0:  π/2 + r
    // that is base + s·r with base = (π/2 - copysign(π/2, x)) + copysign(π/4 - copysign(π/4, d), x)
    // (0, π/2, π; exact in float) and s the product of the signs of d and x. Both are ready
    // long before r, so the polynomial's last step a·P(a²) becomes the one operation
    // base + (s·a)·P(a²): after the polynomial only that and y's sign remain on the chain
    // (they were two copysigns and two additions, and π/2 + r was rounded twice).
    // min and max are single instructions, the reflections copysign (bit operations). d = 0
    // only when ax = ay (gradual underflow). x = -0 counts as negative, as in std::atan2:
    // atan2(±0, -0) = ±π.
    const float ax = std::fabs(x), ay = std::fabs(y);
    const float hi = ay > ax ? ay : ax;  // MAXSS
    // min as one MINPS of splatted vectors: a scalar ?: here became a branch (GCC shares
    // its comparison with the max), and the integer-mask select a trip through general
    // registers.
#if HAIRSCATTER_HAS_VECTOR_EXT
    const detail::F32x4 vax = {ax, ax, ax, ax}, vay = {ay, ay, ay, ay};
    const float lo = (vax < vay ? vax : vay)[0];
#else
    const float lo = select(ay > ax, ax, ay);
#endif
    const float a = lo / (hi <= 0.0f ? 1.0f : hi);  // lo = 0 when hi = 0; NaN stays
    const float d = ax - ay;
    const float base = (kHalfPi<float> - std::copysign(kHalfPi<float>, x)) +
                       std::copysign(kQuarterPi<float> - std::copysign(kQuarterPi<float>, d), x);
    // s·a: the sign of the product d·x is the product of the signs even where it rounds to
    // ±0 or overflows (and NaN inputs have already made a NaN).
    const float signed_a = std::copysign(a, d * x);
    return std::copysign(base + signed_a * detail::atan_unit_factor(a), y);
#endif
}

// e^x of every element: in float with GCC and Clang each group of four (eight with AVX) is
// one vector (detail::exp_float_lanes), elsewhere one branch-free loop that compilers may vectorise, so a
// batch of lobe terms costs about one exp. exp_batch<T>(n) is the size
// to pad a batch of n exps to (with zeros): a whole vector for float, n itself for double,
// whose exp is libm's, one call per element.
template <typename T> HAIRSCATTER_HD constexpr int exp_batch(int n) {
    if (!std::is_same<T, float>::value) return n;
    int b = 1;
    while (b < n) b *= 2;
    return b;
}
template <typename T, std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void exp_each(T (&x)[N]) {
    for (int k = 0; k < int(N); ++k) x[k] = exp(x[k]);
}
template <std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void exp_each(float (&x)[N]) {
#if defined(__CUDA_ARCH__)
    for (int k = 0; k < int(N); ++k) x[k] = ::expf(x[k]);
#else
#if HAIRSCATTER_HAS_VECTOR_EXT
    // One vector per group of four or eight lanes (detail::each_group).
    if (detail::each_group(x, detail::ExpLanes<>{})) return;
#endif
    for (int k = 0; k < int(N); ++k) x[k] = detail::exp_float<true>(x[k]);
#endif
}
// exp_each for exponents x ≤ 0 (NaN and -Inf allowed): the lobes' and the transmittances'.
// The same results; in float the vector groups skip the clamp at 88 (exp_float_lanes).
template <typename T, std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void exp_each_nonpositive(T (&x)[N]) {
#if HAIRSCATTER_HAS_VECTOR_EXT && !defined(__CUDA_ARCH__)
    if constexpr (std::is_same<T, float>::value)
        if (detail::each_group(x, detail::ExpLanes<false>{})) return;
#endif
    exp_each(x);
}

// exp_each_nonpositive, and in double on the host with GCC's and Clang's vector extensions
// four lanes at a time (two without AVX) by detail::exp_double_lanes instead of one libm call per element
// (within 2 ulp of it; a remainder that does not fill a vector by exp<double>).
// For batches of transmittances (HuangFiber's walk).
template <typename T, std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void exp_lanes_nonpositive(T (&x)[N]) {
#if HAIRSCATTER_HAS_VECTOR_EXT && !defined(__CUDA_ARCH__)
    if constexpr (std::is_same<T, double>::value) {
#if defined(__AVX__)
        using F = detail::F64x4;
        using I = detail::I64x4;
#else
        using F = detail::F64x2;
        using I = detail::I64x2;
#endif
        constexpr int kLanes = int(sizeof(F) / sizeof(double));
        int k = 0;
        for (; k + kLanes <= int(N); k += kLanes) {
            F v;
            std::memcpy(&v, x + k, sizeof v);
            v = detail::exp_double_lanes<F, I>(v);
            std::memcpy(x + k, &v, sizeof v);
        }
        for (; k < int(N); ++k) x[k] = exp(x[k]);
        return;
    }
#endif
    exp_each_nonpositive(x);
}

// Writes {a, b, c, d} to out[0..3] as one store where it can (float with GCC and Clang: the
// vector is built in a register). Four lanes stored one by one and then read as one vector
// stall the load until the stores reach the cache.
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void store4(T* out, T a, T b, T c, T d) {
    out[0] = a;
    out[1] = b;
    out[2] = c;
    out[3] = d;
}
// The same for eight lanes.
template <typename T>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void store8(T* out, T a, T b, T c, T d, T e, T f, T g, T h) {
    store4(out, a, b, c, d);
    store4(out + 4, e, f, g, h);
}
#if HAIRSCATTER_HAS_VECTOR_EXT
template <> HAIRSCATTER_FORCE_INLINE void store4(float* out, float a, float b, float c, float d) {
    const detail::F32x4 v = {a, b, c, d};
    std::memcpy(out, &v, sizeof v);
}
#if defined(__AVX__)
template <>
HAIRSCATTER_FORCE_INLINE void store8(float* out, float a, float b, float c, float d, float e, float f, float g, float h) {
    const detail::F32x8 v = {a, b, c, d, e, f, g, h};
    std::memcpy(out, &v, sizeof v);
}
#endif
#endif
// out[0..7] = in[0..3] twice, for a batch of eight lanes built from one of four: in float
// with AVX one 16-byte load and one 32-byte store (the eight lanes are then read whole).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void repeat4(const T* in, T* out) {
    for (int k = 0; k < 8; ++k) out[k] = in[k & 3];
}
#if HAIRSCATTER_HAS_VECTOR_EXT && defined(__AVX__)
template <> HAIRSCATTER_FORCE_INLINE void repeat4(const float* in, float* out) {
    detail::F32x4 v;
    std::memcpy(&v, in, sizeof v);
    const detail::F32x8 w = __builtin_shufflevector(v, v, 0, 1, 2, 3, 0, 1, 2, 3);
    std::memcpy(out, &w, sizeof w);
}
#endif

// Natural logarithm of a positive normal number (callers floor their arguments).
template <typename T> HAIRSCATTER_HD T log(T x) {
    using std::log;
    return log(x);
}
template <> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE float log(float x) {
#if defined(__CUDA_ARCH__)
    return ::logf(x);
#else
    return detail::log_float(x);
#endif
}

// sin and cos together, for angles within a few turns of zero.
template <typename T> HAIRSCATTER_HD void sincos(T x, T& s, T& c) {
    using std::cos;
    using std::sin;
    s = sin(x);
    c = cos(x);
}
template <> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void sincos(float x, float& s, float& c) {
#if defined(__CUDA_ARCH__)
    ::sincosf(x, &s, &c);
#else
    detail::sincos_float(x, s, c);
#endif
}

// The range of detail::asin_small_poly.
inline constexpr float kAsinSmallMax = 0.7f;
// asin with the argument clamped to [-1, 1] (rounding can leave it a hair outside).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T asin(T x) { return safe_asin(x); }
template <> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE float asin(float x) {
#if defined(__CUDA_ARCH__)
    return safe_asin(x);
#else
    const float ax = clamp(std::fabs(x), 0.0f, 1.0f);
    // |x| > 0.7: asin(a) = π/2 - 2 asin(sqrt((1 - a)/2)) keeps the polynomial's argument
    // within its range (≤ 0.39). A branch, not a select: it is mispredicted when h is
    // random, but computing both forms puts a sqrt on the wo terms' critical path, which
    // costs more (measured; again over 65536 inputs, where the branch goes wrong as on a
    // renderer's directions: one polynomial on a selected argument made the dual BCSDF's
    // eval 7 % slower). At 0.7 rather than 1/2 it goes one way for 70 % of uniform
    // arguments instead of half, and always for the refracted angle γt of an η ≥ 1/0.7
    // (|sinγt| ≤ 1/η; hair's η = 1.55 among them).
    const float r = ax <= kAsinSmallMax ? detail::asin_small_poly(ax)
                                        : kHalfPi<float> - 2.0f * detail::asin_small_poly(std::sqrt(0.5f * (1.0f - ax)));
    return std::copysign(r, x);
#endif
}

// e^x - 1 for x ≤ 88: |x| < 1/2 by its Taylor series to x¹⁰ (truncation 5e-10 relative),
// otherwise exp(x) - 1, where the subtraction loses at most a factor 2.6 of exp's error.
// -Inf gives -1, NaN NaN.
template <typename T> HAIRSCATTER_HD T expm1(T x) {
    using std::expm1;
    return expm1(x);
}
template <> HAIRSCATTER_HD inline float expm1(float x) {
#if defined(__CUDA_ARCH__)
    return ::expm1f(x);
#else
    if (!(std::fabs(x) < 0.5f)) return detail::exp_float<false>(x) - 1.0f;
    return detail::expm1_series(x);
#endif
}

// expm1 of every element, in one loop: the same two forms as expm1, the choice between them
// a select, so that in float the compilers vectorise the loop (both forms stay finite for
// the x ≤ 88 it takes; the unused one is discarded).
template <typename T, std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void expm1_each(T (&x)[N]) {
    for (int k = 0; k < int(N); ++k) x[k] = expm1(x[k]);
}
template <std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void expm1_each(float (&x)[N]) {
#if defined(__CUDA_ARCH__)
    for (int k = 0; k < int(N); ++k) x[k] = ::expm1f(x[k]);
#else
#if HAIRSCATTER_HAS_VECTOR_EXT
    if (detail::each_group(x, detail::Expm1Lanes{})) return;
#endif
    for (int k = 0; k < int(N); ++k)
        x[k] = select(std::fabs(x[k]) < 0.5f, detail::expm1_series(x[k]), detail::exp_float<true>(x[k]) - 1.0f);
#endif
}

// expm1_each where exp_each of the same x is already known (e): the same results, without a
// second exp in float, whose expm1 lane form is exp - 1 beyond |x| = 1/2 with exp_each's own
// exp (elsewhere expm1_each itself). For a pair of constants that a material built per hit
// needs both of (lobes/deon_lobes.hpp).
template <typename T, std::size_t N>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void expm1_each_given_exp(T (&x)[N], const T (&e)[N]) {
#if HAIRSCATTER_HAS_VECTOR_EXT && !defined(__CUDA_ARCH__)
    if constexpr (std::is_same<T, float>::value) {
        HAIRSCATTER_NO_UNROLL
        for (int k = 0; k < int(N); ++k) x[k] = select(std::fabs(x[k]) < 0.5f, detail::expm1_series(x[k]), e[k] - 1.0f);
        return;
    }
#endif
    (void)e;
    expm1_each(x);
}

// ln(1 + x) for x > -1: with s = x / (2 + x), ln(1 + x) = 2 atanh s; |s| ≤ 0.172 (x within
// [-0.29, 0.41]) by the series to s⁹ (truncation 2e-9 relative), beyond it the float log of
// 1 + x (whose rounding costs at most 3 ulp there). Inf and NaN go to the standard library.
template <typename T> HAIRSCATTER_HD T log1p(T x) {
    using std::log1p;
    return log1p(x);
}
template <> HAIRSCATTER_HD inline float log1p(float x) {
#if defined(__CUDA_ARCH__)
    return ::log1pf(x);
#else
    if (!(x > -0.29f && x < 0.41f)) return x > -1.0f && x <= 3.0e38f ? detail::log_float(1.0f + x) : std::log1p(x);
    return detail::log1p_series(x);
#endif
}

// x[k] *= y[k] for every element. In float with four elements one vector product, spelled as
// such: GCC -O3 vectorised the plain loop of Chiang's lobe gains (a branch that is not even
// taken by default) with its own 64-, 16- and 8-byte pieces, and to do so kept the attenuation
// rows in memory on every path; the stateless pdf was 4 % slower for it (GCC 12, Zen 5).
template <typename T, std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void mul_each(T (&x)[N], const T (&y)[N]) {
#if HAIRSCATTER_HAS_VECTOR_EXT && !defined(__CUDA_ARCH__)
    if constexpr (std::is_same<T, float>::value && N == 4) {
        detail::F32x4 a, b;
        std::memcpy(&a, x, sizeof a);
        std::memcpy(&b, y, sizeof b);
        a *= b;
        std::memcpy(x, &a, sizeof a);
        return;
    }
#endif
    for (int k = 0; k < int(N); ++k) x[k] *= y[k];
}

// log of every element, each a positive normal number (as log_float): in float the lanes
// of one vector (bit-identical to elem::log), elsewhere one call each.
template <typename T, std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void log_each(T (&x)[N]) {
    for (int k = 0; k < int(N); ++k) x[k] = log(x[k]);
}
template <std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void log_each(float (&x)[N]) {
#if HAIRSCATTER_HAS_VECTOR_EXT && !defined(__CUDA_ARCH__)
    if (detail::each_group(x, detail::LogLanes{})) return;
#endif
    for (int k = 0; k < int(N); ++k) x[k] = log(x[k]);
}

// log1p of every element x ≥ 0 (or +Inf, NaN), in one loop: log1p's two forms, the choice a
// select, so that in float the loop vectorises.
template <typename T, std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void log1p_each(T (&x)[N]) {
    for (int k = 0; k < int(N); ++k) x[k] = log1p(x[k]);
}
template <std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void log1p_each(float (&x)[N]) {
#if defined(__CUDA_ARCH__)
    for (int k = 0; k < int(N); ++k) x[k] = ::log1pf(x[k]);
#else
#if HAIRSCATTER_HAS_VECTOR_EXT
    if (detail::each_group(x, detail::Log1pLanes{})) return;
#endif
    for (int k = 0; k < int(N); ++k) {
        const bool near0 = (x[k] > -0.29f) & (x[k] < 0.41f);  // & not &&: no branch
        const float r = select(near0, detail::log1p_series(x[k]), detail::log_float(1.0f + x[k]));
        x[k] = select(x[k] <= 3.0e38f, r, x[k]);  // +Inf stays +Inf, NaN NaN
    }
#endif
}

// x^y of every element, for x ∈ [0, 1] and y ≥ 1 (a transmittance through y layers): in
// float e^(y ln x) as one loop that vectorises (relative error about 2e-7 |y ln x|, x = 0
// gives 0), in double the standard library's pow.
template <typename T, std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void pow_each(T (&x)[N], T y) {
    using std::pow;
    for (int k = 0; k < int(N); ++k) x[k] = pow(x[k], y);
}
template <std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void pow_each(float (&x)[N], float y) {
#if defined(__CUDA_ARCH__)
    for (int k = 0; k < int(N); ++k) x[k] = ::powf(x[k], y);
#else
#if HAIRSCATTER_HAS_VECTOR_EXT
    if (detail::each_group(x, detail::PowLanes{y})) return;
#endif
    for (int k = 0; k < int(N); ++k) x[k] = y * detail::log_float(x[k]);  // log 0 reads as -88: e^(-88 y) flushes to 0
    exp_each(x);
#endif
}

// √x of every element (x ≥ 0, or NaN). A loop of std::sqrt stays scalar, with a compare
// and a branch per element, because each sqrt may set errno (unless -fno-math-errno); x86
// has a vector square root that never does, so there four floats are one SQRTPS and two
// doubles one SQRTPD, or with AVX eight floats and four doubles one VSQRTPS / VSQRTPD (the
// library's only intrinsics, with this loop as the portable form everywhere else; the
// square root is correctly rounded either way, so the results are the same).
template <typename T, std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void sqrt_each(T (&x)[N]) {
    using std::sqrt;
    for (int k = 0; k < int(N); ++k) x[k] = sqrt(x[k]);
}
template <std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void sqrt_each(double (&x)[N]) {
#if HAIRSCATTER_HAS_SSE2_SQRT
#if HAIRSCATTER_HAS_AVX_SQRT
    if constexpr (N % 4 == 0) {
        for (int k = 0; k < int(N); k += 4) _mm256_storeu_pd(x + k, _mm256_sqrt_pd(_mm256_loadu_pd(x + k)));
        return;
    }
#endif
    if constexpr (N % 2 == 0) {
        for (int k = 0; k < int(N); k += 2) _mm_storeu_pd(x + k, _mm_sqrt_pd(_mm_loadu_pd(x + k)));
        return;
    }
#endif
    for (int k = 0; k < int(N); ++k) x[k] = std::sqrt(x[k]);
}
template <std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void sqrt_each(float (&x)[N]) {
#if HAIRSCATTER_HAS_SSE_SQRT
#if HAIRSCATTER_HAS_AVX_SQRT
    if constexpr (N % 8 == 0) {
        for (int k = 0; k < int(N); k += 8) _mm256_storeu_ps(x + k, _mm256_sqrt_ps(_mm256_loadu_ps(x + k)));
        return;
    }
#endif
    if constexpr (N % 4 == 0) {
        for (int k = 0; k < int(N); k += 4) _mm_storeu_ps(x + k, _mm_sqrt_ps(_mm_loadu_ps(x + k)));
        return;
    }
#endif
    for (int k = 0; k < int(N); ++k) x[k] = std::sqrt(x[k]);
}

}  // namespace elem
}  // namespace hairscatter
