// The cost of a material built per hit (textured melanin and roughness): ChiangMaterial's
// checked constructor, ChiangMaterial::unchecked, and unchecked after FiberParamBounds::clamp,
// next to a whole per-hit shade (fiber, at(wo), eval, sample) with a shared material and
// with a material made for the hit. Every iteration takes the next of 4096 parameter sets
// (σa from random concentrations, β_m random in [0.1, 0.6]), as a texture lookup would.
// Results: bench/results/material_<date>.txt (the run's command is in the file).
#include <cstddef>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include <hairscatter/hairscatter.hpp>

namespace {

namespace hs = hairscatter;
constexpr std::size_t kCount = 4096, kMask = kCount - 1;

template <typename T> struct Inputs {
    std::vector<hs::FiberParams<T>> params;
    std::vector<glm::vec<3, T>> wo, wi;
    std::vector<glm::vec<4, T>> u;
    std::vector<T> h;
    hs::FiberParamBounds<T> bounds;
    Inputs() {
        std::mt19937 rng(12345u);
        std::uniform_real_distribution<T> r(T(0), T(1));
        std::normal_distribution<T> g(T(0), T(1));
        const auto dir = [&] {
            const glm::vec<3, T> d(g(rng), g(rng), g(rng));
            return d / glm::length(d);
        };
        for (std::size_t i = 0; i < kCount; ++i) {
            hs::FiberParams<T> p;
            p.beta_m = T(0.1) + T(0.5) * r(rng);
            p.sigma_a = hs::sigma_a_from_concentrations(T(8) * r(rng), T(2) * r(rng));
            params.push_back(p);
            wo.push_back(dir());
            wi.push_back(dir());
            u.push_back(glm::vec<4, T>(r(rng), r(rng), r(rng), r(rng)));
            h.push_back(T(2) * r(rng) - T(1));
        }
        hs::FiberParams<T> lo, hi;
        lo.beta_m = T(0.1);
        hi.beta_m = T(0.6);
        lo.sigma_a = glm::vec<3, T>(T(0));
        hi.sigma_a = hs::sigma_a_from_concentrations(T(8), T(2));
        bounds = hs::FiberParamBounds<T>::checked(lo, hi);
    }
};
template <typename T> const Inputs<T>& inputs() {
    static const Inputs<T> in;
    return in;
}

template <typename T> void BM_MaterialChecked(benchmark::State& state) {
    const auto& in = inputs<T>();
    std::size_t i = 0;
    for (auto _ : state) {
        const hs::ChiangMaterial<T> m(in.params[i]);
        benchmark::DoNotOptimize(m);
        i = (i + 1) & kMask;
    }
}

template <typename T> void BM_MaterialUnchecked(benchmark::State& state) {
    const auto& in = inputs<T>();
    std::size_t i = 0;
    for (auto _ : state) {
        const auto m = hs::ChiangMaterial<T>::unchecked(in.params[i]);
        benchmark::DoNotOptimize(m);
        i = (i + 1) & kMask;
    }
}

template <typename T> void BM_MaterialClampUnchecked(benchmark::State& state) {
    const auto& in = inputs<T>();
    std::size_t i = 0;
    for (auto _ : state) {
        const auto m = hs::ChiangMaterial<T>::unchecked(in.bounds.clamp(in.params[i]));
        benchmark::DoNotOptimize(m);
        i = (i + 1) & kMask;
    }
}

// One path vertex: fiber, at(wo), eval toward a light, a sample.
template <typename T> HAIRSCATTER_FORCE_INLINE void shade(const hs::ChiangMaterial<T>& m, const Inputs<T>& in,
                                                          std::size_t i) {
    const auto at = hs::ChiangFiber<T>(m, in.h[i]).at(in.wo[i]);
    const auto f = at.eval(in.wi[i]);
    const auto s = at.sample(in.u[i]);
    benchmark::DoNotOptimize(f);
    benchmark::DoNotOptimize(s);
}

template <typename T> void BM_HitSharedMaterial(benchmark::State& state) {
    const auto& in = inputs<T>();
    static const hs::ChiangMaterial<T> m(in.params[0]);
    std::size_t i = 0;
    for (auto _ : state) {
        shade(m, in, i);
        i = (i + 1) & kMask;
    }
}

template <typename T> void BM_HitPerHitMaterial(benchmark::State& state) {
    const auto& in = inputs<T>();
    std::size_t i = 0;
    for (auto _ : state) {
        const auto m = hs::ChiangMaterial<T>::unchecked(in.bounds.clamp(in.params[i]));
        shade(m, in, i);
        i = (i + 1) & kMask;
    }
}

// Huang's material: a full build (interface tables, the microsurface's walk, the residual's
// profile and azimuth; 0.3-0.5 s) against one made from a built material's tables with
// another absorption (HuangMaterial(like, params): the lattice only), which is what a
// per-strand colour or a quadrature preset of one fiber costs.
template <typename T> void BM_HuangMaterialBuild(benchmark::State& state) {
    hs::HuangParams<T> p;
    for (auto _ : state) {
        const hs::HuangMaterial<T> m(p);
        benchmark::DoNotOptimize(&m);
    }
}
template <typename T> void BM_HuangMaterialLike(benchmark::State& state) {
    const hs::HuangMaterial<T> like{hs::HuangParams<T>()};
    hs::HuangParams<T> p;
    T s = T(0);
    for (auto _ : state) {
        p.sigma_a = glm::vec<3, T>(s);
        s = s < T(4) ? s + T(0.01) : T(0);
        const hs::HuangMaterial<T> m(like, p);
        benchmark::DoNotOptimize(&m);
    }
}

}  // namespace

BENCHMARK_TEMPLATE(BM_HuangMaterialBuild, float)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_HuangMaterialLike, float)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_MaterialChecked, float);
BENCHMARK_TEMPLATE(BM_MaterialUnchecked, float);
BENCHMARK_TEMPLATE(BM_MaterialClampUnchecked, float);
BENCHMARK_TEMPLATE(BM_HitSharedMaterial, float);
BENCHMARK_TEMPLATE(BM_HitPerHitMaterial, float);
BENCHMARK_TEMPLATE(BM_MaterialChecked, double);
BENCHMARK_TEMPLATE(BM_MaterialUnchecked, double);
BENCHMARK_TEMPLATE(BM_MaterialClampUnchecked, double);
BENCHMARK_TEMPLATE(BM_HitSharedMaterial, double);
BENCHMARK_TEMPLATE(BM_HitPerHitMaterial, double);

BENCHMARK_MAIN();
