// Benchmarks of the tabulated far-field fiber (models/tabulated.hpp): the table build per
// resolution, and ns per call of eval / pdf / sample (per call and on a fiber bound to wo by
// at()) per resolution, float and double; next to them the exact far-field fiber it
// tabulates (DeonFarFieldFiber, 32 h nodes) and the calibration loop of chiang_bench, whose
// float time is the unit u of the speed goals. Inputs are cycled from bench/reference/
// inputs.hpp as in chiang_bench.
//
// BM_Part splits the default eval into its table, φ and M_p parts (see there).
//
// Arguments: res = resolution (0 coarse, 1 default, 2 fine, 3 fast: TabulatedOptions; fast
// is the default azimuthal table with M_p tabulated, TabulatedLongitudinal::kTable), bm = β_m
// index (0.05, 0.3, 1.0), wi = 0 for wi uniform on the sphere, 1 for wi drawn by a sampler
// (so that the lobe peaks are hit).
#include <cmath>
#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include <hairscatter/hairscatter.hpp>

#include "reference/calibration.hpp"
#include "reference/inputs.hpp"

namespace {

namespace hs = hairscatter;
using bench_ref::inputs;
using bench_ref::kMask;

const char* const kResName[4] = {"coarse", "default", "fine", "fast"};

hs::TabulatedOptions resolution(int r) {
    return r == 0   ? hs::TabulatedOptions::coarse()
           : r == 2 ? hs::TabulatedOptions::fine()
           : r == 3 ? hs::TabulatedOptions::fast()
                    : hs::TabulatedOptions();
}

std::string label(const benchmark::State& state, bool with_wi) {
    std::string s = std::string(kResName[state.range(0)]) +
                    " beta_m=" + std::to_string(bench_ref::kBetaM[state.range(1)]).substr(0, 4);
    if (with_wi) s += state.range(2) ? " wi=sampled" : " wi=uniform";
    return s;
}

// Every resolution at β_m = 0.3, the default resolution at the other two β_m, and fast at β_m = 1.
void res_args(benchmark::internal::Benchmark* b) {
    b->ArgNames({"res", "bm"});
    for (int r = 0; r < 4; ++r) b->Args({r, 1});
    b->Args({1, 0});
    b->Args({1, 2});
    b->Args({3, 2});
}
void res_wi_args(benchmark::internal::Benchmark* b) {
    b->ArgNames({"res", "bm", "wi"});
    for (int w = 0; w < 2; ++w) {
        for (int r = 0; r < 4; ++r) b->Args({r, 1, w});
        b->Args({1, 0, w});
        b->Args({1, 2, w});
        b->Args({3, 2, w});
    }
}

// One material per (resolution, β_m), built on first use.
template <typename T> const hs::TabulatedMaterial<T>& material(int res, int bm) {
    static std::unique_ptr<hs::TabulatedMaterial<T>> m[4][3];
    if (!m[res][bm]) m[res][bm] = std::make_unique<hs::TabulatedMaterial<T>>(bench_ref::bench_params<T>(bm), resolution(res));
    return *m[res][bm];
}

// The unit of the speed goals: one calibration body over random a, b ∈ [0, 1).
template <typename T> void BM_Calib(benchmark::State& state) {
    const auto& in = inputs<T>();
    std::size_t i = 0;
    for (auto _ : state) {
        T r = bench_ref::calibration_body(in.calib_a[i], in.calib_b[i]);
        benchmark::DoNotOptimize(r);
        i = (i + 1) & bench_ref::kCalibMask;  // the unit's cycle (reference/inputs.hpp)
    }
    state.SetItemsProcessed(state.iterations());
}

// Runs call(i) over the cycled inputs, the result through DoNotOptimize, and labels the run.
template <typename F> void cycle(benchmark::State& state, bool with_wi, F&& call) {
    std::size_t i = 0;
    for (auto _ : state) {
        auto r = call(i);
        benchmark::DoNotOptimize(r);
        i = (i + 1) & kMask;
    }
    state.SetLabel(label(state, with_wi));
}

template <typename T> struct Args {
    const bench_ref::Inputs<T>& in = inputs<T>();
    hs::TabulatedFiber<T> fiber;
    const std::vector<glm::vec<3, T>>& wi;
    Args(const benchmark::State& state, bool with_wi)
        : fiber(material<T>(int(state.range(0)), int(state.range(1)))),
          wi(in.wi[with_wi ? state.range(2) : 0][std::size_t(state.range(1))]) {}
};

// Per material: validation, the h quadrature and the tables (σa varied so nothing is reused).
template <typename T> void BM_Build(benchmark::State& state) {
    const auto& in = inputs<T>();
    hs::FiberParams<T> p = bench_ref::bench_params<T>(int(state.range(1)));
    const auto sigma = p.sigma_a;
    const hs::TabulatedOptions opt = resolution(int(state.range(0)));
    std::size_t i = 0;
    for (auto _ : state) {
        p.sigma_a = sigma * (T(1) + T(0.1) * in.h[i]);
        hs::TabulatedMaterial<T> m(p, opt);
        benchmark::DoNotOptimize(m.data().data());
        i = (i + 1) & kMask;
    }
    state.counters["bytes"] = double(material<T>(int(state.range(0)), int(state.range(1))).bytes());
    state.SetLabel(label(state, false));
}

template <typename T> void BM_Eval(benchmark::State& state) {
    const Args<T> a(state, true);
    cycle(state, true, [&](std::size_t i) { return a.fiber.eval(a.in.wo[i], a.wi[i]); });
}

template <typename T> void BM_Pdf(benchmark::State& state) {
    const Args<T> a(state, true);
    cycle(state, true, [&](std::size_t i) { return a.fiber.pdf(a.in.wo[i], a.wi[i]); });
}

template <typename T> void BM_EvalPdf(benchmark::State& state) {
    const Args<T> a(state, true);
    cycle(state, true, [&](std::size_t i) { return a.fiber.eval_pdf(a.in.wo[i], a.wi[i]); });
}

template <typename T> void BM_Sample(benchmark::State& state) {
    const Args<T> a(state, false);
    cycle(state, false, [&](std::size_t i) { return a.fiber.sample(a.in.wo[i], a.in.u[i]); });
}

// at(wo): the wo terms once per hit.
template <typename T> void BM_At(benchmark::State& state) {
    const Args<T> a(state, false);
    cycle(state, false, [&](std::size_t i) { return a.fiber.at(a.in.wo[i]); });
}

// eval / sample of a bound fiber: 64 bound fibers (different wo) cycled against the 65536
// wi / u inputs.
template <typename T> std::vector<typename hs::TabulatedFiber<T>::At> bound(const Args<T>& a) {
    std::vector<typename hs::TabulatedFiber<T>::At> at;
    for (std::size_t k = 0; k < 64; ++k) at.push_back(a.fiber.at(a.in.wo[k]));
    return at;
}

template <typename T> void BM_AtEval(benchmark::State& state) {
    const Args<T> a(state, true);
    const auto at = bound(a);
    cycle(state, true, [&](std::size_t i) { return at[i & 63].eval(a.wi[i]); });
}

template <typename T> void BM_AtSample(benchmark::State& state) {
    const Args<T> a(state, false);
    const auto at = bound(a);
    cycle(state, false, [&](std::size_t i) { return at[i & 63].sample(a.in.u[i]); });
}

// The exact model it tabulates: DeonFarFieldFiber at its default 32 h nodes (β_m = 0.3).
template <typename T> void BM_ExactEval(benchmark::State& state) {
    const auto& in = inputs<T>();
    static const hs::DeonFarFieldMaterial<T> mat(bench_ref::bench_params<T>(1));
    const hs::DeonFarFieldFiber<T> fiber(mat);
    const auto& wi = in.wi[state.range(0)][1];
    std::size_t i = 0;
    for (auto _ : state) {
        auto r = fiber.eval(in.wo[i], wi[i]);
        benchmark::DoNotOptimize(r);
        i = (i + 1) & kMask;
    }
    state.SetLabel(state.range(0) ? "beta_m=0.30 wi=sampled" : "beta_m=0.30 wi=uniform");
}

// Where eval's time goes (default resolution, β_m = 0.3, wi sampled), each part written with
// the view's public accessors exactly as TabulatedFiber::eval does it:
//   part 0, table:        the row and node cells and the 36-value bilinear interpolation
//                         of the three lobes, with φ replaced by a value that costs nothing
//                         (|wi.y| ∈ [0, 1], so only the first third of the nodes is read);
//   part 1, table + φ:    the same with φ from the atan2 of the azimuthal cross and dot;
//   part 2, longitudinal: cosθi and the four exact M_p at the tilted θo' (d'Eon 2011).
// The three do not add up to eval (they overlap in the pipeline); their differences show
// what a faster φ or M_p can save at most.
template <typename T> void BM_Part(benchmark::State& state) {
    using V3 = glm::vec<3, T>;
    const Args<T> a(state, true);
    const hs::TabulatedView<T>& v = a.fiber.view();
    const int part = int(state.range(3));
    constexpr int kStride = hs::TabulatedView<T>::kNodeStride;
    cycle(state, true, [&](std::size_t k) {
        const V3& wo = a.in.wo[k];
        const V3& wi = a.wi[k];
        const T sin_o = hs::clamp(wo.x, T(-1), T(1)), cos_o = hs::cos_from_sin(sin_o);
        const T sin_i = hs::clamp(wi.x, T(-1), T(1));
        if (part == 2) {
            const T cos_i = hs::cos_from_sin(sin_i);
            T m = T(0);
            for (int p = 0; p < 4; ++p) {
                const auto r = v.tilt().rotate(p, sin_o, cos_o);
                m += v.longitudinal(p).eval(sin_i, cos_i, r.sin_theta, r.cos_theta);
            }
            return V3(m);
        }
        int row, i;
        T t, u;
        v.theta_cell(cos_o, row, t);
        const T phi = part == 1 ? hs::elem::atan2(wo.y * wi.z - wo.z * wi.y, wo.y * wi.y + wo.z * wi.z) : wi.y;
        v.phi_cell(phi < T(0) ? -phi : phi, i, u);
        const T* n0 = v.lobes(row) + i * kStride;
        const T* n1 = v.lobes(row + 1) + i * kStride;
        const T w00 = (T(1) - t) * (T(1) - u), w01 = (T(1) - t) * u, w10 = t * (T(1) - u), w11 = t * u;
        constexpr int kVec = kStride & ~3;  // 8 of the 9 values as one loop, as eval reads them
        T n[kStride];
        for (int j = 0; j < kVec; ++j) n[j] = w00 * n0[j] + w01 * n0[kStride + j] + w10 * n1[j] + w11 * n1[kStride + j];
        for (int j = kVec; j < kStride; ++j) n[j] = w00 * n0[j] + w01 * n0[kStride + j] + w10 * n1[j] + w11 * n1[kStride + j];
        V3 f(T(0));
        for (int p = 0; p < 3; ++p) f += V3(n[3 * p], n[3 * p + 1], n[3 * p + 2]);
        return f;
    });
    static const char* const kPartName[3] = {" part=table", " part=table+phi", " part=longitudinal"};
    state.SetLabel(label(state, true) + kPartName[part]);
}

void part_args(benchmark::internal::Benchmark* b) {
    b->ArgNames({"res", "bm", "wi", "part"});
    for (int part = 0; part < 3; ++part) b->Args({1, 1, 1, part});
}

}  // namespace

BENCHMARK_TEMPLATE(BM_Calib, float);
BENCHMARK_TEMPLATE(BM_Calib, double);

BENCHMARK_TEMPLATE(BM_Build, float)->Apply(res_args)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Build, double)->Apply(res_args)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Eval, float)->Apply(res_wi_args);
BENCHMARK_TEMPLATE(BM_Eval, double)->Apply(res_wi_args);
BENCHMARK_TEMPLATE(BM_Pdf, float)->Apply(res_wi_args);
BENCHMARK_TEMPLATE(BM_Pdf, double)->Apply(res_wi_args);
BENCHMARK_TEMPLATE(BM_EvalPdf, float)->Apply(res_wi_args);
BENCHMARK_TEMPLATE(BM_EvalPdf, double)->Apply(res_wi_args);
BENCHMARK_TEMPLATE(BM_Sample, float)->Apply(res_args);
BENCHMARK_TEMPLATE(BM_Sample, double)->Apply(res_args);
BENCHMARK_TEMPLATE(BM_At, float)->Apply(res_args);
BENCHMARK_TEMPLATE(BM_At, double)->Apply(res_args);
BENCHMARK_TEMPLATE(BM_AtEval, float)->Apply(res_wi_args);
BENCHMARK_TEMPLATE(BM_AtEval, double)->Apply(res_wi_args);
BENCHMARK_TEMPLATE(BM_AtSample, float)->Apply(res_args);
BENCHMARK_TEMPLATE(BM_AtSample, double)->Apply(res_args);
BENCHMARK_TEMPLATE(BM_Part, float)->Apply(part_args);
BENCHMARK_TEMPLATE(BM_Part, double)->Apply(part_args);
BENCHMARK_TEMPLATE(BM_ExactEval, float)->ArgName("wi")->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_ExactEval, double)->ArgName("wi")->Arg(0)->Arg(1);

#ifndef HAIRSCATTER_BENCH_FLAGS_STRING
#define HAIRSCATTER_BENCH_FLAGS_STRING "(unknown)"
#endif

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
#if defined(__clang__)
    benchmark::AddCustomContext("compiler", "clang " __clang_version__);
#elif defined(__GNUC__)
    benchmark::AddCustomContext("compiler", "gcc " __VERSION__);
#endif
    benchmark::AddCustomContext("flags", HAIRSCATTER_BENCH_FLAGS_STRING);
    benchmark::AddCustomContext("inputs", std::to_string(bench_ref::kInputs) + " (wo, wi, u) tuples, cycled");
    // Build the inputs and tables before the first timing (they are function-local statics).
    (void)inputs<float>();
    (void)inputs<double>();
    for (int r = 0; r < 4; ++r)
        for (int b = 0; b < 3; ++b) {
            (void)material<float>(r, b);
            (void)material<double>(r, b);
        }
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
