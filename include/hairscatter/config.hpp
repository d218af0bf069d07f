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

// HAIRSCATTER_INLINE forces the inlining of a model's internal per-call stages (the wo
// terms, the lobe sum) into eval / pdf / sample. Without it GCC stops inlining them once a
// program instantiates a model in several places (measured: pdf 77 → 94 ns, at(wo)
// 33 → 45 ns in bench/chiang_bench.cpp), because the stages return ~200-byte structs.
#if defined(__CUDACC__)
#define HAIRSCATTER_INLINE __forceinline__
#elif defined(__GNUC__) || defined(__clang__)
#define HAIRSCATTER_INLINE inline __attribute__((always_inline))
#elif defined(_MSC_VER)
#define HAIRSCATTER_INLINE __forceinline
#else
#define HAIRSCATTER_INLINE inline
#endif

// Debug-only internal invariant checks; the hot path carries none in release builds.
#if !defined(NDEBUG) && !defined(__CUDA_ARCH__)
#include <cassert>
#define HAIRSCATTER_DCHECK(cond) assert(cond)
#else
#define HAIRSCATTER_DCHECK(cond) ((void)0)
#endif
