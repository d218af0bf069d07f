// hairscatter — exp, atan2 and asin for the hot paths. double uses the standard library;
// float on the host uses the inline versions below, accurate to a few ulp (tested against
// the standard library in tests/math_test.cpp) but free of libm's call overhead and
// special-case handling, which dominate the cost of a hair evaluation; on a GPU, CUDA's
// own device functions.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#include "../config.hpp"
#include "constants.hpp"
#include "functions.hpp"

namespace hairscatter {
namespace elem {

namespace detail {

// e^x for x ≤ 88 (callers pass x ≤ 0): Cody–Waite reduction x = n ln2 + r, |r| ≤ ln2/2,
// the degree-7 Taylor polynomial of e^r (truncation 5e-9 relative), and 2^n written into
// the exponent bits. Below -87.3 (where e^x is subnormal) it returns 0.
inline float exp_float(float x) {
    const float xc = clamp(x, -87.3f, 88.0f);
    // Round x·log2(e) to an integer with the 1.5·2^23 trick (no libm call, any rounding mode
    // that is round-to-nearest, which is the default).
    const float t = xc * 1.44269504088896341f + 12582912.0f;
    const float n = t - 12582912.0f;
    const float r = (xc - n * 0.693145751953125f) - n * 1.42860682030941723212e-6f;
    const float p = hairscatter::detail::horner(r, 1.0f, 1.0f, 0.5f, 1.0f / 6, 1.0f / 24, 1.0f / 120, 1.0f / 720, 1.0f / 5040);
    const std::int32_t bits = (std::int32_t(n) + 127) << 23;
    float scale;
    std::memcpy(&scale, &bits, sizeof scale);
    return x < -87.3f ? 0.0f : p * scale;
}

// atan(a) for a ∈ [0, 1] as a·P(a²), P fitted for this library (Chebyshev interpolation
// against mpmath): absolute error 1e-8.
inline float atan_unit(float a) {
    const float z = a * a;
    return a * hairscatter::detail::horner(z, 0.99999998178865573f, -0.33333036709286276f, 0.19991872029109072f,
                      -0.14197797794085123f, 0.10618370636953849f, -0.074568548260045474f,
                      0.042137623589193041f, -0.015731249122183653f, 0.002766283501762026f);
}

// asin(x) for x ∈ [0, 1/2] as x + x³Q(x²), Q fitted likewise: relative error 2e-8.
inline float asin_half(float x) {
    const float z = x * x;
    return x + x * z *
                   hairscatter::detail::horner(z, 0.16666672414795305f, 0.074988550726008211f, 0.045001380069910168f,
                          0.026554542206161328f, 0.038085023561092654f);
}

}  // namespace detail

template <typename T> HAIRSCATTER_HD T exp(T x) {
    using std::exp;
    return exp(x);
}
template <> HAIRSCATTER_HD inline float exp(float x) {
#if defined(__CUDA_ARCH__)
    return ::expf(x);
#else
    return detail::exp_float(x);
#endif
}

template <typename T> HAIRSCATTER_HD T atan2(T y, T x) {
    using std::atan2;
    return atan2(y, x);
}
template <> HAIRSCATTER_HD inline float atan2(float y, float x) {
#if defined(__CUDA_ARCH__)
    return ::atan2f(y, x);
#else
    // Octant reduction to atan(min/max) ∈ [0, π/4], then the quadrant from the signs.
    const float ax = std::fabs(x), ay = std::fabs(y);
    const float hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
    float r = detail::atan_unit(hi > 0.0f ? lo / hi : 0.0f);
    if (ay > ax) r = kHalfPi<float> - r;
    if (x < 0.0f) r = kPi<float> - r;
    return std::copysign(r, y);
#endif
}

// asin with the argument clamped to [-1, 1] (rounding can leave it a hair outside).
template <typename T> HAIRSCATTER_HD T asin(T x) { return safe_asin(x); }
template <> HAIRSCATTER_HD inline float asin(float x) {
#if defined(__CUDA_ARCH__)
    return safe_asin(x);
#else
    const float ax = clamp(std::fabs(x), 0.0f, 1.0f);
    // |x| > 1/2: asin(a) = π/2 - 2 asin(sqrt((1 - a)/2)) keeps the polynomial's argument small.
    const float r = ax <= 0.5f ? detail::asin_half(ax)
                               : kHalfPi<float> - 2.0f * detail::asin_half(std::sqrt(0.5f * (1.0f - ax)));
    return std::copysign(r, x);
#endif
}

}  // namespace elem
}  // namespace hairscatter
