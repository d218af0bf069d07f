// The speed/accuracy trade of every model and knob: for each setting, ns per
// eval / pdf / sample from Google Benchmark (medians of repetitions, in the same run as
// the calibration loop), the error of f against an independent double-precision
// reference of the model family the setting approximates, and the furnace deviation.
// Writes a CSV and a Markdown table; scripts/tradeoff.sh adds the log-log plot
// (bench/tradeoff.gp) and puts all three into docs/.
//
//   tradeoff --out DIR [--min-time S] [--repetitions N] [--quick]
//
// References (tests/support/):
//   near field (Chiang 2016 at a given h): reference_chiang.hpp, a transcription of
//     pbrt-v4's model in double with Boost's I0;
//   far field (d'Eon 2011, integrated over h), also for the tabulated model:
//     reference_farfield.hpp, adaptive Gauss–Kronrod over h to 1e-11;
//   Huang 2022 (microfacet fiber): reference_huang.hpp, brute-force Monte Carlo over the
//     section and every microfacet normal, 2·10⁵ paths per pair on every 8th pair (its
//     noise floor, the L1 between two independent runs, is reported beside the errors).
// Error: relative L1 of f over a fixed set of direction pairs (half wi uniform on the
// sphere, half drawn by the full model's sampler so the peaks are covered), in all three
// colour channels: Σ|f - f_ref| / Σ|f_ref|. Furnace: ∫ f dωi of a lossless fiber by a
// 256 × 512 Gauss–Legendre product rule in (sinθi, φ), at θo = 0°, 40°, 80°, 89°
// (near-field models also at h = -0.6, 0, 0.9); the worst |∫ f dωi - 1| is reported
// (dropping lobes drops their energy, and Marschner's model is not normalised: the
// deviation is a figure, not a test).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include <hairscatter/hairscatter.hpp>
#include <hairscatter/math/quadrature.hpp>

#include "reference/calibration.hpp"
#include "reference/inputs.hpp"
#include "reference/pbrt_style.hpp"
#include "support/reference_chiang.hpp"
#include "support/reference_farfield.hpp"
#include "support/reference_huang.hpp"

namespace hs = hairscatter;

namespace {

constexpr std::size_t kPairs = 1024;  // a power of two: inputs are cycled with a mask
constexpr std::size_t kMask = kPairs - 1;

// The material of the study: medium roughness, a 2° tilt, brown hair.
hs::FiberParams<double> study_params(bool lossless) {
    hs::FiberParams<double> p;
    p.eta = 1.55;
    p.beta_m = 0.3;
    p.beta_n = 0.3;
    p.alpha = hs::radians(2.0);
    p.sigma_a = lossless ? glm::dvec3(0.0) : hs::sigma_a_from_concentrations(0.8, 0.0);
    return p;
}

template <typename T> hs::FiberParams<T> cast(const hs::FiberParams<double>& p) {
    hs::FiberParams<T> r;
    r.eta = T(p.eta);
    r.beta_m = T(p.beta_m);
    r.beta_n = T(p.beta_n);
    r.alpha = T(p.alpha);
    r.sigma_a = glm::vec<3, T>(p.sigma_a);
    return r;
}

ref::Params ref_params(const hs::FiberParams<double>& p) {
    ref::Params r;
    r.eta = p.eta;
    r.beta_m = p.beta_m;
    r.beta_n = p.beta_n;
    r.alpha = p.alpha;
    r.sigma_a = p.sigma_a;
    return r;
}

// The fixed inputs: (wo, wi, h, u) in double; each setting converts them once.
struct Inputs {
    std::vector<glm::dvec3> wo, wi;
    std::vector<glm::dvec4> u;
    std::vector<double> h;
    Inputs() {
        std::mt19937_64 rng(20261122);
        std::uniform_real_distribution<double> uni(0, 1);
        const hs::ChiangMaterial<double> mat(study_params(false));
        auto sphere = [&] {
            const double z = 2 * uni(rng) - 1, a = 2 * ref::kPi * uni(rng), r = std::sqrt(1 - z * z);
            return glm::dvec3(z, r * std::cos(a), r * std::sin(a));
        };
        for (std::size_t i = 0; i < kPairs; ++i) {
            wo.push_back(sphere());
            h.push_back(2 * uni(rng) - 1);
            const double a = uni(rng), b = uni(rng), c = uni(rng), d = uni(rng);
            u.emplace_back(a, b, c, d);
            if (i % 2 == 0) {
                wi.push_back(sphere());
            } else {
                const double e = uni(rng), f = uni(rng), g = uni(rng), k = uni(rng);
                wi.push_back(hs::ChiangFiber<double>(mat, h.back()).sample(wo.back(), glm::dvec4(e, f, g, k)).wi);
            }
        }
    }
};
const Inputs& inputs() {
    static const Inputs in;
    return in;
}

// A setting's shading calls over the cycled inputs in its working type T. Fiber is any
// model with eval(wo, wi), pdf(wo, wi) and sample(wo, u); make(h) builds the one for an
// offset h (far-field models ignore h).
template <typename T, typename Fiber> struct Shader {
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    std::function<Fiber(T, const V3&)> make;
    std::vector<Fiber> fibers;
    std::vector<V3> wo, wi;
    std::vector<V4> u;

    explicit Shader(std::function<Fiber(T, const V3&)> m) : make(std::move(m)) {
        const Inputs& in = inputs();
        for (std::size_t i = 0; i < kPairs; ++i) {
            fibers.push_back(make(T(in.h[i]), V3(in.wo[i])));
            wo.push_back(V3(in.wo[i]));
            wi.push_back(V3(in.wi[i]));
            u.push_back(V4(in.u[i]));
        }
    }
    glm::dvec3 f(double h, const glm::dvec3& o, const glm::dvec3& i) const {
        return glm::dvec3(make(T(h), V3(o)).eval(V3(o), V3(i)));
    }
};

// The model's reference family.
enum class Family { kNearField, kFarField, kMarschner, kHuang };

const char* family_name(Family f) {
    return f == Family::kNearField ? "near field"
           : f == Family::kFarField ? "far field"
           : f == Family::kMarschner ? "Marschner 16 nodes"
                                     : "Huang brute force";
}

// Huang et al. 2022's fiber in the study: the study material's η, α and σa, its βm as the
// microfacet roughness, a round section (the other models' shape).
template <typename T> hs::HuangParams<T> huang_params(const hs::FiberParams<T>& p) {
    hs::HuangParams<T> h;
    h.eta = p.eta;
    h.roughness = p.beta_m;
    h.alpha = p.alpha;
    h.sigma_a = p.sigma_a;
    return h;
}
// The Huang reference is Monte Carlo (0.5 s per pair): every kHuangStride-th pair only.
constexpr std::size_t kHuangStride = 8;
constexpr int kHuangPaths = 200000;

// Marschner's model in the study: the study material's η, σa and βn with the paper's own
// α_R = -7.5°, β_R = 7.5° (its Table 1; its lobes are not parameterised by βm).
template <typename T> hs::MarschnerParams<T> marschner_params(const hs::FiberParams<T>& p) {
    hs::MarschnerParams<T> m;
    m.eta = p.eta;
    m.sigma_a = p.sigma_a;
    m.beta_n = p.beta_n;
    return m;
}

struct Result {
    std::string name, model, knob, precision;
    Family family = Family::kNearField;
    double eval_ns = 0, pdf_ns = 0, sample_ns = 0;
    double rel_l1 = 0, furnace_dev = 0, furnace_min = 0, furnace_max = 0;
};

std::vector<Result>& results() {
    static std::vector<Result> r;
    return r;
}

ref_huang::Params huang_reference_params() { return ref_huang::params_of(huang_params(study_params(false))); }
// The reference with the model's residual profile and azimuth (reference_huang.hpp,
// residual_density and residual_azimuth).
ref_huang::Reference huang_reference() {
    ref_huang::Reference r{huang_reference_params()};
    const auto mat = std::make_shared<const hs::HuangMaterial<double>>(huang_params(study_params(false)));
    r.residual_density = [mat](double sin_i, double sin_o) { return double(mat->residual_density(sin_o, sin_i)); };
    r.residual_azimuth = [mat](const glm::dvec3& wo_f, const glm::dvec3& wi_f) {
        const glm::dvec3 v = mat->section().to_section(wo_f);
        return double(mat->residual_azimuth_density(wo_f.x, std::atan2(v.z, v.y), hs::relative_azimuth(wo_f, wi_f)));
    };
    return r;
}

// Reference values of f at the inputs, once per family (the far-field one takes seconds).
const std::vector<glm::dvec3>& reference(Family family) {
    static std::map<Family, std::vector<glm::dvec3>> cache;
    auto it = cache.find(family);
    if (it != cache.end()) return it->second;
    const Inputs& in = inputs();
    const ref::Params p = ref_params(study_params(false));
    std::vector<glm::dvec3> f;
    if (family == Family::kNearField) {
        for (std::size_t i = 0; i < kPairs; ++i) f.push_back(ref::Model{p, in.h[i]}.f(in.wo[i], in.wi[i]));
    } else if (family == Family::kFarField) {
        const ref::FarFieldReference r{p};
        for (std::size_t i = 0; i < kPairs; ++i) f.push_back(r.f(in.wo[i], in.wi[i]));
    } else if (family == Family::kHuang) {
        const ref_huang::Reference r = huang_reference();
        std::mt19937_64 rng(29);
        for (std::size_t i = 0; i < kPairs; ++i)
            f.push_back(i % kHuangStride == 0 ? r.f(in.wo[i], in.wi[i], kHuangPaths, rng) : glm::dvec3(0.0));
    } else {
        // Marschner's model is its own reference: double, the most roughness nodes.
        const hs::MarschnerMaterial<double> mat(marschner_params(study_params(false)),
                                                hs::MarschnerMaterial<double>::kMaxNodes);
        const hs::MarschnerFiber<double> fiber(mat);
        for (std::size_t i = 0; i < kPairs; ++i) f.push_back(fiber.eval(in.wo[i], in.wi[i]));
    }
    return cache.emplace(family, std::move(f)).first->second;
}

template <typename S> double relative_l1(const S& s, Family family) {
    const Inputs& in = inputs();
    const std::vector<glm::dvec3>& ref_f = reference(family);
    double num = 0, den = 0;
    for (std::size_t i = 0; i < kPairs; ++i) {
        if (family == Family::kHuang && i % kHuangStride != 0) continue;
        const glm::dvec3 f = s.f(in.h[i], in.wo[i], in.wi[i]);
        for (int c = 0; c < 3; ++c) {
            num += std::abs(f[c] - ref_f[i][c]);
            den += std::abs(ref_f[i][c]);
        }
    }
    return num / den;
}

// ∫ f dωi = ∫∫ f d(sinθi) dφ (f has the cosine inside), Gauss–Legendre on 16 panels in
// sinθi and 32 in φ, 16 nodes each; returns the channel mean.
template <typename S> double furnace(const S& s, double h, const glm::dvec3& wo) {
    static const hs::GaussLegendre<double> gl(16);
    double total = 0;
    for (int a = 0; a < 16; ++a)
        for (int i = 0; i < 16; ++i) {
            const double sin_i = -1 + (a + 0.5 * (gl.nodes[std::size_t(i)] + 1)) * (2.0 / 16);
            const double wsin = gl.weights[std::size_t(i)] * (1.0 / 16);
            const double cos_i = std::sqrt(std::max(0.0, 1 - sin_i * sin_i));
            for (int b = 0; b < 32; ++b)
                for (int j = 0; j < 16; ++j) {
                    const double phi = -ref::kPi + (b + 0.5 * (gl.nodes[std::size_t(j)] + 1)) * (2 * ref::kPi / 32);
                    const double w = wsin * gl.weights[std::size_t(j)] * (ref::kPi / 32);
                    const glm::dvec3 wi(sin_i, cos_i * std::cos(phi), cos_i * std::sin(phi));
                    const glm::dvec3 f = s.f(h, wo, wi);
                    total += w * (f.x + f.y + f.z) / 3;
                }
        }
    return total;
}

// Google Benchmark: eval, pdf and sample of the setting, each over the cycled inputs.
template <typename S> void register_timings(const std::string& name, std::shared_ptr<const S> s) {
    auto reg = [&](const std::string& what, auto call) {
        benchmark::RegisterBenchmark((name + "/" + what).c_str(), [s, call](benchmark::State& state) {
            std::size_t i = 0;
            for (auto _ : state) {
                auto r = call(*s, i);
                benchmark::DoNotOptimize(r);
                i = (i + 1) & kMask;
            }
        });
    };
    reg("eval", [](const S& x, std::size_t i) { return x.fibers[i].eval(x.wo[i], x.wi[i]); });
    reg("pdf", [](const S& x, std::size_t i) { return x.fibers[i].pdf(x.wo[i], x.wi[i]); });
    reg("sample", [](const S& x, std::size_t i) { return x.fibers[i].sample(x.wo[i], x.u[i]); });
}

// One setting: a shader over the study material (error and timings) and one over its
// lossless twin (furnace).
template <typename T, typename Fiber>
void add(const std::string& model, const std::string& knob, Family family,
         const std::function<std::function<Fiber(T, const glm::vec<3, T>&)>(const hs::FiberParams<T>&)>& factory,
         bool quick) {
    Result r;
    r.model = model;
    r.knob = knob;
    r.precision = sizeof(T) == 4 ? "float" : "double";
    r.family = family;
    r.name = model + " " + knob + " " + r.precision;
    using S = Shader<T, Fiber>;
    const auto s = std::make_shared<const S>(factory(cast<T>(study_params(false))));
    r.rel_l1 = relative_l1(*s, family);
    const S lossless(factory(cast<T>(study_params(true))));
    r.furnace_min = 1e300;
    r.furnace_max = -1e300;
    const std::vector<double> hs_ = family == Family::kNearField ? std::vector<double>{-0.6, 0.0, 0.9}
                                                                   : std::vector<double>{0.0};
    for (double theta_deg : {0.0, 40.0, 80.0, 89.0}) {
        // Huang's eval walks every path (µs): its furnace at 40° only.
        if ((quick && theta_deg > 0) || (family == Family::kHuang && theta_deg != 40.0)) continue;
        const double t = theta_deg * ref::kPi / 180;
        const glm::dvec3 wo(std::sin(t), std::cos(t) * std::cos(0.3), std::cos(t) * std::sin(0.3));
        for (double h : hs_) {
            const double e = furnace(lossless, h, wo);
            r.furnace_min = std::min(r.furnace_min, e);
            r.furnace_max = std::max(r.furnace_max, e);
            r.furnace_dev = std::max(r.furnace_dev, std::abs(e - 1));
        }
    }
    std::fprintf(stderr, "tradeoff: %-40s rel L1 %.3g, furnace %.5f–%.5f\n", r.name.c_str(), r.rel_l1,
                 r.furnace_min, r.furnace_max);
    register_timings<S>(r.name, s);
    results().push_back(r);
}

// ---- the settings ----------------------------------------------------------------------

template <typename T, hairscatter::LobeSet kSet> void add_chiang(const std::string& knob, bool quick) {
    using Fiber = hs::BasicChiangFiber<T, kSet>;
    add<T, Fiber>("chiang", knob, Family::kNearField,
                  [](const hs::FiberParams<T>& p) {
                      const hs::ChiangMaterial<T> mat(p);
                      return std::function<Fiber(T, const glm::vec<3, T>&)>([mat](T h, const glm::vec<3, T>&) { return Fiber(mat, h); });
                  },
                  quick);
}

// pbrt-v4's algorithm (bench/reference/pbrt_style.hpp) behind the same calls: the anchor.
template <typename T> struct PbrtStyle {
    bench_ref::HairBxDF<T> bxdf;
    glm::vec<3, T> eval(const glm::vec<3, T>& wo, const glm::vec<3, T>& wi) const { return bxdf.fsum(wo, wi); }
    T pdf(const glm::vec<3, T>& wo, const glm::vec<3, T>& wi) const { return bxdf.PDF(wo, wi); }
    auto sample(const glm::vec<3, T>& wo, const glm::vec<4, T>& u) const { return bxdf.Sample_f(wo, u); }
};

template <typename T> void add_pbrt(bool quick) {
    add<T, PbrtStyle<T>>("pbrt-v4-style", "all lobes", Family::kNearField,
                         [](const hs::FiberParams<T>& p) {
                             return std::function<PbrtStyle<T>(T, const glm::vec<3, T>&)>([p](T h, const glm::vec<3, T>&) {
                                 return PbrtStyle<T>{bench_ref::HairBxDF<T>(h, p.eta, p.sigma_a, p.beta_m, p.beta_n, p.alpha)};
                             });
                         },
                         quick);
}

template <typename T> void add_far_field(int nodes, bool quick) {
    using Fiber = hs::DeonFarFieldFiber<T>;
    add<T, Fiber>("deon-farfield",
                  nodes == hs::DeonFarFieldMaterial<T>::kAutoNodes
                      ? "auto (" + std::to_string(hs::DeonFarFieldMaterial<T>::auto_nodes(T(0.3))) + ") nodes"
                      : std::to_string(nodes) + " nodes",
                  Family::kFarField,
                  [nodes](const hs::FiberParams<T>& p) {
                      const auto mat = std::make_shared<const hs::DeonFarFieldMaterial<T>>(p, nodes);
                      return std::function<Fiber(T, const glm::vec<3, T>&)>([mat](T, const glm::vec<3, T>&) { return Fiber(*mat); });
                  },
                  quick);
}

template <typename T> void add_tabulated(const std::string& knob, const hs::TabulatedOptions& o, bool quick) {
    using Fiber = hs::TabulatedFiber<T>;
    add<T, Fiber>("tabulated", knob, Family::kFarField,
                  [o](const hs::FiberParams<T>& p) {
                      const auto mat = std::make_shared<const hs::TabulatedMaterial<T>>(p, o);
                      return std::function<Fiber(T, const glm::vec<3, T>&)>([mat](T, const glm::vec<3, T>&) { return Fiber(*mat); });
                  },
                  quick);
}

// A fiber bound to its wo with at(wo) (what a renderer that evaluates a light sample and
// draws a continuation at the same hit uses): eval / pdf / sample take wi or u only.
template <typename At> struct BoundAt {
    At at;
    template <typename V3> auto eval(const V3&, const V3& wi) const { return at.eval(wi); }
    template <typename V3> auto pdf(const V3&, const V3& wi) const { return at.pdf(wi); }
    template <typename V3, typename V4> auto sample(const V3&, const V4& u) const { return at.sample(u); }
};

template <typename T> void add_tabulated_bound(const std::string& knob, const hs::TabulatedOptions& o, bool quick) {
    using Fiber = BoundAt<typename hs::TabulatedFiber<T>::At>;
    add<T, Fiber>("tabulated", knob + " + at(wo)", Family::kFarField,
                  [o](const hs::FiberParams<T>& p) {
                      const auto mat = std::make_shared<const hs::TabulatedMaterial<T>>(p, o);
                      return std::function<Fiber(T, const glm::vec<3, T>&)>(
                          [mat](T, const glm::vec<3, T>& wo) { return Fiber{hs::TabulatedFiber<T>(*mat).at(wo)}; });
                  },
                  quick);
}

template <typename T> void add_chiang_bound(bool quick) {
    using Fiber = BoundAt<typename hs::ChiangFiber<T>::At>;
    add<T, Fiber>("chiang", "all lobes + at(wo)", Family::kNearField,
                  [](const hs::FiberParams<T>& p) {
                      const hs::ChiangMaterial<T> mat(p);
                      return std::function<Fiber(T, const glm::vec<3, T>&)>(
                          [mat](T h, const glm::vec<3, T>& wo) { return Fiber{hs::ChiangFiber<T>(mat, h).at(wo)}; });
                  },
                  quick);
}

std::string table_knob(const char* name, const hs::TabulatedOptions& o) {
    return std::string(name) + " " + std::to_string(o.phi_samples) + "x" + std::to_string(o.theta_samples);
}

template <typename T> void add_marschner(int nodes, bool quick) {
    using Fiber = hs::MarschnerFiber<T>;
    add<T, Fiber>("marschner", std::to_string(nodes) + " nodes", Family::kMarschner,
                  [nodes](const hs::FiberParams<T>& p) {
                      const auto mat = std::make_shared<const hs::MarschnerMaterial<T>>(marschner_params(p), nodes);
                      return std::function<Fiber(T, const glm::vec<3, T>&)>([mat](T, const glm::vec<3, T>&) { return Fiber(*mat); });
                  },
                  quick);
}

// Huang at the quadrature (offset nodes, TT points, internal normals per TT path; 0 = auto).
template <typename T> void add_huang(int nodes, int tt, int per_tt, bool quick) {
    using Fiber = hs::HuangFiber<T>;
    using M = hs::HuangMaterial<T>;
    hs::HuangQuadrature q;
    q.offset_nodes = nodes;
    q.tt_points = tt;
    q.trt_per_tt = per_tt;
    const hs::HuangMaterial<double> probe(huang_params(study_params(false)), q);  // the resolved counts, for the knob's name
    const bool is_default = nodes == 0 && tt == 0 && per_tt == 0;
    add<T, Fiber>("huang",
                  std::to_string(probe.nodes()) + " / " + std::to_string(probe.tt_points()) + " × " +
                      std::to_string(probe.trt_per_tt()) + (is_default ? " (default)" : ""),
                  Family::kHuang,
                  [q](const hs::FiberParams<T>& p) {
                      const auto mat = std::make_shared<const M>(huang_params(p), q);
                      return std::function<Fiber(T, const glm::vec<3, T>&)>([mat](T, const glm::vec<3, T>&) { return Fiber(*mat); });
                  },
                  quick);
}

// The Huang reference's noise floor: the relative L1 between two independent runs.
double huang_noise_floor() {
    const Inputs& in = inputs();
    const std::vector<glm::dvec3>& a = reference(Family::kHuang);
    const ref_huang::Reference r = huang_reference();
    std::mt19937_64 rng(31);
    double num = 0, den = 0;
    for (std::size_t i = 0; i < kPairs; i += kHuangStride) {
        const glm::dvec3 b = r.f(in.wo[i], in.wi[i], kHuangPaths, rng);
        for (int c = 0; c < 3; ++c) {
            num += std::abs(b[c] - a[i][c]);
            den += std::abs(a[i][c]);
        }
    }
    return num / den;
}

void add_settings(bool quick) {
    using hs::LobeSet;
    add_chiang<float, LobeSet::kAll>("all lobes", quick);
    add_chiang<double, LobeSet::kAll>("all lobes", quick);
    add_chiang<float, LobeSet::kPrimary>("R+TT+TRT", quick);
    add_chiang<float, LobeSet::kR | LobeSet::kTT>("R+TT", quick);
    add_chiang<float, LobeSet::kR>("R only", quick);
    add_chiang_bound<float>(quick);
    add_pbrt<float>(quick);
    for (int n : {4, 8, 16, 32, 64}) add_far_field<float>(n, quick);
    add_far_field<double>(64, quick);
    add_far_field<float>(hs::DeonFarFieldMaterial<float>::kAutoNodes, quick);
    add_tabulated<float>(table_knob("coarse", hs::TabulatedOptions::coarse()), hs::TabulatedOptions::coarse(), quick);
    add_tabulated<float>(table_knob("default", hs::TabulatedOptions()), hs::TabulatedOptions(), quick);
    add_tabulated<float>(table_knob("fine", hs::TabulatedOptions::fine()), hs::TabulatedOptions::fine(), quick);
    add_tabulated<double>(table_knob("default", hs::TabulatedOptions()), hs::TabulatedOptions(), quick);
    add_tabulated<float>("fast (M table)", hs::TabulatedOptions::fast(), quick);
    add_tabulated_bound<float>(table_knob("default", hs::TabulatedOptions()), hs::TabulatedOptions(), quick);
    add_tabulated_bound<float>("fast (M table)", hs::TabulatedOptions::fast(), quick);
    for (int n : {1, 3, 7, 16}) add_marschner<float>(n, quick);
    add_marschner<double>(7, quick);
    add_huang<float>(4, 4, 1, quick);
    add_huang<float>(0, 16, 2, quick);
    add_huang<float>(0, 32, 2, quick);
    add_huang<float>(0, 0, 0, quick);
    add_huang<float>(0, 64, 4, quick);
    add_huang<float>(0, 128, 4, quick);
    add_huang<double>(0, 0, 0, quick);
}

// Collects the medians (CPU time, ns) of every benchmark by name.
class Collector : public benchmark::ConsoleReporter {
  public:
    std::map<std::string, double> median_ns;
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& run : runs)
            if (run.run_type == Run::RT_Aggregate && run.aggregate_name == "median")
                median_ns[run.run_name.function_name] = run.GetAdjustedCPUTime();
        ConsoleReporter::ReportRuns(runs);
    }
};

}  // namespace

#ifndef HAIRSCATTER_BENCH_FLAGS_STRING
#define HAIRSCATTER_BENCH_FLAGS_STRING "(unknown)"
#endif

int main(int argc, char** argv) {
    std::string out = ".";
    bool quick = false;
    std::vector<char*> args{argv[0]};
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--out" && i + 1 < argc) out = argv[++i];
        else if (a == "--quick") quick = true;
        else args.push_back(argv[i]);
    }
    int n = int(args.size());
    benchmark::Initialize(&n, args.data());
    if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;

    // The calibration loop exactly as bench/chiang_bench.cpp runs it (same inputs).
    benchmark::RegisterBenchmark("calibration/float", [](benchmark::State& state) {
        const auto& in = bench_ref::inputs<float>();
        std::size_t i = 0;
        for (auto _ : state) {
            float r = bench_ref::calibration_body(in.calib_a[i], in.calib_b[i]);
            benchmark::DoNotOptimize(r);
            i = (i + 1) & bench_ref::kCalibMask;
        }
    });
    add_settings(quick);

    Collector collector;
    benchmark::RunSpecifiedBenchmarks(&collector);
    benchmark::Shutdown();

    const double unit = collector.median_ns["calibration/float"];
    if (!(unit > 0)) {
        std::fprintf(stderr, "tradeoff: no median for the calibration loop (run with --benchmark_repetitions=3 or more)\n");
        return 1;
    }
    for (Result& r : results()) {
        r.eval_ns = collector.median_ns[r.name + "/eval"];
        r.pdf_ns = collector.median_ns[r.name + "/pdf"];
        r.sample_ns = collector.median_ns[r.name + "/sample"];
    }

    std::ofstream csv(out + "/tradeoff.csv");
    csv << "model,knob,precision,reference,eval_ns,pdf_ns,sample_ns,eval_u,rel_l1,furnace_dev,furnace_min,furnace_max\n";
    // A text field as RFC 4180 wants it: quoted (quotes doubled) if it holds a comma, a quote
    // or a line break. (A knob once held a comma unquoted, which shifted its row's columns
    // for every reader, the plot included; the labels now avoid commas, and this keeps any
    // later one from doing that again.)
    const auto field = [](const std::string& f) {
        if (f.find_first_of(",\"\n\r") == std::string::npos) return f;
        std::string q = "\"";
        for (char c : f) q += c == '"' ? std::string("\"\"") : std::string(1, c);
        return q + "\"";
    };
    for (const Result& r : results())
        csv << field(r.model) << ',' << field(r.knob) << ',' << field(r.precision) << ','
            << field(family_name(r.family)) << ',' << r.eval_ns << ',' << r.pdf_ns
            << ',' << r.sample_ns << ',' << r.eval_ns / unit << ',' << r.rel_l1 << ',' << r.furnace_dev << ','
            << r.furnace_min << ',' << r.furnace_max << '\n';

    const double huang_floor = huang_noise_floor();
    std::ofstream md(out + "/tradeoff_table.md");
    char line[512];
    std::snprintf(line, sizeof line, "Calibration unit u = %.1f ns (float loop of bench/reference/calibration.hpp). Flags: %s.\n\n",
                  unit, HAIRSCATTER_BENCH_FLAGS_STRING);
    md << line;
    md << "| model | knob | type | reference | eval ns (u) | pdf ns | sample ns | rel. L1 error of f | furnace ∫f dω (worst) |\n";
    md << "|---|---|---|---|---|---|---|---|---|\n";
    for (const Result& r : results()) {
        std::snprintf(line, sizeof line, "| %s | %s | %s | %s | %.1f (%.2f) | %.1f | %.1f | %.2e | %.5f–%.5f |\n",
                      r.model.c_str(), r.knob.c_str(), r.precision.c_str(),
                      family_name(r.family), r.eval_ns, r.eval_ns / unit,
                      r.pdf_ns, r.sample_ns, r.rel_l1, r.furnace_min, r.furnace_max);
        md << line;
    }
    std::snprintf(line, sizeof line,
                  "\nThe Huang reference's own noise (relative L1 between two independent runs): %.2e.\n", huang_floor);
    md << line;
    std::fprintf(stderr, "tradeoff: wrote %s/tradeoff.csv and %s/tradeoff_table.md\n", out.c_str(), out.c_str());
    return 0;
}
