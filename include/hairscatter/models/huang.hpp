// hairscatter — Huang, Hullin & Hanika 2022's microfacet-based fiber: a far-field fiber of
// elliptical cross-section whose surface is a rough dielectric (GGX microfacets about the
// cuticle-tilted "mesonormal"), R reflected at the surface, TT and TRT refracted and
// reflected through microfacets on their way through the fiber, and every higher order
// lumped into one residual lobe (docs/theory.md §3.6, docs/models.md).
//
// Deterministic: eval integrates the cross-section and the internal microfacet normals by
// fixed quadrature rules (two knobs: the offset nodes and the normal nodes), draws no random
// numbers, and sample() draws from exactly the density pdf() returns.
#pragma once

#include <cmath>
#include <algorithm>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../fiber/ellipse.hpp"
#include "../fiber/frame.hpp"
#include "../fiber/params.hpp"
#include "../lobes/longitudinal.hpp"
#include "../lobes/microfacet.hpp"
#include "../math/constants.hpp"
#include "../math/distributions.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"
#include "../math/quadrature.hpp"
#include "contract.hpp"

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

// Everything that depends only on the parameters and the two node counts, built once on the
// host (the constructor throws std::invalid_argument naming a bad parameter or count).
// Trivially copyable, a few KB: copy it to device memory once and pass the fiber a pointer.
//
// The offset integral: a far-field ray hits the section at h ∈ (-1, 1) uniformly
// (fiber/ellipse.hpp); nodes of an n-point Gauss–Legendre rule in γ = asin h (the rim goes
// like sqrt(1 - h²) and is smooth in γ), each weighted by how much of the beam the tilted
// surface there intercepts, ∝ max(0, v·m) |A⁻¹c| per unit γ (the cosine to the mesonormal
// m instead of the section's normal), renormalised to sum to 1 at every wo.
//
// The internal microfacet normals (TT's entry, TRT's internal reflection): the visible-normal
// distribution's unit square (u1 the cap's azimuth, u2 its height, lobes/microfacet.hpp) by
// k midpoints in u1 (periodic) × k Gauss–Legendre nodes in u2, k = normal_nodes.
//
// The reflectance tables: E(c) = ∫ F(v·h) D_v(h) dh, the share of the light arriving at
// cos c to the mesonormal that the interface reflects, outside (index η) and inside (1/η,
// with total internal reflection), tabulated on kTableSize cosines from a fine product rule.
// They fix each interface's split exactly: the quadrature's normals only decide where the
// transmitted (or internally reflected) part goes, and the energy stays exact.
template <typename T> class HuangMaterial {
  public:
    static constexpr int kLobes = 3;  // R, TT, TRT explicit; index 3 is the residual
    static constexpr int kMaxNodes = 128;
    static constexpr int kAutoNodes = 0;  // choose the offset nodes from the roughness (auto_nodes)
    static constexpr int kMaxNormalNodes = 4;
    static constexpr int kMaxNormalPoints = kMaxNormalNodes * kMaxNormalNodes;
    static constexpr int kDefaultNormalNodes = 2;
    static constexpr int kTableSize = 129;

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

    explicit HuangMaterial(const HuangParams<T>& params, int nodes = kAutoNodes, int normal_nodes = kDefaultNormalNodes)
        : params_(params) {
        const std::string m = validate(params);
        if (!m.empty()) HAIRSCATTER_THROW(std::invalid_argument("hairscatter: invalid Huang parameters: " + m));
        if (!(nodes >= 0 && nodes <= kMaxNodes))
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: HuangMaterial: nodes = " + std::to_string(nodes) +
                                                    " is outside its range [1, " + std::to_string(kMaxNodes) +
                                                    "] (or 0 for the automatic choice)"));
        if (!(normal_nodes >= 1 && normal_nodes <= kMaxNormalNodes))
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: HuangMaterial: normal_nodes = " +
                                                    std::to_string(normal_nodes) + " is outside its range [1, " +
                                                    std::to_string(kMaxNormalNodes) + "]"));
        nodes_ = nodes == kAutoNodes ? auto_nodes(params.roughness) : nodes;
        normal_nodes_ = normal_nodes;
        section_ = EllipticalSection<T>(params.aspect_ratio, params.orientation);
        ggx_ = Ggx<T>(params.roughness);
        // The residual lumps every order past TRT: a wide longitudinal lobe (variance 4β, as
        // Blender Cycles' implementation of the model) and uniform in azimuth, as Chiang et
        // al. 2016's residual.
        residual_ = DeonLongitudinal<T>(T(4) * params.roughness);
        using std::cos;
        using std::sin;
        sin_tilt_ = T(sin(double(params.alpha)));
        cos_tilt_ = T(cos(double(params.alpha)));

        const GaussLegendre<double> gl(nodes_);
        const double half_pi = 1.57079632679489661923;
        for (int k = 0; k < nodes_; ++k) {
            // The middle node of an odd rule is 0 analytically; Newton leaves it at ~1e-17.
            const double gamma = nodes_ % 2 == 1 && k == nodes_ / 2 ? 0.0 : half_pi * gl.nodes[std::size_t(k)];
            h_[k] = T(std::sin(gamma));
            cos_gamma_[k] = T(std::cos(gamma));
            weight_[k] = T(half_pi * gl.weights[std::size_t(k)]);
        }

        const GaussLegendre<double> glu(normal_nodes_);
        for (int i = 0; i < normal_nodes_; ++i)
            for (int j = 0; j < normal_nodes_; ++j) {
                const int q = i * normal_nodes_ + j;
                cos_u1_[q] = T(std::cos(6.28318530717958647692 * (i + 0.5) / normal_nodes_));
                sin_u1_[q] = T(std::sin(6.28318530717958647692 * (i + 0.5) / normal_nodes_));
                u2_[q] = T(0.5 + 0.5 * glu.nodes[std::size_t(j)]);
                uw_[q] = T(0.5 * glu.weights[std::size_t(j)] / normal_nodes_);
            }

        const GaussLegendre<double> table_rule(kTableRule);
        for (int i = 0; i < kTableSize; ++i) {
            const double c = double(i) / (kTableSize - 1);
            outside_[i] = T(mean_reflectance(double(params.roughness), c, double(params.eta), table_rule));
            inside_[i] = T(mean_reflectance(double(params.roughness), c, 1 / double(params.eta), table_rule));
        }
    }

    // E(c) = ∫ F(v·h, n) D_v(h) dh for v at cos c to the normal, n = η_t/η_i, in double by a
    // k-midpoint (azimuth) × k-point Gauss–Legendre (height) product rule over D_v's unit
    // square, gl the k-point rule (the tables use k = kTableRule; tests/huang_test.cpp
    // measures the error against k = 1024).
    static constexpr int kTableRule = 40;
    static double mean_reflectance(double roughness, double c, double n, const GaussLegendre<double>& gl) {
        const Ggx<double> ggx(roughness);
        const glm::dvec3 v(std::sqrt(std::max(0.0, 1 - c * c)), 0.0, c);
        const int k = int(gl.nodes.size());
        double e = 0;
        for (int i = 0; i < k; ++i)
            for (int j = 0; j < k; ++j) {
                const glm::dvec3 h = ggx.sample_visible_local(v, (i + 0.5) / k, 0.5 + 0.5 * gl.nodes[std::size_t(j)]);
                e += 0.5 * gl.weights[std::size_t(j)] / k * fresnel_any(glm::dot(v, h), n);
            }
        return e;
    }

    HAIRSCATTER_HD const HuangParams<T>& params() const { return params_; }
    HAIRSCATTER_HD const EllipticalSection<T>& section() const { return section_; }
    HAIRSCATTER_HD const Ggx<T>& ggx() const { return ggx_; }
    HAIRSCATTER_HD const DeonLongitudinal<T>& residual() const { return residual_; }
    HAIRSCATTER_HD T sin_tilt() const { return sin_tilt_; }
    HAIRSCATTER_HD T cos_tilt() const { return cos_tilt_; }

    HAIRSCATTER_HD int nodes() const { return nodes_; }
    HAIRSCATTER_HD T node_h(int k) const { return h_[k]; }
    HAIRSCATTER_HD T node_cos_gamma(int k) const { return cos_gamma_[k]; }
    HAIRSCATTER_HD T node_weight(int k) const { return weight_[k]; }

    HAIRSCATTER_HD int normal_nodes() const { return normal_nodes_; }
    HAIRSCATTER_HD int normal_points() const { return normal_nodes_ * normal_nodes_; }
    HAIRSCATTER_HD T normal_cos_u1(int q) const { return cos_u1_[q]; }
    HAIRSCATTER_HD T normal_sin_u1(int q) const { return sin_u1_[q]; }
    HAIRSCATTER_HD T normal_u2(int q) const { return u2_[q]; }
    HAIRSCATTER_HD T normal_weight(int q) const { return uw_[q]; }

    // E(c) outside and inside, linearly interpolated in c ∈ [0, 1].
    HAIRSCATTER_HD T reflectance_outside(T c) const { return lookup(outside_, c); }
    HAIRSCATTER_HD T reflectance_inside(T c) const { return lookup(inside_, c); }

  private:
    HAIRSCATTER_HD static T lookup(const T* table, T c) {
        const T x = clamp(c, T(0), T(1)) * T(kTableSize - 1);
        const int i = table_cell(x, kTableSize - 2);
        const T f = x - T(i);
        return table[i] + f * (table[i + 1] - table[i]);
    }

    HuangParams<T> params_;
    EllipticalSection<T> section_;
    Ggx<T> ggx_;
    DeonLongitudinal<T> residual_;
    T sin_tilt_ = T(0), cos_tilt_ = T(1);
    int nodes_ = 0, normal_nodes_ = 0;
    T h_[kMaxNodes] = {}, cos_gamma_[kMaxNodes] = {}, weight_[kMaxNodes] = {};
    T cos_u1_[kMaxNormalPoints] = {}, sin_u1_[kMaxNormalPoints] = {}, u2_[kMaxNormalPoints] = {}, uw_[kMaxNormalPoints] = {};
    T outside_[kTableSize] = {}, inside_[kTableSize] = {};
};

// The fiber. Same frame and convention as every model (contract.hpp): unit vectors in the
// fiber frame, wo toward the viewer, wi toward the light, eval with the cosine inside
// (∫ eval dωi = 1 for σa = 0). The light is traced from wo (reciprocity of the far field):
//
//   f(wo, wi) = Σ_k ŵ_k [ R_k(wi) + Σ_j t_kj TT_kj(wi) + Σ_j Σ_l t_kj r_kjl TRT_kjl(wi) ]
//             + E_res M(θi | θo) / 2π,
//
// k the offset nodes (weights ŵ_k), j the entry normals, l the internal reflection normals;
//   R_k   = F(v·h) D_v(h) / (4 v·h), h the half vector of wo and wi (Huang et al.'s R lobe);
//   TT, TRT = (1 - F(v·h)) D_v(h) |wi·h| / |η v + wi|², the refraction out of the fiber at
//           the exit's mesonormal, v the internal ray reversed (their TT and TRT, with the
//           generalised half vector of Walter et al. 2007);
//   t_kj  = (1 - E_out(wo·m_k)) ŵ'_j (1 - F_j) / Σ ŵ'(1 - F) · A_1, the light refracted
//           into the fiber at normal node j, times the chord's transmittance;
//   r_kjl = E_in(c_2) ŵ'_l F_l / Σ ŵ'F · A_2, the light reflected at the exit by node l;
//   E_res = what TRT's exit reflects, E_in(c_3) Σ_{n≥1} A_3^n R̄^(n-1) (1 - R̄) summed in
//           closed form, A_3 = sqrt(A_1 A_2) and R̄ the Fresnel reflectance at the mesonormal
//           (Chiang et al. 2016's geometric series); plus whatever the geometry cannot
//           follow (a chord that does not enter, an exit hit from behind its mesonormal).
// Shadowing–masking of the scattered direction is left out: every microfacet event keeps
// its energy, which is the energy compensation the paper adds taken to its limit.
//
// sample picks a path end (node k, then R, one TT_kj, one TRT_kjl or the residual) with
// probability ∝ its energy's channel mean, then a direction from that end's lobe: a
// visible normal and its reflection (R), a visible normal and the refraction through it —
// or its reflection where it totally reflects (TT, TRT) — or the residual's M and a uniform
// φ. pdf is that mixture's density, computed in the same loop as f.
//
// Holds a pointer to the material, which must outlive the fiber and its at(wo) objects (a
// temporary material is rejected at compile time; on a GPU, a pointer to a device copy).
// Each call walks every path (n (1 + 2k² + k⁴) ends), so the cost is linear in the offset
// nodes and grows as k⁴ in the normal nodes (docs/tradeoff.md).
template <typename T> class HuangFiber : public FiberModel<HuangFiber<T>, T> {
  public:
    using V2 = glm::vec<2, T>;
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    using Material = HuangMaterial<T>;
    static constexpr int kLobes = Material::kLobes;

    HAIRSCATTER_HD explicit HuangFiber(const Material& material) : mat_(&material) {}
    HuangFiber(const Material&&) = delete;

    HAIRSCATTER_HD const Material& material() const { return *mat_; }

    // Σ of every path end's energy: the directional albedo, exact up to the reflectance
    // tables' interpolation (each lobe integrates to its end's energy).
    HAIRSCATTER_HD V3 albedo(const V3& wo) const {
        if (!is_finite(wo)) return V3(T(0));
        const Outgoing o = outgoing<false>(wo);
        V3 a(T(0));
        for (int k = 0; k < mat_->nodes(); ++k) walk(o, k, [&](const End& e) { a += e.energy; });
        return a;
    }

  private:
    friend class FiberModel<HuangFiber, T>;
    friend class BoundFiber<HuangFiber>;

    // The terms that depend on wo only: wo in the section frame, the far-field view and the
    // offset weights' normaliser.
    struct Outgoing {
        V3 v;
        T sin_o, cos_o;
        typename EllipticalSection<T>::View view;
        T inv_total;   // 1 / Σ_k W_k |A⁻¹c_k| max(0, v·m_k)
        bool visible;  // false: no node sees its mesonormal (|θo| within α of a pole)
    };

    // One end of a path: the light that reaches the last interface (prefix), what that
    // interface scatters in all (energy) and how: R (p = 0) reflects off the outside, TT and
    // TRT (1, 2) refract out, the residual (3) is M/2π. v is on the incident side of the
    // interface normal m, cos_v = v·m > 0.
    struct End {
        int p;
        V3 prefix, energy;
        V3 v, m;
        T cos_v;
    };

    static HAIRSCATTER_HD T mean(const V3& x) { return (x.x + x.y + x.z) * T(1.0 / 3.0); }

    HAIRSCATTER_HD V3 mesonormal(const V2& c) const {
        const V2 n = mat_->section().normal(c);
        return V3(mat_->sin_tilt(), mat_->cos_tilt() * n.x, mat_->cos_tilt() * n.y);
    }

    HAIRSCATTER_HD V3 transmittance(T length) const {
        const V3& s = mat_->params().sigma_a;
        return V3(elem::exp(-s.x * length), elem::exp(-s.y * length), elem::exp(-s.z * length));
    }

    // The far-field weight of node k before normalising, and its circle point and mesonormal.
    struct NodeGeometry {
        V2 c;
        V3 m;
        T cos_v, raw;
    };
    HAIRSCATTER_HD NodeGeometry node(const Outgoing& o, int k) const {
        NodeGeometry g;
        g.c = EllipticalSection<T>::hit(o.view, mat_->node_h(k), mat_->node_cos_gamma(k));
        g.m = mesonormal(g.c);
        g.cos_v = glm::dot(o.v, g.m);
        g.raw = mat_->node_weight(k) * mat_->section().normal_scale(g.c);
        if (o.visible) g.raw *= g.cos_v > T(0) ? g.cos_v : T(0);
        return g;
    }

    template <bool kW> HAIRSCATTER_HD Outgoing outgoing(const V3& wo) const {
        Outgoing o;
        o.v = mat_->section().to_section(wo);
        o.sin_o = clamp(wo.x, T(-1), T(1));
        o.cos_o = cos_from_sin(o.sin_o);
        o.view = mat_->section().view(o.v);
        o.visible = true;
        T total = T(0);
        for (int k = 0; k < mat_->nodes(); ++k) total += node(o, k).raw;
        if (!(total > T(0))) {
            // No mesonormal faces wo: every node's share goes to the residual, by offset width.
            o.visible = false;
            total = T(0);
            for (int k = 0; k < mat_->nodes(); ++k) total += node(o, k).raw;
        }
        o.inv_total = T(1) / total;
        return o;
    }

    // The normal nodes of D_v about m from v, and each one's share ŵ'(1 - F) of the
    // transmitted light (transmit) or ŵ'F of the reflected light, F at relative index n.
    struct NormalNodes {
        V3 h[Material::kMaxNormalPoints];
        T share[Material::kMaxNormalPoints];
        T sum;
    };
    HAIRSCATTER_HD NormalNodes normal_nodes(const V3& m, const V3& v, T n, bool transmit) const {
        NormalNodes r;
        r.sum = T(0);
        const TangentFrame<T> frame(m, v);
        const V3 v_local = frame.to_local(v);
        for (int q = 0; q < mat_->normal_points(); ++q) {
            r.h[q] = frame.to_world(mat_->ggx().sample_visible_local(v_local, mat_->normal_cos_u1(q),
                                                                     mat_->normal_sin_u1(q), mat_->normal_u2(q)));
            const T f = fresnel_any(glm::dot(v, r.h[q]), n);
            r.share[q] = mat_->normal_weight(q) * (transmit ? T(1) - f : f);
            r.sum += r.share[q];
        }
        return r;
    }

    // Calls visit(End) for every path end of node k, in a fixed order (sample relies on it).
    template <typename Visit> HAIRSCATTER_HD void walk(const Outgoing& o, int k, Visit&& visit) const {
        const NodeGeometry g = node(o, k);
        const T w = g.raw * o.inv_total;
        if (!(w > T(0))) return;
        if (!o.visible || !(g.cos_v > T(0))) {
            visit(residual_end(V3(w)));
            return;
        }
        const T eta = mat_->params().eta, inv_eta = T(1) / eta;
        const T e_out = mat_->reflectance_outside(g.cos_v);
        visit(End{0, V3(w), V3(w * e_out), o.v, g.m, g.cos_v});

        // Entry: the transmitted share (1 - E_out) split over the normal nodes ∝ ŵ'(1 - F).
        const NormalNodes nn = normal_nodes(g.m, o.v, eta, true);
        const T transmitted = w * (T(1) - e_out);
        if (!(nn.sum > T(0))) {
            visit(residual_end(V3(transmitted)));
            return;
        }
        for (int q = 0; q < mat_->normal_points(); ++q) {
            const Refracted<T> r = refract_through(o.v, nn.h[q], inv_eta);
            // Refraction into the denser side always exists; normalise away the rounding.
            const V3 t = r.ok ? glm::normalize(r.o) : -g.m;
            inside(g.c, t, V3(transmitted * nn.share[q] / nn.sum), visit);
        }
    }

    // The light entering at circle point c along t with throughput `in`: the chord, the exit
    // (TT), and per internal-reflection node the second chord and TRT's exit and residual.
    template <typename Visit>
    HAIRSCATTER_HD void inside(const V2& c, const V3& t, const V3& in, Visit&& visit) const {
        const T eta = mat_->params().eta, inv_eta = T(1) / eta;
        const auto chord = mat_->section().chord(c, V2(t.y, t.z));
        if (!chord.ok) {
            visit(residual_end(in));
            return;
        }
        const V3 a1 = transmittance(chord.length);
        const V3 at_exit = in * a1;
        const V3 m_in = -mesonormal(chord.c);
        const V3 v2 = -t;
        const T cos2 = glm::dot(v2, m_in);
        if (!(cos2 > T(0))) {
            visit(residual_end(at_exit));
            return;
        }
        const T e_in = mat_->reflectance_inside(cos2);
        visit(End{1, at_exit, at_exit * (T(1) - e_in), v2, m_in, cos2});

        // Internal reflection: the reflected share E_in split over the normal nodes ∝ ŵ'F;
        // F ≥ ((η - 1)/(η + 1))² > 0 at every normal, so the sum is > 0.
        const NormalNodes nn = normal_nodes(m_in, v2, inv_eta, false);
        for (int q = 0; q < mat_->normal_points(); ++q) {
            const V3 in2 = at_exit * (e_in * nn.share[q] / nn.sum);
            const V3 r = glm::normalize(reflect_about(v2, nn.h[q]));
            const auto chord2 = mat_->section().chord(chord.c, V2(r.y, r.z));
            if (!chord2.ok) {
                visit(residual_end(in2));
                continue;
            }
            const V3 a2 = transmittance(chord2.length);
            const V3 at_exit2 = in2 * a2;
            const V3 m3 = -mesonormal(chord2.c);
            const T cos3 = -glm::dot(r, m3);
            if (!(cos3 > T(0))) {
                visit(residual_end(at_exit2));
                continue;
            }
            const T e3 = mat_->reflectance_inside(cos3);
            visit(End{2, at_exit2, at_exit2 * (T(1) - e3), -r, m3, cos3});
            // Orders past TRT: A_3 Σ (A_3 R̄)^n (1 - R̄); its limit 1 where A_3 R̄ → 1 (no loss).
            const T r_bar = fresnel_any(cos3, inv_eta);
            V3 series;
            for (int ch = 0; ch < 3; ++ch) {
                using std::sqrt;
                const T a3 = sqrt(a1[ch] * a2[ch]);
                const T den = T(1) - a3 * r_bar;
                series[ch] = den > T(1e-6) ? a3 * (T(1) - r_bar) / den : T(1);
            }
            visit(residual_end(at_exit2 * e3 * series));
        }
    }

    HAIRSCATTER_HD static End residual_end(const V3& energy) {
        End e{};
        e.p = kLobes;
        e.energy = energy;
        return e;
    }

    // The lobe of end e at wi (section frame): f's factor (times e.prefix) and the
    // sampler's density.
    struct LobeValue {
        T f, q;
    };
    template <bool kF, bool kPdf> HAIRSCATTER_HD LobeValue lobe(const End& e, const V3& wi) const {
        const T eta = mat_->params().eta;
        const InterfaceLobes<T> l{&mat_->ggx(), e.v, e.m, e.cos_v};
        LobeValue r{T(0), T(0)};
        if (e.p == 0) {
            const auto x = l.reflection(wi);
            if (kF && x.q > T(0)) r.f = fresnel_any(x.v_dot_h, eta) * x.q;
            r.q = x.q;
            return r;
        }
        const auto x = l.refraction(wi, eta);
        if (kF && x.q > T(0)) r.f = (T(1) - fresnel_any(x.v_dot_h, T(1) / eta)) * x.q;
        if (kPdf) r.q = x.q + l.total_reflection(wi, eta);
        return r;
    }

    template <bool kF, bool kPdf> HAIRSCATTER_HD HairEvalPdf<T> query(const Outgoing& o, const V3& wo, const V3& wi) const {
        (void)wo;
        const V3 w = mat_->section().to_section(wi);
        V3 f(T(0)), residual(T(0));
        T pdf = T(0), total = T(0);
        for (int k = 0; k < mat_->nodes(); ++k)
            walk(o, k, [&](const End& e) {
                const T weight = mean(e.energy);
                total += weight;
                if (e.p == kLobes) {
                    residual += e.energy;
                    return;
                }
                const LobeValue x = lobe<kF, kPdf>(e, w);
                if (kF) f += x.f * e.prefix;
                if (kPdf) pdf += weight * x.q;
            });
        const T sin_i = clamp(wi.x, T(-1), T(1));
        const T m = mat_->residual().eval(sin_i, cos_from_sin(sin_i), o.sin_o, o.cos_o) * kInvTwoPi<T>;
        HairEvalPdf<T> r;
        r.f = f + m * residual;
        // total ≥ the R ends' share, > 0 (E_out ≥ F0 at every node), or the residual's.
        r.pdf = (pdf + m * mean(residual)) / total;
        return r;
    }

    // u.x picks the node and then, its leftover rescaled, the path end; (u.y, u.z) the
    // visible normal of the end's interface or θi of the residual, u.w the residual's φ.
    HAIRSCATTER_HD HairSample<T> sample_from(const Outgoing& o, const V3& wo, const V4& u) const {
        const int n = mat_->nodes();
        T t[Material::kMaxNodes] = {};
        T total = T(0);
        for (int k = 0; k < n; ++k) {
            T s = T(0);
            walk(o, k, [&](const End& e) { s += mean(e.energy); });
            t[k] = s;
            total += s;
        }
        const DiscreteChoice<T> node_choice = sample_discrete(t, n, u.x, total);
        const T target = node_choice.rescaled * t[node_choice.index];
        // The first end whose cumulative weight passes the target (or the last with weight).
        End chosen = residual_end(V3(T(0)));
        T before = T(0);
        bool done = false;
        walk(o, node_choice.index, [&](const End& e) {
            const T weight = mean(e.energy);
            if (done || !(weight > T(0))) return;
            chosen = e;
            before += weight;
            done = target < before;
        });

        const T eta = mat_->params().eta;
        const InterfaceLobes<T> l{&mat_->ggx(), chosen.v, chosen.m, chosen.cos_v};
        V3 wi;
        if (chosen.p == 0) {
            wi = mat_->section().from_section(l.sample_reflection(u.y, u.z));
        } else if (chosen.p < kLobes) {
            wi = mat_->section().from_section(l.sample_exit(eta, u.y, u.z));
        } else {
            const T sin_i = mat_->residual().sample_sin_theta(o.sin_o, o.cos_o, u.y, u.z);
            wi = direction_from_azimuth(wo, sin_i, kTwoPi<T> * u.w - kPi<T>);
        }
        return make_sample(wi, lobe_tag(chosen.p), query<true, true>(o, wo, wi));
    }

    const Material* mat_;
};

static_assert(is_fiber_model_v<HuangFiber<float>> && is_fiber_model_v<HuangFiber<double>>);

}  // namespace hairscatter
