// vs_pbrt: hairscatter's Chiang fiber against pbrt-v4's algorithm (reference/pbrt_style.hpp)
// in one process, at β_m = β_n = 0.3, float and double: each call of ours is timed next to
// the reference call that does the same job, repetitions interleaved in random order, and
// the program prints the ratios of the medians itself. scripts/bench.sh --vs-pbrt builds it
// at -O2 and at -O3 (targets vs_pbrt_o2, vs_pbrt_o3), runs both and writes
// bench/results/vs_pbrt.md, from which it regenerates the README's speed table.
//
// The pairs (ours / reference):
//   eval         ChiangFiber::eval(wo, wi)                 / HairBxDF::f(wo, wi)
//   pdf          ChiangFiber::pdf(wo, wi)                  / HairBxDF::PDF(wo, wi)
//   sample       ChiangFiber::sample(wo, u)                / HairBxDF::Sample_f(wo, u)
//   path vertex  fiber(h) + at(wo) + eval(wi) + sample(u)  / HairBxDF(h) + f + Sample_f
//   at(wo).eval  a bound fiber's eval(wi)                  / HairBxDF::f (pbrt has no bound form)
//   batch.*      ChiangBatch over 256 hits, per hit         / the prebuilt eval, pdf, sample
// wi is uniform on the sphere; the inputs are reference/inputs.hpp's 65536 cycled tuples
// (fewer would let the branch predictor learn the cycle: see there).
// The calibration loop (reference/calibration.hpp, float) gives the unit u of
// docs/tradeoff.md, so that at(wo).eval can also be read in units.
//
// Besides Google Benchmark's console output it prints one line per pair, the medians of
// the repetitions' CPU times and then their minima (less sensitive to other load),
//   RESULT <type> <label> <call> <ours ns> <reference ns> <ratio> <ours> <ref> <ratio (minima)>
// and `RESULT float <label> unit <ns> <ns (minimum)>`, which scripts/bench.sh reads.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include <hairscatter/hairscatter.hpp>

#include "reference/calibration.hpp"
#include "reference/inputs.hpp"
#include "reference/pbrt_style.hpp"

#ifndef HAIRSCATTER_BENCH_LABEL
#define HAIRSCATTER_BENCH_LABEL "?"
#endif
#ifndef HAIRSCATTER_BENCH_FLAGS_STRING
#define HAIRSCATTER_BENCH_FLAGS_STRING "(unknown)"
#endif

namespace {

using bench_ref::inputs;
using bench_ref::kMask;

constexpr std::size_t kBeta = 1;  // β_m = 0.3 (bench_ref::kBetaM)

template <typename F> void cycle(benchmark::State& state, F&& call) {
    std::size_t i = 0;
    for (auto _ : state) {
        auto r = call(i);
        benchmark::DoNotOptimize(r);
        i = (i + 1) & kMask;
    }
}

template <typename T> const std::vector<glm::vec<3, T>>& wi_uniform() { return inputs<T>().wi[0][kBeta]; }

template <typename T> void BM_Calib(benchmark::State& state) {
    const auto& in = inputs<T>();
    std::size_t i = 0;
    for (auto _ : state) {  // over the unit's own cycle (reference/inputs.hpp: kCalibInputs)
        auto r = bench_ref::calibration_body(in.calib_a[i], in.calib_b[i]);
        benchmark::DoNotOptimize(r);
        i = (i + 1) & bench_ref::kCalibMask;
    }
}

template <typename T> void BM_OursEval(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) { return in.fibers[kBeta][i].eval(in.wo[i], wi_uniform<T>()[i]); });
}
template <typename T> void BM_RefEval(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) { return in.refs[kBeta][i].f(in.wo[i], wi_uniform<T>()[i]); });
}

template <typename T> void BM_OursPdf(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) { return in.fibers[kBeta][i].pdf(in.wo[i], wi_uniform<T>()[i]); });
}
template <typename T> void BM_RefPdf(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) { return in.refs[kBeta][i].PDF(in.wo[i], wi_uniform<T>()[i]); });
}

template <typename T> void BM_OursSample(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) { return in.fibers[kBeta][i].sample(in.wo[i], in.u[i]); });
}
template <typename T> void BM_RefSample(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) { return in.refs[kBeta][i].Sample_f(in.wo[i], in.u[i]); });
}

// One path vertex as a renderer shades it: the fiber for the hit, eval for the light
// sample, sample for the continuation.
template <typename T> void BM_OursVertex(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) {
        const auto at = hairscatter::ChiangFiber<T>(in.materials[kBeta], in.h[i]).at(in.wo[i]);
        return std::make_pair(at.eval(wi_uniform<T>()[i]), at.sample(in.u[i]));
    });
}
template <typename T> void BM_RefVertex(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) {
        const auto ref = bench_ref::make_ref<T>(int(kBeta), in.h[i]);
        return std::make_pair(ref.f(in.wo[i], wi_uniform<T>()[i]), ref.Sample_f(in.wo[i], in.u[i]));
    });
}

// Stateless calls as a renderer makes them: the fiber is built from h inside the timed call
// (ours: ChiangFiber(material, h), which takes asin(h); the reference: HairBxDF(h, ...), as
// pbrt builds its BxDF per hit), so the prebuilt fibers' stored γo is not in our favour.
template <typename T> void BM_OursFreshEval(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) {
        return hairscatter::ChiangFiber<T>(in.materials[kBeta], in.h[i]).eval(in.wo[i], wi_uniform<T>()[i]);
    });
}
template <typename T> void BM_RefFreshEval(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) { return bench_ref::make_ref<T>(int(kBeta), in.h[i]).f(in.wo[i], wi_uniform<T>()[i]); });
}
template <typename T> void BM_OursFreshPdf(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) {
        return hairscatter::ChiangFiber<T>(in.materials[kBeta], in.h[i]).pdf(in.wo[i], wi_uniform<T>()[i]);
    });
}
template <typename T> void BM_RefFreshPdf(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) { return bench_ref::make_ref<T>(int(kBeta), in.h[i]).PDF(in.wo[i], wi_uniform<T>()[i]); });
}
template <typename T> void BM_OursFreshSample(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) { return hairscatter::ChiangFiber<T>(in.materials[kBeta], in.h[i]).sample(in.wo[i], in.u[i]); });
}
template <typename T> void BM_RefFreshSample(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) { return bench_ref::make_ref<T>(int(kBeta), in.h[i]).Sample_f(in.wo[i], in.u[i]); });
}

// Parameters that vary per hit (textures, strand variation): every one of the 65536 inputs
// has its own η ∈ [1.5, 1.6], β_m and β_n ∈ [0.25, 0.35], α ∈ [1°, 3°] and eumelanin
// concentration ∈ [0.8, 1.8], and both sides build their material per call: ours
// ChiangMaterial::per_hit (then the fiber), the reference its HairBxDF (as pbrt does).
template <typename T> const std::vector<hairscatter::FiberParams<T>>& hit_params() {
    static const std::vector<hairscatter::FiberParams<T>> params = [] {
        std::vector<hairscatter::FiberParams<T>> v;
        std::uint64_t x = 0x9E3779B97F4A7C15ull;
        auto uniform = [&x]() {  // (splitmix64)
            x += 0x9E3779B97F4A7C15ull;
            std::uint64_t z = x;
            z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
            z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
            return double((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
        };
        for (std::size_t i = 0; i <= kMask; ++i) {
            hairscatter::FiberParams<T> p;
            p.eta = T(1.5 + 0.1 * uniform());
            p.beta_m = T(0.25 + 0.1 * uniform());
            p.beta_n = T(0.25 + 0.1 * uniform());
            p.alpha = hairscatter::radians(T(1.0 + 2.0 * uniform()));
            p.sigma_a = hairscatter::sigma_a_from_concentrations(T(0.8 + uniform()), T(0));
            v.push_back(p);
        }
        return v;
    }();
    return params;
}
template <typename T> bench_ref::HairBxDF<T> ref_at_hit(std::size_t i, T h) {
    const hairscatter::FiberParams<T>& p = hit_params<T>()[i];
    return bench_ref::HairBxDF<T>(h, p.eta, p.sigma_a, p.beta_m, p.beta_n, p.alpha);
}
template <typename T> void BM_OursHitEval(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) {
        return hairscatter::ChiangFiber<T>::per_hit_eval(hit_params<T>()[i], in.h[i], in.wo[i], wi_uniform<T>()[i]);
    });
}
// The same from its parts: the material built by the caller, then the fiber's eval.
template <typename T> void BM_OursHitEvalParts(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) {
        const auto m = hairscatter::ChiangMaterial<T>::per_hit(hit_params<T>()[i]);
        return hairscatter::ChiangFiber<T>(m, in.h[i]).eval(in.wo[i], wi_uniform<T>()[i]);
    });
}
template <typename T> void BM_RefHitEval(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) { return ref_at_hit<T>(i, in.h[i]).f(in.wo[i], wi_uniform<T>()[i]); });
}
// per_hit_vertex also gives the pdf toward wi (for a renderer's MIS weight), which the
// reference's f does not: more work on our side.
template <typename T> void BM_OursHitVertex(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) {
        return hairscatter::ChiangFiber<T>::per_hit_vertex(hit_params<T>()[i], in.h[i], in.wo[i],
                                                            wi_uniform<T>()[i], in.u[i]);
    });
}
template <typename T> void BM_OursHitVertexParts(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) {
        const auto m = hairscatter::ChiangMaterial<T>::per_hit(hit_params<T>()[i]);
        const auto at = hairscatter::ChiangFiber<T>(m, in.h[i]).at(in.wo[i]);
        return std::make_pair(at.eval(wi_uniform<T>()[i]), at.sample(in.u[i]));
    });
}
template <typename T> void BM_RefHitVertex(benchmark::State& state) {
    const auto& in = inputs<T>();
    cycle(state, [&](std::size_t i) {
        const auto ref = ref_at_hit<T>(i, in.h[i]);
        return std::make_pair(ref.f(in.wo[i], wi_uniform<T>()[i]), ref.Sample_f(in.wo[i], in.u[i]));
    });
}
// The per-hit material alone (its build cost in ns).
template <typename T> void BM_OursHitBuild(benchmark::State& state) {
    cycle(state, [&](std::size_t i) { return hairscatter::ChiangMaterial<T>::per_hit(hit_params<T>()[i]); });
}
template <typename T> void BM_OursCheckedBuild(benchmark::State& state) {
    cycle(state, [&](std::size_t i) { return hairscatter::ChiangMaterial<T>(hit_params<T>()[i]); });
}

// eval, pdf and sample at β_m = β_n = 0.05 and 1 as well (argument: bench_ref::kBetaM's
// index), prebuilt fibers as above: where the reference takes other paths (its log-space
// M_p below v = 0.1, its I0 series' subnormals at β_m = 1).
template <typename T> void BM_OursEvalB(benchmark::State& state) {
    const auto& in = inputs<T>();
    const std::size_t b = std::size_t(state.range(0));
    cycle(state, [&](std::size_t i) { return in.fibers[b][i].eval(in.wo[i], in.wi[0][b][i]); });
}
template <typename T> void BM_RefEvalB(benchmark::State& state) {
    const auto& in = inputs<T>();
    const std::size_t b = std::size_t(state.range(0));
    cycle(state, [&](std::size_t i) { return in.refs[b][i].f(in.wo[i], in.wi[0][b][i]); });
}
template <typename T> void BM_OursSampleB(benchmark::State& state) {
    const auto& in = inputs<T>();
    const std::size_t b = std::size_t(state.range(0));
    cycle(state, [&](std::size_t i) { return in.fibers[b][i].sample(in.wo[i], in.u[i]); });
}
template <typename T> void BM_RefSampleB(benchmark::State& state) {
    const auto& in = inputs<T>();
    const std::size_t b = std::size_t(state.range(0));
    cycle(state, [&](std::size_t i) { return in.refs[b][i].Sample_f(in.wo[i], in.u[i]); });
}

// 64 fibers bound to their wo, cycled against the 65536 wi.
template <typename T> void BM_OursAtEval(benchmark::State& state) {
    const auto& in = inputs<T>();
    std::vector<typename hairscatter::ChiangFiber<T>::At> at;
    for (std::size_t k = 0; k < 64; ++k) at.push_back(in.fibers[kBeta][k].at(in.wo[k]));
    cycle(state, [&](std::size_t i) { return at[i & 63].eval(wi_uniform<T>()[i]); });
}

// Batches as a wavefront renderer shades them (models/chiang_batch.hpp): kBatchHits hits of
// the material per call, structure-of-arrays in and out, cycled through the same 65536
// inputs as the one-hit rows (h per hit: the stateless calls' work). One iteration is a
// batch; print_results divides by kBatchHits and sets the time per hit against the
// reference's prebuilt per-hit calls (BM_RefEval, BM_RefPdf, BM_RefSample: its BxDF built
// outside the timing, the harder comparison).
constexpr std::size_t kBatchHits = 256;
static_assert((kMask + 1) % kBatchHits == 0, "the batches tile the inputs");
template <typename T> struct BatchData {
    std::vector<T> h, wo[3], wi[3], u[4];                      // the inputs, as arrays
    std::vector<T> f[3], pdf, s_wi[3], s_weight[3], s_pdf;     // one batch's results
    std::vector<hairscatter::SampledLobe> lobe;
    BatchData() : pdf(kBatchHits), s_pdf(kBatchHits), lobe(kBatchHits) {
        const auto& in = inputs<T>();
        for (std::size_t i = 0; i <= kMask; ++i) {
            h.push_back(in.h[i]);
            for (int c = 0; c < 3; ++c) wo[c].push_back(in.wo[i][c]), wi[c].push_back(wi_uniform<T>()[i][c]);
            for (int c = 0; c < 4; ++c) u[c].push_back(in.u[i][c]);
        }
        for (int c = 0; c < 3; ++c) f[c].resize(kBatchHits), s_wi[c].resize(kBatchHits), s_weight[c].resize(kBatchHits);
    }
    hairscatter::ChiangBatchQuery<T> query(std::size_t i) const {
        hairscatter::ChiangBatchQuery<T> q;
        q.n = kBatchHits;
        q.h = h.data() + i;
        q.wo = {wo[0].data() + i, wo[1].data() + i, wo[2].data() + i};
        q.wi = {wi[0].data() + i, wi[1].data() + i, wi[2].data() + i};
        return q;
    }
    hairscatter::ChiangBatchSampleQuery<T> sample_query(std::size_t i) const {
        hairscatter::ChiangBatchSampleQuery<T> q;
        q.n = kBatchHits;
        q.h = h.data() + i;
        q.wo = {wo[0].data() + i, wo[1].data() + i, wo[2].data() + i};
        for (int c = 0; c < 4; ++c) q.u[c] = u[c].data() + i;
        return q;
    }
    hairscatter::Arrays3<T> f_out() { return {f[0].data(), f[1].data(), f[2].data()}; }
};
template <typename T> BatchData<T>& batch_data() {
    static BatchData<T> data;
    return data;
}
template <typename T, typename F> void cycle_batches(benchmark::State& state, F&& call) {
    std::size_t i = 0;
    for (auto _ : state) {
        call(i);
        benchmark::ClobberMemory();
        i = (i + kBatchHits) & kMask;
    }
}
template <typename T> void BM_OursBatchEval(benchmark::State& state) {
    BatchData<T>& d = batch_data<T>();
    const hairscatter::ChiangBatch<T> batch(inputs<T>().materials[kBeta]);
    cycle_batches<T>(state, [&](std::size_t i) { batch.eval(d.query(i), d.f_out()); });
}
template <typename T> void BM_OursBatchPdf(benchmark::State& state) {
    BatchData<T>& d = batch_data<T>();
    const hairscatter::ChiangBatch<T> batch(inputs<T>().materials[kBeta]);
    cycle_batches<T>(state, [&](std::size_t i) { batch.pdf(d.query(i), d.pdf.data()); });
}
template <typename T> void BM_OursBatchSample(benchmark::State& state) {
    BatchData<T>& d = batch_data<T>();
    const hairscatter::ChiangBatch<T> batch(inputs<T>().materials[kBeta]);
    hairscatter::ChiangBatchSamples<T> out;
    out.wi = {d.s_wi[0].data(), d.s_wi[1].data(), d.s_wi[2].data()};
    out.weight = {d.s_weight[0].data(), d.s_weight[1].data(), d.s_weight[2].data()};
    out.pdf = d.s_pdf.data();
    out.lobe = d.lobe.data();
    cycle_batches<T>(state, [&](std::size_t i) { batch.sample(d.sample_query(i), out); });
}

// Collects every repetition's CPU time per benchmark while the console reporter prints.
class Collector : public benchmark::ConsoleReporter {
  public:
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& r : runs)
            if (r.run_type == Run::RT_Iteration && !r.error_occurred)
                times_[r.run_name.str()].push_back(r.GetAdjustedCPUTime());
        ConsoleReporter::ReportRuns(runs);
    }
    // The median (q = 0.5) or the minimum (q = 0) of the repetitions' CPU times.
    double quantile(const std::string& name, double q) const {
        const auto it = times_.find(name);
        if (it == times_.end() || it->second.empty()) return 0.0;
        std::vector<double> t = it->second;
        std::sort(t.begin(), t.end());
        const std::size_t n = t.size();
        if (q == 0.0) return t[0];
        return n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
    }

  private:
    std::map<std::string, std::vector<double>> times_;
};

void print_results(const Collector& c) {
    const char* calls[][4] = {{"eval", "BM_OursEval", "BM_RefEval"},
                              {"pdf", "BM_OursPdf", "BM_RefPdf"},
                              {"sample", "BM_OursSample", "BM_RefSample"},
                              {"vertex", "BM_OursVertex", "BM_RefVertex"},
                              {"at.eval", "BM_OursAtEval", "BM_RefEval"},
                              {"fresh.eval", "BM_OursFreshEval", "BM_RefFreshEval"},
                              {"fresh.pdf", "BM_OursFreshPdf", "BM_RefFreshPdf"},
                              {"fresh.sample", "BM_OursFreshSample", "BM_RefFreshSample"},
                              {"hit.eval", "BM_OursHitEval", "BM_RefHitEval"},
                              {"hit.eval.parts", "BM_OursHitEvalParts", "BM_RefHitEval"},
                              {"hit.vertex", "BM_OursHitVertex", "BM_RefHitVertex"},
                              {"hit.vertex.parts", "BM_OursHitVertexParts", "BM_RefHitVertex"},
                              {"b0.05.eval", "BM_OursEvalB", "BM_RefEvalB", "/0"},
                              {"b1.eval", "BM_OursEvalB", "BM_RefEvalB", "/2"},
                              {"b0.05.sample", "BM_OursSampleB", "BM_RefSampleB", "/0"},
                              {"b1.sample", "BM_OursSampleB", "BM_RefSampleB", "/2"}};
    std::printf("\n");
    for (const char* type : {"float", "double"}) {
        const std::string t = std::string("<") + type + ">";
        for (const auto& call : calls) {
            const std::string arg = call[3] ? call[3] : "";
            const std::string o = call[1] + t + arg, rf = call[2] + t + arg;
            const double ours = c.quantile(o, 0.5), ref = c.quantile(rf, 0.5);
            const double ours_min = c.quantile(o, 0.0), ref_min = c.quantile(rf, 0.0);
            if (ours > 0.0 && ref > 0.0)
                std::printf("RESULT %s %s %s %.2f %.2f %.3f %.2f %.2f %.3f\n", type, HAIRSCATTER_BENCH_LABEL, call[0],
                            ours, ref, ref / ours, ours_min, ref_min, ref_min / ours_min);
        }
    }
    // The batches per hit (kBatchHits hits per timed call).
    const char* batch_calls[][3] = {{"batch.eval", "BM_OursBatchEval", "BM_RefEval"},
                                    {"batch.pdf", "BM_OursBatchPdf", "BM_RefPdf"},
                                    {"batch.sample", "BM_OursBatchSample", "BM_RefSample"}};
    for (const char* type : {"float", "double"}) {
        const std::string t = std::string("<") + type + ">";
        for (const auto& call : batch_calls) {
            const std::string o = call[1] + t, rf = call[2] + t;
            const double hits = double(kBatchHits);
            const double ours = c.quantile(o, 0.5) / hits, ref = c.quantile(rf, 0.5);
            const double ours_min = c.quantile(o, 0.0) / hits, ref_min = c.quantile(rf, 0.0);
            if (ours > 0.0 && ref > 0.0)
                std::printf("RESULT %s %s %s %.2f %.2f %.3f %.2f %.2f %.3f\n", type, HAIRSCATTER_BENCH_LABEL, call[0],
                            ours, ref, ref / ours, ours_min, ref_min, ref_min / ours_min);
        }
    }
    const double unit = c.quantile("BM_Calib<float>", 0.5), unit_min = c.quantile("BM_Calib<float>", 0.0);
    if (unit > 0.0) std::printf("RESULT float %s unit %.2f %.2f\n", HAIRSCATTER_BENCH_LABEL, unit, unit_min);
    for (const char* type : {"float", "double"}) {  // the per-hit material's own cost
        const std::string t = std::string("<") + type + ">";
        const double hit = c.quantile("BM_OursHitBuild" + t, 0.5), checked = c.quantile("BM_OursCheckedBuild" + t, 0.5);
        if (hit > 0.0 && checked > 0.0)
            std::printf("RESULT %s %s build %.2f %.2f %.2f %.2f\n", type, HAIRSCATTER_BENCH_LABEL, hit, checked,
                        c.quantile("BM_OursHitBuild" + t, 0.0), c.quantile("BM_OursCheckedBuild" + t, 0.0));
    }
}

}  // namespace

BENCHMARK_TEMPLATE(BM_Calib, float);
BENCHMARK_TEMPLATE(BM_OursEval, float);
BENCHMARK_TEMPLATE(BM_RefEval, float);
BENCHMARK_TEMPLATE(BM_OursPdf, float);
BENCHMARK_TEMPLATE(BM_RefPdf, float);
BENCHMARK_TEMPLATE(BM_OursSample, float);
BENCHMARK_TEMPLATE(BM_RefSample, float);
BENCHMARK_TEMPLATE(BM_OursVertex, float);
BENCHMARK_TEMPLATE(BM_RefVertex, float);
BENCHMARK_TEMPLATE(BM_OursAtEval, float);
BENCHMARK_TEMPLATE(BM_OursEval, double);
BENCHMARK_TEMPLATE(BM_RefEval, double);
BENCHMARK_TEMPLATE(BM_OursPdf, double);
BENCHMARK_TEMPLATE(BM_RefPdf, double);
BENCHMARK_TEMPLATE(BM_OursSample, double);
BENCHMARK_TEMPLATE(BM_RefSample, double);
BENCHMARK_TEMPLATE(BM_OursVertex, double);
BENCHMARK_TEMPLATE(BM_RefVertex, double);
BENCHMARK_TEMPLATE(BM_OursAtEval, double);
#define HAIRSCATTER_BOTH(bm) BENCHMARK_TEMPLATE(bm, float); BENCHMARK_TEMPLATE(bm, double)
HAIRSCATTER_BOTH(BM_OursFreshEval);
HAIRSCATTER_BOTH(BM_RefFreshEval);
HAIRSCATTER_BOTH(BM_OursFreshPdf);
HAIRSCATTER_BOTH(BM_RefFreshPdf);
HAIRSCATTER_BOTH(BM_OursFreshSample);
HAIRSCATTER_BOTH(BM_RefFreshSample);
HAIRSCATTER_BOTH(BM_OursHitEval);
HAIRSCATTER_BOTH(BM_OursHitEvalParts);
HAIRSCATTER_BOTH(BM_RefHitEval);
HAIRSCATTER_BOTH(BM_OursHitVertex);
HAIRSCATTER_BOTH(BM_OursHitVertexParts);
HAIRSCATTER_BOTH(BM_RefHitVertex);
HAIRSCATTER_BOTH(BM_OursHitBuild);
HAIRSCATTER_BOTH(BM_OursCheckedBuild);
HAIRSCATTER_BOTH(BM_OursBatchEval);
HAIRSCATTER_BOTH(BM_OursBatchPdf);
HAIRSCATTER_BOTH(BM_OursBatchSample);
BENCHMARK_TEMPLATE(BM_OursEvalB, float)->Arg(0)->Arg(2);
BENCHMARK_TEMPLATE(BM_RefEvalB, float)->Arg(0)->Arg(2);
BENCHMARK_TEMPLATE(BM_OursSampleB, float)->Arg(0)->Arg(2);
BENCHMARK_TEMPLATE(BM_RefSampleB, float)->Arg(0)->Arg(2);

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::AddCustomContext("flags", HAIRSCATTER_BENCH_FLAGS_STRING);
    (void)inputs<float>();  // build the inputs before the first timing
    (void)inputs<double>();
    (void)hit_params<float>();
    (void)hit_params<double>();
    (void)batch_data<float>();
    (void)batch_data<double>();
    Collector collector;
    benchmark::RunSpecifiedBenchmarks(&collector);
    print_results(collector);
    benchmark::Shutdown();
    return 0;
}
