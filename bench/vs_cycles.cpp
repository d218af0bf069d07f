// HuangFiber against Blender Cycles' published scheme for the same model
// (bench/reference/cycles_huang.hpp), in one process: time per call (Google Benchmark) and
// accuracy against the physical reference's cache (tests/data/physical_fiber.txt).
//
//   vs_cycles [benchmark flags]           ns per eval / at(wo).eval / sample / hit, float and double
//   vs_cycles --accuracy CACHE [--seeds N] relative L1 per case of every setting (double)
//
// Settings of HuangFiber: "default" (automatic quadrature), "fast" (huang_fast_quadrature),
// "fine" (huang_scaled_quadrature) and "cycles-class" (huang_cycles_class_quadrature). The Cycles scheme's normals come from a seed per
// shading point: the benchmark draws a new seed per call; the accuracy mode reports one seed
// (as a renderer sees one shading point) and the mean of N seeds' f (its bias).
//
// "Hit" rows time what a path tracer asks at one shading point: a new wo, two light samples
// evaluated with their pdf (for MIS) and one continuation sampled. Ours binds wo once
// (at(wo), which keeps the walk's path ends) or calls the stateless eval_pdf and sample;
// Cycles' scheme evaluates twice and samples once with the point's seed.
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <benchmark/benchmark.h>
#include <hairscatter/models/huang.hpp>

#include "reference/cycles_huang.hpp"
#include "support/physical_fiber_huang.hpp"

namespace hs = hairscatter;

namespace {

constexpr std::size_t kInputs = 65536;
constexpr std::size_t kMask = kInputs - 1;

// Uniform directions on the sphere for wo and wi, and four uniform numbers.
struct Raw {
    std::vector<glm::dvec3> wo, wi;
    std::vector<glm::dvec4> u;
    Raw() {
        std::mt19937_64 rng(2026);
        std::uniform_real_distribution<double> x(0.0, 1.0);
        const auto dir = [&] {
            const double z = 2 * x(rng) - 1, phi = 2 * hs::kPi<double> * x(rng), r = std::sqrt(1 - z * z);
            return glm::dvec3(z, r * std::cos(phi), r * std::sin(phi));
        };
        for (std::size_t i = 0; i < kInputs; ++i) {
            wo.push_back(dir());
            wi.push_back(dir());
            u.push_back(glm::dvec4(x(rng), x(rng), x(rng), x(rng)));
        }
    }
};
const Raw& raw() {
    static const Raw r;
    return r;
}

// The benchmark's fiber: round or b/a 0.5 at ψ 45°, β 0.3 or 0.1, blond.
template <typename T> hs::HuangParams<T> params(bool elliptic, T beta) {
    hs::HuangParams<T> p;
    p.roughness = beta;
    p.alpha = hs::radians(T(2));
    p.sigma_a = glm::vec<3, T>(T(phys_fiber::kBlond[0]), T(phys_fiber::kBlond[1]), T(phys_fiber::kBlond[2]));
    p.aspect_ratio = elliptic ? T(0.5) : T(1);
    p.orientation = elliptic ? hs::radians(T(45)) : T(0);
    return p;
}
template <typename T> hs::HuangQuadrature quadrature(int setting, T beta) {
    if (setting == 1) return hs::huang_fast_quadrature(beta);
    if (setting == 2) return hs::huang_scaled_quadrature(beta);
    if (setting == 3) return hs::huang_cycles_class_quadrature(beta);
    return hs::HuangQuadrature();
}
constexpr int kSettings = 4;
const char* kSetting[kSettings] = {"default", "fast", "fine", "cycles-class"};

template <typename T> struct Dirs {
    std::vector<glm::vec<3, T>> wo, wi;
    std::vector<glm::vec<4, T>> u;
    Dirs() {
        for (std::size_t i = 0; i < kInputs; ++i) {
            wo.push_back(glm::vec<3, T>(raw().wo[i]));
            wi.push_back(glm::vec<3, T>(raw().wi[i]));
            u.push_back(glm::vec<4, T>(raw().u[i]));
        }
    }
};
template <typename T> const Dirs<T>& dirs() {
    static const Dirs<T> d;
    return d;
}

// args: setting (0 default, 1 fast, 2 fine, 3 cycles-class), elliptic, β × 100. `call(i)` is timed over
// the inputs in turn.
template <typename T> T beta_of(const benchmark::State& state) { return T(state.range(2)) / T(100); }
template <typename Call> void time_calls(benchmark::State& state, const Call& call) {
    std::size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(call(i));
        i = (i + 1) & kMask;
    }
}
// kind: 0 eval(wo, wi), 1 at(wo[0]).eval(wi), 2 sample(wo, u), 3 a hit through at(wo),
// 4 the same hit by stateless calls, 5 at(wo) alone, 6 at(wo[0]).sample(u).
template <typename T, int kind> void BM_Ours(benchmark::State& state) {
    const T beta = beta_of<T>(state);
    const hs::HuangMaterial<T> mat(params<T>(state.range(1) != 0, beta), quadrature<T>(int(state.range(0)), beta));
    const hs::HuangFiber<T> fiber(mat);
    const Dirs<T>& d = dirs<T>();
    const auto bound = fiber.at(d.wo[0]);
    if (kind == 0) time_calls(state, [&](std::size_t i) { return fiber.eval(d.wo[i], d.wi[i]); });
    if (kind == 1) time_calls(state, [&](std::size_t i) { return bound.eval(d.wi[i]); });
    if (kind == 2) time_calls(state, [&](std::size_t i) { return fiber.sample(d.wo[i], d.u[i]); });
    if (kind == 5) time_calls(state, [&](std::size_t i) { return fiber.at(d.wo[i]).valid(); });
    if (kind == 6) time_calls(state, [&](std::size_t i) { return bound.sample(d.u[i]); });
    const auto next = [](std::size_t i) { return (i + 1) & kMask; };
    if (kind == 3)
        time_calls(state, [&](std::size_t i) {
            const auto at = fiber.at(d.wo[i]);
            const hs::HairEvalPdf<T> a = at.eval_pdf(d.wi[i]), b = at.eval_pdf(d.wi[next(i)]);
            const hs::HairSample<T> s = at.sample(d.u[i]);
            return a.f * a.pdf + b.f * b.pdf + s.weight * s.pdf;
        });
    if (kind == 4)
        time_calls(state, [&](std::size_t i) {
            const hs::HairEvalPdf<T> a = fiber.eval_pdf(d.wo[i], d.wi[i]), b = fiber.eval_pdf(d.wo[i], d.wi[next(i)]);
            const hs::HairSample<T> s = fiber.sample(d.wo[i], d.u[i]);
            return a.f * a.pdf + b.f * b.pdf + s.weight * s.pdf;
        });
}
template <typename T> void BM_OursEval(benchmark::State& state) { BM_Ours<T, 0>(state); }
template <typename T> void BM_OursBoundEval(benchmark::State& state) { BM_Ours<T, 1>(state); }
template <typename T> void BM_OursSample(benchmark::State& state) { BM_Ours<T, 2>(state); }
template <typename T> void BM_OursHitBound(benchmark::State& state) { BM_Ours<T, 3>(state); }
template <typename T> void BM_OursHitStateless(benchmark::State& state) { BM_Ours<T, 4>(state); }
template <typename T> void BM_OursBind(benchmark::State& state) { BM_Ours<T, 5>(state); }
template <typename T> void BM_OursBoundSample(benchmark::State& state) { BM_Ours<T, 6>(state); }
// The Cycles scheme: a new seed per call (one shading point each).
template <typename T> void BM_CyclesEval(benchmark::State& state) {
    const bench_ref::CyclesHuang<T> cycles(params<T>(state.range(1) != 0, beta_of<T>(state)));
    const Dirs<T>& d = dirs<T>();
    time_calls(state, [&](std::size_t i) { return cycles.eval(d.wo[i], d.wi[i], std::uint32_t(i * 2654435761u)); });
}
template <typename T> void BM_CyclesSample(benchmark::State& state) {
    const bench_ref::CyclesHuang<T> cycles(params<T>(state.range(1) != 0, beta_of<T>(state)));
    const Dirs<T>& d = dirs<T>();
    time_calls(state, [&](std::size_t i) {
        const glm::vec<4, T>& u = d.u[i];
        return cycles.sample(d.wo[i], glm::vec<3, T>(u.x, u.y, u.z), std::uint32_t(i * 2654435761u));
    });
}

template <typename T> void BM_CyclesHit(benchmark::State& state) {
    const bench_ref::CyclesHuang<T> cycles(params<T>(state.range(1) != 0, beta_of<T>(state)));
    const Dirs<T>& d = dirs<T>();
    time_calls(state, [&](std::size_t i) {
        const std::uint32_t seed = std::uint32_t(i * 2654435761u);
        const glm::vec<4, T>& u = d.u[i];
        const auto s = cycles.sample(d.wo[i], glm::vec<3, T>(u.x, u.y, u.z), seed);
        return cycles.eval(d.wo[i], d.wi[i], seed) + cycles.eval(d.wo[i], d.wi[(i + 1) & kMask], seed) + s.weight * s.pdf;
    });
}

void ours_args(benchmark::internal::Benchmark* b) {
    b->ArgNames({"setting", "elliptic", "beta100"});
    for (int beta : {30, 10})
        for (int setting = 0; setting < kSettings; ++setting) b->Args({setting, 0, beta});
    b->Args({0, 1, 30});
    b->Args({1, 1, 30});
    b->Args({3, 1, 30});
}
void cycles_args(benchmark::internal::Benchmark* b) {
    b->ArgNames({"setting", "elliptic", "beta100"});
    for (int beta : {30, 10}) b->Args({0, 0, beta});
    b->Args({0, 1, 30});
}

BENCHMARK_TEMPLATE(BM_OursEval, float)->Apply(ours_args);
BENCHMARK_TEMPLATE(BM_CyclesEval, float)->Apply(cycles_args);
BENCHMARK_TEMPLATE(BM_OursBoundEval, float)->Apply(ours_args);
BENCHMARK_TEMPLATE(BM_OursSample, float)->Apply(ours_args);
BENCHMARK_TEMPLATE(BM_CyclesSample, float)->Apply(cycles_args);
BENCHMARK_TEMPLATE(BM_OursHitBound, float)->Apply(ours_args);
BENCHMARK_TEMPLATE(BM_OursHitStateless, float)->Apply(ours_args);
BENCHMARK_TEMPLATE(BM_OursBind, float)->Apply(ours_args);
BENCHMARK_TEMPLATE(BM_OursBoundSample, float)->Apply(ours_args);
BENCHMARK_TEMPLATE(BM_CyclesHit, float)->Apply(cycles_args);
BENCHMARK_TEMPLATE(BM_OursEval, double)->Apply(ours_args);
BENCHMARK_TEMPLATE(BM_CyclesEval, double)->Apply(cycles_args);
BENCHMARK_TEMPLATE(BM_OursBoundEval, double)->Apply(ours_args);
BENCHMARK_TEMPLATE(BM_OursSample, double)->Apply(ours_args);
BENCHMARK_TEMPLATE(BM_CyclesSample, double)->Apply(cycles_args);
BENCHMARK_TEMPLATE(BM_OursHitBound, double)->Apply(ours_args);
BENCHMARK_TEMPLATE(BM_OursHitStateless, double)->Apply(ours_args);
BENCHMARK_TEMPLATE(BM_OursBind, double)->Apply(ours_args);
BENCHMARK_TEMPLATE(BM_OursBoundSample, double)->Apply(ours_args);
BENCHMARK_TEMPLATE(BM_CyclesHit, double)->Apply(cycles_args);

// ---- accuracy against the physical reference ----

// The HuangFiber settings the accuracy mode compares: default, fast and fine, or those given
// as --quadrature n/tt/m (offset nodes, TT points, internal normals per path; 0 = auto).
struct Setting {
    std::string name;
    int kind = 0;  // 0 default, 1 fast, 2 fine, 3 cycles-class, kSettings explicit
    hs::HuangQuadrature q;
    hs::HuangQuadrature at(double beta) const { return kind == kSettings ? q : quadrature<double>(kind, beta); }
};

struct Row {
    std::vector<std::array<double, 2>> err;  // per setting, then Cycles one seed, Cycles mean of seeds
    double albedo_cycles = 0;
};

Row accuracy_row(const phys_fiber::CachedCase& c, const std::vector<Setting>& settings, int seeds) {
    Row row;
    row.err.assign(settings.size() + 2, {0.0, 0.0});
    for (int blond = 0; blond < 2; ++blond) {
        const hs::HuangParams<double> p = phys_fiber::huang_params(c.c, blond != 0);
        const auto add = [&](std::size_t k, const std::vector<glm::dvec3>& bins) {
            for (int ch = 0; ch < (blond ? 3 : 1); ++ch)
                row.err[k][std::size_t(blond)] += phys_fiber::compare(c, bins, ch, blond ? ch + 1 : 0).l1 / (blond ? 3 : 1);
        };
        for (std::size_t s = 0; s < settings.size(); ++s) {
            const hs::HuangMaterial<double> mat(p, settings[s].at(p.roughness));
            const hs::HuangFiber<double> fiber(mat);
            const auto bound = fiber.at(c.c.wo());  // the same values as eval, in a fraction of the time
            add(s, phys_fiber::model_bins(c, [&](const glm::dvec3&, const glm::dvec3& wi) { return bound.eval(wi); }));
        }
        if (seeds == 0) continue;
        const bench_ref::CyclesHuang<double> cycles(p);
        std::vector<glm::dvec3> mean;
        for (int seed = 0; seed < seeds; ++seed) {
            const std::uint32_t sd = 12345u + 7919u * std::uint32_t(seed);
            const auto bins = phys_fiber::model_bins(c, [&](const glm::dvec3& wo, const glm::dvec3& wi) { return cycles.eval(wo, wi, sd); });
            if (seed == 0) {
                add(settings.size(), bins);
                mean = bins;
            } else {
                for (std::size_t b = 0; b < bins.size(); ++b) mean[b] += bins[b];
            }
        }
        for (auto& x : mean) x /= double(seeds);
        add(settings.size() + 1, mean);
        if (!blond) {
            const double dw = (2.0 / c.n_u) * (2 * hs::kPi<double> / c.n_phi);
            for (const auto& x : mean) row.albedo_cycles += x.x * dw;
        }
    }
    return row;
}

int accuracy(const std::string& cache, const std::vector<Setting>& settings, int seeds, int threads) {
    const std::vector<phys_fiber::CachedCase> cases = phys_fiber::read_cache(cache);
    std::vector<Row> rows(cases.size());
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            for (std::size_t k = std::size_t(t); k < cases.size(); k += std::size_t(threads))
                rows[k] = accuracy_row(cases[k], settings, seeds);
        });
    for (auto& th : pool) th.join();
    const std::size_t columns = settings.size() + (seeds > 0 ? 2 : 0);
    std::printf("Relative L1 against the physical reference (%s), lossless / blond (RGB mean).\n", cache.c_str());
    if (seeds > 0)
        std::printf("Cycles' scheme: one seed (one shading point), and the mean f of %d seeds (its bias) with its\n"
                    "lossless albedo.\n", seeds);
    std::printf("\n| case |");
    for (const Setting& s : settings) std::printf(" %s |", s.name.c_str());
    if (seeds > 0) std::printf(" Cycles, one seed | Cycles, mean of %d | Cycles albedo |", seeds);
    std::printf("\n|---|");
    for (std::size_t k = 0; k < columns + (seeds > 0 ? 1 : 0); ++k) std::printf("---|");
    std::printf("\n");
    std::vector<double> worst(columns, 0.0), mean(columns, 0.0);
    for (std::size_t k = 0; k < cases.size(); ++k) {
        std::printf("| %s |", cases[k].c.name().c_str());
        for (std::size_t s = 0; s < columns; ++s) {
            std::printf(" %.1f / %.1f %% |", 100 * rows[k].err[s][0], 100 * rows[k].err[s][1]);
            for (int b = 0; b < 2; ++b) {
                worst[s] = std::max(worst[s], rows[k].err[s][std::size_t(b)]);
                mean[s] += rows[k].err[s][std::size_t(b)] / (2.0 * double(cases.size()));
            }
        }
        if (seeds > 0) std::printf(" %.3f |", rows[k].albedo_cycles);
        std::printf("\n");
    }
    std::printf("| worst |");
    for (double w : worst) std::printf(" %.1f %% |", 100 * w);
    std::printf("%s\n| mean |", seeds > 0 ? " |" : "");
    for (double m : mean) std::printf(" %.1f %% |", 100 * m);
    std::printf("%s\n", seeds > 0 ? " |" : "");
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc >= 3 && std::strcmp(argv[1], "--accuracy") == 0) {
        int seeds = 16, threads = 2;
        std::vector<Setting> settings;
        for (int i = 3; i + 1 < argc; i += 2) {
            if (std::strcmp(argv[i], "--seeds") == 0) seeds = std::atoi(argv[i + 1]);
            else if (std::strcmp(argv[i], "--threads") == 0) threads = std::atoi(argv[i + 1]);
            else if (std::strcmp(argv[i], "--quadrature") == 0) {
                Setting s;
                s.kind = kSettings;
                s.name = argv[i + 1];
                if (std::sscanf(argv[i + 1], "%d/%d/%d", &s.q.offset_nodes, &s.q.tt_points, &s.q.trt_per_tt) != 3) {
                    std::fprintf(stderr, "vs_cycles: --quadrature n/tt/m, read '%s'\n", argv[i + 1]);
                    return 1;
                }
                settings.push_back(s);
            } else {
                std::fprintf(stderr, "vs_cycles: unknown option %s\n", argv[i]);
                return 1;
            }
        }
        if (settings.empty())
            for (int k = 0; k < kSettings; ++k) settings.push_back(Setting{kSetting[k], k, hs::HuangQuadrature()});
        try {
            return accuracy(argv[2], settings, seeds < 0 ? 0 : seeds, threads < 1 ? 1 : threads);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "vs_cycles: %s\n", e.what());
            return 1;
        }
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::AddCustomContext("flags", HAIRSCATTER_BENCH_FLAGS_STRING);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
