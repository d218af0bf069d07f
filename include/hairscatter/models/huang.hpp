// hairscatter — Huang, Hullin & Hanika 2022's microfacet-based fiber: a far-field fiber of
// elliptical cross-section whose surface is a rough dielectric (GGX microfacets about the
// cuticle-tilted "mesonormal"), R reflected at the surface, TT and TRT refracted and
// reflected through microfacets on their way through the fiber, and every higher order
// lumped into one residual lobe (docs/theory.md §3.6, docs/models.md).
//
// Deterministic: eval integrates the cross-section and the internal microfacet normals by
// fixed quadrature rules (three knobs: the R rule's offset nodes, the TT and TRT lattices'
// points), draws no random
// numbers, and sample() draws from exactly the density pdf() returns.
#pragma once

#include <cmath>
#include <algorithm>
#include <iterator>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../fiber/ellipse.hpp"
#include "../fiber/frame.hpp"
#include "../fiber/params.hpp"
#include "../lobes/lobe_controls.hpp"
#include "../lobes/longitudinal.hpp"
#include "../lobes/microfacet.hpp"
#include "../math/constants.hpp"
#include "../math/distributions.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"
#include "../math/quadrature.hpp"
#include "contract.hpp"
#include "huang_residual.hpp"

namespace hairscatter {

// The parameters of Huang et al. 2022's fiber (their Table 1 names in brackets).
template <typename T> struct HuangParams {
    T eta = T(1.55);                 // index of refraction [η], > 1
    T roughness = T(0.3);            // GGX α of the cuticle's microfacets [β], [kMinHuangRoughness, 1]
    T alpha = radians(T(2));         // cuticle tilt of the mesonormal toward the tip [α], |α| ≤ π/8
    glm::vec<3, T> sigma_a{T(0)};    // absorption per unit major semi-axis, RGB, ≥ 0 and finite
    T aspect_ratio = T(1);           // minor over major semi-axis [b/a], [kMinAspectRatio, 1]
    T orientation = T(0);            // the major axis' angle from the fiber frame's y axis, [-π, π]
};

// α below 0.02 leaves the far-field integral a comb of separate highlights even at the most
// offset nodes (kMaxNodes); smoother fibers are Chiang's near-field model's domain.
template <typename T> inline constexpr T kMinHuangRoughness = T(0.02);
// Human hair ranges from round (b/a = 1) to about 0.5 in tightly curled hair (eccentricity
// 0.85, b/a ≈ 0.53).
template <typename T> inline constexpr T kMinAspectRatio = T(0.5);

// Empty when valid, else one message per bad field naming it, its value and its range.
// Never throws; finiteness is read from the bits (fast-math safe).
template <typename T> std::string validate(const HuangParams<T>& p) {
    auto within = [](T x, T lo, T hi) { return is_finite(x) && x >= lo && x <= hi; };
    const T inf = std::numeric_limits<T>::max();
    bool ok = within(p.eta, T(1), inf) && p.eta > T(1) && within(p.roughness, kMinHuangRoughness<T>, T(1)) &&
              within(p.alpha, -kMaxCuticleTilt<T>, kMaxCuticleTilt<T>) &&
              within(p.aspect_ratio, kMinAspectRatio<T>, T(1)) && within(p.orientation, -kPi<T>, kPi<T>);
    for (int c = 0; c < 3; ++c) ok = ok && within(p.sigma_a[c], T(0), inf);
    if (ok) return std::string();
    std::ostringstream msg;
    auto check = [&](bool good, const char* name, double value, const char* range) {
        if (good) return;
        if (msg.tellp() > 0) msg << "; ";
        msg << name << " = " << value << " is outside its range " << range;
    };
    check(within(p.eta, T(1), inf) && p.eta > T(1), "eta", double(p.eta), "(1, inf) (finite)");
    check(within(p.roughness, kMinHuangRoughness<T>, T(1)), "roughness", double(p.roughness), "[0.02, 1]");
    check(within(p.alpha, -kMaxCuticleTilt<T>, kMaxCuticleTilt<T>), "alpha", double(p.alpha), "[-pi/8, pi/8] radians");
    const char* channel[3] = {"sigma_a.r", "sigma_a.g", "sigma_a.b"};
    for (int c = 0; c < 3; ++c) check(within(p.sigma_a[c], T(0), inf), channel[c], double(p.sigma_a[c]), "[0, inf) (finite)");
    check(within(p.aspect_ratio, kMinAspectRatio<T>, T(1)), "aspect_ratio", double(p.aspect_ratio), "[0.5, 1]");
    check(within(p.orientation, -kPi<T>, kPi<T>), "orientation", double(p.orientation), "[-pi, pi] radians");
    return msg.str();
}

// The quadrature of HuangFiber, three knobs (0: the automatic choice of each):
//   offset_nodes  the R rule: Gauss–Legendre nodes in γ (auto_nodes);
//   tt_points     the paths into the fiber: points of a rank-1 lattice over (h, u1, u2),
//                 the offset and the entry's visible normal (auto_tt_points);
//   trt_per_tt    internal reflections per path: with them the TRT paths are the points of
//                 a rank-1 lattice of N_TT × trt_per_tt points over (h, u1, u2, u1', u2'),
//                 (u1', u2') the visible normal that reflects inside (auto_trt_per_tt).
struct HuangQuadrature {
    int offset_nodes = 0;
    int tt_points = 0;
    int trt_per_tt = 0;
};

// Everything that depends only on the parameters, the quadrature and the lobe controls,
// built once on the host (the constructor throws std::invalid_argument naming a bad
// parameter, count or control). Trivially copyable, ~52 KB in float: copy it to device
// memory once and pass the fiber a pointer.
//
// The offset integral: a far-field ray hits the section at h ∈ (-1, 1) uniformly
// (fiber/ellipse.hpp); in γ = asin h (the rim goes like sqrt(1 - h²) and is smooth in γ)
// each offset is weighted by how much of the beam the section there intercepts, ∝ |A⁻¹c|
// max(0, v·n) = |A⁻¹v| cos γ per unit γ, n the section's own normal: the silhouette stops
// the beam, the cuticle tilt turns only the microfacets about the mesonormal m (the beam
// uniform in h of d'Eon et al. 2011's far-field integral; weighting by v·m instead, as
// this model did, put up to a third of the light at θo 75° on the rims). Where m turns
// away from v (v·m ≤ 0) the offset's light goes to the residual.
//
// Rules that integrate each path order jointly:
//   R    n Gauss–Legendre nodes in γ (the R lobe is closed-form in the normal);
//   TT   a rank-1 lattice of N_TT points over (h, u1, u2): u the entry's visible normal in
//        the unit square of lobes/microfacet.hpp (u1 the cap's azimuth, u2 its height), h
//        uniform as the beam is, so that the paths carry equal shares of it (uniform in γ
//        and weighted by cos γ, most of the paths sat where little light enters, and TT
//        was far lumpier: docs/models.md);
//   TRT  a rank-1 lattice of N_TRT = m N_TT points over (h, u1, u2, u1', u2'), (u1', u2')
//        the visible normal that reflects inside, whose generator is m times TT's in its
//        first three coordinates: TRT point k continues TT path k mod N_TT, so each TT path
//        reflects at m normals of its own and the TRT paths share TT's entries and chords.
// A lattice's N points are x_k = frac((k g + 1/2) / N) with the Korobov generator
// g = (1, a, a², …) mod N (TRT's last two: (b, b²) mod N_TRT) whose a (b) minimises the
// worst-case error P₂ (Sloan & Joe 1994) of the unshifted lattice, found at construction,
// and shifted by half a cell. (The tent map 1 - |2x - 1| of Hickernell 2002 on the
// offset and the heights measured worse here: it halves the distinct offsets, and the integrand
// has kinks anyway.) Unlike a product rule,
// every point has its own offset and its own normals, so TT and TRT are not a few shifted
// copies of the same lobes.
//
// The energies stay exact: the R rule fixes the light reflected at the surface,
// Σ_k ŵ_k E_out, and so the light transmitted, Σ_k ŵ_k (1 - E_out); the TT paths' weights
// ∝ (1 - F(v·h)) (the beam per unit h is uniform) are scaled to carry exactly that, and each path's exit
// splits its light into E_in(c₂) reflected, shared by its m internal normals ∝ F, and the
// rest refracted out. E(c) = ∫ F(v·h) D_v(h) dh,
// the share of the light arriving at cos c to the mesonormal that the interface reflects,
// outside (index η) and inside (1/η, with total internal reflection), comes from tables over
// kTableSize cosines built from a fine product rule.
template <typename T> class HuangMaterial {
  public:
    using V3 = glm::vec<3, T>;
    static constexpr int kLobes = 3;  // R, TT, TRT explicit; index 3 is the residual
    static constexpr int kMaxNodes = 128;
    static constexpr int kAutoNodes = 0;  // the automatic choice of any of the three knobs
    static constexpr int kMaxTTPoints = 1024;
    static constexpr int kMaxTrtPerTT = 8;
    static constexpr int kMaxTRTPoints = 2048;  // N_TT × trt_per_tt
    static constexpr int kTableSize = 129;
    static constexpr int kWidths = 9;
    static constexpr int kWideSize = 65;
    static constexpr double kWidthStep = 1.3;
    static constexpr double kInvLogWidthStep = 3.8114946867084014;  // 1 / ln 1.3
    // The residual's profile: rows at sin θo = −1 … 1, bins in sin θi (huang_residual.hpp).
    static constexpr int kResidualRows = 33;
    static constexpr int kResidualBins = 72;
    // The residual's azimuth (huang_residual::AzimuthTrace): rows at |θo| = 0°, 15°, …, 90°
    // (the last uniform: light along the axis has no azimuth), columns at wo's azimuth in the
    // section frame folded into [0°, 90°] by the ellipse's symmetries (every 22.5°), bins in
    // φ − φo over [−π, π). Each traced cell holds kAzimuthRays rays' exits, smoothed to their
    // Fourier series up to kAzimuthHarmonics, for the exits' noise (against the physical
    // fiber the default's mean error is 9.14, 9.03, 8.99 and 8.97 % at 2048, 4096, 8192 and
    // 16384 rays; 9.05 and 9.08 % with 2 and 6 harmonics; docs/models.md).
    static constexpr int kAzimuthRows = 7;
    static constexpr int kAzimuthCols = 5;
    static constexpr int kAzimuthBins = 48;
    static constexpr int kAzimuthRays = 4096;
    static constexpr int kAzimuthHarmonics = 4;

    // Offset nodes that resolve the R lobe: R's exit azimuth turns by 2 per unit γ, and the
    // rule's widest gap (at the centre) is π²/(2n) in γ: n = ⌈π²/(1.6 α)⌉ keeps neighbouring
    // nodes' highlights closer than ~1.25 α, the GGX reflection lobe's half width, in
    // [16, kMaxNodes] (α = 0.3: 21 nodes; 0.1: 62). The error this leaves is measured
    // against the brute-force reference in tests/huang_test.cpp and docs/tradeoff.md.
    static int auto_nodes(T roughness) {
        const double n = std::ceil(9.8696044010893586188 / (1.6 * double(roughness)));
        const int k = n > double(kMaxNodes) ? kMaxNodes : int(n);
        return k < 16 ? 16 : k;
    }
    // The lattices' sizes, chosen from the measured error against cost (tests/huang_test.cpp
    // prints it): N_TT = kDefaultTT at roughness 0.3 and above, growing as 1/α below it (the
    // lobes narrow and the points must follow) up to kMaxTRTPoints / kDefaultTrtPerTT.
    static int auto_tt_points(T roughness) {
        const double r = double(roughness);
        const double n = r >= 0.3 ? kDefaultTT : std::ceil(kDefaultTT * 0.3 / r);
        const double max = kMaxTRTPoints / kDefaultTrtPerTT;
        return n > max ? int(max) : int(n);
    }
    static int auto_trt_per_tt(T) { return kDefaultTrtPerTT; }

    explicit HuangMaterial(const HuangParams<T>& params, const HuangQuadrature& quadrature = HuangQuadrature(),
                           const LobeControls<T>& controls = LobeControls<T>())
        : HuangMaterial(params, quadrature, controls, nullptr) {}
    // The material for params with the tables of `like` wherever they would come out the
    // same. The interface, residual and azimuth tables depend on η, roughness, the cuticle
    // tilt and the aspect ratio alone, so a material that differs from `like` in absorption,
    // orientation, quadrature or lobe controls costs the lattice's setup (16 µs) instead of a
    // build (about 0.3 s; bench/results/huang_material_2026-12-08.txt): presets of one fiber,
    // or its colours. Any other difference builds the tables as the plain constructor does.
    // Validated the same way; the result is the plain constructor's material bit for bit.
    HuangMaterial(const HuangMaterial& like, const HuangParams<T>& params,
                  const HuangQuadrature& quadrature = HuangQuadrature(), const LobeControls<T>& controls = LobeControls<T>())
        : HuangMaterial(params, quadrature, controls, &like) {}
    // Whether materials of a and b share their tables (the constructor above reuses them).
    static bool same_tables(const HuangParams<T>& a, const HuangParams<T>& b) {
        return a.eta == b.eta && a.roughness == b.roughness && a.alpha == b.alpha && a.aspect_ratio == b.aspect_ratio;
    }

  private:
    HuangMaterial(const HuangParams<T>& params, const HuangQuadrature& quadrature, const LobeControls<T>& controls,
                  const HuangMaterial* like)
        : params_(params), controls_(controls) {
        const std::string m = validate(params);
        if (!m.empty()) HAIRSCATTER_THROW(std::invalid_argument("hairscatter: invalid Huang parameters: " + m));
        check_count("offset_nodes", quadrature.offset_nodes, kMaxNodes);
        check_count("tt_points", quadrature.tt_points, kMaxTTPoints);
        check_count("trt_per_tt", quadrature.trt_per_tt, kMaxTrtPerTT);
        const std::string c = validate(controls);
        if (!c.empty()) HAIRSCATTER_THROW(std::invalid_argument("hairscatter: invalid lobe controls: " + c));
        if (controls.alpha_override != 0u)
            HAIRSCATTER_THROW(std::invalid_argument(
                "hairscatter: HuangMaterial: alpha_override = " + std::to_string(controls.alpha_override) +
                " is not supported: the cuticle tilt is the mesonormal's, shared by every interface of every "
                "path (set HuangParams::alpha instead)"));
        for (int p = 0; p <= kLobes; ++p) lobe_weight_[p] = controls.weight(p);

        nodes_ = quadrature.offset_nodes == kAutoNodes ? auto_nodes(params.roughness) : quadrature.offset_nodes;
        tt_n_ = quadrature.tt_points == kAutoNodes ? auto_tt_points(params.roughness) : quadrature.tt_points;
        per_tt_ = quadrature.trt_per_tt == kAutoNodes ? auto_trt_per_tt(params.roughness) : quadrature.trt_per_tt;
        if (tt_n_ * per_tt_ > kMaxTRTPoints)
            HAIRSCATTER_THROW(std::invalid_argument(
                "hairscatter: HuangMaterial: tt_points × trt_per_tt = " + std::to_string(tt_n_) + " × " +
                std::to_string(per_tt_) + " is more than the " + std::to_string(kMaxTRTPoints) + " TRT points it holds"));
        section_ = EllipticalSection<T>(params.aspect_ratio, params.orientation);
        ggx_ = Ggx<T>(params.roughness);
        sin_tilt_ = T(std::sin(double(params.alpha)));
        cos_tilt_ = T(std::cos(double(params.alpha)));

        const GaussLegendre<double> gl(nodes_);
        const double half_pi = 1.57079632679489661923;
        for (int k = 0; k < nodes_; ++k) {
            // The middle node of an odd rule is 0 analytically; Newton leaves it at ~1e-17.
            const double gamma = nodes_ % 2 == 1 && k == nodes_ / 2 ? 0.0 : half_pi * gl.nodes[std::size_t(k)];
            h_[k] = T(std::sin(gamma));
            cos_gamma_[k] = T(std::cos(gamma));
            weight_[k] = T(half_pi * gl.weights[std::size_t(k)]);
        }

        long long g[3], b[2];
        korobov(tt_n_, g);
        for (int i = 0; i < tt_n_; ++i) tt_[i] = entry_point(tt_n_, i, g);
        const int n = tt_n_ * per_tt_;
        korobov_extension(tt_n_, per_tt_, g, b);
        for (int i = 0; i < tt_n_; ++i)
            for (int l = 0; l < per_tt_; ++l) {
                const int k = i + l * tt_n_;
                reflect_[i * per_tt_ + l] = normal_point(lattice(n, k, b[0]), lattice(n, k, b[1]));
            }

        // TT's kernel: each path stands for its cell of the lattice, 1/N_TT of the unit cube
        // over (h, u1, u2); its projection onto the entry normal's (u1, u2) spans N_TT^(-2/3)
        // (the cube's side N_TT^(-1/3) squared).
        entry_cell_ = T(std::pow(double(tt_n_), -2.0 / 3.0));
        // entry_row's limits: row j ≥ k + 1 where α² ≥ β² kWidthStep^(2k + 1) (the rounding of
        // exit_row), that is where entry_cell / (2π D_v) ≥ β² (kWidthStep^(2k + 1) − 1); only
        // the limits at α ≤ 1 count, since α stops at 1.
        const double beta2 = double(params.roughness) * double(params.roughness);
        row_limits_ = 0;
        for (int k = 0; k + 1 < kWidths; ++k) row_limit_[k] = std::numeric_limits<T>::max();
        for (int k = 0; k + 1 < kWidths; ++k) {
            const double a2 = beta2 * std::pow(kWidthStep, 2.0 * k + 1);
            if (a2 > 1) break;
            row_limit_[row_limits_++] = T(6.28318530717958647692 * (a2 - beta2));
        }
        if (like != nullptr && same_tables(like->params_, params)) {
            copy_tables(*like);
        } else {
            build_interface_tables();
            build_residual_profile();
            build_residual_azimuth();
        }
    }

  public:
    // The lobe controls with the default quadrature.
    HuangMaterial(const HuangParams<T>& params, const LobeControls<T>& controls)
        : HuangMaterial(params, HuangQuadrature(), controls) {}

    // E(c) = ∫ F(v·h, n) D_v(h) dh for v at cos c to the normal, n = η_t/η_i, in double by a
    // k-midpoint (azimuth u1) × k-point Gauss–Legendre (height u2) rule over D_v's unit
    // square, gl the k-point rule (the tables use k = kTableRule; tests/huang_test.cpp
    // measures the error against k = 1024). Leaving the denser side (n < 1) F has a kink
    // where v·h crosses the critical cosine sqrt(1 - n²) (total internal reflection below
    // it), which slows any product rule: each height line is cut there (found by a scan of
    // kKinkScan points and bisection) and every piece gets the k-point rule.
    static constexpr int kTableRule = 40;
    // The interfaces' totals: kWalksPerCosine walks of the microsurface at each of
    // kWalkCosines + 1 cosines, from fixed seeds (the same tables run after run). Against the
    // physical fiber the default measured a mean of 7.73 % with them, 7.70 % with 100000
    // walks at each of the 129 table cosines and 7.79 % with 4096 walks.
    static constexpr int kWalkCosines = 16;
    static constexpr int kWalksPerCosine = 8192;
    static constexpr std::uint64_t kWalkSeedOut = 0x51ed270b27d1ULL, kWalkSeedIn = 0x2545f4914f6cdd1dULL;
    static constexpr int kKinkScan = 16;
    static double mean_reflectance(double roughness, double c, double n, const GaussLegendre<double>& gl) {
        return interface_energies(roughness, c, n, gl).reflect_mean;  // the tables' own sum
    }

    // The product rule of mean_reflectance over D_v's unit square for v at cos c to m = z
    // (c in [-1, 1]: a ray that bounces on the microsurface can meet it from below its
    // horizon, where the spherical-cap sampler still draws D_v), calling visit(v, h, weight).
    template <typename Visit>
    static void visible_normal_rule(double roughness, double c, double n, const GaussLegendre<double>& gl, Visit&& visit) {
        const Ggx<double> ggx(roughness);
        const glm::dvec3 v(std::sqrt(std::max(0.0, 1 - c * c)), 0.0, c);
        const int k = int(gl.nodes.size());
        const double critical = n < 1 ? std::sqrt(1 - n * n) : -2.0;  // -2: no cut
        for (int i = 0; i < k; ++i) {
            const double u1 = (i + 0.5) / k;
            const auto gap = [&](double u2) { return glm::dot(v, ggx.sample_visible_local(v, u1, u2)) - critical; };
            double cuts[kKinkScan + 2];
            int n_cuts = 0;
            cuts[n_cuts++] = 0;
            if (n < 1) {
                double lo = 0, g_lo = gap(0);
                for (int j = 1; j <= kKinkScan; ++j) {
                    const double hi = double(j) / kKinkScan, g_hi = gap(hi);
                    if ((g_lo < 0) != (g_hi < 0)) {
                        double a = lo, b = hi;
                        for (int it = 0; it < 60; ++it) {
                            const double mid = 0.5 * (a + b);
                            if ((gap(mid) < 0) == (g_lo < 0)) a = mid;
                            else b = mid;
                        }
                        cuts[n_cuts++] = 0.5 * (a + b);
                    }
                    lo = hi;
                    g_lo = g_hi;
                }
            }
            cuts[n_cuts++] = 1;
            for (int piece = 0; piece + 1 < n_cuts; ++piece) {
                const double a = cuts[piece], width = cuts[piece + 1] - a;
                for (int j = 0; j < k; ++j) {
                    const double u2 = a + width * (0.5 + 0.5 * gl.nodes[std::size_t(j)]);
                    visit(v, ggx.sample_visible_local(v, u1, u2), width * 0.5 * gl.weights[std::size_t(j)] / k);
                }
            }
        }
    }

    // What one rough interface does with light from v at cos c to the mesonormal, n =
    // η_t/η_i, in single scattering: the reflection and transmission that no microfacet
    // shadows (reflection with the height-correlated G2, transmission with the scattered
    // direction's G1; Heitz 2014). The total reflectance, the light that a microfacet shadows
    // included, comes from the microsurface's random walk instead (build_interface_tables;
    // Heitz et al. 2016, docs/theory.md §3.6).
    // reflect_mean: E(c), mean_reflectance's sum, from the same visits (the material's
    // tables take it from here rather than a second pass of the rule).
    struct InterfaceEnergies {
        double reflect_single = 0, transmit_single = 0, reflect_total = 0, reflect_mean = 0;
    };
    static InterfaceEnergies interface_energies(double roughness, double c, double n, const GaussLegendre<double>& gl) {
        InterfaceEnergies r;
        const Ggx<double> ggx(roughness);
        const double g1_v = ggx.g1(c);
        visible_normal_rule(roughness, c, n, gl, [&](const glm::dvec3& v, const glm::dvec3& h, double w) {
            const double vh = glm::dot(v, h);
            const double f = fresnel_any(vh, n);
            r.reflect_mean += w * f;
            const glm::dvec3 o = 2 * vh * h - v;
            r.reflect_single += w * f * ggx.unshadowed_reflection(g1_v, o.z);
            if (f < 1) {
                const Refracted<double> t = refract_through(v, h, 1 / n);
                if (!t.ok) return;
                r.transmit_single += w * (1 - f) * ggx.g1(-t.o.z);
            }
        });
        return r;
    }

    // A visible normal's unit-square coordinates, u1 as its cosine and sine.
    struct NormalPoint {
        T cos_u1, sin_u1, u2;
    };
    // A lattice point's offset (h and cos γ = sqrt(1 − h²)) and entry normal.
    struct EntryPoint {
        T h, cos_gamma;
        NormalPoint normal;
    };

    HAIRSCATTER_HD const HuangParams<T>& params() const { return params_; }
    HAIRSCATTER_HD const LobeControls<T>& controls() const { return controls_; }
    // Lobe p's factor on its energy, gain_p × tint_p (1 without controls).
    HAIRSCATTER_HD const V3& lobe_weight(int p) const { return lobe_weight_[p]; }
    HAIRSCATTER_HD const EllipticalSection<T>& section() const { return section_; }
    HAIRSCATTER_HD const Ggx<T>& ggx() const { return ggx_; }
    // The residual's density over sin θi at sin θo (per unit sin θi; uniform in φ, so f's
    // share per solid angle is this over 2π): piecewise constant in kResidualBins bins, the
    // rows at kResidualRows values of sin θo mixed linearly.
    HAIRSCATTER_HD T residual_density(T sin_o, T sin_i) const {
        int r;
        const T t = residual_row(sin_o, r);
        T y = (clamp(sin_i, T(-1), T(1)) + T(1)) * T(0.5 * kResidualBins);
        int j = int(y);
        j = j < 0 ? 0 : (j > kResidualBins - 1 ? kResidualBins - 1 : j);
        return (T(1) - t) * residual_pdf_[r * kResidualBins + j] + t * residual_pdf_[(r + 1) * kResidualBins + j];
    }
    // sin θi drawn from residual_density(sin_o, ·): u1 picks one of the two rows, u2 inverts
    // its CDF.
    HAIRSCATTER_HD T sample_residual(T sin_o, T u1, T u2) const {
        int r;
        const T t = residual_row(sin_o, r);
        if (!(u1 < T(1) - t)) ++r;
        const T x = invert_cdf(residual_cdf_ + r * (kResidualBins + 1), kResidualBins, u2);
        return clamp(T(-1) + x * T(2.0 / kResidualBins), T(-1), T(1));
    }
    // The four azimuth cells around (|θo|, a) and their bilinear weights; flip: a was folded
    // by a mirror of the section, which turns φ into −φ.
    struct AzimuthMix {
        int cell[4];
        T w[4];
        bool flip;
    };
    HAIRSCATTER_HD AzimuthMix azimuth_mix(T sin_o, T a) const {
        AzimuthMix m;
        const T theta = elem::asin(clamp(sin_o < T(0) ? -sin_o : sin_o, T(0), T(1)));
        const T x = theta * T((kAzimuthRows - 1) / 1.57079632679489661923);
        int r = int(x);
        r = r < 0 ? 0 : (r > kAzimuthRows - 2 ? kAzimuthRows - 2 : r);
        const T tr = clamp(x - T(r), T(0), T(1));
        // The section is symmetric under a half turn (a → a + π, φ kept) and under the
        // mirrors in its axes (a → −a, φ → −φ): a into [0, π), then [0, π/2].
        T am = a < T(0) ? a + kPi<T> : a;
        if (am >= kPi<T>) am -= kPi<T>;
        m.flip = am > kHalfPi<T>;
        if (m.flip) am = kPi<T> - am;
        const T y = clamp(am, T(0), kHalfPi<T>) * T((kAzimuthCols - 1) / 1.57079632679489661923);
        int c = int(y);
        c = c < 0 ? 0 : (c > kAzimuthCols - 2 ? kAzimuthCols - 2 : c);
        const T tc = clamp(y - T(c), T(0), T(1));
        m.cell[0] = r * kAzimuthCols + c;
        m.cell[1] = m.cell[0] + 1;
        m.cell[2] = m.cell[0] + kAzimuthCols;
        m.cell[3] = m.cell[2] + 1;
        m.w[0] = (T(1) - tr) * (T(1) - tc);
        m.w[1] = (T(1) - tr) * tc;
        m.w[2] = tr * (T(1) - tc);
        m.w[3] = tr * tc;
        return m;
    }
    // The residual's density over φ = φi − φo (per radian; integrates to 1 over [−π, π)) for
    // wo at inclination sin_o and azimuth a in the section frame: the four cells around
    // (|θo|, a folded into [0, π/2]) mixed bilinearly, each piecewise constant in φ.
    HAIRSCATTER_HD T residual_azimuth_density(T sin_o, T a, T phi) const {
        return residual_azimuth_density(azimuth_mix(sin_o, a), phi);
    }
    HAIRSCATTER_HD T residual_azimuth_density(const AzimuthMix& m, T phi) const {
        if (m.flip) phi = -phi;
        int j = int((phi + kPi<T>) * T(kAzimuthBins / 6.28318530717958647692));
        j = j < 0 ? 0 : (j > kAzimuthBins - 1 ? kAzimuthBins - 1 : j);
        T d = T(0);
        for (int k = 0; k < 4; ++k) d += m.w[k] * azimuth_pdf_[m.cell[k] * kAzimuthBins + j];
        return d;
    }
    // φ drawn from residual_azimuth_density(sin_o, a, ·): u picks one of the four cells by its
    // weight and, rescaled, inverts that cell's CDF.
    HAIRSCATTER_HD T sample_residual_azimuth(T sin_o, T a, T u) const {
        return sample_residual_azimuth(azimuth_mix(sin_o, a), u);
    }
    HAIRSCATTER_HD T sample_residual_azimuth(const AzimuthMix& m, T u) const {
        int k = 0;
        T before = T(0);
        for (; k < 3; ++k) {
            if (m.w[k] > T(0) && u < before + m.w[k]) break;
            before += m.w[k];
        }
        while (k > 0 && !(m.w[k] > T(0))) --k;  // rounding past the last weight: the last with weight
        const T uu = m.w[k] > T(0) ? clamp((u - before) / m.w[k], T(0), T(1)) : T(0.5);
        const T x = invert_cdf(azimuth_cdf_ + m.cell[k] * (kAzimuthBins + 1), kAzimuthBins, uu);
        const T phi = clamp(-kPi<T> + x * T(6.28318530717958647692 / kAzimuthBins), -kPi<T>, kPi<T>);
        return m.flip ? -phi : phi;
    }
    // The residual's share of the azimuths |φ − centre| < π/2 (centre in [−π, π]): the
    // integral of residual_azimuth_density over that half. Host only (lobe_split).
    double residual_azimuth_share(T sin_o, T a, double centre) const {
        const AzimuthMix m = azimuth_mix(sin_o, a);
        const double pi = 3.14159265358979323846;
        if (m.flip) centre = -centre;
        double share = 0;
        for (int k = 0; k < 4; ++k) {
            if (!(m.w[k] > T(0))) continue;
            const T* cdf = azimuth_cdf_ + m.cell[k] * (kAzimuthBins + 1);
            // The CDF at x ∈ [−π, π], linear within a bin; the half wraps around ±π.
            const auto at = [&](double x) {
                const double y = (x + pi) / (2 * pi) * kAzimuthBins;
                int j = int(y);
                j = j < 0 ? 0 : (j > kAzimuthBins - 1 ? kAzimuthBins - 1 : j);
                const double f = std::min(1.0, std::max(0.0, y - j));
                return double(cdf[j]) + f * (double(cdf[j + 1]) - double(cdf[j]));
            };
            double lo = centre - pi / 2, hi = centre + pi / 2, s = 0;
            if (lo < -pi) s = at(hi) + (1 - at(lo + 2 * pi));
            else if (hi > pi) s = (1 - at(lo)) + at(hi - 2 * pi);
            else s = at(hi) - at(lo);
            share += double(m.w[k]) * s;
        }
        return share;
    }
    HAIRSCATTER_HD T sin_tilt() const { return sin_tilt_; }
    HAIRSCATTER_HD T cos_tilt() const { return cos_tilt_; }

    HAIRSCATTER_HD int nodes() const { return nodes_; }
    HAIRSCATTER_HD T node_h(int k) const { return h_[k]; }
    HAIRSCATTER_HD T node_cos_gamma(int k) const { return cos_gamma_[k]; }
    HAIRSCATTER_HD T node_weight(int k) const { return weight_[k]; }
    HAIRSCATTER_HD int tt_points() const { return tt_n_; }
    HAIRSCATTER_HD int trt_per_tt() const { return per_tt_; }
    HAIRSCATTER_HD int trt_points() const { return tt_n_ * per_tt_; }
    HAIRSCATTER_HD const EntryPoint& tt_point(int i) const { return tt_[i]; }
    // The share of D_v's unit square that one TT path's entry normal stands for.
    HAIRSCATTER_HD T entry_cell() const { return entry_cell_; }
    // The l-th internal normal of TT path i (TRT point i + l N_TT).
    HAIRSCATTER_HD const NormalPoint& reflect_point(int i, int l) const { return reflect_[i * per_tt_ + l]; }

    // E(c) outside and inside, linearly interpolated in c ∈ [0, 1]: the mean reflectance of
    // one microfacet event, shadowing ignored.
    HAIRSCATTER_HD T reflectance_outside(T c) const { return lookup(outside_, c); }
    HAIRSCATTER_HD T reflectance_inside(T c) const { return lookup(inside_, c); }
    // The interface's total reflectance with shadowing (interface_energies), outside and
    // inside: the share of the light that stays on its side.
    HAIRSCATTER_HD T total_reflectance_outside(T c) const { return lookup(total_out_, c); }
    HAIRSCATTER_HD T total_reflectance_inside(T c) const { return lookup(total_in_, c); }
    // The same of N cosines at once, in loops that vectorise (the table's cell found by
    // selects, the entries gathered).
    template <std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void reflectance_inside(const T (&c)[N], T (&e)[N]) const {
        for (int j = 0; j < int(N); ++j) e[j] = lookup_lane(inside_, c[j]);
    }
    template <std::size_t N>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void total_reflectance_inside(const T (&c)[N], T (&e)[N]) const {
        for (int j = 0; j < int(N); ++j) e[j] = lookup_lane(total_in_, c[j]);
    }
    // The lobes' scales: the reflection lobe from outside carries the total reflectance in
    // the shape of its unshadowed single scattering (total / single), the transmission lobe
    // leaving the fiber its total transmittance (1 − total_in) / transmit_single.
    HAIRSCATTER_HD T reflection_gain_outside(T c) const { return lookup(gain_r_out_, c); }
    HAIRSCATTER_HD T exit_gain(T c) const { return lookup(exit_gains_, c); }
    // Exit lobes wider than β (TT's kernel, HuangFiber): the roughness α_j = min(1, β
    // kWidthStep^j) of the row j nearest to `alpha` in log α (j < kWidths), and row j's gain
    // (1 − total_in(c)) / transmit_single(c, α_j), tabulated at kWideSize cosines, so that a
    // lobe of roughness α_j carries exactly the light the interface lets out (to the tables'
    // interpolation in c; the gain is far from linear in α past the critical angle, so a
    // lobe takes a row's roughness rather than one in between). Row 0 is β's own.
    HAIRSCATTER_HD int exit_row(T alpha) const {
        using std::log;
        // Rounded to the nearest row; table_cell keeps the index in range (NaN too).
        return table_cell(log(alpha / ggx_.alpha()) * T(kInvLogWidthStep) + T(0.5), kWidths - 1);
    }
    // The row of exit_row(sqrt(min(1, β² + entry_cell / (2π d)))) for a path whose entry
    // normal has D_v = d (α = 1 where d ≤ 0), found by comparing entry_cell with d times
    // each row's limit: no square root, division or logarithm per path. The same row but
    // where α lies within rounding of a boundary between rows (tests/huang_test.cpp).
    HAIRSCATTER_HD int entry_row(T d) const {
        if (!(d > T(0))) return row_limits_;
        int j = 0;
        for (int k = 0; k < row_limits_; ++k) j += entry_cell_ >= row_limit_[k] * d ? 1 : 0;
        return j;
    }
    // entry_row of N values of D_v at once, in a loop that vectorises: every limit compared
    // (those past row_limits_ are the largest T, passed only by a subnormal d, which the
    // last select caps): the same rows.
    template <std::size_t N>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void entry_row(const T (&d)[N], int (&row)[N]) const {
        for (int j = 0; j < int(N); ++j) {
            int r = 0;
            for (int k = 0; k < kWidths - 1; ++k) r += entry_cell_ >= row_limit_[k] * d[j] ? 1 : 0;
            row[j] = ((d[j] > T(0)) & (r < row_limits_)) ? r : row_limits_;
        }
    }
    HAIRSCATTER_HD T exit_row_roughness(int j) const { return wide_alpha_[j]; }
    HAIRSCATTER_HD T exit_gain(T c, int j) const {
        return j == 0 ? exit_gain(c) : lookup<kWideSize>(exit_gains_ + wide_offset(j), c);
    }
    // exit_gain(c[k], row[k]) of N exits at once, in a loop that vectorises (the row's table
    // and cell found by selects, the entries gathered): the same values.
    template <std::size_t N>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void exit_gain(const T (&c)[N], const int (&row)[N], T (&g)[N]) const {
        for (int k = 0; k < int(N); ++k) {
            const bool wide = row[k] > 0;
            const int base = wide ? wide_offset(row[k]) : 0;
            const T top = select(wide, T(kWideSize - 1), T(kTableSize - 1)), last = top - T(1);
            const T above = select(c[k] < T(0), T(0), c[k]);
            const T x = select(above > T(1), T(1), above) * top;
            const int i = base + int(select(x > T(0), select(x < last, x, last), T(0)));
            const T f = x - T(i - base);
            g[k] = exit_gains_[i] + f * (exit_gains_[i + 1] - exit_gains_[i]);
        }
    }
    // The same for the light entering: (1 − total_out) / transmit_single, so that each
    // offset passes its own total into the fiber (s_TT only corrects the rules' error).
    HAIRSCATTER_HD T entry_gain(T c) const { return lookup(gain_t_out_, c); }
    template <std::size_t N> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void entry_gain(const T (&c)[N], T (&g)[N]) const {
        for (int j = 0; j < int(N); ++j) g[j] = lookup_lane(gain_t_out_, c[j]);
    }

    // For the dual-scattering tables (dual/tables.hpp): lobe p peaks near θi = lobe_shift(p)
    // - θo, the first-order shifts of a tilted mesonormal (R 2α, TT -α, TRT -4α, as
    // Marschner et al. 2003's cuticle shifts), with variance lobe_variance(p): the R, TT,
    // TRT variances β², β²/2, 2β² of d'Eon et al. 2011 read with the microfacet roughness
    // as βm, and the residual's own 4β.
    HAIRSCATTER_HD T lobe_shift(int p) const {
        const T a = params_.alpha;
        return p == 0 ? T(2) * a : p == 1 ? -a : p == 2 ? T(-4) * a : T(0);
    }
    HAIRSCATTER_HD T lobe_variance(int p) const {
        const T b = params_.roughness;
        return p == 0 ? b * b : p == 1 ? T(0.5) * b * b : p == 2 ? T(2) * b * b : T(4) * b;
    }

  private:
    static constexpr int kDefaultTT = 64;
    static constexpr int kDefaultTrtPerTT = 2;
    static void check_count(const char* name, int n, int max) {
        if (!(n >= 0 && n <= max))
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: HuangMaterial: " + std::string(name) + " = " +
                                                    std::to_string(n) + " is outside its range [1, " +
                                                    std::to_string(max) + "] (or 0 for the automatic choice)"));
    }

    // frac(i g / N) in double.
    // frac((i g + 1/2) / N): the lattice shifted by half a cell, so that no point sits on the
    // edges (h = ±1, the cap's rim) and every coordinate is a midpoint rule of N points.
    static double lattice(int n, int i, long long g) { return (double((static_cast<long long>(i) * g) % n) + 0.5) / n; }
    static NormalPoint normal_point(double u1, double u2) {
        const double two_pi = 6.28318530717958647692;
        return {T(std::cos(two_pi * u1)), T(std::sin(two_pi * u1)), T(u2)};
    }
    static EntryPoint entry_point(int n, int i, const long long* g) {
        const double h = 2 * lattice(n, i, g[0]) - 1;
        return {T(h), T(std::sqrt(1 - h * h)), normal_point(lattice(n, i, g[1]), lattice(n, i, g[2]))};
    }
    // P₂ = -1 + (1/n) Σ_k Π_j (1 + 2π² B₂(x_kj)), B₂(x) = x² - x + 1/6, of the unshifted
    // rank-1 lattice of n points with generator g (d coordinates): the worst-case error of
    // lattice rules for the Korobov space of smoothness 2 (Sloan & Joe 1994). Stops once
    // the sum passes `stop` (n times the best P₂ + 1 so far).
    static double p2_sum(int n, const long long* g, int d, double stop) {
        const double two_pi2 = 19.739208802178717238;
        double sum = 0;
        for (int k = 0; k < n && sum < stop; ++k) {
            double prod = 1;
            for (int j = 0; j < d; ++j) {
                const double u = double((static_cast<long long>(k) * g[j]) % n) / n;
                prod *= 1 + two_pi2 * (u * u - u + 1.0 / 6.0);
            }
            sum += prod;
        }
        return sum;
    }
    static bool coprime(long long a, long long n) {
        while (n != 0) {
            const long long t = a % n;
            a = n;
            n = t;
        }
        return a == 1;
    }
    // TT's generator (1, a, a²) mod n minimising P₂; a and n - a are equivalent (B₂ is
    // symmetric), so a ≤ n/2. O(n²): 3 ms at n = 1024.
    static void korobov(int n, long long* g) {
        g[0] = g[1] = g[2] = 1;
        double best = std::numeric_limits<double>::max();
        for (long long a = 2; a <= n / 2; ++a) {
            if (!coprime(a, n)) continue;
            const long long c[3] = {1, a, a * a % n};
            const double sum = p2_sum(n, c, 3, best);
            if (sum < best) {
                best = sum;
                g[1] = c[1];
                g[2] = c[2];
            }
        }
    }
    // TRT's generator (m g, b, b²) mod N = m n: its first three coordinates are TT's lattice
    // (point k at TT point k mod n), b ≤ N/2 minimising P₂ of all five. O(N²): 20 ms at
    // N = 2048.
    static void korobov_extension(int n, int m, const long long* g, long long* b) {
        const long long big = static_cast<long long>(n) * m;
        b[0] = b[1] = 1;
        double best = std::numeric_limits<double>::max();
        for (long long a = 1; a <= big / 2 || a == 1; ++a) {
            if (!coprime(a, big)) continue;
            const long long c[5] = {m * g[0], m * g[1], m * g[2], a, a * a % big};
            const double sum = p2_sum(int(big), c, 5, best);
            if (sum < best) {
                best = sum;
                b[0] = c[3];
                b[1] = c[4];
            }
        }
    }

    // lookup's value with table_cell's and clamp's branches as selects.
    HAIRSCATTER_HD static HAIRSCATTER_FORCE_INLINE T lookup_lane(const T* table, T c) {
        constexpr T last = T(kTableSize - 2);
        const T above = select(c < T(0), T(0), c);
        const T x = select(above > T(1), T(1), above) * T(kTableSize - 1);
        const int i = int(select(x > T(0), select(x < last, x, last), T(0)));
        const T f = x - T(i);
        return table[i] + f * (table[i + 1] - table[i]);
    }
    template <int kSize = kTableSize> HAIRSCATTER_HD static T lookup(const T* table, T c) {
        const T x = clamp(c, T(0), T(1)) * T(kSize - 1);
        const int i = table_cell(x, kSize - 2);
        const T f = x - T(i);
        return table[i] + f * (table[i + 1] - table[i]);
    }

    HuangParams<T> params_;
    LobeControls<T> controls_;
    V3 lobe_weight_[kLobes + 1] = {V3(T(1)), V3(T(1)), V3(T(1)), V3(T(1))};
    EllipticalSection<T> section_;
    Ggx<T> ggx_;
    T sin_tilt_ = T(0), cos_tilt_ = T(1);
    T residual_pdf_[kResidualRows * kResidualBins] = {};
    T residual_cdf_[kResidualRows * (kResidualBins + 1)] = {};
    T azimuth_pdf_[kAzimuthRows * kAzimuthCols * kAzimuthBins] = {};
    T azimuth_cdf_[kAzimuthRows * kAzimuthCols * (kAzimuthBins + 1)] = {};
    // The trace of huang_residual.hpp per cell, smoothed to its Fourier series up to
    // kAzimuthHarmonics (only the cosines where a mirror of the section keeps wo: the round
    // section, and wo along either axis, a = 0 or π/2); every bin keeps 10⁻⁴ of a uniform
    // density. A round section's cells are the same in every column.
    void build_residual_azimuth() {
        const double pi = 3.14159265358979323846, b = double(params_.aspect_ratio);
        const huang_residual::AzimuthTrace trace(double(params_.eta), double(params_.roughness), double(params_.alpha), b);
        const bool round = b == 1;
        constexpr double kFloor = 1e-4;
        constexpr int n = kAzimuthBins;
        for (int r = 0; r < kAzimuthRows; ++r)
            for (int c = 0; c < kAzimuthCols; ++c) {
                const int cell = r * kAzimuthCols + c;
                std::vector<double> p(std::size_t(n), 1.0 / n);
                if (round && c > 0) {
                    for (int j = 0; j < n; ++j) p[std::size_t(j)] = double(azimuth_pdf_[r * kAzimuthCols * n + j]) * (2 * pi / n);
                } else if (r < kAzimuthRows - 1) {
                    const double theta = r * (pi / 2) / (kAzimuthRows - 1), a = c * (pi / 2) / (kAzimuthCols - 1);
                    const std::vector<double> x =
                        trace.profile(std::sin(theta), a, n, kAzimuthRays, 0x417a696dULL + std::uint64_t(cell) * 7919u);
                    double sum = 0;
                    for (double v : x) sum += v;
                    if (sum > 0) {
                        const bool mirror = round || c == 0 || c == kAzimuthCols - 1;
                        for (int k = 1; k <= kAzimuthHarmonics; ++k) {
                            double ck = 0, sk = 0;
                            for (int j = 0; j < n; ++j) {
                                const double phi = -pi + (j + 0.5) * 2 * pi / n;
                                ck += x[std::size_t(j)] / sum * std::cos(k * phi);
                                sk += x[std::size_t(j)] / sum * std::sin(k * phi);
                            }
                            if (mirror) sk = 0;
                            for (int j = 0; j < n; ++j) {
                                const double phi = -pi + (j + 0.5) * 2 * pi / n;
                                p[std::size_t(j)] += 2.0 / n * (ck * std::cos(k * phi) + sk * std::sin(k * phi));
                            }
                        }
                    }
                    double total = 0;
                    for (double& v : p) total += (v = std::max(0.0, v));
                    for (double& v : p) v = total > 0 ? (1 - kFloor) * v / total + kFloor / n : 1.0 / n;
                }
                double cum = 0;
                azimuth_cdf_[cell * (n + 1)] = T(0);
                for (int j = 0; j < n; ++j) {
                    azimuth_pdf_[cell * n + j] = T(p[std::size_t(j)] * (n / (2 * pi)));
                    cum += p[std::size_t(j)];
                    azimuth_cdf_[cell * (n + 1) + j + 1] = T(std::min(1.0, cum));
                }
                azimuth_cdf_[cell * (n + 1) + n] = T(1);
            }
    }
    // A piecewise constant density's inverse CDF: cdf holds n + 1 values from 0 to 1; the
    // position in bins, in [0, n], where it reaches u.
    static HAIRSCATTER_HD T invert_cdf(const T* cdf, int n, T u) {
        int lo = 0, hi = n;  // cdf[lo] ≤ u < cdf[hi]
        while (hi - lo > 1) {
            const int mid = (lo + hi) / 2;
            if (cdf[mid] <= u) lo = mid;
            else hi = mid;
        }
        const T width = cdf[lo + 1] - cdf[lo];
        T f = width > T(0) ? (u - cdf[lo]) / width : T(0.5);
        f = clamp(f, T(0), T(1));
        return T(lo) + f;
    }
    // The row below sin θo and the weight of the one above.
    HAIRSCATTER_HD T residual_row(T sin_o, int& r) const {
        const T x = (clamp(sin_o, T(-1), T(1)) + T(1)) * T(0.5 * (kResidualRows - 1));
        r = int(x);
        r = r < 0 ? 0 : (r > kResidualRows - 2 ? kResidualRows - 2 : r);
        return clamp(x - T(r), T(0), T(1));
    }
    // The chain of huang_residual.hpp per row; every bin keeps 10⁻⁴ of a uniform density, so
    // that no direction the sampler can reach has density 0 at a bin's edge.
    void build_residual_profile() {
        const huang_residual::Chain chain(double(params_.eta), double(params_.roughness), double(params_.alpha),
                                          kResidualBins);
        constexpr double kFloor = 1e-4;
        for (int r = 0; r < kResidualRows; ++r) {
            std::vector<double> p = chain.profile(-1 + 2.0 * r / (kResidualRows - 1));
            double sum = 0;
            for (double x : p) sum += x;
            for (double& x : p) x = sum > 0 ? (1 - kFloor) * x / sum + kFloor / kResidualBins : 1.0 / kResidualBins;
            double c = 0;
            residual_cdf_[r * (kResidualBins + 1)] = T(0);
            for (int j = 0; j < kResidualBins; ++j) {
                residual_pdf_[r * kResidualBins + j] = T(p[std::size_t(j)] * (0.5 * kResidualBins));
                c += p[std::size_t(j)];
                residual_cdf_[r * (kResidualBins + 1) + j + 1] = T(std::min(1.0, c));
            }
            residual_cdf_[r * (kResidualBins + 1) + kResidualBins] = T(1);
        }
    }
    int nodes_ = 0, tt_n_ = 0, per_tt_ = 0;
    T entry_cell_ = T(0);
    int row_limits_ = 0;
    T row_limit_[kWidths - 1] = {};
    T h_[kMaxNodes] = {}, cos_gamma_[kMaxNodes] = {}, weight_[kMaxNodes] = {};
    EntryPoint tt_[kMaxTTPoints] = {};
    NormalPoint reflect_[kMaxTRTPoints] = {};
    // The interface tables at kTableSize cosines in [0, 1]: E (one event), the totals with
    // shadowing, and the lobes' gains (interface_energies). A total is the microsurface's:
    // the single scattering that no microfacet shadows (closed form) plus what its random
    // walk reflects after two or more events (huang_residual::multiple_reflectance, at
    // kWalkCosines + 1 cosines, linear between them). The two-event rule that it replaced
    // ran 4-8 % high outside and 2-3 % low inside near grazing at roughness 0.3
    // (docs/models.md, "The interfaces' totals from the microsurface's walk").
    void build_interface_tables() {
        const double rough = double(params_.roughness), eta = double(params_.eta);
        const GaussLegendre<double> table_rule(kTableRule);
        double multiple_out[kWalkCosines + 1], multiple_in[kWalkCosines + 1];
        const huang_residual::Microsurface surface(rough);
        for (int j = 0; j <= kWalkCosines; ++j) {
            const double c = double(j) / kWalkCosines;
            multiple_out[j] = huang_residual::multiple_reflectance(surface, c, eta, kWalksPerCosine, kWalkSeedOut);
            multiple_in[j] = huang_residual::multiple_reflectance(surface, c, 1 / eta, kWalksPerCosine, kWalkSeedIn);
        }
        const auto multiple = [](const double* m, double c) {
            const double x = c * kWalkCosines;
            const int j = std::min(kWalkCosines - 1, int(x));
            return m[j] + (x - j) * (m[j + 1] - m[j]);
        };
        double last_gain_t = 1, last_gain_in = 1;
        for (int i = kTableSize - 1; i >= 0; --i) {
            const double c = double(i) / (kTableSize - 1);
            InterfaceEnergies o = interface_energies(rough, c, eta, table_rule);
            InterfaceEnergies n = interface_energies(rough, c, 1 / eta, table_rule);
            outside_[i] = T(o.reflect_mean);
            inside_[i] = T(n.reflect_mean);
            // At most 1: where the single scattering is nearly all (total internal reflection
            // at a small roughness) the line between two cosines could pass it.
            o.reflect_total = std::min(1.0, o.reflect_single + multiple(multiple_out, c));
            n.reflect_total = std::min(1.0, n.reflect_single + multiple(multiple_in, c));
            total_out_[i] = T(o.reflect_total);
            total_in_[i] = T(n.reflect_total);
            gain_r_out_[i] = T(o.reflect_single > 0 ? o.reflect_total / o.reflect_single : 1.0);
            // At grazing c nothing transmits singly; the gain of the nearest cosine that does.
            if (n.transmit_single > 1e-4) last_gain_t = (1 - n.reflect_total) / n.transmit_single;
            exit_gains_[i] = T(last_gain_t);
            if (o.transmit_single > 1e-4) last_gain_in = (1 - o.reflect_total) / o.transmit_single;
            gain_t_out_[i] = T(last_gain_in);
        }
        // The widened exits: the same total over a rougher interface's single transmission
        // (its G1 and its D_v), by the tables' rule; row 0 is the interface's own.
        wide_alpha_[0] = params_.roughness;
        for (int j = 1; j < kWidths; ++j) {
            const double a = std::min(1.0, rough * std::pow(kWidthStep, double(j)));
            wide_alpha_[j] = T(a);
            const Ggx<double> wide(a);
            double last = 1;
            for (int i = kWideSize - 1; i >= 0; --i) {
                const double c = double(i) / (kWideSize - 1);
                double single = 0;
                visible_normal_rule(a, c, 1 / eta, table_rule, [&](const glm::dvec3& v, const glm::dvec3& h, double w) {
                    const double f = fresnel_any(glm::dot(v, h), 1 / eta);
                    if (!(f < 1)) return;
                    const Refracted<double> t = refract_through(v, h, eta);
                    if (t.ok) single += w * (1 - f) * wide.g1(-t.o.z);
                });
                if (single > 1e-4) last = (1 - double(lookup(total_in_, T(c)))) / single;
                exit_gains_[wide_offset(j) + i] = T(last);
            }
        }
    }

    T outside_[kTableSize] = {}, inside_[kTableSize] = {};
    T total_out_[kTableSize] = {}, total_in_[kTableSize] = {};
    T gain_r_out_[kTableSize] = {}, gain_t_out_[kTableSize] = {};
    // exit_gain(c, j), one table after the other: row 0 at kTableSize cosines, rows 1 … at
    // kWideSize from wide_offset(j); and the rows' α_j.
    HAIRSCATTER_HD static constexpr int wide_offset(int j) { return kTableSize + (j - 1) * kWideSize; }
    T exit_gains_[kTableSize + (kWidths - 1) * kWideSize] = {};
    T wide_alpha_[kWidths] = {};

    // Every table that build_interface_tables, build_residual_profile and
    // build_residual_azimuth fill, from a material with the same_tables parameters.
    void copy_tables(const HuangMaterial& o) {
        using M = HuangMaterial;
        copy_arrays(o, &M::outside_, &M::inside_, &M::total_out_, &M::total_in_, &M::gain_r_out_, &M::gain_t_out_,
                    &M::exit_gains_, &M::wide_alpha_, &M::residual_pdf_, &M::residual_cdf_, &M::azimuth_pdf_,
                    &M::azimuth_cdf_);
    }
    template <typename... Arrays> void copy_arrays(const HuangMaterial& o, Arrays... member) {
        ((void)std::copy(std::begin(o.*member), std::end(o.*member), std::begin(this->*member)), ...);
    }
};

// A quadrature finer than the automatic one that scales with roughness as it does: the
// automatic offset nodes, `factor` times the automatic paths into the fiber (at most
// kMaxTTPoints) and up to `per_tt` internal reflections each (fewer where the paths would
// exceed kMaxTRTPoints TRT points). docs/models.md's finer setting is
// huang_scaled_quadrature(β): 128 × 4 at β ≥ 0.3, 384 × 4 at β = 0.1 (a fixed 128 × 4 has
// fewer paths than the automatic 192 × 2 there, and measured worse than it), 1024 × 2 at
// the smallest roughness.
template <typename T> HuangQuadrature huang_scaled_quadrature(T roughness, int factor = 2, int per_tt = 4) {
    using M = HuangMaterial<T>;
    HuangQuadrature q;
    q.offset_nodes = M::auto_nodes(roughness);
    const long long n = static_cast<long long>(M::auto_tt_points(roughness)) * (factor < 1 ? 1 : factor);
    q.tt_points = n > M::kMaxTTPoints ? M::kMaxTTPoints : int(n);
    const int most = M::kMaxTRTPoints / q.tt_points;
    q.trt_per_tt = per_tt < 1 ? 1 : (per_tt > most ? most : per_tt);
    return q;
}

// A quadrature coarser than the automatic one, scaling with roughness as it does: the
// automatic offset nodes, the automatic paths into the fiber divided by `divisor` (at least
// 8) and one internal reflection each. docs/performance.md times it against Blender
// Cycles' scheme and docs/models.md gives its error against the physical reference.
template <typename T> HuangQuadrature huang_fast_quadrature(T roughness, int divisor = 2) {
    using M = HuangMaterial<T>;
    HuangQuadrature q;
    q.offset_nodes = M::auto_nodes(roughness);
    const int n = M::auto_tt_points(roughness) / (divisor < 1 ? 1 : divisor);
    q.tt_points = n < 8 ? 8 : n;
    q.trt_per_tt = 1;
    return q;
}

// A quadrature as accurate as Blender Cycles' scheme for this model (one random normal per
// Simpson node, bench/reference/cycles_huang.hpp) at a fraction of its eval time: an
// eighth (`divisor`) of the automatic paths into the fiber (at least 4), as many offset
// nodes for R, one internal reflection each; 8 / 8 × 1 at β ≥ 0.3, 24 / 24 × 1 at β = 0.1.
// Against the physical fiber it is far coarser than the default (docs/models.md gives both,
// with Cycles' one-seed error; docs/performance.md the times), but it keeps what Cycles'
// scheme does not: no noise, the exact pdf and an albedo of 1 when lossless.
template <typename T> HuangQuadrature huang_cycles_class_quadrature(T roughness, int divisor = 8) {
    using M = HuangMaterial<T>;
    HuangQuadrature q;
    const int n = M::auto_tt_points(roughness) / (divisor < 1 ? 1 : divisor);
    q.tt_points = n < 4 ? 4 : n;
    q.offset_nodes = q.tt_points;
    q.trt_per_tt = 1;
    return q;
}

// The fiber. Same frame and convention as every model (contract.hpp): unit vectors in the
// fiber frame, wo toward the viewer, wi toward the light, eval with the cosine inside
// (∫ eval dωi = 1 for σa = 0). The light is traced from wo (reciprocity of the far field):
//
//   f(wo, wi) = W_R Σ_k ŵ_k R_k(wi) + W_TT s_TT Σ_i y_i A_1 TT_i(wi)
//             + W_TRT s_TT Σ_i Σ_l y_i A_1 r_il A_2 TRT_il(wi) + W_res E_res P(θi | θo) N(φ | wo),
//
// k the R rule's offset nodes (weights ŵ_k), i the TT lattice's paths, l each path's
// internal normals, W_p the lobe controls' gain × tint (1 without controls);
//   R_k   = F(v·h) D_v(h) / (4 v·h), h the half vector of wo and wi (Huang et al. 2022's
//           R lobe, with the visible normals of Heitz 2014);
//   TT, TRT = (1 - F(v·h)) D_v(h) |wi·h| / |η v + wi|², the refraction out of the fiber at
//           the exit's mesonormal, v the internal ray reversed (their TT and TRT, with the
//           generalised half vector and Jacobian of Walter et al. 2007 eqs. 16–17), with
//           D_v of path i's own roughness α_i ≥ β: the exit kernel of its entry cell
//           (entry_kernel), the gain keeping the exit's energy (HuangMaterial::exit_gain);
//   y_i   = (1 - F) at path i's entry normal (0 where v·m ≤ 0), A_1, A_2 the
//           chords' transmittances;
//   s_TT  = Σ_k ŵ_k (1 - E_out) / Σ_i y_i: the paths carry exactly the light the surface
//           transmits;
//   r_il  = E_in(c₂) F_l / Σ_l F_l, the exit's reflected share split over the normals;
//   E_res = what TRT's exit reflects, E_in(c₃) Σ_{n≥1} A_3^n R̄^(n-1) (1 - R̄) summed in
//           closed form, A_3 = sqrt(A_1 A_2) and R̄ the Fresnel reflectance at the mesonormal
//           (Chiang et al. 2016's geometric series); plus whatever the geometry cannot
//           follow (a chord that does not enter, an exit hit from behind its mesonormal);
//   P, N  = the residual's profile over sin θi (a chain of the light inside a round section)
//           and its azimuth over φ = φi − φo (a trace of the elliptical section), both
//           through the Smith microsurface's random walk (huang_residual.hpp).
// Shadowing–masking of the scattered direction is left out: every microfacet event keeps
// its energy, which is the energy compensation the paper adds taken to its limit.
//
// sample picks a lobe with probability ∝ its energy's channel mean, then one of its path
// ends (an R node, a TT path or a TRT point) ∝ that end's, then a direction from the end's lobe:
// a visible normal and its reflection (R), a visible normal and the refraction through it —
// or its reflection where it totally reflects (TT, TRT) — or the residual's profile in θi
// and its azimuth's table in φ. pdf is that mixture's density, computed in the same walk as f.
//
// Holds a pointer to the material, which must outlive the fiber and its at(wo) objects (a
// temporary material is rejected at compile time; on a GPU, a pointer to a device copy).
// Each stateless call walks every path (n + N_TT + N_TT m ends), so the cost is linear in
// the offset nodes and the TT points, and in m (docs/tradeoff.md). Almost all of that walk
// depends on wo alone: at(wo) walks once and keeps the ends (up to kBoundEnds of them, each
// 68 bytes in float, 136 in double), and its eval, pdf and sample then evaluate only the
// ends' lobes at wi, with the stateless calls' results: bit for bit without FMA
// contraction (tests/huang_test.cpp); with it (-march=native) the compiler fuses
// multiply-adds differently in the two and they differ by rounding (docs/performance.md
// gives the measured bound). A material with more ends than kBoundEnds, or kBoundEnds = 0, binds only the
// outgoing terms and walks per call. The stateless sample, which passes over the ends three
// times, keeps one walk's ends the same way (on the stack: up to 52 KB in float, 104 KB in
// double) and so walks once. The default, HAIRSCATTER_HUANG_BOUND_ENDS, is 768
// (52 KB in float: every automatic quadrature down to β = 0.1) on the host and 0 under
// nvcc, whose threads' stacks are too small for it; HuangFiber<T, K> with different K are
// different types, so translation units compiled by both compilers stay consistent.
#ifndef HAIRSCATTER_HUANG_BOUND_ENDS
#if defined(__CUDACC__)
#define HAIRSCATTER_HUANG_BOUND_ENDS 0
#else
#define HAIRSCATTER_HUANG_BOUND_ENDS 768
#endif
#endif
template <typename T, int kBoundEnds_ = HAIRSCATTER_HUANG_BOUND_ENDS>
class HuangFiber : public FiberModel<HuangFiber<T, kBoundEnds_>, T> {
  public:
    using V2 = glm::vec<2, T>;
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    using Material = HuangMaterial<T>;
    static constexpr int kLobes = Material::kLobes;
    static constexpr int kBoundEnds = kBoundEnds_;
    static_assert(kBoundEnds >= 0, "HuangFiber: kBoundEnds, the path ends at(wo) keeps, is >= 0");
    using LobeSplit = hairscatter::LobeSplit<T, kLobes>;

    HAIRSCATTER_HD explicit HuangFiber(const Material& material)
        : mat_(&material), sigma_a_(material.params().sigma_a) {}
    // The material's geometry with this hit's absorption (melanin or a dye that varies per
    // strand or along it; its own sigma_a is not read). No table of the material depends on
    // the absorption, so this is the material built with sigma_a, bit for bit, at the cost of
    // three numbers instead of a build. A NaN, infinite or negative channel absorbs nothing
    // (device-callable, so no throw; HuangMaterial's constructor validates on the host).
    HAIRSCATTER_HD HuangFiber(const Material& material, const V3& sigma_a) : mat_(&material) {
        for (int c = 0; c < 3; ++c) sigma_a_[c] = is_finite(sigma_a[c]) && sigma_a[c] > T(0) ? sigma_a[c] : T(0);
    }
    HuangFiber(const Material&&) = delete;
    HuangFiber(const Material&&, const V3&) = delete;

    HAIRSCATTER_HD const Material& material() const { return *mat_; }
    // The absorption the fiber's paths use: the material's, or the one given per hit.
    HAIRSCATTER_HD const V3& sigma_a() const { return sigma_a_; }

    // Σ of every path end's energy: the directional albedo, exact up to the reflectance
    // tables' interpolation (each lobe integrates to its end's energy).
    // A non-finite or zero wo gives 0; any other length is normalised.
    HAIRSCATTER_HD V3 albedo(V3 wo) const {
        if (!unit_direction(wo)) return V3(T(0));
        return albedo_from(outgoing<false>(wo));
    }

    // Path i's entry into the fiber from wo (i < material().tt_points()) as the walk
    // computes it, in the section frame: the circle point it enters at, the refracted
    // direction, its weight (0 where nothing enters) and its exit kernel's row. For tests and
    // tools; a zero or non-finite wo gives weight 0.
    struct Entry {
        V2 c;
        V3 t;
        T weight;
        int row;
    };
    HAIRSCATTER_HD Entry entry(V3 wo, int i) const {
        Entry r{V2(T(0)), V3(T(0)), T(0), 0};
        if (!unit_direction(wo) || i < 0 || i >= mat_->tt_points()) return r;
        const Outgoing o = outgoing<false>(wo);
        if (!o.visible) return r;
        EntryLanes e;
        const int j = i % kEntryLanes;
        enter_lanes(o, i - j, e);
        return Entry{V2(e.c_x[j], e.c_y[j]), V3(e.t_x[j], e.t_y[j], e.t_z[j]), e.y[j], e.row[j]};
    }

    // Per lobe: its energy A_p(wo) (exact, as albedo) and the fraction of it scattered into
    // the half |φ - centre| < π/2 (φ relative to wo's azimuth), channel sums: the lobe's f
    // integrated over that half by a Gauss–Legendre product rule in θi × φ
    // (dω = cos θi dθi dφ; kSplitNodes per panel, 12 panels in θi and 10 in φ between the
    // half's edges), over A_p; the residual's is its azimuth table's integral over the half. Complementary halves add up to
    // ∫ f_p / A_p, 1 within the reflectance tables' error and the rule's (the refracted lobes
    // end abruptly where no microfacet refracts): 0.6 % at worst, near grazing θo
    // (tests/huang_test.cpp). Host only; 4320 evaluations of the lobes per call, for the
    // dual-scattering tables.
    static constexpr int kSplitNodes = 6;
    LobeSplit lobe_split(V3 wo, T centre = T(0)) const {
        LobeSplit r = empty_split();
        if (!unit_direction(wo)) return r;
        const Outgoing o = outgoing<false>(wo);
        const Lobes e = lobes<false, false>(o, V3(T(0)), T(0));
        static const GaussLegendre<double> gl(kSplitNodes);
        const double pi = 3.14159265358979323846;
        // Panels graded toward the half's edges φ = centre ± π/2, where the forward lobes'
        // tails and abrupt ends cross into it: edges at (π/2) sin(π x / 2), x uniform.
        const int panels_theta = 12, panels_phi = 10;
        double back[std::size_t(kLobes)] = {};
        for (int a = 0; a < panels_theta * kSplitNodes; ++a) {
            const double x = 0.5 + 0.5 * gl.nodes[std::size_t(a % kSplitNodes)];
            const double theta = -pi / 2 + pi * (a / kSplitNodes + x) / panels_theta;
            const double wt = pi / panels_theta * 0.5 * gl.weights[std::size_t(a % kSplitNodes)] * std::cos(theta);
            for (int b = 0; b < panels_phi * kSplitNodes; ++b) {
                const int j = b / kSplitNodes;
                const double lo = pi / 2 * std::sin(pi / 2 * (-1 + 2.0 * j / panels_phi));
                const double hi = pi / 2 * std::sin(pi / 2 * (-1 + 2.0 * (j + 1) / panels_phi));
                const double phi = double(centre) + lo + (hi - lo) * (0.5 + 0.5 * gl.nodes[std::size_t(b % kSplitNodes)]);
                const double w = wt * (hi - lo) * 0.5 * gl.weights[std::size_t(b % kSplitNodes)];
                const V3 wi = direction_from_azimuth(wo, T(std::sin(theta)), T(phi));
                const Lobes f = lobes<true, false>(o, mat_->section().to_section(wi), wi.x);
                for (int p = 0; p < kLobes; ++p) back[p] += w * double(f.f[p].x + f.f[p].y + f.f[p].z);
            }
        }
        for (int p = 0; p <= kLobes; ++p) {
            r.a[p] = e.energy[p];
            const double total = double(e.energy[p].x + e.energy[p].y + e.energy[p].z);
            if (p < kLobes && total > 0) r.backward[p] = T(std::min(1.0, std::max(0.0, back[p] / total)));
        }
        r.backward[kLobes] = T(mat_->residual_azimuth_share(o.sin_o, elem::atan2(o.v.z, o.v.y), double(centre)));
        return r;
    }

    // lobe_split(wo, ψ_j) for every centre ψ_j = π j / (n_psi - 1) at once, as the
    // dual-scattering tables need them (dual/tables.hpp uses it when a fiber offers it):
    // each path end's lobe is sampled through its own microfacet sampler at kWindowSamples
    // points of a golden-ratio lattice over the visible normal, weighted by f / q there (the
    // Fresnel factor and the shadowing), and the end's energy is split between the halves
    // in proportion. Energies are exact, as lobe_split's; a half's share differs from
    // lobe_split's cubature by ~1e-2 at most (tests/huang_test.cpp). Host only; about 1 % of
    // n_psi calls of lobe_split.
    static constexpr int kWindowSamples = 256;
    std::vector<LobeSplit> lobe_windows(const V3& wo, int n_psi) const {
        std::vector<LobeSplit> out(std::size_t(n_psi > 1 ? n_psi : 1), empty_split());
        if (!is_finite(wo)) return out;
        const Outgoing o = outgoing<false>(wo);
        const Lobes e = lobes<false, false>(o, V3(T(0)), T(0));
        const double pi = 3.14159265358979323846;
        const T eta = mat_->params().eta;
        std::vector<double> back(out.size() * kLobes, 0.0);
        double total[std::size_t(kLobes)] = {};
        const auto visit = [&](const End& end) {
            const double energy = double(mean(end.energy));
            if (!(energy > 0)) return;
            const TangentFrame<T> frame(end.m, end.v);
            const V3 v_local = frame.to_local(end.v);
            double w_sum = 0;
            std::vector<std::pair<double, double>> samples;  // (φ, weight)
            samples.reserve(kWindowSamples);
            for (int k = 0; k < kWindowSamples; ++k) {
                const T u1 = T((k + 0.5) / kWindowSamples);
                const T u2 = T(std::fmod(k * 0.6180339887498949 + 0.5 / kWindowSamples, 1.0));
                const Ggx<T> ggx(end.alpha);
                const V3 h = frame.to_world(ggx.sample_visible_local(v_local, u1, u2));
                V3 dir;
                double w;
                if (end.p == 0) {
                    dir = glm::normalize(reflect_about(end.v, h));
                    w = double(fresnel_any(glm::dot(end.v, h), eta) *
                               mat_->ggx().unshadowed_reflection(end.g1_v, glm::dot(dir, end.m)));
                } else {
                    const Refracted<T> r = refract_through(end.v, h, eta);
                    if (!r.ok) continue;
                    dir = glm::normalize(r.o);
                    w = double((T(1) - fresnel_any(glm::dot(end.v, h), T(1) / eta)) * ggx.g1(-glm::dot(dir, end.m)));
                }
                if (!(w > 0)) continue;
                const V3 wi = mat_->section().from_section(dir);
                samples.push_back({double(relative_azimuth(wo, wi)), w});
                w_sum += w;
            }
            if (!(w_sum > 0)) return;
            total[end.p] += energy;
            for (std::size_t j = 0; j < out.size(); ++j) {
                const double centre = out.size() > 1 ? pi * double(j) / double(out.size() - 1) : 0.0;
                double in = 0;
                for (const auto& x : samples) {
                    double d = std::fabs(x.first - centre);
                    if (d > pi) d = 2 * pi - d;
                    if (d < 0.5 * pi) in += x.second;
                }
                back[j * kLobes + std::size_t(end.p)] += energy * in / w_sum;
            }
        };
        RuleTotals unused;
        walk_r(o, unused, visit);
        walk_paths(o, unused, visit);
        for (std::size_t j = 0; j < out.size(); ++j)
            for (int p = 0; p <= kLobes; ++p) {
                out[j].a[p] = e.energy[p];
                if (p < kLobes && total[p] > 0)
                    out[j].backward[p] = T(std::min(1.0, std::max(0.0, back[j * kLobes + std::size_t(p)] / total[p])));
            }
        for (std::size_t j = 0; j < out.size(); ++j) {
            const double centre = out.size() > 1 ? pi * double(j) / double(out.size() - 1) : 0.0;
            out[j].backward[kLobes] = T(mat_->residual_azimuth_share(o.sin_o, elem::atan2(o.v.z, o.v.y), centre));
        }
        return out;
    }

  private:
    friend class FiberModel<HuangFiber, T>;

    // No energy, each lobe split evenly: what lobe_split and lobe_windows start from.
    static LobeSplit empty_split() { return empty_lobe_split<T, kLobes>(); }
    friend class BoundFiber<HuangFiber>;

    // The terms that depend on wo only: wo in the section frame, the far-field view and the
    // R rule's normaliser.
    struct Outgoing {
        V3 v;
        T sin_o, cos_o;
        typename EllipticalSection<T>::View view;
        typename Material::AzimuthMix azimuth;  // the residual's azimuth cells at wo
        T inv_total;   // 1 / Σ_k W_k cos γ_k (hit's beam)
        bool visible;  // false: no node sees its mesonormal (|θo| within α of a pole)
    };

    // One end of a path: the light that reaches the last interface (prefix), what that
    // interface scatters in all (energy), in the units of its rule (before s_TT and the
    // controls), and how: R (p = 0) reflects off the outside, TT and TRT (1, 2) refract
    // out. v is on the incident side of the interface normal m, cos_v = v·m > 0.
    struct End {
        int p;
        V3 prefix, energy;
        V3 v, m;
        T cos_v;
        T gain;  // the lobe's scale: its total energy over its unshadowed single scattering
        T g1_v;  // R's G1(v) (its shadowing of the scattered direction depends on it); 0 at the
                 // exits, whose lobes shadow by G1 of the scattered direction alone
        T alpha;  // the lobe's GGX roughness
    };

    // What a walk adds up besides its ends: the paths' weights y_i, what goes to the
    // residual, and the light the surface transmits (R's rule).
    struct RuleTotals {
        V3 residual{T(0)};
        T norm = T(0), transmitted = T(0);
    };

    // What at(wo) keeps: the outgoing terms, the two walks' totals and their ends in order
    // (R's first); n < 0 where the ends would not fit, and every call walks.
    struct Bound {
        Outgoing o;
        RuleTotals r, paths;
        int n_r, n;
        End ends[std::size_t(kBoundEnds > 0 ? kBoundEnds : 1)];
    };

    // The walks over the path ends, live from the outgoing terms or replayed from a Bound:
    // the same ends in the same order, so that f and pdf come out the same.
    struct Live {
        const HuangFiber* fiber;
        const Outgoing* o;
        HAIRSCATTER_HD const Outgoing& outgoing() const { return *o; }
        template <typename Visit> HAIRSCATTER_HD void r(RuleTotals& s, Visit&& visit) const { fiber->walk_r(*o, s, visit); }
        template <typename Visit> HAIRSCATTER_HD void paths(RuleTotals& s, Visit&& visit) const {
            fiber->walk_paths(*o, s, visit);
        }
    };
    struct Replay {
        const Bound* b;
        HAIRSCATTER_HD const Outgoing& outgoing() const { return b->o; }
        template <typename Visit> HAIRSCATTER_HD void r(RuleTotals& s, Visit&& visit) const {
            s = b->r;
            for (int k = 0; k < b->n_r; ++k) visit(b->ends[k]);
        }
        template <typename Visit> HAIRSCATTER_HD void paths(RuleTotals& s, Visit&& visit) const {
            s = b->paths;
            for (int k = b->n_r; k < b->n; ++k) visit(b->ends[k]);
        }
    };
    HAIRSCATTER_HD Live live(const Outgoing& o) const { return Live{this, &o}; }

    // at(wo)'s state (the contract's bind): one walk, its ends kept.
    template <int K = kBoundEnds, typename std::enable_if<(K > 0), int>::type = 0>
    HAIRSCATTER_HD Bound bind(const V3& wo) const {
        return bind_from(outgoing<true>(wo));
    }
    // Whether the material's path ends fit in a Bound.
    HAIRSCATTER_HD bool ends_fit() const {
        const long long most = static_cast<long long>(mat_->nodes()) +
                               static_cast<long long>(mat_->tt_points()) * (1 + mat_->trt_per_tt());
        return most <= kBoundEnds;
    }
    template <int K = kBoundEnds, typename std::enable_if<(K > 0), int>::type = 0>
    HAIRSCATTER_HD Bound bind_from(const Outgoing& o) const {
        Bound b;
        b.o = o;
        b.n_r = 0;
        b.n = -1;
        if (!ends_fit()) return b;
        b.n = 0;
        const auto keep = [&](const End& e) { b.ends[b.n++] = e; };
        walk_r(b.o, b.r, keep);
        b.n_r = b.n;
        walk_paths(b.o, b.paths, keep);
        return b;
    }
    // The stateless sample (the contract's sample_fresh): sample_walk passes over the path
    // ends three times (the lobes' energies, the chosen end, f and pdf at the sampled wi),
    // which live would be three walks; the ends of one walk are kept on the stack instead,
    // as at(wo) keeps them, and replayed: the results of at(wo).sample. Where the ends do
    // not fit it walks per pass, and with kBoundEnds = 0 (nvcc) the contract's sample_from
    // does. Under -ffast-math it is left out: the compiler may then reassociate the replay
    // and the walk differently (5e-4 relative between a sample's pdf and eval_pdf of its
    // direction in float, measured), where the contract wants them to agree; the stateless
    // sample then walks per pass, as eval_pdf does.
#if !defined(__FAST_MATH__)
    template <int K = kBoundEnds, typename std::enable_if<(K > 0), int>::type = 0>
    HAIRSCATTER_HD HairSample<T> sample_fresh(const Outgoing& o, const V3& wo, const V4& u) const {
        if (!ends_fit()) return sample_walk(live(o), wo, u);
        const Bound b = bind_from(o);
        return sample_walk(Replay{&b}, wo, u);
    }
#endif
    template <bool kF, bool kPdf> HAIRSCATTER_HD HairEvalPdf<T> query(const Bound& b, const V3& wo, const V3& wi) const {
        if (b.n < 0) return query<kF, kPdf>(b.o, wo, wi);
        return query_walk<kF, kPdf>(Replay{&b}, wi);
    }
    HAIRSCATTER_HD HairSample<T> sample_from(const Bound& b, const V3& wo, const V4& u) const {
        if (b.n < 0) return sample_from(b.o, wo, u);
        return sample_walk(Replay{&b}, wo, u);
    }
    HAIRSCATTER_HD V3 albedo_from(const Bound& b) const {
        if (b.n < 0) return albedo_from(b.o);
        return energy_sum(lobes<false, false>(Replay{&b}, V3(T(0)), T(0)));
    }
    HAIRSCATTER_HD V3 albedo_from(const Outgoing& o) const { return energy_sum(lobes<false, false>(live(o), V3(T(0)), T(0))); }

    static HAIRSCATTER_HD T mean(const V3& x) { return (x.x + x.y + x.z) * T(1.0 / 3.0); }

    HAIRSCATTER_HD V3 mesonormal(const V2& c) const {
        const V2 n = mat_->section().normal(c);
        return V3(mat_->sin_tilt(), mat_->cos_tilt() * n.x, mat_->cos_tilt() * n.y);
    }

    // Whether a batch of exps is vector operations (on the host with GCC's and Clang's
    // vector extensions, elem::exp_lanes_nonpositive: float and double), where more lanes
    // cost little; elsewhere (nvcc) every exp is a call of its own.
    static constexpr bool kVectorExp = HAIRSCATTER_HAS_VECTOR_EXT != 0;

    // A block's TRT second chords: x holds −σ ℓ₂ (its first N lanes, channel by channel as
    // a1) and −σ (ℓ₁ + ℓ₂)/2 (the last N); on return A_2 and the residual's mean chord A_3 =
    // sqrt(A_1 A_2). With vector exps A_3 is e^(−σ (ℓ₁ + ℓ₂)/2), in the same batch as A_2;
    // elsewhere square roots are cheaper than more exps.
    template <std::size_t N>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void second_chords(const T (&a1)[N], T (&x)[2 * N]) const {
        if constexpr (kVectorExp) {
            elem::exp_lanes_nonpositive(x);
        } else {
            T a2[N], a3[N];
            for (int k = 0; k < int(N); ++k) a2[k] = x[k];
            elem::exp_each_nonpositive(a2);
            for (int k = 0; k < int(N); ++k) a3[k] = a1[k] * a2[k];
            elem::sqrt_each(a3);
            for (int k = 0; k < int(N); ++k) {
                x[k] = a2[k];
                x[N + k] = a3[k];
            }
        }
    }

    // The far-field hit at offset (h, cos γ): its circle point, mesonormal, v·m and the beam
    // it intercepts per unit γ up to a constant, cos γ (|A⁻¹c| where no offset is visible).
    struct Hit {
        V2 c;
        V3 m;
        T cos_v, beam;
    };
    HAIRSCATTER_HD Hit hit(const Outgoing& o, T h, T cos_gamma) const {
        Hit g;
        g.c = EllipticalSection<T>::hit(o.view, h, cos_gamma);
        g.m = mesonormal(g.c);
        g.cos_v = glm::dot(o.v, g.m);
        // The silhouette stops the beam, the tilt turns only the microfacets: per unit γ
        // the section intercepts |A⁻¹c| (v·n) = |A⁻¹v| cos γ, n its own normal (uniform in
        // h, d'Eon et al. 2011), and the constant |A⁻¹v| cancels in inv_total.
        g.beam = o.visible ? cos_gamma : mat_->section().normal_scale(g.c);
        return g;
    }

    template <bool kW> HAIRSCATTER_HD Outgoing outgoing(const V3& wo) const {
        Outgoing o;
        o.v = mat_->section().to_section(wo);
        o.sin_o = clamp(wo.x, T(-1), T(1));
        o.cos_o = cos_from_sin(o.sin_o);
        o.view = mat_->section().view(o.v);
        o.azimuth = mat_->azimuth_mix(o.sin_o, elem::atan2(o.v.z, o.v.y));
        const auto beam_total = [&]() {
            T total = T(0);
            for (int k = 0; k < mat_->nodes(); ++k)
                total += mat_->node_weight(k) * hit(o, mat_->node_h(k), mat_->node_cos_gamma(k)).beam;
            return total;
        };
        o.visible = true;
        T total = beam_total();
        if (!(total > T(0))) {
            // No mesonormal faces wo: every node's share goes to the residual, by offset width.
            o.visible = false;
            total = beam_total();
        }
        o.inv_total = T(1) / total;
        return o;
    }

    // R's rule: per offset node the surface reflection and the transmitted share.
    template <typename Visit> HAIRSCATTER_HD void walk_r(const Outgoing& o, RuleTotals& s, Visit&& visit) const {
        for (int k = 0; k < mat_->nodes(); ++k) {
            const Hit g = hit(o, mat_->node_h(k), mat_->node_cos_gamma(k));
            const T w = mat_->node_weight(k) * g.beam * o.inv_total;
            if (!(w > T(0))) continue;
            if (!o.visible || !(g.cos_v > T(0))) {
                s.residual += V3(w);
                continue;
            }
            const T e_out = mat_->total_reflectance_outside(g.cos_v);
            s.transmitted += w * (T(1) - e_out);
            visit(End{0, V3(w), V3(w * e_out), o.v, g.m, g.cos_v, mat_->reflection_gain_outside(g.cos_v),
                      mat_->ggx().g1(g.cos_v), mat_->ggx().alpha()});
        }
    }

    // TT's kernel (docs/theory.md §3.6): a path stands for the entry normals of its lattice
    // cell, whose spread the one normal h leaves out and which would spread the light leaving
    // the fiber as much as the exit's own roughness does (a slope change δ at either
    // interface turns the light leaving by about (η − 1) δ). The cell covers entry_cell of
    // D_v's unit square, a solid angle A = entry_cell / D_v(h) of normals about h: a disc's,
    // whose per-axis variance is A / 4π. Slope variances add (β²/2 per axis for a Beckmann
    // surface, which GGX's core follows), so the exit lobe's roughness becomes
    // sqrt(β² + A / 2π): a kernel that shrinks as the lattice grows and is widest where the
    // lattice is sparsest (D_v's tail), at most 1.
    // HuangMaterial::entry_row rounds it to a row without computing it, from D_v(h), which
    // enter_lanes computes with the entry.
    // The entries of a block of kEntryLanes consecutive lattice points, structure-of-arrays
    // over the points: per point the circle point c it enters at, the direction t the light
    // refracts into through the point's visible normal, its weight y = (1 - F) G1 gain (the
    // beam per unit h is uniform: hit), 0 where nothing enters, and its exit kernel's row.
    // The same formulas as hit (the mesonormal), TangentFrame with Ggx's visible-normal sampler,
    // refract_through, fresnel_any, Ggx::g1 and Ggx::visible, each step one loop across the
    // points with its conditionals as selects (math/functions.hpp) and its square roots
    // batched between the steps (elem::sqrt_each), so that GCC and Clang vectorise the loops
    // across the points (eight floats to an AVX register).
#if defined(__CUDACC__)
    static constexpr int kEntryLanes = 1;  // a GPU thread gains nothing from lanes
#else
    static constexpr int kEntryLanes = 8;
#endif
    struct EntryLanes {
        T c_x[kEntryLanes], c_y[kEntryLanes];
        T t_x[kEntryLanes], t_y[kEntryLanes], t_z[kEntryLanes];
        T y[kEntryLanes];
        int row[kEntryLanes];
    };
    // The lane forms of the walk's geometric steps over arrays of N lanes: the formulas of
    // EllipticalSection, TangentFrame, Ggx and fresnel_any in the same order, conditionals as
    // selects and square roots batched (elem::sqrt_each), each loop free of branches.
    template <std::size_t N> using Lanes = T[N];
    static HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T lane_clamp(T x, T lo, T hi) {
        return select(x < lo, lo, select(x > hi, hi, x));
    }
    static HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T lane_floor0(T x) { return select(x > T(0), x, T(0)); }
    // mesonormal(c) at circle points c, and |A⁻¹c| (EllipticalSection::normal_scale).
    template <std::size_t N>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void mesonormal_lanes(const Lanes<N>& cx, const Lanes<N>& cy, Lanes<N>& mx, Lanes<N>& my, Lanes<N>& mz,
                                         Lanes<N>& scale) const {
        const T st = mat_->sin_tilt(), ct = mat_->cos_tilt(), inv_b = mat_->section().inv_aspect();
        for (int j = 0; j < int(N); ++j) scale[j] = cx[j] * cx[j] + sqr(cy[j] * inv_b);
        elem::sqrt_each(scale);
        for (int j = 0; j < int(N); ++j) {
            mx[j] = st;
            my[j] = ct * (cx[j] / scale[j]);
            mz[j] = ct * (cy[j] * inv_b / scale[j]);
        }
    }
    // EllipticalSection::chord from c along (dx, dy): the exit point and the length, 0 where
    // the chord is not ok (a chord that is has length > 0).
    template <std::size_t N>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void chord_lanes(const Lanes<N>& cx, const Lanes<N>& cy, const Lanes<N>& dx,
                                                             const Lanes<N>& dy, Lanes<N>& ex, Lanes<N>& ey,
                                                             Lanes<N>& length) const {
        const T inv_b = mat_->section().inv_aspect();
        Lanes<N> r;
        for (int j = 0; j < int(N); ++j) {
            const T ux = dx[j], uy = dy[j] * inv_b;
            const T dd = ux * ux + uy * uy;
            const T sl = T(-2) * (cx[j] * ux + cy[j] * uy) / dd;
            length[j] = select((dd > T(1e-12)) & (sl > T(0)), sl, T(0));
            ex[j] = cx[j] + length[j] * ux;
            ey[j] = cy[j] + length[j] * uy;
            r[j] = ex[j] * ex[j] + ey[j] * ey[j];
        }
        elem::sqrt_each(r);
        for (int j = 0; j < int(N); ++j) {
            const bool ok = length[j] > T(0);
            ex[j] = select(ok, ex[j] / r[j], cx[j]);
            ey[j] = select(ok, ey[j] / r[j], cy[j]);
        }
    }
    // TangentFrame(m, w)'s s (its fallback where w lies along m), and w in the frame
    // stretched by α and normalised (Ggx::stretch of TangentFrame::to_local).
    template <std::size_t N>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void frame_lanes(const Lanes<N>& mx, const Lanes<N>& my, const Lanes<N>& mz, const Lanes<N>& wx,
                                    const Lanes<N>& wy, const Lanes<N>& wz, Lanes<N>& sx, Lanes<N>& sy, Lanes<N>& sz,
                                    Lanes<N>& vx, Lanes<N>& vy, Lanes<N>& vz) const {
        const T a = mat_->ggx().alpha();
        Lanes<N> r;
        for (int j = 0; j < int(N); ++j) {
            const T wm = wx[j] * mx[j] + wy[j] * my[j] + wz[j] * mz[j];
            const T px = wx[j] - wm * mx[j], py = wy[j] - wm * my[j], pz = wz[j] - wm * mz[j];
            const T len2 = px * px + py * py + pz * pz;
            const T sign = select(mz[j] >= T(0), T(1), T(-1));
            const T fa = T(-1) / (sign + mz[j]), fb = mx[j] * my[j] * fa;
            const T fx = T(1) + sign * mx[j] * mx[j] * fa, fy = sign * fb, fz = -sign * mx[j];
            const bool along = !(len2 > T(1e-12));
            sx[j] = select(along, fx, px);
            sy[j] = select(along, fy, py);
            sz[j] = select(along, fz, pz);
            r[j] = select(along, fx * fx + fy * fy + fz * fz, len2);
        }
        elem::sqrt_each(r);
        for (int j = 0; j < int(N); ++j) {
            sx[j] /= r[j];
            sy[j] /= r[j];
            sz[j] /= r[j];
            const T tx = my[j] * sz[j] - sy[j] * mz[j], ty = mz[j] * sx[j] - sz[j] * mx[j], tz = mx[j] * sy[j] - sx[j] * my[j];
            vx[j] = a * (wx[j] * sx[j] + wy[j] * sy[j] + wz[j] * sz[j]);
            vy[j] = a * (wx[j] * tx + wy[j] * ty + wz[j] * tz);
            vz[j] = wx[j] * mx[j] + wy[j] * my[j] + wz[j] * mz[j];
            r[j] = vx[j] * vx[j] + vy[j] * vy[j] + vz[j] * vz[j];
        }
        elem::sqrt_each(r);
        for (int j = 0; j < int(N); ++j) {
            const T inv = T(1) / r[j];
            vx[j] *= inv;
            vy[j] *= inv;
            vz[j] *= inv;
        }
    }
    // Ggx::sample_visible_stretched from the stretched v at (u1 as its cosine and sine, u2),
    // then TangentFrame::to_world with the frame (s, m × s, m): the visible normal h.
    template <std::size_t N>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void visible_normal_lanes(const Lanes<N>& mx, const Lanes<N>& my, const Lanes<N>& mz,
                                             const Lanes<N>& sx, const Lanes<N>& sy, const Lanes<N>& sz,
                                             const Lanes<N>& vx, const Lanes<N>& vy, const Lanes<N>& vz,
                                             const Lanes<N>& cos_u1, const Lanes<N>& sin_u1, const Lanes<N>& u2,
                                             Lanes<N>& hx, Lanes<N>& hy, Lanes<N>& hz) const {
        const T a = mat_->ggx().alpha();
        Lanes<N> z, r, len2;
        for (int j = 0; j < int(N); ++j) {
            z[j] = (T(1) - u2[j]) * (T(1) + vz[j]) - vz[j];
            const T zc = lane_clamp(z[j], T(-1), T(1));
            r[j] = lane_floor0((T(1) - zc) * (T(1) + zc));
        }
        elem::sqrt_each(r);
        for (int j = 0; j < int(N); ++j) {
            hx[j] = a * (r[j] * cos_u1[j] + vx[j]);
            hy[j] = a * (r[j] * sin_u1[j] + vy[j]);
            hz[j] = z[j] + vz[j];
            len2[j] = hx[j] * hx[j] + hy[j] * hy[j] + hz[j] * hz[j];
            r[j] = len2[j];
        }
        elem::sqrt_each(r);
        for (int j = 0; j < int(N); ++j) {
            const bool tiny = !(len2[j] > T(1e-30));
            const T lx = select(tiny, T(0), hx[j] / r[j]), ly = select(tiny, T(0), hy[j] / r[j]),
                    lz = select(tiny, T(1), hz[j] / r[j]);
            const T tx = my[j] * sz[j] - sy[j] * mz[j], ty = mz[j] * sx[j] - sz[j] * mx[j], tz = mx[j] * sy[j] - sx[j] * my[j];
            hx[j] = lx * sx[j] + ly * tx + lz * mx[j];
            hy[j] = lx * sy[j] + ly * ty + lz * my[j];
            hz[j] = lx * sz[j] + ly * tz + lz * mz[j];
        }
    }
    // fresnel_any(cos_i, n): the square root's argument, then the value from its root.
    static HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T fresnel_root_arg(T cos_i, T n2) {
        const T ci = lane_clamp(cos_i, T(0), T(1));
        return lane_floor0(n2 - (T(1) - ci) * (T(1) + ci));
    }
    static HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T fresnel_from_root(T cos_i, T n2, T root) {
        const T ci = lane_clamp(cos_i, T(0), T(1));
        const T sin2_i = (T(1) - ci) * (T(1) + ci), n2c = n2 * ci;
        const T f = T(0.5) * (sqr((ci - root) / (ci + root)) + sqr((n2c - root) / (n2c + root)));
        return select(sin2_i >= n2, T(1), f);
    }

    // Points past the lattice's end (a last, partial block) repeat its last point; the walk
    // reads only the block's first `count`.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void enter_lanes(const Outgoing& o, int first, EntryLanes& e) const {
        constexpr int K = kEntryLanes;
        const int last = mat_->tt_points() - 1;
        const T a = mat_->ggx().alpha(), a2 = a * a;
        const T eta = mat_->params().eta, inv_eta = T(1) / eta, eta2 = eta * eta, inv_eta2 = inv_eta * inv_eta;
        const V3 v = o.v;
        T cos_u1[K], sin_u1[K], u2[K], vx[K], vy[K], vz[K];
        T m_x[K], m_y[K], m_z[K], cos_v[K], s_x[K], s_y[K], s_z[K], w_x[K], w_y[K], w_z[K];
        T h_x[K], h_y[K], h_z[K], cos_i[K], sin2_t[K], r0[K], r1[K], r2[K];
        for (int j = 0; j < K; ++j) {
            const int i = first + j < last ? first + j : last;
            const typename Material::EntryPoint& q = mat_->tt_point(i);
            cos_u1[j] = q.normal.cos_u1;
            sin_u1[j] = q.normal.sin_u1;
            u2[j] = q.normal.u2;
            e.c_x[j] = q.h * o.view.e.x + q.cos_gamma * o.view.d.x;  // hit
            e.c_y[j] = q.h * o.view.e.y + q.cos_gamma * o.view.d.y;
            vx[j] = v.x;
            vy[j] = v.y;
            vz[j] = v.z;
        }
        mesonormal_lanes(e.c_x, e.c_y, m_x, m_y, m_z, r0);
        for (int j = 0; j < K; ++j) {
            cos_v[j] = v.x * m_x[j] + v.y * m_y[j] + v.z * m_z[j];
        }
        frame_lanes(m_x, m_y, m_z, vx, vy, vz, s_x, s_y, s_z, w_x, w_y, w_z);
        visible_normal_lanes(m_x, m_y, m_z, s_x, s_y, s_z, w_x, w_y, w_z, cos_u1, sin_u1, u2, h_x, h_y, h_z);
        for (int j = 0; j < K; ++j) {
            // The three roots that need h: refraction's cos θt, Fresnel's, visible_scale(v·m).
            cos_i[j] = v.x * h_x[j] + v.y * h_y[j] + v.z * h_z[j];
            sin2_t[j] = inv_eta2 * (T(1) - cos_i[j]) * (T(1) + cos_i[j]);
            r0[j] = lane_floor0(T(1) - sin2_t[j]);
            r1[j] = fresnel_root_arg(cos_i[j], eta2);
            r2[j] = a2 * (T(1) - cos_v[j]) * (T(1) + cos_v[j]) + cos_v[j] * cos_v[j];
        }
        elem::sqrt_each(r0);
        elem::sqrt_each(r1);
        elem::sqrt_each(r2);
        T f[K], d_v[K];
        for (int j = 0; j < K; ++j) {
            // refract_through (1/η): t before normalising; fresnel_any(v·h, η); D_v for the
            // exit kernel (Ggx::visible at v·m, v·h, h·m).
            const T k = inv_eta * cos_i[j] - r0[j];
            w_x[j] = k * h_x[j] - inv_eta * v.x;
            w_y[j] = k * h_y[j] - inv_eta * v.y;
            w_z[j] = k * h_z[j] - inv_eta * v.z;
            f[j] = fresnel_from_root(cos_i[j], eta2, r1[j]);
            const T scale_v = T(1) / (cos_v[j] + r2[j]);
            const T cos_h = h_x[j] * m_x[j] + h_y[j] * m_y[j] + h_z[j] * m_z[j];
            const T d = a2 * kInvPi<T> / sqr((T(1) - cos_h) * (T(1) + cos_h) + a2 * (cos_h * cos_h));
            d_v[j] = select((cos_i[j] > T(0)) & (cos_h > T(0)), T(2) * cos_i[j] * d * scale_v, T(0));
            r0[j] = w_x[j] * w_x[j] + w_y[j] * w_y[j] + w_z[j] * w_z[j];
        }
        elem::sqrt_each(r0);
        for (int j = 0; j < K; ++j) {
            // t (normalised; −m where refraction fails, which into the denser side is
            // rounding), and G1's root at −t·m.
            const T inv = T(1) / r0[j];
            const bool ok = sin2_t[j] < T(1);
            e.t_x[j] = select(ok, w_x[j] * inv, -m_x[j]);
            e.t_y[j] = select(ok, w_y[j] * inv, -m_y[j]);
            e.t_z[j] = select(ok, w_z[j] * inv, -m_z[j]);
            const T cw = -(e.t_x[j] * m_x[j] + e.t_y[j] * m_y[j] + e.t_z[j] * m_z[j]);
            r2[j] = select(cw > T(0), select(cw < T(1), cw, T(1)), T(0));
            r1[j] = a2 * (T(1) - r2[j]) * (T(1) + r2[j]) + r2[j] * r2[j];
        }
        elem::sqrt_each(r1);
        for (int j = 0; j < K; ++j) {
            const T g1 = select(r2[j] > T(0), T(2) * r2[j] * (T(1) / (r2[j] + r1[j])), T(0));
            // The beam per unit h is uniform (hit), a constant that s_TT's normaliser removes.
            const T y = (T(1) - f[j]) * g1;
            e.y[j] = select(cos_v[j] > T(0), y, T(0));
        }
        // The tables' lookups (gain, row) across the block too.
        mat_->entry_gain(cos_v, r0);
        mat_->entry_row(d_v, e.row);
        for (int j = 0; j < K; ++j) e.y[j] *= r0[j];
    }

    // The paths into the fiber, a block of kEntryLanes TT points at a time, every step
    // computed across the block's points (the lane forms above): the entries, the chords,
    // the exits' mesonormals and the internal reflections' normals, then the transmittances,
    // the exit (TT) and its reflected share E_in split over the path's m internal normals
    // ∝ F, per normal the second chord, the exit (TRT) and the residual's series. The ends
    // are handed to `visit` path by path, in that order.
    template <typename Visit> HAIRSCATTER_HD void walk_paths(const Outgoing& o, RuleTotals& s, Visit&& visit) const {
        if (!o.visible) return;
        constexpr int K = kEntryLanes;
        const T inv_eta = T(1) / mat_->params().eta, inv_eta2 = inv_eta * inv_eta;
        const int m = mat_->trt_per_tt(), n = mat_->tt_points();
        EntryLanes e;
        T ex[K], ey[K], len[K], mx[K], my[K], mz[K], ns[K], vx[K], vy[K], vz[K], sx[K], sy[K], sz[K];
        T wx[K], wy[K], wz[K], cu[K], su[K], u2[K], hx[K], hy[K], hz[K];
        // Per internal normal l: the reflected direction, its Fresnel factor (before the
        // share; 0 where it points outward); the second chord and the TRT exit's mesonormal
        // and cosine.
        T rx[Material::kMaxTrtPerTT][kEntryLanes], ry[Material::kMaxTrtPerTT][kEntryLanes], rz[Material::kMaxTrtPerTT][kEntryLanes], fr[Material::kMaxTrtPerTT][kEntryLanes], ex2[Material::kMaxTrtPerTT][kEntryLanes], ey2[Material::kMaxTrtPerTT][kEntryLanes], len2[Material::kMaxTrtPerTT][kEntryLanes];
        T mx3[Material::kMaxTrtPerTT][kEntryLanes], my3[Material::kMaxTrtPerTT][kEntryLanes], mz3[Material::kMaxTrtPerTT][kEntryLanes], cos3[Material::kMaxTrtPerTT][kEntryLanes], e3[Material::kMaxTrtPerTT][kEntryLanes];
        for (int first = 0; first < n; first += K) {
            enter_lanes(o, first, e);
            for (int j = 0; j < K; ++j) {
                vx[j] = -e.t_x[j];
                vy[j] = -e.t_y[j];
                vz[j] = -e.t_z[j];
            }
            chord_lanes(e.c_x, e.c_y, e.t_y, e.t_z, ex, ey, len);
            mesonormal_lanes(ex, ey, mx, my, mz, ns);
            for (int j = 0; j < K; ++j) {
                mx[j] = -mx[j];  // the exit's mesonormal, inward
                my[j] = -my[j];
                mz[j] = -mz[j];
            }
            // The exit's cosine and its tables.
            T cos2[K], e_in[K], e_mean[K];
            for (int j = 0; j < K; ++j) cos2[j] = vx[j] * mx[j] + vy[j] * my[j] + vz[j] * mz[j];
            mat_->reflectance_inside(cos2, e_mean);
            mat_->total_reflectance_inside(cos2, e_in);
            // The internal reflections: v2 = −t in the frame of the inward mesonormal.
            frame_lanes(mx, my, mz, vx, vy, vz, sx, sy, sz, wx, wy, wz);
            for (int l = 0; l < m; ++l) {
                for (int j = 0; j < K; ++j) {
                    const int i = first + j < n ? first + j : n - 1;
                    const typename Material::NormalPoint& q = mat_->reflect_point(i, l);
                    cu[j] = q.cos_u1;
                    su[j] = q.sin_u1;
                    u2[j] = q.u2;
                }
                visible_normal_lanes(mx, my, mz, sx, sy, sz, wx, wy, wz, cu, su, u2, hx, hy, hz);
                T r[K], root[K];
                for (int j = 0; j < K; ++j) {
                    const T vh = vx[j] * hx[j] + vy[j] * hy[j] + vz[j] * hz[j];
                    rx[l][j] = T(2) * vh * hx[j] - vx[j];  // reflect_about, then normalised
                    ry[l][j] = T(2) * vh * hy[j] - vy[j];
                    rz[l][j] = T(2) * vh * hz[j] - vz[j];
                    r[j] = rx[l][j] * rx[l][j] + ry[l][j] * ry[l][j] + rz[l][j] * rz[l][j];
                    root[j] = fresnel_root_arg(vh, inv_eta2);
                    fr[l][j] = vh;
                }
                elem::sqrt_each(r);
                elem::sqrt_each(root);
                for (int j = 0; j < K; ++j) {
                    const T inv = T(1) / r[j];
                    rx[l][j] *= inv;
                    ry[l][j] *= inv;
                    rz[l][j] *= inv;
                    const bool inward = rx[l][j] * mx[j] + ry[l][j] * my[j] + rz[l][j] * mz[j] > T(0);
                    fr[l][j] = select(inward, fresnel_from_root(fr[l][j], inv_eta2, root[j]), T(0));
                }
                chord_lanes(ex, ey, ry[l], rz[l], ex2[l], ey2[l], len2[l]);
                mesonormal_lanes(ex2[l], ey2[l], mx3[l], my3[l], mz3[l], ns);
                for (int j = 0; j < K; ++j) {
                    mx3[l][j] = -mx3[l][j];
                    my3[l][j] = -my3[l][j];
                    mz3[l][j] = -mz3[l][j];
                    cos3[l][j] = -(rx[l][j] * mx3[l][j] + ry[l][j] * my3[l][j] + rz[l][j] * mz3[l][j]);
                }
                mat_->total_reflectance_inside(cos3[l], e3[l]);
            }
            // The rest across the block too, each lane's residual in its own sum (selects
            // where the one-path form branched): A_1 of every path as one batch of exps, the
            // exit gains, each internal normal's share (F_l E_in / (m E), a share unbiased
            // whatever m is: a ratio F / ΣF over the path's own few normals made TRT 40 % too
            // bright against the physical fiber; the reflected direction is not weighted by
            // its masking, which measured further from it, docs/theory.md §3.6), then per
            // normal A_2 and the residual's mean chord A_3 as another batch. The ends are then
            // handed on path by path, in the one-path order.
            const int count = n - first < K ? n - first : K;
            const V3& sigma_a = sigma_a_;
            const T sigma[3] = {sigma_a.x, sigma_a.y, sigma_a.z};
            T a1[3 * K], res[3 * K], gain2[K], sum[K];
            for (int ch = 0; ch < 3; ++ch)
                for (int j = 0; j < K; ++j) a1[ch * K + j] = -sigma[ch] * len[j];
            elem::exp_lanes_nonpositive(a1);
            mat_->exit_gain(cos2, e.row, gain2);
            T share[K];
            for (int j = 0; j < K; ++j) {
                share[j] = select(e_mean[j] > T(0), e_in[j] / (T(m) * e_mean[j]), T(0));
                sum[j] = T(0);
            }
            for (int l = 0; l < m; ++l)
                for (int j = 0; j < K; ++j) {
                    fr[l][j] *= share[j];  // now the normal's share f_l
                    sum[j] += fr[l][j];
                }
            // What the normals leave over (or overdraw) crosses a chord like the first and
            // leaves by the residual's series: energy kept exactly when lossless, and absorbed
            // like the light it stands for. A chord that does not enter, or an exit met from
            // behind its mesonormal, sends its light to the residual.
            for (int ch = 0; ch < 3; ++ch)
                for (int j = 0; j < K; ++j) {
                    const T a = a1[ch * K + j], e2 = e_in[j], at_exit = e.y[j] * a;
                    const T den = T(1) - a * e2;
                    const T onward = select(den > T(1e-6), a * (T(1) - e2) / den, T(1));
                    res[ch * K + j] =
                        select(len[j] > T(0), select(cos2[j] > T(0), at_exit * (e2 - sum[j]) * onward, at_exit), e.y[j]);
                }
            // Per internal normal: the light reaching the TRT exit, and the orders past TRT,
            // A_3 Σ (A_3 R̄)^n (1 - R̄) with every later interface reflecting R̄ = the total
            // internal reflectance at this one's angle (its limit 1 where A_3 R̄ → 1).
            T at_exit2[Material::kMaxTrtPerTT][3 * K], gain3[Material::kMaxTrtPerTT][K];
            for (int l = 0; l < m; ++l) {
                T x[6 * K];  // A_2, then A_3
                for (int ch = 0; ch < 3; ++ch)
                    for (int j = 0; j < K; ++j) {
                        x[ch * K + j] = -sigma[ch] * len2[l][j];
                        x[(3 + ch) * K + j] = -sigma[ch] * (T(0.5) * (len[j] + len2[l][j]));
                    }
                second_chords(a1, x);
                mat_->exit_gain(cos3[l], e.row, gain3[l]);
                for (int ch = 0; ch < 3; ++ch)
                    for (int j = 0; j < K; ++j) {
                        const T in2 = e.y[j] * a1[ch * K + j] * fr[l][j];
                        const T out = in2 * x[ch * K + j], a3 = x[(3 + ch) * K + j], r_bar = e3[l][j];
                        const T den = T(1) - a3 * r_bar;
                        const T series = select(den > T(1e-6), a3 * (T(1) - r_bar) / den, T(1));
                        const T later = select(len2[l][j] > T(0), select(cos3[l][j] > T(0), out * r_bar * series, out), in2);
                        const bool on = (len[j] > T(0)) & (cos2[j] > T(0)) & (fr[l][j] > T(0));
                        res[ch * K + j] += select(on, later, T(0));
                        at_exit2[l][ch * K + j] = out;
                    }
            }
            for (int j = 0; j < count; ++j) {
                const T y = e.y[j];
                if (!(y > T(0))) continue;
                s.norm += y;
                s.residual += V3(res[j], res[K + j], res[2 * K + j]);
                if (!(len[j] > T(0)) || !(cos2[j] > T(0))) continue;
                const T alpha = mat_->exit_row_roughness(e.row[j]);
                const V3 at_exit = y * V3(a1[j], a1[K + j], a1[2 * K + j]);
                visit(End{1, at_exit, at_exit * (T(1) - e_in[j]), V3(vx[j], vy[j], vz[j]), V3(mx[j], my[j], mz[j]), cos2[j],
                          gain2[j], T(0), alpha});
                for (int l = 0; l < m; ++l) {
                    if (!(fr[l][j] > T(0)) || !(len2[l][j] > T(0)) || !(cos3[l][j] > T(0))) continue;
                    const V3 out(at_exit2[l][j], at_exit2[l][K + j], at_exit2[l][2 * K + j]);
                    visit(End{2, out, out * (T(1) - e3[l][j]), -V3(rx[l][j], ry[l][j], rz[l][j]),
                              V3(mx3[l][j], my3[l][j], mz3[l][j]), cos3[l][j], gain3[l][j], T(0), alpha});
                }
            }
        }
    }

    // The paths' scale s_TT (R's is 1) and the residual's energy, from the two walks'
    // totals; with no path that enters, the transmitted light goes to the residual.
    struct Scales {
        T s_tt;
        V3 residual;
    };
    HAIRSCATTER_HD static Scales scales(const RuleTotals& r, const RuleTotals& paths) {
        Scales sc;
        sc.s_tt = paths.norm > T(0) ? r.transmitted / paths.norm : T(0);
        sc.residual = r.residual + sc.s_tt * paths.residual;
        if (!(paths.norm > T(0))) sc.residual += V3(r.transmitted);
        // The internal reflections' overdraw is zero on average; never below zero.
        sc.residual = glm::max(sc.residual, V3(T(0)));
        return sc;
    }

    // The lobe of end e at wi (section frame): f's factor (times e.prefix) and the
    // sampler's density.
    struct LobeValue {
        T f, q;
    };
    template <bool kF, bool kPdf> HAIRSCATTER_HD LobeValue lobe(const End& e, const V3& wi) const {
        // f alone: the shadowing below is 0 where wi is behind the reflecting side (R) or
        // in front of the side light leaves by (TT, TRT), so those ends add exactly 0 (the
        // sampler's density q, which pdf needs, does not vanish there).
        if (kF && !kPdf) {
            const T side = glm::dot(wi, e.m);
            if (!(e.p == 0 ? side > T(0) : side < T(0))) return LobeValue{T(0), T(0)};
        }
        const T eta = mat_->params().eta;
        const Ggx<T> ggx(e.alpha);
        const InterfaceLobes<T> l{&ggx, e.v, e.m, e.cos_v};
        LobeValue r{T(0), T(0)};
        if (e.p == 0) {
            const auto x = l.reflection(wi);
            if (kF && x.q > T(0))
                r.f = fresnel_any(x.v_dot_h, eta) * x.q * e.gain *
                      mat_->ggx().unshadowed_reflection(e.g1_v, glm::dot(wi, e.m));
            r.q = x.q;
            return r;
        }
        const auto x = l.refraction(wi, eta);
        if (kF && x.q > T(0))
            r.f = (T(1) - fresnel_any(x.v_dot_h, T(1) / eta)) * x.q * e.gain * ggx.g1(-glm::dot(wi, e.m));
        if (kPdf) r.q = x.q + l.total_reflection(wi, eta);
        return r;
    }

    // lobe<true, false> (f alone) of up to kLobeLanes ends of one kind at once, R's
    // reflections or the exits' refractions: structure-of-arrays across the ends, the
    // conditionals as selects and the square roots batched, so that the loops vectorise;
    // the same formulas in the same order (InterfaceLobes, Ggx::d, visible_scale, g1,
    // lambda, fresnel_any), so the same values.
    static constexpr int kLobeLanes = kEntryLanes;
    struct EndBatch {
        int n = 0;
        T vx[kLobeLanes], vy[kLobeLanes], vz[kLobeLanes], mx[kLobeLanes], my[kLobeLanes], mz[kLobeLanes];
        T cos_v[kLobeLanes], a2[kLobeLanes], gain[kLobeLanes], g1_v[kLobeLanes];
        int p[kLobeLanes];
        V3 prefix[kLobeLanes];
        HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void add(const End& e) {
            vx[n] = e.v.x;
            vy[n] = e.v.y;
            vz[n] = e.v.z;
            mx[n] = e.m.x;
            my[n] = e.m.y;
            mz[n] = e.m.z;
            cos_v[n] = e.cos_v;
            a2[n] = e.alpha * e.alpha;
            gain[n] = e.gain;
            g1_v[n] = e.g1_v;
            p[n] = e.p;
            prefix[n] = e.prefix;
            ++n;
        }
        // Lanes past n repeat the first end's values.
        HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void pad() {
            for (int j = n; j < kLobeLanes; ++j) {
                vx[j] = vx[0];
                vy[j] = vy[0];
                vz[j] = vz[0];
                mx[j] = mx[0];
                my[j] = my[0];
                mz[j] = mz[0];
                cos_v[j] = cos_v[0];
                a2[j] = a2[0];
                gain[j] = gain[0];
                g1_v[j] = g1_v[0];
            }
        }
    };
    template <bool kReflect>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void lobe_f_lanes(const EndBatch& b, const V3& wi, T (&f)[kLobeLanes]) const {
        constexpr int K = kLobeLanes;
        const T eta = mat_->params().eta, n_f = kReflect ? eta : T(1) / eta, n2 = n_f * n_f;
        const T a2_mat = sqr(mat_->ggx().alpha());
        const T(&vx)[K] = b.vx;
        const T(&vy)[K] = b.vy;
        const T(&vz)[K] = b.vz;
        const T(&mx)[K] = b.mx;
        const T(&my)[K] = b.my;
        const T(&mz)[K] = b.mz;
        const T(&cv)[K] = b.cos_v;
        const T(&a2)[K] = b.a2;
        const T(&gain)[K] = b.gain;
        const T(&g1v)[K] = b.g1_v;
        T sx[K], sy[K], sz[K], len2[K], root[K];
        for (int j = 0; j < K; ++j) {
            // h's direction: v + wi (reflection), η v + wi (refraction out, Walter et al. 2007)
            sx[j] = (kReflect ? vx[j] : eta * vx[j]) + wi.x;
            sy[j] = (kReflect ? vy[j] : eta * vy[j]) + wi.y;
            sz[j] = (kReflect ? vz[j] : eta * vz[j]) + wi.z;
            len2[j] = sx[j] * sx[j] + sy[j] * sy[j] + sz[j] * sz[j];
            root[j] = len2[j];
        }
        elem::sqrt_each(root);
        T cos_h[K], vh[K], odh[K], inv_len[K], cos_o[K], c[K], r1[K], r2[K], r3[K];
        for (int j = 0; j < K; ++j) {
            T hx, hy, hz;
            if (kReflect) {
                hx = sx[j] / root[j];
                hy = sy[j] / root[j];
                hz = sz[j] / root[j];
            } else {
                inv_len[j] = T(1) / root[j];
                hx = sx[j] * inv_len[j];
                hy = sy[j] * inv_len[j];
                hz = sz[j] * inv_len[j];
            }
            cos_h[j] = hx * mx[j] + hy * my[j] + hz * mz[j];
            odh[j] = wi.x * hx + wi.y * hy + wi.z * hz;
            vh[j] = vx[j] * hx + vy[j] * hy + vz[j] * hz;
            cos_o[j] = wi.x * mx[j] + wi.y * my[j] + wi.z * mz[j];
            r1[j] = a2[j] * (T(1) - cv[j]) * (T(1) + cv[j]) + cv[j] * cv[j];
            r2[j] = fresnel_root_arg(vh[j], n2);
            // R: λ(wi·m) of the material's roughness; the exits: G1(−wi·m) of the end's.
            c[j] = kReflect ? select(cos_o[j] < T(1), cos_o[j], T(1)) : select(-cos_o[j] < T(1), -cos_o[j], T(1));
            r3[j] = (kReflect ? a2_mat : a2[j]) * (T(1) - c[j]) * (T(1) + c[j]) + c[j] * c[j];
        }
        elem::sqrt_each(r1);
        elem::sqrt_each(r2);
        elem::sqrt_each(r3);
        for (int j = 0; j < K; ++j) {
            const T d = a2[j] * kInvPi<T> / sqr((T(1) - cos_h[j]) * (T(1) + cos_h[j]) + a2[j] * (cos_h[j] * cos_h[j]));
            const T scale = T(1) / (cv[j] + r1[j]);
            T q, shadow;
            bool ok;
            if (kReflect) {
                ok = (len2[j] > T(1e-20)) & (cos_h[j] > T(0)) & (cos_o[j] > T(0));
                q = T(0.5) * d * scale;
                const T lambda = select(cos_o[j] > T(1e-30), T(0.5) * (r3[j] / c[j] - T(1)), T(1e30));
                shadow = T(1) / (T(1) + lambda * g1v[j]);
            } else {
                ok = (len2[j] > T(1e-20)) & (cos_h[j] > T(0)) & (odh[j] < T(0)) & (vh[j] > T(0)) & (cos_o[j] < T(0));
                q = T(2) * vh[j] * d * scale * (-odh[j]) * inv_len[j] * inv_len[j];
                shadow = T(2) * c[j] * (T(1) / (c[j] + r3[j]));
            }
            const T fr = fresnel_from_root(vh[j], n2, r2[j]);
            const T value = (kReflect ? fr : T(1) - fr) * q * gain[j] * shadow;
            f[j] = select(ok & (q > T(0)), value, T(0));
        }
    }

    // Per lobe p (3 the residual) at wi (section frame; sin_i its inclination), with the
    // rules' scales and the controls applied: f, the energy-weighted sampling density
    // Σ energy·q, and the energy. kF, kPdf: whether f and the density are wanted (neither:
    // the energies only, no lobe is evaluated).
    struct Lobes {
        V3 f[std::size_t(kLobes + 1)], q[std::size_t(kLobes + 1)], energy[std::size_t(kLobes + 1)];
        Scales scales;
    };
    template <bool kF, bool kPdf> HAIRSCATTER_HD Lobes lobes(const Outgoing& o, const V3& w, T sin_i) const {
        return lobes<kF, kPdf>(live(o), w, sin_i);
    }
    template <bool kF, bool kPdf, typename Walk> HAIRSCATTER_HD Lobes lobes(const Walk& walk, const V3& w, T sin_i) const {
        const Outgoing& o = walk.outgoing();
        V3 f[std::size_t(kLobes)], q[std::size_t(kLobes)], energy[std::size_t(kLobes)];
        for (int p = 0; p < kLobes; ++p) f[p] = q[p] = energy[p] = V3(T(0));
        RuleTotals r, paths;
        if constexpr (kF && !kPdf) {
            // f alone: the ends that face wi in batches of one kind (R's, the exits'), each
            // batch's lobes in lanes and added in the ends' order, as one by one.
            EndBatch reflected, exits;
            const auto flush = [&](EndBatch& b, auto reflect) {
                T x[kLobeLanes];
                b.pad();
                lobe_f_lanes<decltype(reflect)::value>(b, w, x);
                for (int k = 0; k < b.n; ++k) f[b.p[k]] += x[k] * b.prefix[k];
                b.n = 0;
            };
            const auto add = [&](const End& e) {
                energy[e.p] += e.energy;
                // lobe()'s side test first: an end whose shadowing is 0 at wi adds exactly 0
                // (a branch: the one-end form's, and faster than batching every end).
                const T side = glm::dot(w, e.m);
                if (!(e.p == 0 ? side > T(0) : side < T(0))) return;
                EndBatch& b = e.p == 0 ? reflected : exits;
                b.add(e);
                if (b.n < kLobeLanes) return;
                if (e.p == 0) flush(b, std::true_type());
                else flush(b, std::false_type());
            };
            walk.r(r, add);
            walk.paths(paths, add);
            if (reflected.n > 0) flush(reflected, std::true_type());
            if (exits.n > 0) flush(exits, std::false_type());
        } else {
            const auto add = [&](const End& e) {
                energy[e.p] += e.energy;
                if (!(kF || kPdf)) return;
                const LobeValue x = lobe<kF, kPdf>(e, w);
                if (kF) f[e.p] += x.f * e.prefix;
                if (kPdf) q[e.p] += x.q * e.energy;
            };
            walk.r(r, add);
            walk.paths(paths, add);
        }
        Lobes out;
        out.scales = scales(r, paths);
        for (int p = 0; p < kLobes; ++p) {
            const V3 s = (p == 0 ? T(1) : out.scales.s_tt) * mat_->lobe_weight(p);
            out.f[p] = s * f[p];
            out.q[p] = s * q[p];
            out.energy[p] = s * energy[p];
        }
        out.energy[kLobes] = out.scales.residual * mat_->lobe_weight(kLobes);
        T m = T(0);
        if (kF || kPdf)
            m = mat_->residual_density(o.sin_o, sin_i) *
                mat_->residual_azimuth_density(o.azimuth, relative_azimuth(o.v, w));
        out.f[kLobes] = m * out.energy[kLobes];
        out.q[kLobes] = out.f[kLobes];
        return out;
    }

    static HAIRSCATTER_HD V3 energy_sum(const Lobes& e) { return e.energy[0] + e.energy[1] + e.energy[2] + e.energy[3]; }

    template <bool kF, bool kPdf> HAIRSCATTER_HD HairEvalPdf<T> query(const Outgoing& o, const V3& wo, const V3& wi) const {
        (void)wo;
        return query_walk<kF, kPdf>(live(o), wi);
    }
    template <bool kF, bool kPdf, typename Walk> HAIRSCATTER_HD HairEvalPdf<T> query_walk(const Walk& walk, const V3& wi) const {
        const T sin_i = clamp(wi.x, T(-1), T(1));
        const Lobes l = lobes<kF, kPdf>(walk, mat_->section().to_section(wi), sin_i);
        HairEvalPdf<T> r;
        T q = T(0), total = T(0);
        for (int p = 0; p <= kLobes; ++p) {
            r.f += l.f[p];
            q += mean(l.q[p]);
            total += mean(l.energy[p]);
        }
        // total > 0 unless the controls zero every lobe (then nothing is sampled either).
        r.pdf = total > T(0) ? q / total : T(0);
        return r;
    }

    // u.x picks the lobe and then, its leftover rescaled, the path end; (u.y, u.z) the
    // visible normal of the end's interface or θi of the residual, u.w the residual's φ.
    HAIRSCATTER_HD HairSample<T> sample_from(const Outgoing& o, const V3& wo, const V4& u) const {
        return sample_walk(live(o), wo, u);
    }
    template <typename Walk> HAIRSCATTER_HD HairSample<T> sample_walk(const Walk& walk, const V3& wo, const V4& u) const {
        const Outgoing& o = walk.outgoing();
        const Lobes e = lobes<false, false>(walk, V3(T(0)), T(0));
        T w[std::size_t(kLobes + 1)], total = T(0);
        for (int p = 0; p <= kLobes; ++p) {
            w[p] = mean(e.energy[p]);
            total += w[p];
        }
        // Nothing scatters (every gain 0, or all of it absorbed): a residual direction with
        // pdf 0 and weight 0.
        const DiscreteChoice<T> lobe_choice = sample_discrete(w, kLobes + 1, u.x, total);
        const int p = total > T(0) ? lobe_choice.index : kLobes;
        const V3 weight = (p == 0 ? T(1) : e.scales.s_tt) * mat_->lobe_weight(p);
        const T target = lobe_choice.rescaled * w[p];
        // The first end of lobe p whose cumulative weight passes the target (or the last
        // with weight).
        End chosen{};
        chosen.p = kLobes;
        T before = T(0);
        bool done = false;
        const auto pick = [&](const End& end) {
            const T x = end.p == p ? mean(weight * end.energy) : T(0);
            if (done || !(x > T(0))) return;
            chosen = end;
            before += x;
            done = target < before;
        };
        RuleTotals unused;
        if (p == 0) walk.r(unused, pick);
        if (p == 1 || p == 2) walk.paths(unused, pick);

        const T eta = mat_->params().eta;
        const Ggx<T> ggx(chosen.p < kLobes ? chosen.alpha : mat_->ggx().alpha());
        const InterfaceLobes<T> l{&ggx, chosen.v, chosen.m, chosen.cos_v};
        V3 wi;
        if (chosen.p == 0) {
            wi = mat_->section().from_section(l.sample_reflection(u.y, u.z));
        } else if (chosen.p < kLobes) {
            wi = mat_->section().from_section(l.sample_exit(eta, u.y, u.z));
        } else {
            const T sin_i = mat_->sample_residual(o.sin_o, u.y, u.z);
            wi = direction_from_azimuth(wo, sin_i, mat_->sample_residual_azimuth(o.azimuth, u.w));
        }
        return make_sample(wi, lobe_tag(chosen.p), query_walk<true, true>(walk, wi));
    }

    const Material* mat_;
    V3 sigma_a_{T(0)};
};

static_assert(is_fiber_model_v<HuangFiber<float>> && is_fiber_model_v<HuangFiber<double>>);
static_assert(is_fiber_model_v<HuangFiber<float, 0>> && is_fiber_model_v<HuangFiber<double, 0>>);

}  // namespace hairscatter
