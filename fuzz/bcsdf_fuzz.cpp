// libFuzzer target: Huang's elliptical fiber and the dual-scattering BCSDF, float and double
// for Huang, float for the dual BCSDF (the renderers' precision).
//   - Huang: parameters and lobe controls from the bytes (raw floats, or mapped into their
//     ranges so that valid ones are common) → HuangMaterial with a small quadrature → the
//     contract's calls (fuzz_support.hpp). The material is built exactly when validate()
//     returns "" for the parameters and the controls and no tilt override is set.
//   - Dual: three fixed table sets built once (Chiang blond and improved, Chiang dark and
//     Zinke 2008's formulation, Huang elliptical), or small tables built from a Chiang
//     material and settings read from the bytes; the fiber's h, wo, wi, u, the sampler's
//     spread hint and the light state (any float: NaN, Inf, negative counts, a broken T_f)
//     from the bytes. Checked: eval, pdf, at(wo).eval/pdf/sample and sample are finite and
//     non-negative for finite unit directions and any light; a non-finite wo or wi gives 0.
// A violation aborts (libFuzzer reports it with the input).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>

#include <hairscatter/dual.hpp>
#include <hairscatter/hairscatter.hpp>

#include "fuzz_support.hpp"

namespace hs = hairscatter;

namespace {

using fuzz::check;
using fuzz::non_negative;
using fuzz::Reader;

// Huang's quadrature kept small for speed (the rules' sizes do not change the code paths).
const hs::HuangQuadrature kQuadrature{8, 16, 2};

// A Huang material takes ~40 ms to build (its reflectance tables), so the valid ones are
// kept, by the bytes they were read from, for the inputs that share them (mutations mostly
// change the directions): the results are the same, only faster.
template <typename T> const hs::HuangMaterial<T>& huang_material(const std::string& key, const hs::HuangParams<T>& p,
                                                                 const hs::LobeControls<T>& c) {
    static std::map<std::string, std::unique_ptr<const hs::HuangMaterial<T>>> cache;
    auto it = cache.find(key);
    if (it != cache.end()) return *it->second;
    if (cache.size() >= 512) cache.clear();
    auto m = std::make_unique<const hs::HuangMaterial<T>>(p, kQuadrature, c);  // throws before it is kept
    return *cache.emplace(key, std::move(m)).first->second;
}

template <typename T> void run_huang(Reader& r, std::uint8_t mode) {
    const bool mapped = (mode & 8u) != 0u;
    const std::uint8_t* start = r.p;
    auto value = [&](T lo, T hi) { return r.parameter<T>(lo, hi, mapped); };
    hs::HuangParams<T> p;
    p.eta = value(T(1), T(3));
    p.roughness = value(hs::kMinHuangRoughness<T>, T(1));
    p.alpha = value(-hs::kMaxCuticleTilt<T>, hs::kMaxCuticleTilt<T>);
    for (int c = 0; c < 3; ++c) p.sigma_a[c] = value(T(0), T(20));
    p.aspect_ratio = value(hs::kMinAspectRatio<T>, T(1));
    p.orientation = value(-hs::kPi<T>, hs::kPi<T>);
    hs::LobeControls<T> c = fuzz::read_controls<T>(r, mode);
    if (mapped) c.alpha_override = 0u;
    const std::string key = std::string(1, char(mode)) + std::string(reinterpret_cast<const char*>(start), std::size_t(r.p - start));
    const bool valid = hs::validate(p).empty() && hs::validate(c).empty() && c.alpha_override == 0u;
    try {
        const hs::HuangMaterial<T>& m = huang_material<T>(key, p, c);
        check(valid);
        fuzz::exercise<T>(hs::HuangFiber<T>(m), r);
    } catch (const std::invalid_argument&) {
        check(!valid);
    }
}

// The fixed materials and their tables, each built on its first use. Building dual tables
// evaluates the fiber often: Huang's gets the smallest quadrature (0.7 s at -O1, a few
// seconds under the sanitizers; its rules' sizes do not change the BCSDF's code paths).
hs::FiberParams<float> chiang_params(float sigma, float beta_m, float beta_n) {
    hs::FiberParams<float> p;
    p.beta_m = beta_m;
    p.beta_n = beta_n;
    p.sigma_a = glm::vec3(sigma, 1.6f * sigma, 3.2f * sigma);
    return p;
}
hs::DualTableOptions<float> table_options(hs::DualScatteringSettings<float> s) {
    hs::DualTableOptions<float> o;
    o.theta_samples = 8;
    o.psi_samples = 9;
    o.h_nodes = 8;
    o.settings = s;
    return o;
}
template <typename Material, typename Fiber> struct DualSet {
    Material material;
    hs::DualScatteringTables<float> tables;
    template <typename Params, typename... Extra>
    DualSet(hs::DualScatteringSettings<float> s, const Params& p, const Extra&... extra)
        : material(p, extra...), tables(hs::DualScatteringTables<float>::build<Fiber>(material, table_options(s))) {}
};
using ChiangSet = DualSet<hs::ChiangMaterial<float>, hs::ChiangFiber<float>>;
using HuangSet = DualSet<hs::HuangMaterial<float>, hs::HuangFiber<float>>;

const ChiangSet& blond_set() {
    static const ChiangSet s(hs::DualScatteringSettings<float>::improved(), chiang_params(0.05f, 0.3f, 0.3f));
    return s;
}
const ChiangSet& dark_set() {
    static const ChiangSet s(hs::DualScatteringSettings<float>::zinke2008(), chiang_params(2.0f, 0.05f, 0.9f));
    return s;
}
const HuangSet& huang_set() {
    static const HuangSet s = [] {
        hs::HuangParams<float> p;
        p.sigma_a = glm::vec3(0.2f, 0.4f, 0.8f);
        p.aspect_ratio = 0.6f;
        p.orientation = 0.4f;
        return HuangSet(hs::DualScatteringSettings<float>::improved(), p, hs::HuangQuadrature{4, 4, 1});
    }();
    return s;
}

hs::DualScatteringLight<float> read_light(Reader& r) {
    hs::DualScatteringLight<float> l;
    const std::uint8_t bits = r.byte();
    l.direct_fraction = (bits & 1u) ? r.next() : r.unit<float>();
    // Bit 128: counts up to 1e7 (log-uniform), with the large gains of read_controls.
    l.n = (bits & 2u) ? r.next() : ((bits & 128u) ? std::pow(10.0f, 7.0f * r.unit<float>()) : 20.0f * r.unit<float>());
    l.beyond = (bits & 4u) ? r.next() : ((bits & 8u) ? hs::kUnbounded<float> : 20.0f * r.unit<float>());
    l.use_transmittance = (bits & 16u) != 0u;
    if (l.use_transmittance) {
        l.T_f = (bits & 32u) ? glm::vec3(r.next(), r.next(), r.next())
                             : glm::vec3(r.unit<float>(), r.unit<float>(), r.unit<float>());
        l.sigma2_f = (bits & 64u) ? r.next() : r.unit<float>();
    }
    return l;
}

template <typename Fiber> void exercise_dual(const Fiber& fiber, const hs::DualScatteringTables<float>& tables,
                                             Reader& r) {
    using V3 = glm::vec3;
    using V4 = glm::vec4;
    const hs::DualScatteringBcsdf<Fiber> d(fiber, tables);
    for (int k = 0; k < 3; ++k) {
        V3 wo(r.next(), r.next(), r.next()), wi(r.next(), r.next(), r.next());
        V4 u(r.next(), r.next(), r.next(), r.next());
        const float spread = r.byte() & 1u ? r.next() : r.unit<float>();
        const hs::DualScatteringLight<float> light = read_light(r);
        const bool directions = hs::is_finite(wo) && hs::is_finite(wi);
        const bool proper = fuzz::make_proper(wo, wi, u);
        const V3 f = d.eval(wo, wi, light);
        const float pdf = d.pdf(wo, wi);
        const hs::DualSample<float> s = d.sample(wo, u);
        const auto at = d.at(wo, spread);
        const V3 fa = at.eval(wi, light);
        const float pa = at.pdf(wi);
        const hs::DualSample<float> sa = at.sample(u);
        if (!directions) {
            check(f == V3(0.0f) && pdf == 0.0f && fa == V3(0.0f) && pa == 0.0f);
        } else if (proper) {
            check(non_negative(f) && non_negative(fa));
            check(hs::is_finite(pdf) && pdf >= 0.0f && hs::is_finite(pa) && pa >= 0.0f);
            check(hs::is_finite(s.pdf) && s.pdf >= 0.0f && hs::is_finite(s.wi));
            check(hs::is_finite(sa.pdf) && sa.pdf >= 0.0f && hs::is_finite(sa.wi));
        }
        if (!hs::is_finite(wo)) check(s.pdf == 0.0f && sa.pdf == 0.0f);
    }
}

// Dual tables built from the bytes: a Chiang material (parameters raw or mapped into their
// ranges, lobe controls) and the settings (formulation, d_f, d_b: raw or in [0, 1]). Built
// exactly when the parameters, controls and settings are valid; then the BCSDF's calls.
void run_dual_built(Reader& r, std::uint8_t mode) {
    const bool mapped = (mode & 8u) != 0u;
    auto value = [&](float lo, float hi) { return r.parameter<float>(lo, hi, mapped); };
    hs::FiberParams<float> p;
    p.eta = value(1.0f, 3.0f);
    p.beta_m = value(hs::kMinRoughness<float>, 1.0f);
    p.beta_n = value(hs::kMinRoughness<float>, 1.0f);
    p.alpha = value(-hs::kMaxCuticleTilt<float>, hs::kMaxCuticleTilt<float>);
    for (int c = 0; c < 3; ++c) p.sigma_a[c] = value(0.0f, 20.0f);
    const hs::LobeControls<float> c = fuzz::read_controls<float>(r, mode);
    hs::DualScatteringSettings<float> s;
    const std::uint8_t f = r.byte();
    s.formulation = hs::DualFormulation(mapped ? f % 2 : f);
    s.d_f = value(0.0f, 1.0f);
    s.d_b = value(0.0f, 1.0f);
    const bool settings_ok = (s.formulation == hs::DualFormulation::kImproved ||
                              s.formulation == hs::DualFormulation::kZinke2008) &&
                             hs::is_finite(s.d_f) && s.d_f >= 0.0f && s.d_f <= 1.0f && hs::is_finite(s.d_b) &&
                             s.d_b >= 0.0f && s.d_b <= 1.0f;
    const bool valid = hs::validate(p).empty() && hs::validate(c).empty() && settings_ok;
    try {
        const hs::ChiangMaterial<float> m(p, c);
        const auto tables = hs::DualScatteringTables<float>::build<hs::ChiangFiber<float>>(m, table_options(s));
        check(valid);
        exercise_dual(hs::ChiangFiber<float>(m, r.offset<float>()), tables, r);
    } catch (const std::invalid_argument&) {
        check(!valid);
    }
}

void run_dual(Reader& r, std::uint8_t which) {
    if (which % 3 == 2) {
        exercise_dual(hs::HuangFiber<float>(huang_set().material), huang_set().tables, r);
        return;
    }
    const float h = r.offset<float>();
    const ChiangSet& set = which % 3 == 0 ? blond_set() : dark_set();
    exercise_dual(hs::ChiangFiber<float>(set.material, h), set.tables, r);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    Reader r{data, size};
    const std::uint8_t sel = r.byte();
    const std::uint8_t mode = r.byte();
    switch (sel % 3) {
        case 0: run_huang<float>(r, mode); break;
        case 1: run_huang<double>(r, mode); break;
        default:
            if ((sel / 3) % 4 == 3)
                run_dual_built(r, mode);
            else
                run_dual(r, mode);
            break;
    }
    return 0;
}
