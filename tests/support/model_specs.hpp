// The models the contract suite (contract_suite.hpp) runs over, one spec per model: its
// random materials, edge cases, chi-square grid, lossless case and invalid constructions.
// The model tests reuse them (a chi-square negative control runs at its grid's options).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include <hairscatter/hairscatter.hpp>

#include "contract_suite.hpp"

namespace specs {

namespace hs = hairscatter;
using contract::Chi2Case;
using contract::Instance;
using contract::Invalid;
using contract::kPi;
using contract::make_instance;

inline double deg(double d) { return d * kPi / 180; }

template <typename T> hs::FiberParams<T> fiber_params(double beta_m, double beta_n, double alpha_deg, glm::dvec3 sigma_a) {
    hs::FiberParams<T> p;
    p.beta_m = T(beta_m);
    p.beta_n = T(beta_n);
    p.alpha = T(deg(alpha_deg));
    p.sigma_a = glm::vec<3, T>(sigma_a);
    return p;
}

// A random material of the d'Eon family: βm 0.05–1, βn 0.1–1, α ±5°, coloured σa on odd k.
template <typename T> hs::FiberParams<T> random_params(std::mt19937_64& rng, int k) {
    std::uniform_real_distribution<double> uni(0, 1);
    const double sa = (k % 2) * 2 * uni(rng);
    const double bm = 0.05 + 0.95 * uni(rng), bn = 0.1 + 0.9 * uni(rng), al = -5 + 10 * uni(rng);
    return fiber_params<T>(bm, bn, al, glm::dvec3(sa, 0.5 * sa, 2 * sa));
}

inline std::string label(double bm, double bn, double al, double sa) {
    return "βm " + std::to_string(bm) + " βn " + std::to_string(bn) + " α " + std::to_string(al) + "° σa " +
           std::to_string(sa);
}

// The d'Eon family's edge-case parameters: βm 0.01, 0.3 and 1, the given βn and α (the
// limit ±22.5° scaled by 0.9999 to stay inside it), σa 0 and 50; visit(params, label).
template <typename T, typename Visit>
void for_extreme_params(std::initializer_list<double> beta_n, std::initializer_list<double> alpha_deg, Visit visit) {
    for (double bm : {0.01, 0.3, 1.0})
        for (double bn : beta_n)
            for (double al : alpha_deg)
                for (double sa : {0.0, 50.0}) {
                    hs::FiberParams<T> p = fiber_params<T>(bm, bn, 0, glm::dvec3(sa));
                    p.alpha = T(deg(al)) * T(0.9999);
                    visit(p, label(bm, bn, al, sa));
                }
}

// A chi-square case of the far-field family: parameters, θo and the model's own setting
// (the far field's node count, the tabulated fiber's options); σa is coloured (σa, 0.6σa,
// 0.3σa).
template <typename Setting> struct DeonChi2Case {
    double beta_m, beta_n, alpha_deg, theta_o_deg, sigma_a;
    Setting setting;

    template <typename T> hs::FiberParams<T> params() const {
        return fiber_params<T>(beta_m, beta_n, alpha_deg, glm::dvec3(sigma_a, 0.6 * sigma_a, 0.3 * sigma_a));
    }
    std::string label() const { return specs::label(beta_m, beta_n, alpha_deg, sigma_a); }
};

// The chi-square cases of a far-field grid: make(params, setting, label) builds each.
template <typename T, typename Fiber, typename Setting, typename Make>
std::vector<Chi2Case<Fiber>> deon_chi2_cases(const std::vector<DeonChi2Case<Setting>>& grid, Make make) {
    std::vector<Chi2Case<Fiber>> r;
    for (const DeonChi2Case<Setting>& c : grid) r.push_back({make(c.template params<T>(), c.setting, c.label()), c.theta_o_deg});
    return r;
}

// Invalid constructions, one bad field each: add(field, change) copies start, applies
// change to the copy and records build(copy) as a construction that must be rejected.
template <typename Value, typename Build> auto invalid_adder(std::vector<Invalid>& r, const Value& start, Build build) {
    return [&r, start, build](const char* field, auto change) {
        Value v = start;
        change(v);
        r.push_back({[v, build] { build(v); }, field});
    };
}

// Every bad FiberParams field, for the three models built from FiberParams.
template <typename Material> std::vector<Invalid> invalid_fiber_params() {
    using T = std::decay_t<decltype(std::declval<Material>().params().eta)>;
    std::vector<Invalid> r;
    auto add = invalid_adder(r, hs::FiberParams<T>(), [](const hs::FiberParams<T>& p) { Material m(p); });
    add("eta", [](auto& p) { p.eta = T(1); });
    add("beta_m", [](auto& p) { p.beta_m = T(0); });
    add("beta_m", [](auto& p) { p.beta_m = T(1.5); });
    add("beta_n", [](auto& p) { p.beta_n = T(0); });
    add("beta_n", [](auto& p) { p.beta_n = T(1.5); });
    add("alpha", [](auto& p) { p.alpha = T(0.5); });
    add("sigma_a.g", [](auto& p) { p.sigma_a.g = T(-1); });
    add("sigma_a.r", [](auto& p) { p.sigma_a.r = std::numeric_limits<T>::infinity(); });
    return r;
}

// What every spec states about its model: the fiber and material types, how many random
// materials and directions the sample/pdf check draws, whether the lossless albedo is 1 and
// how close ∫ eval dω must come to albedo(wo), how deep the furnace cubature refines, how
// far the chi-square cubature's ∫ pdf may be from 1, and which lobes sample() may report
// (lobe indices 0 … kLobes, or 0 … kLobes - 1 without a residual).
template <typename F, typename M, int kMaterials, int kDirections, bool kConserves, bool kResidual = true>
struct SpecBase {
    using Fiber = F;
    using Material = M;
    static constexpr int kRandomMaterials = kMaterials;
    static constexpr int kRandomDirections = kDirections;
    static constexpr bool kConservesEnergy = kConserves;
    static constexpr double kFurnaceTolerance = kConserves ? 1e-5 : 1e-2;  // Marschner: the albedo estimate's error (4e-3)
    static constexpr int kFurnaceDepth = kConserves ? 5 : 3;
    static constexpr double kPdfTotalTolerance = kConserves ? 1e-3 : 2e-3;
    static bool may_sample(hs::SampledLobe lobe) {
        return hs::lobe_index(lobe) >= 0 && hs::lobe_index(lobe) < F::kLobes + (kResidual ? 1 : 0);
    }
};

// The chi-square options of a grid: num_tests the Bonferroni count, each cell's cubature
// starting as 4 × 25 pdf nodes (min_depth 1) and refining where they disagree.
inline chi2::Options grid_options(int num_tests, std::int64_t samples, int theta_bins, int phi_bins, int max_depth) {
    chi2::Options o;
    o.num_tests = num_tests;
    o.samples = samples;
    o.theta_bins = theta_bins;
    o.phi_bins = phi_bins;
    o.min_depth = 1;
    o.max_depth = max_depth;
    return o;
}

// ---- Chiang, and its lobe subsets ----

// Chiang's chi-square grid (the full model).
struct ChiangChi2Case {
    double beta_m, beta_n, alpha_deg, h, theta_o_deg, sigma_a;
};
inline const std::vector<ChiangChi2Case>& chiang_chi2_grid() {
    static const std::vector<ChiangChi2Case> g = {
        {0.3, 0.3, 2, 0.0, 30, 0.5},     {0.3, 0.3, 2, 0.5, -60, 0.0},   {0.3, 0.3, 2, -0.9, 85, 0.5},
        {0.01, 0.3, 2, 0.2, 20, 0.0},    {0.01, 0.3, 0, -0.5, 70, 0.5},  {0.01, 0.05, 2, 0.0, 0, 0.0},
        {0.05, 0.1, -2, 0.7, 45, 0.5},   {0.1, 0.2, 2, -0.3, -30, 50.0}, {0.2, 0.5, 0, 1.0, 10, 0.0},
        {0.2, 0.5, 0, -1.0, 10, 0.5},    {0.5, 0.7, 2, 0.4, 60, 0.0},    {0.7, 0.9, 2, -0.6, -80, 0.5},
        {1.0, 1.0, 0, 0.0, 0, 0.0},      {1.0, 1.0, 22.5, 0.9, 40, 0.5}, {1.0, 0.3, -22.5, -0.2, 89.9, 0.0},
        {0.3, 1.0, 2, 0.3, 90, 0.5},     {0.3, 0.05, 2, 0.3, -90, 0.0},  {0.3, 0.3, 22.5, 0.1, 80, 0.0},
        {0.3, 0.3, -22.5, 0.8, -45, 50}, {0.15, 0.15, 5, -0.8, 15, 0.0}, {0.4, 0.25, 2, 0.99, 50, 0.5},
        {0.6, 0.4, -5, -0.99, -20, 0.0}, {0.8, 0.6, 2, 0.5, 75, 50.0},   {0.03, 0.5, 2, 0.0, -10, 0.5},
        {0.02, 0.8, -2, 0.6, 35, 0.0},   {0.9, 0.1, 2, -0.4, 65, 0.5},   {0.25, 0.75, 10, 0.25, -75, 0.0},
        {0.35, 0.35, 2, -0.75, 5, 0.5},  {0.45, 0.15, 0, 0.15, 87, 0.0}, {0.55, 0.95, 2, 0.85, -87, 0.5},
        {0.65, 0.45, -10, -0.15, 25, 0}, {0.75, 0.2, 2, 0.65, -55, 0.5}, {0.1, 0.9, 2, -0.65, 45, 0.0},
        {0.12, 0.12, 2, 0.0, 60, 0.5},   {0.3, 0.3, 0, 1.0, 90, 50.0},   {0.01, 1.0, 22.5, -1.0, -89.9, 0.0},
    };
    return g;
}

template <typename T, hs::LobeSet kSet>
struct ChiangSpec : SpecBase<hs::BasicChiangFiber<T, kSet>, hs::ChiangMaterial<T>, kSet == hs::LobeSet::kAll ? 200 : 40,
                             100, true> {
    using Fiber = hs::BasicChiangFiber<T, kSet>;
    using Material = hs::ChiangMaterial<T>;
    // A subset drops energy: its albedo is below 1, and checked against ∫ eval dω only.
    static constexpr bool kConservesEnergy = kSet == hs::LobeSet::kAll;

    static Instance<Fiber> make(const hs::FiberParams<T>& p, double h, std::string name) {
        return make_instance<Fiber>(std::make_shared<const Material>(p), std::move(name), T(h));
    }
    static Instance<Fiber> random(std::mt19937_64& rng, int k) {
        const hs::FiberParams<T> p = random_params<T>(rng, k);
        const double h = std::uniform_real_distribution<double>(-1, 1)(rng);
        return make(p, h, "random " + std::to_string(k));
    }
    static std::vector<Instance<Fiber>> extremes() {
        std::vector<Instance<Fiber>> r;
        for_extreme_params<T>({0.01, 0.3, 1.0}, {-22.5, 0.0, 22.5}, [&](const hs::FiberParams<T>& p, const std::string& l) {
            for (double h : {-1.0, 0.0, 1.0}) r.push_back(make(p, h, l + " h " + std::to_string(h)));
        });
        return r;
    }
    // The full model: 36 combinations of βm from 0.01 to 1, βn from 0.05 to 1, tilts of 0,
    // ±2° and the 22.5° limit, h = ±1 and interior values, θo = 0 to ±90°, σa = 0, 0.5 and
    // 50 (channels σa, 0.6σa, 0.3σa). A subset: one case, the five subsets in both
    // precisions sharing the significance.
    static std::vector<Chi2Case<Fiber>> chi2_cases() {
        std::vector<Chi2Case<Fiber>> r;
        if constexpr (kSet == hs::LobeSet::kAll) {
            for (const ChiangChi2Case& c : chiang_chi2_grid()) {
                const glm::dvec3 sa(c.sigma_a, 0.6 * c.sigma_a, 0.3 * c.sigma_a);
                r.push_back({make(fiber_params<T>(c.beta_m, c.beta_n, c.alpha_deg, sa), c.h,
                                  label(c.beta_m, c.beta_n, c.alpha_deg, c.sigma_a) + " h " + std::to_string(c.h)),
                             c.theta_o_deg});
            }
        } else {
            const hs::FiberParams<T> p = fiber_params<T>(0.25, 0.35, 2, glm::dvec3(0.3));
            const double theta_o = kSet == hs::LobeSet::kR ? 30 : kSet == hs::LobeSet::kTT ? -50
                                 : kSet == (hs::LobeSet::kTRT | hs::LobeSet::kResidual) ? 70
                                 : kSet == hs::LobeSet::kPrimary ? 10 : 85;
            const double h = kSet == hs::LobeSet::kR ? 0.3 : kSet == hs::LobeSet::kTT ? -0.6
                           : kSet == (hs::LobeSet::kTRT | hs::LobeSet::kResidual) ? 0.1
                           : kSet == hs::LobeSet::kPrimary ? 0.8 : -0.2;
            r.push_back({make(p, h, "subset, h " + std::to_string(h)), theta_o});
        }
        return r;
    }
    static chi2::Options chi2_options() {
        chi2::Options o;
        o.num_tests = kSet == hs::LobeSet::kAll ? 2 * int(chiang_chi2_grid().size()) : 10;
        return o;
    }
    static bool may_sample(hs::SampledLobe lobe) { return Fiber::keeps(hs::lobe_index(lobe)); }
    static Instance<Fiber> lossless() { return make(fiber_params<T>(0.3, 0.3, 2, glm::dvec3(0)), 0.3, "lossless"); }
    static std::vector<Invalid> invalid() { return invalid_fiber_params<Material>(); }
};

// ---- d'Eon's far field ----

template <typename T>
struct FarFieldSpec : SpecBase<hs::DeonFarFieldFiber<T>, hs::DeonFarFieldMaterial<T>, 60, 100, true> {
    using Fiber = hs::DeonFarFieldFiber<T>;
    using Material = hs::DeonFarFieldMaterial<T>;

    static Instance<Fiber> make(const hs::FiberParams<T>& p, int nodes, std::string name) {
        return make_instance<Fiber>(std::make_shared<const Material>(p, nodes), std::move(name) + " " +
                                                                                     std::to_string(nodes) + " nodes");
    }
    static Instance<Fiber> random(std::mt19937_64& rng, int k) {
        return make(random_params<T>(rng, k), 1 + k % 20, "random " + std::to_string(k));
    }
    static std::vector<Instance<Fiber>> extremes() {
        std::vector<Instance<Fiber>> r;
        for_extreme_params<T>({0.01, 0.3, 1.0}, {-22.5, 0.0, 22.5}, [&](const hs::FiberParams<T>& p, const std::string& l) {
            for (int nodes : {1, 8, 64}) r.push_back(make(p, nodes, l));
        });
        return r;
    }
    // 14 cases: βm 0.05–1, βn 0.1–1, θo 0 to ±89°, σa 0, 0.5 and 20, node counts 1–16 (the
    // sampler must match the pdf at every N_h, not only in the limit).
    using Case = DeonChi2Case<int>;  // setting: the node count
    static const std::vector<Case>& grid() {
        static const std::vector<Case> g = {
            {0.3, 0.3, 2, 30, 0.5, 8},     {0.05, 0.3, 2, 20, 0.0, 8},   {1.0, 0.3, 0, -45, 0.5, 4},
            {0.3, 0.1, 2, 10, 0.0, 16},    {0.3, 1.0, 5, 60, 0.5, 4},    {0.05, 0.1, -2, 89, 0.0, 8},
            {1.0, 1.0, 0, -89, 20.0, 4},   {0.2, 0.5, 2, -89, 0.0, 7},   {0.5, 0.2, 10, 75, 20.0, 8},
            {0.1, 0.7, -5, 0, 0.0, 1},     {0.7, 0.15, 2, -30, 0.5, 3},  {0.3, 0.3, 22.5, 45, 0.0, 2},
            {0.4, 0.4, 2, 50, 0.5, 12},    {0.05, 1.0, 2, -60, 20.0, 5},
        };
        return g;
    }
    static std::vector<Chi2Case<Fiber>> chi2_cases() { return deon_chi2_cases<T, Fiber>(grid(), make); }
    // A 16 × 32 histogram, 2e5 samples and cell cubature from depth 1 keep each run well
    // under a second (the pdf costs ~0.1 µs per h node).
    // The float pdf's rounding noise keeps the cubature refining narrow lobes to its
    // deepest level (13M evaluations at βn = 0.1); 5 levels resolve them (cells of 0.004 in
    // sinθ and 0.006 rad in φ) at a seventh of the cost of the default 7.
    static chi2::Options chi2_options() {
        return grid_options(2 * int(grid().size()), 200000, 16, 32, sizeof(T) == 4 ? 5 : chi2::Options().max_depth);
    }
    static Instance<Fiber> lossless() { return make(fiber_params<T>(0.3, 0.3, 2, glm::dvec3(0)), 0, "lossless"); }
    static std::vector<Invalid> invalid() {
        std::vector<Invalid> r = invalid_fiber_params<Material>();
        for (int n : {-1, -3, Material::kMaxNodes + 1, 1000})
            r.push_back({[n] { Material m(hs::FiberParams<T>(), n); }, "nodes"});
        return r;
    }
};

// ---- the tabulated far field (exact and tabulated M_p) ----

template <typename T> struct TabulatedSpec : SpecBase<hs::TabulatedFiber<T>, hs::TabulatedMaterial<T>, 40, 200, true> {
    using Fiber = hs::TabulatedFiber<T>;
    using Material = hs::TabulatedMaterial<T>;

    static hs::TabulatedOptions with_table(hs::TabulatedOptions o) {
        o.longitudinal = hs::TabulatedLongitudinal::kTable;
        return o;
    }
    static Instance<Fiber> make(const hs::FiberParams<T>& p, const hs::TabulatedOptions& o, std::string name) {
        return make_instance<Fiber>(std::make_shared<const Material>(p, o),
                                    std::move(name) + " table " + std::to_string(o.phi_samples) + "×" +
                                        std::to_string(o.theta_samples) +
                                        (o.longitudinal == hs::TabulatedLongitudinal::kTable ? " M table" : ""));
    }
    static Instance<Fiber> random(std::mt19937_64& rng, int k) {
        const hs::TabulatedOptions res[5] = {hs::TabulatedOptions::coarse(), hs::TabulatedOptions(), {9, 4, 3},
                                             hs::TabulatedOptions::fast(), with_table({9, 4, 3})};
        return make(random_params<T>(rng, k), res[k % 5], "random " + std::to_string(k));
    }
    static std::vector<Instance<Fiber>> extremes() {
        std::vector<Instance<Fiber>> r;
        const hs::TabulatedOptions smallest{2, 2, 1}, smallest_m{2, 2, 1, hs::TabulatedLongitudinal::kTable, 2, 2};
        for_extreme_params<T>({0.001, 0.3, 1.0}, {-22.5, 22.5}, [&](const hs::FiberParams<T>& p, const std::string& l) {
            for (const hs::TabulatedOptions& o : {smallest, hs::TabulatedOptions::coarse(), smallest_m})
                r.push_back(make(p, o, l));
        });
        return r;
    }
    // 12 cases over βm, βn, α, θo (0 to ±89°), σa 0 to 20 and the resolutions (including a
    // 2 × 2 table and odd sizes): the sampler must invert the interpolant exactly at any
    // size. Then a third of them again with M_p tabulated (the kinks of M̂ make the
    // cubature slow), two with coarse M tables (5 rows of 11 nodes), at the same significance.
    using Case = DeonChi2Case<hs::TabulatedOptions>;
    static const std::vector<Case>& grid() {
        static const std::vector<Case> g = {
            {0.3, 0.3, 2, 30, 0.5, {}},
            {0.05, 0.3, 2, 20, 0.0, {}},
            {1.0, 0.3, 0, -45, 0.5, hs::TabulatedOptions::coarse()},
            {0.3, 0.15, 2, 10, 0.0, hs::TabulatedOptions::fine()},
            {0.3, 1.0, 5, 60, 0.5, {}},
            {0.05, 0.2, -2, 89, 0.0, {}},
            {1.0, 1.0, 0, -89, 20.0, hs::TabulatedOptions::coarse()},
            {0.2, 0.5, 2, -80, 0.0, {7, 5, 9}},
            {0.5, 0.2, 10, 75, 20.0, {}},
            {0.1, 0.7, -5, 0, 0.0, {2, 2, 1}},
            {0.3, 0.3, 22.5, 45, 0.0, {33, 3, 4}},
            {0.4, 0.4, 2, 50, 0.5, hs::TabulatedOptions::fine()},
        };
        return g;
    }
    static std::vector<Chi2Case<Fiber>> chi2_cases() {
        std::vector<Chi2Case<Fiber>> r = deon_chi2_cases<T, Fiber>(grid(), make);
        for (std::size_t k = 0; k < grid().size(); k += 3) {
            const Case& c = grid()[k];
            hs::TabulatedOptions o = with_table(c.setting);
            if (k % 6 == 3) o.m_rows = 5, o.m_nodes = 11;  // coarse M tables are inverted exactly too
            r.push_back({make(c.params<T>(), o, c.label()), c.theta_o_deg});
        }
        return r;
    }
    // The pdf has kinks in φ at every table node: 5 levels (cells of 0.004 in sinθ and
    // 0.006 rad in φ) resolve a cell's integral far below the counts' noise.
    static chi2::Options chi2_options() { return grid_options(2 * int(grid().size()), 200000, 16, 32, 5); }
    static Instance<Fiber> lossless() {
        return make(fiber_params<T>(0.3, 0.3, 2, glm::dvec3(0)), hs::TabulatedOptions(), "lossless");
    }
    static std::vector<Invalid> invalid() {
        std::vector<Invalid> r = invalid_fiber_params<Material>();
        auto add = invalid_adder(r, hs::TabulatedOptions::fast(),
                                 [](const hs::TabulatedOptions& o) { Material m(hs::FiberParams<T>(), o); });
        using O = hs::TabulatedOptions;
        add("phi_samples", [](O& o) { o.phi_samples = 1; });
        add("phi_samples", [](O& o) { o.phi_samples = 0; });
        add("phi_samples", [](O& o) { o.phi_samples = O::kMaxPhiSamples + 1; });
        add("theta_samples", [](O& o) { o.theta_samples = 1; });
        add("theta_samples", [](O& o) { o.theta_samples = -4; });
        add("theta_samples", [](O& o) { o.theta_samples = O::kMaxThetaSamples + 1; });
        add("h_nodes", [](O& o) { o.h_nodes = -1; });
        add("h_nodes", [](O& o) { o.h_nodes = hs::FarFieldQuadrature<double>::kMaxNodes + 1; });
        add("m_rows", [](O& o) { o.m_rows = 1; });
        add("m_rows", [](O& o) { o.m_rows = O::kMaxLongitudinalRows + 1; });
        add("m_nodes", [](O& o) { o.m_nodes = 1; });
        add("m_nodes", [](O& o) { o.m_nodes = O::kMaxLongitudinalNodes + 1; });
        add("longitudinal", [](O& o) { o.longitudinal = static_cast<hs::TabulatedLongitudinal>(7); });
        return r;
    }
};

// ---- Marschner ----

template <typename T> hs::MarschnerParams<T> marschner_params(double beta_r_deg, double beta_n, double alpha_r_deg,
                                                              glm::dvec3 sigma_a, double eccentricity) {
    hs::MarschnerParams<T> p;
    p.beta_r = T(deg(beta_r_deg));
    p.beta_n = T(beta_n);
    p.alpha_r = T(deg(alpha_r_deg));
    p.sigma_a = glm::vec<3, T>(sigma_a);
    p.eccentricity = T(eccentricity);
    return p;
}

// Marschner's model does not conserve energy (its albedo is an estimate) and has no residual.
template <typename T>
struct MarschnerSpec : SpecBase<hs::MarschnerFiber<T>, hs::MarschnerMaterial<T>, 40, 60, false, false> {
    using Fiber = hs::MarschnerFiber<T>;
    using Material = hs::MarschnerMaterial<T>;

    static Instance<Fiber> make(const hs::MarschnerParams<T>& p, int nodes, std::string name) {
        return make_instance<Fiber>(std::make_shared<const Material>(p, nodes), std::move(name));
    }
    static Instance<Fiber> random(std::mt19937_64& rng, int k) {
        std::uniform_real_distribution<double> uni(0, 1);
        const double br = 2 + 30 * uni(rng), bn = 0.1 + 0.9 * uni(rng), ar = -10 + 10 * uni(rng);
        const double sa = k % 2 ? 2 * uni(rng) : 0.0, ecc = k % 3 ? 1.0 : 0.7 + 0.6 * uni(rng);
        return make(marschner_params<T>(br, bn, ar, glm::dvec3(sa), ecc), 1 + k % 9, "random " + std::to_string(k));
    }
    static std::vector<Instance<Fiber>> extremes() {
        std::vector<Instance<Fiber>> r;
        int index = 0;
        for (double eta : {1.0001, 1.55, 10.0})
            for (double br : {1e-4, kPi / 4})
                for (double bn : {0.01, 1.0})
                    for (double sa : {0.0, 1e3})
                        for (double ecc : {0.5, 1.0, 2.0}) {
                            hs::MarschnerParams<T> p = marschner_params<T>(0, bn, 0, glm::dvec3(sa), ecc);
                            p.eta = T(eta), p.beta_r = T(br);
                            p.alpha_r = T((index % 2 ? -1 : 1) * kPi / 6 * 0.9999);
                            const int nodes = 1 + (index * 5) % 16;
                            ++index;
                            r.push_back(make(p, nodes, "η " + std::to_string(eta) + " βR " + std::to_string(br) + " βn " +
                                                           std::to_string(bn) + " σa " + std::to_string(sa) + " a " +
                                                           std::to_string(ecc)));
                        }
        return r;
    }
    // βR 2°–40°, βn 0.1–1, θo 0 to ±85°, σa 0–20, eccentricity 0.7–1.4, 1–16 roughness nodes.
    struct Case {
        double beta_r_deg, beta_n, alpha_r_deg, theta_o_deg, sigma_a, eccentricity;
        int nodes;
    };
    static const std::vector<Case>& grid() {
        static const std::vector<Case> g = {
            {7.5, 0.3, -7.5, 30, 0.0, 1.0, 7},   {2.0, 0.1, -10, -20, 0.5, 1.0, 3},  {20, 0.6, -5, 60, 0.0, 0.85, 5},
            {40, 1.0, 0, -85, 20.0, 1.0, 1},     {5, 0.2, -8, 80, 0.3, 1.4, 4},      {10, 0.4, -6, 0, 0.0, 0.7, 16},
        };
        return g;
    }
    static hs::MarschnerParams<T> chi2_params(const Case& c) {
        return marschner_params<T>(c.beta_r_deg, c.beta_n, c.alpha_r_deg,
                                   glm::dvec3(c.sigma_a, 0.6 * c.sigma_a, 0.3 * c.sigma_a), c.eccentricity);
    }
    static std::vector<Chi2Case<Fiber>> chi2_cases() {
        std::vector<Chi2Case<Fiber>> r;
        for (const Case& c : grid())
            r.push_back({make(chi2_params(c), c.nodes,
                              "βR " + std::to_string(c.beta_r_deg) + "° βn " + std::to_string(c.beta_n) + " a " +
                                  std::to_string(c.eccentricity)),
                         c.theta_o_deg});
        return r;
    }
    // Cells refine to 64 × 25 pdf nodes at most.
    static chi2::Options chi2_options() { return grid_options(2 * int(grid().size()), 100000, 12, 24, 3); }
    static Instance<Fiber> lossless() {
        return make(marschner_params<T>(10, 0.5, -7.5, glm::dvec3(0), 1), Material::kDefaultNodes, "lossless");
    }
    static std::vector<Invalid> invalid() {
        std::vector<Invalid> r;
        auto add = invalid_adder(r, hs::MarschnerParams<T>(), [](const hs::MarschnerParams<T>& p) { Material m(p); });
        const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
        add("eta", [](auto& p) { p.eta = T(1); });
        add("eta", [](auto& p) { p.eta = T(0.5); });
        add("eta", [inf](auto& p) { p.eta = inf; });
        add("sigma_a.g", [](auto& p) { p.sigma_a.g = T(-1); });
        add("sigma_a.b", [nan](auto& p) { p.sigma_a.b = nan; });
        add("beta_r", [](auto& p) { p.beta_r = T(0); });
        add("beta_r", [](auto& p) { p.beta_r = T(1); });
        add("beta_n", [](auto& p) { p.beta_n = T(0); });
        add("beta_n", [](auto& p) { p.beta_n = T(1.5); });
        add("alpha_r", [](auto& p) { p.alpha_r = T(0.6); });
        add("eccentricity", [](auto& p) { p.eccentricity = T(0); });
        add("eccentricity", [](auto& p) { p.eccentricity = T(-1); });
        add("caustic_width", [](auto& p) { p.caustic_width = T(0); });
        add("caustic_width", [](auto& p) { p.caustic_width = T(2); });
        add("caustic_gain", [](auto& p) { p.caustic_gain = T(-0.1); });
        add("caustic_fade", [](auto& p) { p.caustic_fade = T(0); });
        add("caustic_dh_max", [](auto& p) { p.caustic_dh_max = T(0); });
        add("caustic_dh_max", [](auto& p) { p.caustic_dh_max = T(1.5); });
        for (int n : {0, -1, Material::kMaxNodes + 1})
            r.push_back({[n] { Material m(hs::MarschnerParams<T>(), n); }, "azimuthal_nodes"});
        return r;
    }
};

// ---- Huang et al. 2022's microfacet fiber ----

template <typename T>
hs::HuangParams<T> huang_params(double roughness, double alpha_deg, glm::dvec3 sigma_a, double aspect, double orientation) {
    hs::HuangParams<T> p;
    p.roughness = T(roughness);
    p.alpha = T(deg(alpha_deg));
    p.sigma_a = glm::vec<3, T>(sigma_a);
    p.aspect_ratio = T(aspect);
    p.orientation = T(orientation);
    return p;
}

// The furnace compares ∫ eval dω (the lobes' exact integrals) with albedo (the sum of the
// reflectance tables' values): the tables' product rule leaves up to 5e-3 of E_in at single
// cosines (tests/huang_test.cpp), 3e-4 in the furnace's average (measured), which this
// tolerance states with a margin; albedo itself is 1 for σa = 0 to rounding.
template <typename T> struct HuangSpec : SpecBase<hs::HuangFiber<T>, hs::HuangMaterial<T>, 16, 40, true> {
    using Fiber = hs::HuangFiber<T>;
    using Material = hs::HuangMaterial<T>;
    static constexpr double kFurnaceTolerance = 1e-3;
    // The pdf walks every path (µs per call): 3 levels (cells of 0.03 in sinθ, 0.05 rad in
    // φ) integrate this smooth lossless fiber to ~1e-5, within the tolerance.
    static constexpr int kFurnaceDepth = 3;

    static hs::HuangQuadrature quadrature(int nodes, int tt, int per_tt) {
        hs::HuangQuadrature q;
        q.offset_nodes = nodes;
        q.tt_points = tt;
        q.trt_per_tt = per_tt;
        return q;
    }
    static std::string knobs(const hs::HuangQuadrature& q) {
        return std::to_string(q.offset_nodes) + "/" + std::to_string(q.tt_points) + "×" + std::to_string(q.trt_per_tt) +
               " points";
    }
    static Instance<Fiber> make(const hs::HuangParams<T>& p, const hs::HuangQuadrature& q, std::string name,
                                const hs::LobeControls<T>& c = hs::LobeControls<T>()) {
        return make_instance<Fiber>(std::make_shared<const Material>(p, q, c), std::move(name) + " " + knobs(q));
    }
    static std::string label(double rough, double alpha, double sa, double aspect, double psi) {
        return "β " + std::to_string(rough) + " α " + std::to_string(alpha) + "° σa " + std::to_string(sa) + " b/a " +
               std::to_string(aspect) + " ψ " + std::to_string(psi);
    }
    // β 0.1–1, α ±5°, b/a 0.5–1, any orientation, coloured σa on odd k: the parameters of
    // the k-th random material.
    static hs::HuangParams<T> random_params(std::mt19937_64& rng, int k) {
        std::uniform_real_distribution<double> uni(0, 1);
        const double sa = (k % 2) * 2 * uni(rng);
        const double rough = 0.1 + 0.9 * uni(rng), al = -5 + 10 * uni(rng), aspect = 0.5 + 0.5 * uni(rng);
        const double psi = -kPi + 2 * kPi * uni(rng);
        return huang_params<T>(rough, al, glm::dvec3(sa, 0.5 * sa, 2 * sa), aspect, psi);
    }
    // 2–9 offset nodes, 3–24 TT points with 1–3 internal normals each (the sampler must
    // match pdf at every setting, and a few points keep the suite fast).
    static hs::HuangQuadrature random_quadrature(int k) { return quadrature(2 + k % 8, 3 + 7 * (k % 4), 1 + k % 3); }
    static Instance<Fiber> random(std::mt19937_64& rng, int k) {
        return make(random_params(rng, k), random_quadrature(k), "random " + std::to_string(k));
    }
    // The extremes' materials share their tables four by four (absorption and quadrature
    // change no table): each is built from the first of its geometry (HuangMaterial(like,
    // …), the plain constructor's material bit for bit, tested in huang_test).
    static std::vector<Instance<Fiber>> extremes() {
        std::vector<Instance<Fiber>> r;
        std::vector<std::shared_ptr<const Material>> built;
        const auto make_shared = [&](const hs::HuangParams<T>& p, const hs::HuangQuadrature& q, const std::string& l) {
            std::shared_ptr<const Material> m;
            for (const auto& b : built)
                if (Material::same_tables(b->params(), p)) m = std::make_shared<const Material>(*b, p, q);
            if (!m) built.push_back(m = std::make_shared<const Material>(p, q));
            r.push_back(make_instance<Fiber>(m, l + " " + knobs(q)));
        };
        for (double rough : {0.02, 0.3, 1.0})
            for (double al : {-22.5, 0.0, 22.5})
                for (double sa : {0.0, 50.0})
                    for (double aspect : {0.5, 1.0}) {
                        hs::HuangParams<T> p = huang_params<T>(rough, 0, glm::dvec3(sa), aspect, kPi * 0.9999);
                        p.alpha = T(deg(al)) * T(0.9999);
                        const std::string l = label(rough, al, sa, aspect, kPi);
                        make_shared(p, quadrature(1, 1, 1), l);
                        make_shared(p, quadrature(7, 9, 3), l);
                    }
        return r;
    }
    // 8 cases: β 0.1–1, θo 0 to ±89°, σa 0–20, round and strongly elliptical (b/a 0.5)
    // sections at several orientations, tilts to ±10°, offset nodes 1–6, 1–32 TT points
    // with 1–4 internal normals each (the pdf is exact at any count).
    struct Case {
        double roughness, alpha_deg, theta_o_deg, sigma_a, aspect, orientation;
        int nodes, tt, per_tt;
    };
    static const std::vector<Case>& grid() {
        static const std::vector<Case> g = {
            {0.3, 2, 30, 0.5, 1.0, 0.0, 6, 16, 2},   {0.3, 2, 30, 0.0, 0.5, 0.4, 3, 32, 2},
            {0.15, -5, 60, 0.5, 0.5, 1.5, 6, 8, 1},  {1.0, 2, -45, 0.0, 0.7, -2.0, 2, 5, 4},
            {0.3, 10, 89, 0.0, 0.5, 0.0, 5, 12, 1},  {0.3, 2, -89, 20.0, 0.5, 2.5, 4, 16, 3},
            {0.5, 0, 0, 0.5, 0.8, 1.0, 1, 1, 1},     {0.1, 2, -20, 0.5, 0.6, -0.7, 6, 24, 2},
        };
        return g;
    }
    static hs::HuangParams<T> chi2_params(const Case& c) {
        return huang_params<T>(c.roughness, c.alpha_deg, glm::dvec3(c.sigma_a, 0.6 * c.sigma_a, 0.3 * c.sigma_a), c.aspect,
                               c.orientation);
    }
    static std::vector<Chi2Case<Fiber>> chi2_cases() {
        std::vector<Chi2Case<Fiber>> r;
        for (const Case& c : grid())
            r.push_back({make(chi2_params(c), quadrature(c.nodes, c.tt, c.per_tt),
                              label(c.roughness, c.alpha_deg, c.sigma_a, c.aspect, c.orientation)),
                         c.theta_o_deg});
        return r;
    }
    // A 10 × 20 histogram and 6·10⁴ samples; cells refine to 2 levels (16 × 25 pdf nodes):
    // the pdf walks every path (µs per call), and at β ≥ 0.1 the lobes are smooth on the
    // finest cells (0.05 in sinθ, 0.08 rad in φ). About a minute per precision.
    static chi2::Options chi2_options() { return grid_options(2 * int(grid().size()), 60000, 10, 20, 2); }
    static Instance<Fiber> lossless() {
        return make(huang_params<T>(0.3, 2, glm::dvec3(0), 0.7, 0.4), quadrature(8, 16, 2), "lossless");
    }
    // Every bad parameter and knob, and bad controls (add to r).
    static std::vector<Invalid> invalid() {
        std::vector<Invalid> r;
        auto add = [&](const char* field, auto change) {
            hs::HuangParams<T> p;
            change(p);
            r.push_back({[p] { Material m(p); }, field});
        };
        const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
        add("eta", [](auto& p) { p.eta = T(1); });
        add("eta", [nan](auto& p) { p.eta = nan; });
        add("roughness", [](auto& p) { p.roughness = T(0.01); });
        add("roughness", [](auto& p) { p.roughness = T(1.5); });
        add("alpha", [](auto& p) { p.alpha = T(0.5); });
        add("sigma_a.g", [](auto& p) { p.sigma_a.g = T(-1); });
        add("sigma_a.b", [inf](auto& p) { p.sigma_a.b = inf; });
        add("aspect_ratio", [](auto& p) { p.aspect_ratio = T(0.4); });
        add("aspect_ratio", [](auto& p) { p.aspect_ratio = T(1.2); });
        add("aspect_ratio", [nan](auto& p) { p.aspect_ratio = nan; });
        add("orientation", [](auto& p) { p.orientation = T(4); });
        for (int n : {-1, Material::kMaxNodes + 1})
            r.push_back({[n] { Material m(hs::HuangParams<T>(), quadrature(n, 0, 0)); }, "offset_nodes"});
        for (int n : {-1, Material::kMaxTTPoints + 1})
            r.push_back({[n] { Material m(hs::HuangParams<T>(), quadrature(0, n, 0)); }, "tt_points"});
        for (int n : {-3, Material::kMaxTrtPerTT + 1})
            r.push_back({[n] { Material m(hs::HuangParams<T>(), quadrature(0, 0, n)); }, "trt_per_tt"});
        // More TRT points than the material holds.
        r.push_back({[] { Material m(hs::HuangParams<T>(), quadrature(0, Material::kMaxTTPoints, Material::kMaxTrtPerTT)); },
                     "trt_per_tt"});
        return r;
    }
};

// ---- Yan et al.'s fur fibre ----

// The fur fibre: Chiang's cortex around a scattering medulla. Its scattered lobe's azimuthal
// table is piecewise constant (32 bins over |φ|): the furnace cubature meets its steps inside
// cells, which it resolves to ~1e-5 at depth 5 (the tolerance says 1e-4), and the chi-square
// cubature stops at depth 4, where a step costs under 1e-3 of a cell's expected count.
template <typename T> struct FurSpec : SpecBase<hs::FurFiber<T>, hs::FurMaterial<T>, 12, 60, true> {
    using Fiber = hs::FurFiber<T>;
    using Material = hs::FurMaterial<T>;
    static constexpr double kFurnaceTolerance = 1e-4;

    static hs::FurParams<T> params(const hs::FiberParams<T>& cortex, double kappa, double sigma_s, double g, double sa_m) {
        hs::FurParams<T> p;
        p.cortex = cortex;
        p.kappa = T(kappa);
        p.sigma_s = T(sigma_s);
        p.g = T(g);
        p.sigma_a_medulla = glm::vec<3, T>(glm::dvec3(sa_m, 0.5 * sa_m, 0.2 * sa_m));
        return p;
    }
    static std::string label(double kappa, double sigma_s, double g, double sa_m) {
        return "κ " + std::to_string(kappa) + " σs " + std::to_string(sigma_s) + " g " + std::to_string(g) + " σa^m " +
               std::to_string(sa_m);
    }
    static Instance<Fiber> make(const hs::FurParams<T>& p, double h, std::string name) {
        return make_instance<Fiber>(std::make_shared<const Material>(p), std::move(name) + " h " + std::to_string(h), T(h));
    }
    // The d'Eon family's random cortex around a medulla of κ 0–0.95, σs^m 0–20, g ±0.9 and
    // σa^m on every third k.
    static Instance<Fiber> random(std::mt19937_64& rng, int k) {
        std::uniform_real_distribution<double> uni(0, 1);
        const hs::FiberParams<T> cortex = random_params<T>(rng, k);
        const double kappa = 0.95 * uni(rng), sigma_s = 20 * uni(rng), g = -0.9 + 1.8 * uni(rng);
        const double sa_m = k % 3 == 0 ? 3 * uni(rng) : 0;
        const double h = -1 + 2 * uni(rng);
        return make(params(cortex, kappa, sigma_s, g, sa_m), h, "random " + std::to_string(k));
    }
    // No medulla, one filling the fibre densely, a barely scattering and a dense absorbing
    // one, around the d'Eon family's extreme cortices at the tilt's limit; h = -1, 0, 1 share
    // a material. The medulla tables, nearly all of the sweep's time (up to a second each
    // for the dense medullas), do not depend on the smooth cortex's β_m: per medulla and
    // cortex σa the first material's tables are built and saved, and the other β_m load them
    // (FurMaterial::load, bit for bit the tables the constructor builds: fur_tables_test).
    static std::vector<Instance<Fiber>> extremes() {
        std::vector<Instance<Fiber>> r;
        const double medullas[][4] = {{0, 0, 0, 0}, {0.999999, 200, 0.99, 0}, {0.5, 1e-6, -0.99, 50}, {0.9, 50, 0, 50}};
        // A name of this process's own: other test processes may sweep at the same time.
        const std::string stem = ::testing::TempDir() + "hairscatter_fur_extremes_" + std::to_string(sizeof(T)) + "_" +
                                 std::to_string(std::random_device()()) + "_";
        std::vector<std::string> files;
        for (const auto& m : medullas)
            for_extreme_params<T>({0.3}, {22.5}, [&](const hs::FiberParams<T>& cortex, const std::string& l) {
                const hs::FurParams<T> p = params(cortex, m[0], m[1], m[2], m[3]);
                const std::string file = stem + std::to_string(&m - medullas) + (cortex.sigma_a.x > T(0) ? "_absorbing" : "_clear");
                std::shared_ptr<const Material> material;
                if (std::find(files.begin(), files.end(), file) == files.end()) {
                    material = std::make_shared<const Material>(p);
                    material->save(file);
                    files.push_back(file);
                } else {
                    material = std::make_shared<const Material>(Material::load(p, file));
                }
                for (double h : {-1.0, 0.0, 1.0})
                    r.push_back(make_instance<Fiber>(material, l + " " + label(m[0], m[1], m[2], m[3]) + " h " + std::to_string(h), T(h)));
            });
        for (const std::string& f : files) std::remove(f.c_str());
        return r;
    }
    // Medullas small to filling, thin to dense, g from -0.5 to 0.8, θo from 0 to ±85°, offsets
    // that meet the medulla and one that misses it.
    static std::vector<Chi2Case<Fiber>> chi2_cases() {
        std::vector<Chi2Case<Fiber>> r;
        const double grid[][8] = {{0.6, 10, 0, 0, 0.3, 30, 0.3, 0.3}, {0.9, 1, 0.5, 1, -0.7, 60, 0.2, 0.5},
                                  {0.3, 5, -0.5, 0, 0.9, -20, 0.5, 0.3}, {0.8, 30, 0.8, 0.5, 0.0, 85, 0.4, 0.7}};
        for (const auto& c : grid) {
            const hs::FiberParams<T> cortex = fiber_params<T>(c[6], c[7], 2, glm::dvec3(0.4, 0.24, 0.12));
            r.push_back({make(params(cortex, c[0], c[1], c[2], c[3]), c[4], label(c[0], c[1], c[2], c[3])), c[5]});
        }
        return r;
    }
    static chi2::Options chi2_options() {
        chi2::Options o;
        o.num_tests = 8;
        o.max_depth = 4;
        return o;
    }
    static Instance<Fiber> lossless() {
        return make(params(fiber_params<T>(0.3, 0.3, 2, glm::dvec3(0)), 0.6, 5, 0.3, 0), 0.3, "lossless");
    }
    static std::vector<Invalid> invalid() {
        std::vector<Invalid> r;
        auto add = invalid_adder(r, hs::FurParams<T>(), [](const hs::FurParams<T>& p) { Material m(p); });
        add("kappa", [](auto& p) { p.kappa = T(1); });
        add("kappa", [](auto& p) { p.kappa = T(-0.5); });
        add("sigma_s", [](auto& p) { p.sigma_s = T(-1); });
        add("sigma_a_medulla.b", [](auto& p) { p.sigma_a_medulla.b = std::numeric_limits<T>::infinity(); });
        add("g", [](auto& p) { p.g = T(1); });
        add("eta", [](auto& p) { p.cortex.eta = T(1); });
        return r;
    }
};

}  // namespace specs
