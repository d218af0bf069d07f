// hairscatter — configuration: version and the host/device annotation.
#pragma once

// The version: the one place it is written. CMakeLists.txt parses these three lines for
// the project and package version; CHANGELOG.md says what each version holds.
#define HAIRSCATTER_VERSION_MAJOR 0
#define HAIRSCATTER_VERSION_MINOR 2
#define HAIRSCATTER_VERSION_PATCH 0
#define HAIRSCATTER_VERSION \
    (HAIRSCATTER_VERSION_MAJOR * 10000 + HAIRSCATTER_VERSION_MINOR * 100 + HAIRSCATTER_VERSION_PATCH)

// HAIRSCATTER_HD marks every function that may run on a GPU. It is empty on the CPU and
// `__host__ __device__` when the headers are compiled by nvcc (or clang in CUDA mode).
#if defined(__CUDACC__) || defined(__HIPCC__)
#define HAIRSCATTER_HD __host__ __device__
#else
#define HAIRSCATTER_HD
#endif

// -ffast-math. Under it the library does not crash and keeps its non-finite contract (NaN
// or Inf inputs give 0, validate() rejects NaN: both read the bits), but the float exp and
// sincos lose accuracy (-fassociative-math folds their Cody–Waite argument reduction:
// measured 4e-6 relative for exp and 1e-5 absolute for sincos, against 2e-7), NaN checks
// that use comparisons elsewhere (the dual-scattering density grid, ChiangFiber(params, h))
// fold away, and results differ in the last bits between equivalent paths. That is refused
// unless the program says it accepts it.
#if defined(__FAST_MATH__) && !defined(HAIRSCATTER_ALLOW_FAST_MATH)
#error "hairscatter: built with -ffast-math (__FAST_MATH__): the float exp/sincos lose accuracy (4e-6 / 1e-5 instead of 2e-7) and comparison-based NaN checks fold away. Build without -ffast-math (or with -fno-fast-math for the files that include hairscatter), or define HAIRSCATTER_ALLOW_FAST_MATH to accept this (docs/robustness.md)."
#endif

// HAIRSCATTER_FORCE_INLINE forces the inlining of the hot helpers (exp, atan2, asin, the
// Bessel polynomials, Fresnel, the relative azimuth) and of a model's internal per-call
// stages (the wo terms, the lobe sum) into eval / pdf / sample. Without it GCC keeps some
// of them as real calls once a program instantiates a model in several places, or at -O3
// where inlining budgets go to the loops around them: each call then spills the
// registers that hold the lobes' values (docs/performance.md measures the cost).
#if defined(__CUDACC__)
#define HAIRSCATTER_FORCE_INLINE __forceinline__
#elif defined(__GNUC__) || defined(__clang__)
#define HAIRSCATTER_FORCE_INLINE inline __attribute__((always_inline))
#elif defined(_MSC_VER)
#define HAIRSCATTER_FORCE_INLINE __forceinline
#else
#define HAIRSCATTER_FORCE_INLINE inline
#endif
// HAIRSCATTER_NOINLINE keeps a function a call: the dual BCSDF's value, which GCC, once it
// inlined it into its caller, no longer vectorised (7229 instead of 3038 instructions per
// float dual eval at -O3; bench/results/icount_2026-12-02.txt).
#if defined(__CUDACC__)
#define HAIRSCATTER_NOINLINE __noinline__
#elif defined(__GNUC__) || defined(__clang__)
#define HAIRSCATTER_NOINLINE __attribute__((noinline))
#elif defined(_MSC_VER)
#define HAIRSCATTER_NOINLINE __declspec(noinline)
#else
#define HAIRSCATTER_NOINLINE
#endif
// HAIRSCATTER_UNROLL before a loop over a model's lanes (a compile-time trip count of 2
// to 8) unrolls it completely: GCC at -O2 keeps such a loop, once its body is vectorised,
// as a real loop with a counter and a branch per lane.
// (nvcc's host pass takes neither spelling: its front end rejects GCC's, the host
// compiler CUDA's; the loop is left as it is there.)
#if defined(__CUDA_ARCH__) || defined(__clang__)
#define HAIRSCATTER_UNROLL _Pragma("unroll")
#elif defined(__CUDACC__)
#define HAIRSCATTER_UNROLL
#elif defined(__GNUC__)
#define HAIRSCATTER_UNROLL _Pragma("GCC unroll 8")
#else
#define HAIRSCATTER_UNROLL
#endif
// HAIRSCATTER_NO_UNROLL before such a loop that GCC should vectorise as a loop: at -O3 GCC
// unrolls short loops completely before its loop vectoriser runs, and what the straight-line
// vectoriser then makes of the copies may stay scalar (a material built per hit took 399
// instructions at -O3 against 256 at -O2, its tilt's Taylor series scalar). Other
// compilers: nothing.
#if defined(__GNUC__) && !defined(__clang__) && !defined(__CUDACC__)
#define HAIRSCATTER_NO_UNROLL _Pragma("GCC unroll 1")
#else
#define HAIRSCATTER_NO_UNROLL
#endif
// The earlier spelling, kept as an alias.
#define HAIRSCATTER_INLINE HAIRSCATTER_FORCE_INLINE

// Debug-only internal invariant checks; the hot path carries none in release builds.
#if !defined(NDEBUG) && !defined(__CUDA_ARCH__)
#include <cassert>
#define HAIRSCATTER_DCHECK(cond) assert(cond)
#else
#define HAIRSCATTER_DCHECK(cond) ((void)0)
#endif

// Exceptions. Host-side construction (materials, tables, grids, file loaders) reports bad
// input by throwing std::invalid_argument / std::runtime_error. Built without exceptions
// (-fno-exceptions: no __cpp_exceptions), or with HAIRSCATTER_NO_EXCEPTIONS defined, the
// same sites print the exception's message to stderr and abort instead. Such programs check
// their input first with the non-throwing validate() functions (fiber/params.hpp,
// models/marschner.hpp), which return an empty string or the message.
#if !defined(HAIRSCATTER_NO_EXCEPTIONS) && !defined(__cpp_exceptions) && !defined(__EXCEPTIONS) && \
    !(defined(_MSC_VER) && defined(_CPPUNWIND))
#define HAIRSCATTER_NO_EXCEPTIONS 1
#endif

#if defined(HAIRSCATTER_NO_EXCEPTIONS)
#include <cstdio>
#include <cstdlib>
#include <exception>
namespace hairscatter {
namespace detail {
[[noreturn]] inline void fail_fast(const std::exception& e) {
    std::fprintf(stderr, "%s (built without exceptions: aborting)\n", e.what());
    std::abort();
}
}  // namespace detail
}  // namespace hairscatter
#define HAIRSCATTER_THROW(exception) ::hairscatter::detail::fail_fast(exception)
#else
#define HAIRSCATTER_THROW(exception) throw exception
#endif
