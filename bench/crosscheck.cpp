// bench_crosscheck: does bench_ref (the pbrt-v4-style reference of the benchmarks)
// implement the same model as hairscatter::ChiangFiber, and how accurate are the float
// versions of both? Over the benchmark's input set (65536 tuples, wi uniform and wi from
// the sampler, each β_m), it prints maximum and 99th-percentile relative differences:
//   1. double: bench_ref's un-divided sum "fsum" (pbrt's f · |wi.z|) and PDF against our
//      eval and pdf — as pbrt computes them (10-term I0 series, its log I0 asymptotic),
//      and with accurate I0 and log I0 (HairBxDF<double, true>), which isolates those
//      two errors: what is left is the difference between the two implementations;
//   2. double: our sample()'s pdf and weight against bench_ref evaluated at the sampled
//      wi, and the sampled directions themselves (lobes R, TT, TRT);
//   3. float accuracy: our float eval and bench_ref's float fsum against the accurate
//      double reference ("truth").
// Relative differences are taken where the truth exceeds 1e-30 (float's exp underflows
// below that and relative error means nothing there).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <vector>

#include <hairscatter/hairscatter.hpp>

#include "reference/inputs.hpp"
#include "reference/pbrt_style.hpp"

namespace {

using bench_ref::kInputs;

constexpr double kFloor = 1e-30;

struct Stat {
    std::vector<double> d;
    double worst_truth = 0.0;
    std::size_t worst_index = 0;

    void add(double value, double truth, std::size_t index) {
        if (!(std::abs(truth) > kFloor)) return;
        const double r = std::abs(value - truth) / std::abs(truth);
        const double e = std::isfinite(r) ? r : HUGE_VAL;
        if (d.empty() || e > *std::max_element(d.begin(), d.end())) {
            worst_truth = truth;
            worst_index = index;
        }
        d.push_back(e);
    }
    void add3(const glm::dvec3& value, const glm::dvec3& truth, std::size_t index) {
        for (int c = 0; c < 3; ++c) add(value[c], truth[c], index);
    }
    void print(const char* what) const {
        std::vector<double> s = d;
        std::sort(s.begin(), s.end());
        const double mx = s.empty() ? 0.0 : s.back();
        const double p99 = s.empty() ? 0.0 : s[std::size_t(0.99 * double(s.size() - 1))];
        std::printf("  %-46s max %.2e  p99 %.2e  (n = %zu; worst at input %zu, value %.3e)\n", what, mx,
                    p99, s.size(), worst_index, worst_truth);
    }
};

glm::dvec3 to_d(const glm::vec3& v) { return glm::dvec3(v); }

}  // namespace

int main() {
    const bench_ref::RawInputs& raw = bench_ref::raw_inputs();
    const auto& inf = bench_ref::inputs<float>();
    std::printf("bench_crosscheck: %zu inputs per case; relative differences where |truth| > %.0e\n", kInputs,
                kFloor);
    for (int b = 0; b < 3; ++b) {
        const hairscatter::FiberParams<double> pd = bench_ref::bench_params<double>(b);
        const hairscatter::ChiangMaterial<double> mat(pd);
        const hairscatter::ChiangMaterial<float> matf(bench_ref::bench_params<float>(b));
        for (int w = 0; w < 2; ++w) {
            std::printf("beta_m = %.2f, wi %s\n", bench_ref::kBetaM[b], w ? "sampled" : "uniform");
            Stat fp, fa, pp, pa, ours_float, ref_float;
            for (std::size_t i = 0; i < kInputs; ++i) {
                const glm::dvec3 wo = raw.wo[i];
                const glm::dvec3 wi = w ? raw.wi_sampled[b][i] : raw.wi_uniform[i];
                const double h = raw.h[i];
                const hairscatter::ChiangFiber<double> fib(mat, h);
                const bench_ref::HairBxDF<double, false> r10(h, pd.eta, pd.sigma_a, pd.beta_m, pd.beta_n, pd.alpha);
                const bench_ref::HairBxDF<double, true> ra(h, pd.eta, pd.sigma_a, pd.beta_m, pd.beta_n, pd.alpha);
                const hairscatter::HairEvalPdf<double> e = fib.eval_pdf(wo, wi);
                const glm::dvec3 truth = ra.fsum(wo, wi);
                fp.add3(r10.fsum(wo, wi), e.f, i);
                fa.add3(truth, e.f, i);
                pp.add(r10.PDF(wo, wi), e.pdf, i);
                pa.add(ra.PDF(wo, wi), e.pdf, i);
                // float: both implementations on the float-rounded inputs.
                const hairscatter::ChiangFiber<float> fibf(matf, inf.h[i]);
                const glm::vec3 wif = inf.wi[w][std::size_t(b)][i];
                ours_float.add3(to_d(fibf.eval(inf.wo[i], wif)), truth, i);
                ref_float.add3(to_d(inf.refs[std::size_t(b)][i].fsum(inf.wo[i], wif)), truth, i);
            }
            fp.print("double: pbrt-style ref fsum vs our eval");
            fa.print("double: accurate ref fsum vs our eval");
            pp.print("double: pbrt-style ref PDF vs our pdf");
            pa.print("double: accurate ref PDF vs our pdf");
            ours_float.print("float accuracy: our eval vs truth");
            ref_float.print("float accuracy: ref fsum (pbrt-style) vs truth");
        }
        std::printf("beta_m = %.2f, sample (double)\n", bench_ref::kBetaM[b]);
        Stat sp, sw, sdir;
        std::size_t compared = 0;
        for (std::size_t i = 0; i < kInputs; ++i) {
            const glm::dvec3 wo = raw.wo[i];
            const glm::dvec4 u = raw.u[i];
            const double h = raw.h[i];
            const hairscatter::ChiangFiber<double> fib(mat, h);
            const bench_ref::HairBxDF<double, true> ra(h, pd.eta, pd.sigma_a, pd.beta_m, pd.beta_n, pd.alpha);
            const hairscatter::HairSample<double> s = fib.sample(wo, u);
            const double rp = ra.PDF(wo, s.wi);
            sp.add(s.pdf, rp, i);
            if (rp > 0.0) sw.add3(s.weight, ra.fsum(wo, s.wi) / rp, i);
            // Same u, same direction, except where the two samplers map u differently on
            // purpose (residual lobe's φ; u1 < 1e-5, which pbrt clamps).
            if (s.lobe < hairscatter::SampledLobe::kResidual && u.y >= 1e-5) {
                const bench_ref::Sample<double> rs = ra.Sample_f(wo, u);
                const double dist = glm::length(rs.wi - s.wi);
                sdir.d.push_back(dist);
                ++compared;
            }
        }
        sp.print("sample pdf vs ref PDF at the sampled wi");
        sw.print("sample weight vs ref fsum/PDF");
        std::vector<double> dd = sdir.d;
        std::sort(dd.begin(), dd.end());
        std::printf("  %-46s max %.2e  (n = %zu)\n", "sampled wi vs ref Sample_f wi, |difference|",
                    dd.empty() ? 0.0 : dd.back(), compared);
    }
    return 0;
}
