// Benchmarks of dual scattering (dual/): the per-material table build at several
// resolutions, the density grid's ray march, and the dual-scattering BCSDF's eval and
// sample next to the single-fiber model they wrap, per call and bound to a hit's wo.
// Run: scripts/bench.sh --programs (or build/…/bench/dual_bench).
#include <cmath>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include <hairscatter/dual.hpp>

namespace {

namespace hs = hairscatter;
using V3 = glm::dvec3;

hs::FiberParams<double> blond() {
    hs::FiberParams<double> p;
    p.sigma_a = hs::sigma_a_from_concentrations(0.15, 0.05);
    return p;
}

// Tables per fiber parameter set: θ samples × h nodes (the two resolution knobs).
void BM_DualTablesBuild(benchmark::State& state) {
    const hs::ChiangMaterial<double> mat(blond());
    hs::DualTableOptions<double> opt;
    opt.theta_samples = int(state.range(0));
    opt.h_nodes = int(state.range(1));
    for (auto _ : state) {
        auto t = hs::DualScatteringTables<double>::build<hs::ChiangFiber<double>>(mat, opt);
        benchmark::DoNotOptimize(t);
    }
}
BENCHMARK(BM_DualTablesBuild)->ArgNames({"theta", "h"})->Args({64, 32})->Args({256, 32})->Args({64, 8})->Unit(benchmark::kMicrosecond);

// Cycled inputs: as many as bench/reference/inputs.hpp's tuples, and for the same reason
// (a branch predictor learns a short cycle of inputs, a renderer's rays never repeat).
constexpr std::size_t kScene = 65536;

struct Scene {
    std::vector<V3> wo, wi, x, to_light;
    std::vector<glm::dvec4> u;
    std::vector<double> h;
    Scene() {
        std::mt19937_64 rng(3);
        std::uniform_real_distribution<double> uni(0, 1);
        auto dir = [&] {
            const double z = 2 * uni(rng) - 1, p = 6.283185307179586 * uni(rng), r = std::sqrt(1 - z * z);
            return V3(z, r * std::cos(p), r * std::sin(p));
        };
        for (std::size_t i = 0; i < kScene; ++i) {
            wo.push_back(dir());
            wi.push_back(dir());
            to_light.push_back(dir());
            x.push_back(V3(uni(rng), uni(rng), uni(rng)));
            u.emplace_back(uni(rng), uni(rng), uni(rng), uni(rng));
            h.push_back(2 * uni(rng) - 1);
        }
    }
};
const Scene& scene() {
    static const Scene s;
    return s;
}

// A unit cube of hair: 40 × 40 strands along x, 10 cells per side (the march knob at its
// default, half a cell).
void BM_DensityMarch(benchmark::State& state) {
    std::vector<std::vector<V3>> strands;
    for (int j = 0; j < 40; ++j)
        for (int k = 0; k < 40; ++k) strands.push_back({V3(0, (j + 0.5) / 40, (k + 0.5) / 40), V3(1, (j + 0.5) / 40, (k + 0.5) / 40)});
    const auto grid = hs::DensityGrid<double>::from_strands(strands, 0.1, 0.004);
    const Scene& s = scene();
    std::size_t i = 0;
    for (auto _ : state) {
        auto n = grid.fibers_crossed(s.x[i], s.to_light[i], hs::kUnbounded<double>);
        benchmark::DoNotOptimize(n);
        i = (i + 1) & (kScene - 1);
    }
}
BENCHMARK(BM_DensityMarch);

// The shading setup of the eval and sample benchmarks: a material, its dual tables and a
// shadowed point (5 fibers toward the light, 10 beyond).
template <typename T, bool kZinke = false> struct Shading {
    hs::ChiangMaterial<T> mat{params()};
    hs::DualScatteringTables<T> tables = hs::DualScatteringTables<T>::template build<hs::ChiangFiber<T>>(mat, options());
    static hs::DualTableOptions<T> options() {
        hs::DualTableOptions<T> o;
        if (kZinke) o.settings.formulation = hs::DualFormulation::kZinke2008;
        return o;
    }
    hs::DualScatteringLight<T> light = shadowed();
    static hs::FiberParams<T> params() {
        hs::FiberParams<T> p;
        p.sigma_a = hs::sigma_a_from_concentrations(T(0.3), T(0));
        return p;
    }
    static hs::DualScatteringLight<T> shadowed() {
        hs::DualScatteringLight<T> l;
        l.n = T(5);
        l.beyond = T(10);
        l.direct_fraction = T(0);
        return l;
    }
};

// One shading call as a renderer makes it: the fiber of the hit, then eval or sample
// (stateless), for the single fiber and for the dual-scattering BCSDF over it, float and
// double; kZinke: the dual tables in Zinke et al. 2008's formulation (the floor of any dual
// BCSDF over this fiber: no per-θi light transport).
template <typename T, bool kSample, bool kDual, bool kZinke = false> void BM_Shade(benchmark::State& state) {
    using V = glm::vec<3, T>;
    using U4 = glm::vec<4, T>;
    const Shading<T, kZinke> sh;
    const auto& mat = sh.mat;
    const auto& tables = sh.tables;
    const auto& light = sh.light;
    const Scene& s = scene();
    std::size_t i = 0;
    for (auto _ : state) {
        const hs::ChiangFiber<T> fiber(mat, T(s.h[i]));
        const V wo(s.wo[i]), wi(s.wi[i]);
        const U4 u(s.u[i]);
        if constexpr (kDual) {
            const hs::DualScatteringBcsdf<hs::ChiangFiber<T>> d(fiber, tables);
            if constexpr (kSample) {
                auto r = d.sample(wo, u);
                benchmark::DoNotOptimize(r);
            } else {
                auto r = d.eval(wo, wi, light);
                benchmark::DoNotOptimize(r);
            }
        } else if constexpr (kSample) {
            auto r = fiber.sample(wo, u);
            benchmark::DoNotOptimize(r);
        } else {
            auto r = fiber.eval(wo, wi);
            benchmark::DoNotOptimize(r);
        }
        i = (i + 1) & (kScene - 1);
    }
}
// The per-light-sample cost once a hit is bound: 64 hits bound with at(wo) (the single fiber's
// and the dual BCSDF's), cycled against the wi inputs, then eval only.
template <typename T, bool kDual, bool kZinke = false> void BM_AtEval(benchmark::State& state) {
    using V = glm::vec<3, T>;
    const Shading<T, kZinke> sh;
    const Scene& s = scene();
    using Dual = hs::DualScatteringBcsdf<hs::ChiangFiber<T>>;
    std::vector<typename hs::ChiangFiber<T>::At> single;
    std::vector<typename Dual::At> dual;
    for (std::size_t k = 0; k < 64; ++k) {
        const hs::ChiangFiber<T> fiber(sh.mat, T(s.h[k]));
        if constexpr (kDual)
            dual.push_back(Dual(fiber, sh.tables).at(V(s.wo[k])));
        else
            single.push_back(fiber.at(V(s.wo[k])));
    }
    std::size_t i = 0;
    for (auto _ : state) {
        const V wi(s.wi[i]);
        if constexpr (kDual) {
            auto r = dual[i & 63].eval(wi, sh.light);
            benchmark::DoNotOptimize(r);
        } else {
            auto r = single[i & 63].eval(wi);
            benchmark::DoNotOptimize(r);
        }
        i = (i + 1) & (kScene - 1);
    }
}

BENCHMARK_TEMPLATE(BM_Shade, float, false, false)->Name("BM_SingleEval<float>");
BENCHMARK_TEMPLATE(BM_Shade, float, true, false)->Name("BM_SingleSample<float>");
BENCHMARK_TEMPLATE(BM_Shade, float, false, true)->Name("BM_DualEval<float>");
BENCHMARK_TEMPLATE(BM_Shade, float, true, true)->Name("BM_DualSample<float>");
BENCHMARK_TEMPLATE(BM_Shade, float, false, true, true)->Name("BM_DualZinkeEval<float>");
BENCHMARK_TEMPLATE(BM_Shade, float, true, true, true)->Name("BM_DualZinkeSample<float>");
BENCHMARK_TEMPLATE(BM_Shade, double, false, false)->Name("BM_SingleEval<double>");
BENCHMARK_TEMPLATE(BM_Shade, double, true, false)->Name("BM_SingleSample<double>");
BENCHMARK_TEMPLATE(BM_Shade, double, false, true)->Name("BM_DualEval<double>");
BENCHMARK_TEMPLATE(BM_Shade, double, true, true)->Name("BM_DualSample<double>");
BENCHMARK_TEMPLATE(BM_AtEval, float, false)->Name("BM_SingleAtEval<float>");
BENCHMARK_TEMPLATE(BM_AtEval, float, true)->Name("BM_DualAtEval<float>");
BENCHMARK_TEMPLATE(BM_AtEval, float, true, true)->Name("BM_DualZinkeAtEval<float>");
BENCHMARK_TEMPLATE(BM_AtEval, double, false)->Name("BM_SingleAtEval<double>");
BENCHMARK_TEMPLATE(BM_AtEval, double, true)->Name("BM_DualAtEval<double>");

}  // namespace

BENCHMARK_MAIN();
