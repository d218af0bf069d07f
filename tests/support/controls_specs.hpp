// The lobe controls (lobes/lobe_controls.hpp) on every model that takes them: one adapter
// per model (how to build its material with or without controls, a parameter set from
// d'Eon-style βm, βn, α, σa, its random and extreme parameters) over the model's own spec
// (model_specs.hpp), and ControlsSpec<Adapter>, the contract suite's spec of the model with
// random gains, tints and tilt overrides; HuangControlsSpec, Huang's with gains and tints.
// tests/controls_test.cpp uses the adapters, tests/contract/*.cpp instantiate
// the suite with these specs.
#pragma once

#include <algorithm>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <hairscatter/hairscatter.hpp>

#include "model_specs.hpp"

namespace specs {

// Adapter interface (Base: the model's spec, for its tolerances, chi-square options and
// invalid parameters):
//   using Params; static constexpr bool kResidual;
//   static Params params(βm, βn, α in degrees, σa);
//   static Params random_params(rng, k); static void for_extremes(visit(params, label));
//   static std::shared_ptr<const Material> material(params, controls or nullptr, variant);
//   static Fiber fiber(material, h)      (h ignored by the far-field models);
// `variant` picks the model's own setting (node count, table resolution) from a short list.

// The models built from FiberParams (all four lobes): BaseSpec is the model's spec,
// kMinBetaNMilli the narrowest βn of its edge cases in thousandths.
template <typename T, typename BaseSpec, int kMinBetaNMilli> struct DeonFamilyControls : BaseSpec {
    using Base = BaseSpec;
    using Params = hs::FiberParams<T>;
    static constexpr bool kResidual = true;
    static Params params(double bm, double bn, double al, glm::dvec3 sa) { return fiber_params<T>(bm, bn, al, sa); }
    static Params random_params(std::mt19937_64& rng, int k) { return specs::random_params<T>(rng, k); }
    template <typename Visit> static void for_extremes(Visit visit) {
        for_extreme_params<T>({kMinBetaNMilli * 1e-3, 1.0}, {-22.5, 22.5}, visit);
    }
};

template <typename T> struct ChiangControls : DeonFamilyControls<T, ChiangSpec<T, hs::LobeSet::kAll>, 10> {
    using Material = hs::ChiangMaterial<T>;
    using Fiber = hs::ChiangFiber<T>;
    using Params = hs::FiberParams<T>;
    static constexpr const char* kName = "Chiang";
    static std::shared_ptr<const Material> material(const Params& p, const hs::LobeControls<T>* c, int) {
        return c ? std::make_shared<const Material>(p, *c) : std::make_shared<const Material>(p);
    }
    static Fiber fiber(const Material& m, double h) { return Fiber(m, T(h)); }
};

template <typename T> struct FarFieldControls : DeonFamilyControls<T, FarFieldSpec<T>, 10> {
    using Material = hs::DeonFarFieldMaterial<T>;
    using Fiber = hs::DeonFarFieldFiber<T>;
    using Params = hs::FiberParams<T>;
    static constexpr const char* kName = "far field";
    static std::shared_ptr<const Material> material(const Params& p, const hs::LobeControls<T>* c, int variant) {
        const int nodes[5] = {8, 3, 16, 1, 5};
        const int n = nodes[variant % 5];
        return c ? std::make_shared<const Material>(p, n, *c) : std::make_shared<const Material>(p, n);
    }
    static Fiber fiber(const Material& m, double) { return Fiber(m); }
};

template <typename T> struct TabulatedControls : DeonFamilyControls<T, TabulatedSpec<T>, 1> {
    using Base = TabulatedSpec<T>;
    using Material = hs::TabulatedMaterial<T>;
    using Fiber = hs::TabulatedFiber<T>;
    using Params = hs::FiberParams<T>;
    static constexpr const char* kName = "tabulated";
    static std::shared_ptr<const Material> material(const Params& p, const hs::LobeControls<T>* c, int variant) {
        const hs::TabulatedOptions res[5] = {hs::TabulatedOptions(), hs::TabulatedOptions::coarse(), {9, 4, 3},
                                             hs::TabulatedOptions::fast(), Base::with_table({9, 4, 3})};
        const hs::TabulatedOptions& o = res[variant % 5];
        return c ? std::make_shared<const Material>(p, o, *c) : std::make_shared<const Material>(p, o);
    }
    static Fiber fiber(const Material& m, double) { return Fiber(m); }
};

template <typename T> struct MarschnerControls : MarschnerSpec<T> {
    using Base = MarschnerSpec<T>;
    using Params = hs::MarschnerParams<T>;
    using Material = hs::MarschnerMaterial<T>;
    using Fiber = hs::MarschnerFiber<T>;
    static constexpr bool kResidual = false;
    static constexpr const char* kName = "Marschner";
    // βR from 2° (βm 0) to 40° (βm 1), α_R = -2α (Marschner's relation to the scale tilt).
    static Params params(double bm, double bn, double al, glm::dvec3 sa) {
        return marschner_params<T>(2 + 38 * bm, bn, -2 * al, sa, 1.0);
    }
    static Params random_params(std::mt19937_64& rng, int k) {
        std::uniform_real_distribution<double> uni(0, 1);
        const double bm = uni(rng), bn = 0.1 + 0.9 * uni(rng), al = -5 + 10 * uni(rng), sa = (k % 2) * 2 * uni(rng);
        Params p = params(bm, bn, al, glm::dvec3(sa, 0.5 * sa, 2 * sa));
        if (k % 3 == 0) p.eccentricity = T(0.7 + 0.6 * uni(rng));
        return p;
    }
    template <typename Visit> static void for_extremes(Visit visit) {
        for (double br : {1e-4, kPi / 4})
            for (double bn : {0.01, 1.0})
                for (double sa : {0.0, 1e3})
                    for (double sign : {-1.0, 1.0}) {
                        Params p = marschner_params<T>(0, bn, 0, glm::dvec3(sa), sign > 0 ? 1.0 : 0.5);
                        p.beta_r = T(br);
                        p.alpha_r = T(sign * kPi / 6 * 0.9999);
                        visit(p, "βR " + std::to_string(br) + " βn " + std::to_string(bn) + " σa " + std::to_string(sa));
                    }
    }
    static std::shared_ptr<const Material> material(const Params& p, const hs::LobeControls<T>* c, int variant) {
        const int n = 1 + variant % 9;
        return c ? std::make_shared<const Material>(p, n, *c) : std::make_shared<const Material>(p, n);
    }
    static Fiber fiber(const Material& m, double) { return Fiber(m); }
};

// The contract suite's spec of model A with lobe controls: random gains in [0, 3] (a zero on
// some lobe on every third material), tints on R and TRT, TT's tilt overridden; the edge
// cases add gains of 0, 10⁻³⁰ and 10⁶ and every tilt at its limit; the chi-square grid has
// a zero gain on each lobe in turn. Gains break energy conservation, so the furnace checks
// ∫ eval dω against albedo(wo) only (at the model's own tolerance).
template <typename A>
struct ControlsSpec : SpecBase<typename A::Fiber, typename A::Material, std::max(A::Base::kRandomMaterials / 2, 20),
                               A::Base::kRandomDirections, false, A::kResidual> {
    using Fiber = typename A::Fiber;
    using Material = typename A::Material;
    using T = typename Fiber::Real;
    using V3 = glm::vec<3, T>;
    static constexpr double kFurnaceTolerance = A::Base::kFurnaceTolerance;
    static constexpr int kFurnaceDepth = A::Base::kFurnaceDepth;
    static constexpr double kPdfTotalTolerance = A::Base::kPdfTotalTolerance;

    // Gains g0 … g3 (the residual's only where the model has one), tints on R and TRT, and
    // TT's tilt overridden when alpha_tt_deg ≠ 0.
    static hs::LobeControls<T> controls(double g0, double g1, double g2, double g3, double alpha_tt_deg) {
        hs::LobeControls<T> c;
        const double g[4] = {g0, g1, g2, A::kResidual ? g3 : 1.0};
        for (int p = 0; p < 4; ++p) c.gain[p] = T(g[p]);
        c.tint[0] = V3(T(1), T(0.8), T(0.6));
        c.tint[2] = V3(T(0.5), T(1), T(2));
        if (alpha_tt_deg != 0) c.override_alpha(1, T(deg(alpha_tt_deg)));
        return c;
    }
    static Instance<Fiber> make(const typename A::Params& p, const hs::LobeControls<T>& c, double h, int variant,
                                std::string name) {
        const std::shared_ptr<const Material> m = A::material(p, &c, variant);
        return Instance<Fiber>{m, A::fiber(*m, h), std::string(A::kName) + " " + std::move(name)};
    }
    static Instance<Fiber> random(std::mt19937_64& rng, int k) {
        const typename A::Params p = A::random_params(rng, k);
        std::uniform_real_distribution<double> uni(0, 1);
        double g[4];
        for (double& x : g) x = 3 * uni(rng);
        g[k % 4] = k % 3 == 0 ? 0.0 : g[k % 4];  // a zero gain on every third material
        const double h = -1 + 2 * uni(rng), tilt = -10 + 20 * uni(rng);
        return make(p, controls(g[0], g[1], g[2], g[3], tilt), h, k, "random " + std::to_string(k));
    }
    static std::vector<Instance<Fiber>> extremes() {
        std::vector<Instance<Fiber>> r;
        int variant = 0;
        A::for_extremes([&](const typename A::Params& p, const std::string& l) {
            for (double g : {0.0, 1e-30, 1e6})
                for (double h : {-1.0, 0.5}) {
                    const double limit = 22.5 * 0.9999;
                    hs::LobeControls<T> c = controls(g, 1e6 - g, g, 1, limit);
                    c.override_alpha(0, T(deg(h < 0 ? -limit : limit))).override_alpha(2, T(deg(h < 0 ? limit : -limit)));
                    if (A::kResidual) c.tint[3] = V3(T(1e6), T(0), T(1e-30));
                    r.push_back(make(p, c, h, variant++, l + " gain " + std::to_string(g) + " h " + std::to_string(h)));
                }
        });
        return r;
    }
    // Zero gains on each lobe in turn, large and small gains, tints, TT's tilt overridden.
    static std::vector<Chi2Case<Fiber>> chi2_cases() {
        const glm::dvec3 sa(0.5, 0.3, 0.15);
        std::vector<Chi2Case<Fiber>> r;
        r.push_back({make(A::params(0.3, 0.3, 2, sa), controls(1, 0, 1, 1, 0), 0.1, 0, "no TT"), 30});
        r.push_back({make(A::params(0.2, 0.5, 2, sa), controls(0, 1, 1, 1, 0), -0.5, 1, "no R"), -40});
        r.push_back({make(A::params(0.1, 0.2, 2, sa), controls(1, 1, 0, 1, 0), 0.7, 2, "no TRT"), 60});
        r.push_back({make(A::params(0.5, 0.4, -2, sa), controls(2, 0.5, 1.5, 0, 8), 0.3, 3, "no residual, tilt"), 10});
        r.push_back({make(A::params(0.3, 0.3, 5, glm::dvec3(0)), controls(10, 0.1, 3, 0.5, -6), -0.9, 4, "wide"), 75});
        r.push_back({make(A::params(0.05, 0.1, 2, sa), controls(0.2, 4, 0.7, 2, 0), 0.0, 5, "sharp"), -80});
        return r;
    }
    static chi2::Options chi2_options() {
        chi2::Options o = A::Base::chi2_options();
        o.num_tests = 12;  // 6 cases × 2 precisions
        return o;
    }
    static bool may_sample(hs::SampledLobe lobe) {
        return hs::lobe_index(lobe) >= 0 && hs::lobe_index(lobe) <= (A::kResidual ? 3 : 2);
    }
    static Instance<Fiber> lossless() {
        return make(A::params(0.3, 0.3, 2, glm::dvec3(0)), controls(2, 0.5, 1.5, 0.25, 5), 0.3, 0, "lossless, gains");
    }
    // The model's own bad parameters, and bad controls, which every material rejects at
    // construction naming the field.
    static std::vector<Invalid> invalid() {
        std::vector<Invalid> r = A::Base::invalid();
        auto add = [&](const char* field, auto change) {
            hs::LobeControls<T> c;
            change(c);
            r.push_back({[c] { A::material(A::params(0.3, 0.3, 2, glm::dvec3(0.2)), &c, 0); }, field});
        };
        const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
        add("gain_r", [](hs::LobeControls<T>& c) { c.gain[0] = T(-1); });
        add("gain_tt", [nan](hs::LobeControls<T>& c) { c.gain[1] = nan; });
        add("tint_trt.g", [inf](hs::LobeControls<T>& c) { c.tint[2].g = inf; });
        add("alpha_tt", [](hs::LobeControls<T>& c) { c.override_alpha(1, T(1)); });
        add("alpha_override", [](hs::LobeControls<T>& c) { c.alpha_override = 9u; });
        if (!A::kResidual) {  // no residual lobe to weight
            add("gain_residual", [](hs::LobeControls<T>& c) { c.gain[3] = T(2); });
            add("tint_residual", [](hs::LobeControls<T>& c) { c.tint[3].b = T(0.5); });
        }
        return r;
    }
};

// Huang with random gains (a zero on some lobe) and tints: the contract suite's checks
// (chi-square with a zero gain on each lobe in turn, furnace against the scaled albedo,
// lobe split, extremes with gains 0 and 1e6).
template <typename T> struct HuangControlsSpec : HuangSpec<T> {
    using Base = HuangSpec<T>;
    using Fiber = typename Base::Fiber;
    using Material = typename Base::Material;
    using V3 = glm::vec<3, T>;
    static constexpr bool kConservesEnergy = false;

    static hs::LobeControls<T> controls(double g0, double g1, double g2, double g3) {
        hs::LobeControls<T> c;
        const double g[4] = {g0, g1, g2, g3};
        for (int p = 0; p < 4; ++p) c.gain[p] = T(g[p]);
        c.tint[0] = V3(T(1), T(0.8), T(0.6));
        c.tint[2] = V3(T(0.5), T(1), T(2));
        return c;
    }
    static Instance<Fiber> random(std::mt19937_64& rng, int k) {
        const hs::HuangParams<T> p = Base::random_params(rng, k);
        std::uniform_real_distribution<double> uni(0, 1);
        double g[4];
        for (double& x : g) x = 3 * uni(rng);
        g[k % 4] = k % 3 == 0 ? 0.0 : g[k % 4];  // a zero gain on every third material
        return Base::make(p, Base::random_quadrature(k), "random " + std::to_string(k), controls(g[0], g[1], g[2], g[3]));
    }
    static std::vector<Instance<Fiber>> extremes() {
        std::vector<Instance<Fiber>> r;
        for (double rough : {0.02, 1.0})
            for (double sa : {0.0, 50.0})
                for (double g : {0.0, 1e-30, 1e6}) {
                    hs::LobeControls<T> c = controls(g, 1e6 - g, g, 1);
                    c.tint[3] = V3(T(1e6), T(0), T(1e-30));
                    const hs::HuangParams<T> p = huang_params<T>(rough, 22.5 * 0.9999, glm::dvec3(sa), 0.5, 1.0);
                    r.push_back(Base::make(p, Base::quadrature(3, 5, 2), "gain " + std::to_string(g), c));
                }
        return r;
    }
    // Zero gains on each lobe in turn, large and small gains, tints.
    static std::vector<Chi2Case<Fiber>> chi2_cases() {
        const glm::dvec3 sa(0.5, 0.3, 0.15);
        const hs::HuangQuadrature q = Base::quadrature(5, 12, 2);
        std::vector<Chi2Case<Fiber>> r;
        r.push_back({Base::make(huang_params<T>(0.3, 2, sa, 0.8, 0.3), q, "no TT", controls(1, 0, 1, 1)), 30});
        r.push_back({Base::make(huang_params<T>(0.2, 2, sa, 0.6, -1.0), q, "no R", controls(0, 1, 1, 1)), -40});
        r.push_back({Base::make(huang_params<T>(0.5, -3, sa, 1.0, 0.0), q, "no TRT", controls(1, 1, 0, 1)), 60});
        r.push_back({Base::make(huang_params<T>(0.3, 2, glm::dvec3(0), 0.5, 2.0), q, "no residual", controls(2, 0.5, 1.5, 0)), 10});
        return r;
    }
    static chi2::Options chi2_options() { return grid_options(8, 60000, 10, 20, 2); }  // 4 cases × 2 precisions
    static Instance<Fiber> lossless() {
        return Base::make(huang_params<T>(0.3, 2, glm::dvec3(0), 0.7, 0.4), Base::quadrature(8, 16, 2), "lossless, gains",
                          controls(2, 0.5, 1.5, 0.25));
    }
    static std::vector<Invalid> invalid() {
        std::vector<Invalid> r;
        auto add = [&](const char* field, auto change) {
            hs::LobeControls<T> c;
            change(c);
            r.push_back({[c] { Material m(hs::HuangParams<T>(), c); }, field});
        };
        add("gain_r", [](hs::LobeControls<T>& c) { c.gain[0] = T(-1); });
        add("tint_trt.g", [](hs::LobeControls<T>& c) { c.tint[2].g = std::numeric_limits<T>::infinity(); });
        add("alpha_override", [](hs::LobeControls<T>& c) { c.override_alpha(1, T(0.05)); });
        return r;
    }
};

}  // namespace specs
