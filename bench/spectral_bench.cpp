// Benchmarks of the N-channel Chiang fiber (models/chiang_spectral.hpp): ns per eval, sample
// and whole path vertex for N = 1, 3, 4 and 8 channels, float and double, next to the RGB
// ChiangFiber on the same inputs. items_per_second counts channels, so its inverse is the
// cost per channel. β_m = 0.3; σa per input from melanin concentrations at four stratified
// wavelengths (N = 3: the material's RGB σa, so that the row is the RGB model's work).
//
//   spectral_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <cstddef>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include <hairscatter/hairscatter.hpp>

#include "reference/inputs.hpp"

namespace {

namespace hs = hairscatter;
using bench_ref::inputs;
using bench_ref::kMask;

constexpr std::size_t kFibers = 4096;  // fibers (h, σa) cycled against the 65536 directions
constexpr std::size_t kMaterial = 1;   // β_m = 0.3

// σa of N channels for input i: the RGB material's at N = 3, else melanin at N wavelengths.
template <typename T, int N> hs::SpectralValues<T, N> sigma_a(std::size_t i) {
    const auto& in = inputs<T>();
    hs::SpectralValues<T, N> s;
    if constexpr (N == 3) {
        const auto& rgb = in.materials[kMaterial].params().sigma_a;
        for (int c = 0; c < 3; ++c) s[c] = rgb[c];
    } else {
        const auto lambda = hs::sample_uniform_wavelengths<T, N>(in.calib_a[i]);
        s = hs::clamped_spectral_sigma_a(hs::MelaninConcentrations<T>{T(1.3) * in.calib_b[i], T(0.2)}, lambda);
    }
    return s;
}

template <typename T, int N> const std::vector<hs::ChiangSpectralFiber<T, N>>& spectral_fibers() {
    static const std::vector<hs::ChiangSpectralFiber<T, N>> fibers = [] {
        const auto& in = inputs<T>();
        std::vector<hs::ChiangSpectralFiber<T, N>> f;
        for (std::size_t i = 0; i < kFibers; ++i) f.emplace_back(in.materials[kMaterial], in.h[i], sigma_a<T, N>(i));
        return f;
    }();
    return fibers;
}

template <typename F> void cycle(benchmark::State& state, int channels, F&& call) {
    std::size_t i = 0;
    for (auto _ : state) {
        auto r = call(i);
        benchmark::DoNotOptimize(r);
        i = (i + 1) & kMask;
    }
    state.SetItemsProcessed(state.iterations() * channels);
}

// ---- the RGB model (3 channels), the reference --------------------------------------------

template <typename T> void BM_RgbEval(benchmark::State& state) {
    const auto& in = inputs<T>();
    const auto& wi = in.wi[1][kMaterial];
    cycle(state, 3, [&](std::size_t i) { return in.fibers[kMaterial][i & (kFibers - 1)].eval(in.wo[i], wi[i]); });
}
template <typename T> void BM_RgbSample(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, 3, [&](std::size_t i) { return in.fibers[kMaterial][i & (kFibers - 1)].sample(in.wo[i], in.u[i]); });
}
// A path vertex: the fiber for the hit, bound at wo, a light sample's eval and a sample.
template <typename T> void BM_RgbVertex(benchmark::State& state) {
    const auto& in = inputs<T>();
    const auto& wi = in.wi[1][kMaterial];
    cycle(state, 3, [&](std::size_t i) {
        const auto at = hs::ChiangFiber<T>(in.materials[kMaterial], in.h[i]).at(in.wo[i]);
        return std::make_pair(at.eval(wi[i]), at.sample(in.u[i]));
    });
}

// ---- N channels -------------------------------------------------------------------------

template <typename T, int N> void BM_SpectralEval(benchmark::State& state) {
    const auto& in = inputs<T>();
    const auto& wi = in.wi[1][kMaterial];
    const auto& fibers = spectral_fibers<T, N>();
    cycle(state, N, [&](std::size_t i) { return fibers[i & (kFibers - 1)].eval(in.wo[i], wi[i]); });
}
template <typename T, int N> void BM_SpectralSample(benchmark::State& state) {
    const auto& in = inputs<T>();
    const auto& fibers = spectral_fibers<T, N>();
    cycle(state, N, [&](std::size_t i) { return fibers[i & (kFibers - 1)].sample(in.wo[i], in.u[i]); });
}
template <typename T, int N> void BM_SpectralVertex(benchmark::State& state) {
    const auto& in = inputs<T>();
    const auto& wi = in.wi[1][kMaterial];
    std::vector<hs::SpectralValues<T, N>> sigma;
    for (std::size_t i = 0; i < kFibers; ++i) sigma.push_back(sigma_a<T, N>(i));
    cycle(state, N, [&](std::size_t i) {
        const auto at = hs::ChiangSpectralFiber<T, N>(in.materials[kMaterial], in.h[i], sigma[i & (kFibers - 1)]).at(in.wo[i]);
        return std::make_pair(at.eval(wi[i]), at.sample(in.u[i]));
    });
}
// σa at N sampled wavelengths from melanin concentrations, per hit (clamped, unchecked).
template <typename T, int N> void BM_SpectralSigmaA(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, N, [&](std::size_t i) {
        return hs::clamped_spectral_sigma_a(hs::MelaninConcentrations<T>{in.calib_b[i], T(0.2)},
                                            hs::sample_uniform_wavelengths<T, N>(in.calib_a[i]));
    });
}

#define HAIRSCATTER_SPECTRAL_ROWS(T)                  \
    BENCHMARK_TEMPLATE(BM_RgbEval, T);                \
    BENCHMARK_TEMPLATE(BM_SpectralEval, T, 1);        \
    BENCHMARK_TEMPLATE(BM_SpectralEval, T, 3);        \
    BENCHMARK_TEMPLATE(BM_SpectralEval, T, 4);        \
    BENCHMARK_TEMPLATE(BM_SpectralEval, T, 8);        \
    BENCHMARK_TEMPLATE(BM_RgbSample, T);              \
    BENCHMARK_TEMPLATE(BM_SpectralSample, T, 1);      \
    BENCHMARK_TEMPLATE(BM_SpectralSample, T, 3);      \
    BENCHMARK_TEMPLATE(BM_SpectralSample, T, 4);      \
    BENCHMARK_TEMPLATE(BM_SpectralSample, T, 8);      \
    BENCHMARK_TEMPLATE(BM_RgbVertex, T);              \
    BENCHMARK_TEMPLATE(BM_SpectralVertex, T, 1);      \
    BENCHMARK_TEMPLATE(BM_SpectralVertex, T, 3);      \
    BENCHMARK_TEMPLATE(BM_SpectralVertex, T, 4);      \
    BENCHMARK_TEMPLATE(BM_SpectralVertex, T, 8);      \
    BENCHMARK_TEMPLATE(BM_SpectralSigmaA, T, 4);

HAIRSCATTER_SPECTRAL_ROWS(float)
HAIRSCATTER_SPECTRAL_ROWS(double)

}  // namespace

BENCHMARK_MAIN();
