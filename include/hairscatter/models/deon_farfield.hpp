// hairscatter — d'Eon et al. 2011's far-field fiber: the energy-conserving M_p with the
// azimuthal N_p integrated over the offset h, N_p(φ) = ½ ∫ A_p(h) D(φ - Φ(p, h)) dh, D a
// wrapped Gaussian (docs/theory.md §3.4). The fiber needs no h from the renderer (ribbons and
// tubes that do not know where across the fiber they were hit); sample draws h itself.
#pragma once

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../fiber/frame.hpp"
#include "../fiber/params.hpp"
#include "../lobes/attenuation.hpp"
#include "../lobes/azimuthal.hpp"
#include "../lobes/deon_lobes.hpp"
#include "../math/constants.hpp"
#include "../math/distributions.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"
#include "../math/quadrature.hpp"
#include "../math/wrapped_gaussian.hpp"
#include "contract.hpp"

namespace hairscatter {

// Everything that depends only on the fiber parameters and the number of h nodes, computed
// once on the host (validated: the constructor throws std::invalid_argument naming the bad
// parameter). Trivially copyable (≈ 4.4 KB in double, over the 4 KB kernel-parameter
// limit of CUDA < 12.1): copy it to device memory once and pass the fiber a pointer.
//
// The h integral: nodes of an n-point Gauss–Legendre rule placed in γ = asin h rather than
// in h, because A_p and Φ go like √(1 - h²) at the rim and are smooth in γ:
//   ½ ∫_{-1}^{1} f(h) dh = ½ ∫_{-π/2}^{π/2} f(sin γ) cos γ dγ ≈ Σ_k ŵ_k f(sin γ_k),
//   ŵ_k ∝ (π/4) W_k cos γ_k,
// with the ŵ_k renormalised to sum to exactly 1 (the rule's estimate of ½∫ dh = 1 is off
// by 3e-2 at n = 2 and 1e-9 at n = 8): then the lossless fiber conserves energy exactly
// at every n, since Σ_p A_p(h) = 1 at every node. The rule is symmetric and A_p is even in
// h, so only the nodes with h ≥ 0 are stored and each carries its mirror image -h.
//
// Its d'Eon ingredients (longitudinal(p), tilt(), lobe_shift(p), lobe_variance(p)) are
// DeonLobes'.
template <typename T> class DeonFarFieldMaterial : public DeonLobes<T> {
  public:
    static constexpr int kLobes = DeonLobes<T>::kLobes;  // R, TT, TRT explicit; index 3 is the residual
    static constexpr int kMaxNodes = 256;
    static constexpr int kMaxHalfNodes = kMaxNodes / 2;
    static constexpr int kAutoNodes = 0;  // choose the node count from β_n (auto_nodes)

    // The node count that resolves the detector of width σ(β_n) to ~1e-4: the rule samples
    // the exit azimuth Φ(p, h) at spacing |dΦ/dγ| Δγ ≤ 2 · π²/(2n) (R's |dΦ/dγ| = 2 is the
    // largest away from the rim; Gauss–Legendre's widest gap, at the centre, is ≈ π/n in
    // [-1, 1], π²/(2n) in γ), and a sum of Gaussians sampled at spacing Δ deviates from
    // its integral by ≈ 2 exp(-2π²σ²/Δ²) (Poisson summation), 1e-4 at Δ = 1.45σ. So
    // n = ⌈π²/(1.45σ)⌉, rounded up to even and kept in [24, kMaxNodes]: 34 nodes at
    // β_n = 0.3, 156 at β_n = 0.1; below β_n ≈ 0.06 the cap leaves the comb visible (use the
    // near-field ChiangFiber with a random h there). At least 24 nodes: wide detectors are
    // limited instead by the smoothness of A_p and Φ in γ (8 nodes: 1e-3 at β_n = 1, 24:
    // 1e-5). Measured in tests/deon_farfield_test.cpp.
    static int auto_nodes(T beta_n) {
        const double sigma = double(azimuthal_gaussian_width(beta_n));
        const double n = std::ceil(9.8696044010893586188 / (1.45 * sigma));
        int k = n > double(kMaxNodes) ? kMaxNodes : int(n);
        k += k % 2;
        return k < 24 ? 24 : (k > kMaxNodes ? kMaxNodes : k);
    }

    // nodes: the Gauss–Legendre order of the h integral, 1 … kMaxNodes, or kAutoNodes for
    // auto_nodes(β_n) (the cost of eval, pdf and sample is linear in it).
    explicit DeonFarFieldMaterial(const FiberParams<T>& params, int nodes = kAutoNodes)
        : DeonLobes<T>(validated(params).beta_m, params.alpha), params_(params), nodes_(nodes) {
        if (!(nodes >= 0 && nodes <= kMaxNodes))
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DeonFarFieldMaterial: nodes = " + std::to_string(nodes) +
                                        " is outside its range [1, " + std::to_string(kMaxNodes) +
                                        "] (or 0 for the automatic choice)"));
        if (nodes == kAutoNodes) nodes_ = nodes = auto_nodes(params.beta_n);
        n_ = WrappedGaussian<T>(azimuthal_gaussian_width(params.beta_n));

        const GaussLegendre<double> gl(nodes);
        const double quarter_pi = 0.78539816339744830962;
        double total = 0;
        for (int k = 0; k < nodes; ++k) total += quarter_pi * gl.weights[std::size_t(k)] * std::cos(2 * quarter_pi * gl.nodes[std::size_t(k)]);
        // gl.nodes is ascending and symmetric: the upper half (with the middle node h = 0
        // when n is odd, which has no mirror) holds the h ≥ 0 nodes.
        half_nodes_ = (nodes + 1) / 2;
        for (int j = 0; j < half_nodes_; ++j) {
            const int k = nodes - half_nodes_ + j;
            // The middle node of an odd rule is 0 analytically; Newton leaves it at ~1e-17.
            const bool middle = nodes % 2 == 1 && j == 0;
            const double gamma = middle ? 0.0 : 2 * quarter_pi * gl.nodes[std::size_t(k)];
            gamma_[j] = T(gamma);
            h_[j] = T(std::sin(gamma));
            cos_gamma_[j] = T(std::cos(gamma));
            weight_[j] = T(quarter_pi * gl.weights[std::size_t(k)] * std::cos(gamma) / total);
            mirrored_[j] = !middle;
        }
    }

    HAIRSCATTER_HD const FiberParams<T>& params() const { return params_; }
    HAIRSCATTER_HD const WrappedGaussian<T>& azimuthal() const { return n_; }

    // The quadrature: n nodes in all, stored as half_nodes() nodes with h ≥ 0; node j
    // stands for h_j and, when mirrored(j), also for -h_j, each with weight weight(j).
    HAIRSCATTER_HD int nodes() const { return nodes_; }
    HAIRSCATTER_HD int half_nodes() const { return half_nodes_; }
    HAIRSCATTER_HD T node_h(int j) const { return h_[j]; }
    HAIRSCATTER_HD T node_gamma(int j) const { return gamma_[j]; }
    HAIRSCATTER_HD T node_cos_gamma(int j) const { return cos_gamma_[j]; }
    HAIRSCATTER_HD T node_weight(int j) const { return weight_[j]; }
    HAIRSCATTER_HD bool node_mirrored(int j) const { return mirrored_[j]; }

  private:
    FiberParams<T> params_;
    int nodes_ = 0, half_nodes_ = 0;
    WrappedGaussian<T> n_;
    T h_[kMaxHalfNodes] = {}, gamma_[kMaxHalfNodes] = {}, cos_gamma_[kMaxHalfNodes] = {}, weight_[kMaxHalfNodes] = {};
    bool mirrored_[kMaxHalfNodes] = {};
};

// The far-field fiber. Same frame and convention as ChiangFiber: unit vectors in the fiber
// frame (x = tangent), wo toward the viewer, wi toward the light, eval with the cosine
// inside (∫ eval dωi = 1 for σa = 0).
//
//   f(wo, wi) = Σ_p M_p(θi | θo'_p) Σ_k ŵ_k A_p(h_k) D(φ - Φ(p, h_k)),  p = R, TT, TRT,
//             + M_3(θi | θo) Σ_k ŵ_k A_3(h_k) / 2π                        (residual).
//
// sample picks (k, p) with probability P(k, p) = ŵ_k mean(A_p(h_k)) / mean(albedo), then θi
// from M_p and φ = Φ(p, h_k) + a wrapped-Gaussian sample (residual: φ uniform). Its density
// Σ_k Σ_p P(k, p) M_p D is linear in A_p, so pdf = mean(f) / mean(albedo) exactly, computed
// in the same loop as f.
//
// Holds a pointer to the material, which must outlive the fiber and its at(wo) objects (a
// temporary material is rejected at compile time; on a GPU, a pointer to a device copy).
// at(wo) caches θo, its tilts and the refraction set-up; the per-node A_p(h_j) (up to 128
// nodes) are recomputed per call, to keep the bound object small. Each call loops over the ⌈n/2⌉ stored nodes, so the cost is
// linear in n: at 32 nodes about 1 µs per eval in float (docs/tradeoff.md), some 12× the
// ChiangFiber. Accuracy needs the nodes' exit azimuths closer than the Gaussian's σ; the
// automatic node count (DeonFarFieldMaterial::auto_nodes) gives ~1e-4 down to β_n ≈ 0.06.
// Energy and sampling are exact at any n.
template <typename T> class DeonFarFieldFiber : public FiberModel<DeonFarFieldFiber<T>, T> {
  public:
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    using Material = DeonFarFieldMaterial<T>;
    static constexpr int kLobes = Material::kLobes;
    using LobeSplit = hairscatter::LobeSplit<T, kLobes>;

    HAIRSCATTER_HD explicit DeonFarFieldFiber(const Material& material) : mat_(&material) {}
    DeonFarFieldFiber(const Material&&) = delete;

    HAIRSCATTER_HD const Material& material() const { return *mat_; }

    // ½ ∫ Σ_p A_p(h) dh by the same quadrature: the directional albedo, exact for this
    // model because every M_p and D is normalised.
    HAIRSCATTER_HD V3 albedo(const V3& wo) const { return split_albedo(split<false>(wo)); }

    // Per lobe: ½ ∫ A_p(h) dh and the part of N_p in the backward half |φ| < π/2, each
    // node's wrapped Gaussian weighted by the channel sum of its A_p(h_j).
    // centre: the mass on |φ - centre| < π/2 instead (the dual-scattering window).
    HAIRSCATTER_HD LobeSplit lobe_split(const V3& wo, T centre = T(0)) const { return split<true>(wo, centre); }


    // The quadrature's terms at wo's inclination, for tabulating N_p (models/tabulated.hpp):
    // A_p(h_j) for every lobe (even in h, so shared with the mirror node -h_j) and the exit
    // azimuths Φ(p, h_j) of R, TT, TRT (the mirror's is -Φ(p, h_j) modulo 2π). Then
    //   N_p(φ) A_p = Σ_j ŵ_j A_p(h_j) [D(φ - Φ(p, h_j)) + (if mirrored(j)) D(φ + Φ(p, h_j))].
    struct NodeTerms {
        V3 a[kLobes + 1];
        T phi[kLobes];
    };
    HAIRSCATTER_HD NodeTerms node_terms(const V3& wo, int j) const {
        const Node nd = node(outgoing<false>(wo), j);
        NodeTerms r;
        for (int p = 0; p <= kLobes; ++p) r.a[p] = nd.att.a[p];
        for (int p = 0; p < kLobes; ++p) r.phi[p] = exit_azimuth(p, mat_->node_gamma(j), nd.gamma_t);
        return r;
    }

  private:
    friend class FiberModel<DeonFarFieldFiber, T>;
    friend class BoundFiber<DeonFarFieldFiber>;

    // The terms that depend on wo only.
    struct Outgoing {
        T sin_o, cos_o;
        T sin_p[kLobes + 1], cos_p[kLobes + 1];  // tilted θo' per lobe
        DeonLanes<T, kLobes + 1> m;               // M_p at θo', side by side
        FiberRefraction<T> refraction;            // γt and the chord, per h
    };
    struct Node {
        Attenuation<T, kLobes> att;
        T gamma_t;
    };

    // lobe_split, with the backward fractions only when asked for (albedo needs none).
    template <bool kBackward> HAIRSCATTER_HD LobeSplit split(const V3& wo, T centre = T(0)) const {
        const Outgoing o = outgoing<false>(wo);
        const T sigma = mat_->azimuthal().sigma();
        LobeSplit r;
        T back[kLobes + 1] = {};
        for (int p = 0; p <= kLobes; ++p) r.a[p] = V3(T(0));
        for (int j = 0; j < mat_->half_nodes(); ++j) {
            const Node nd = node(o, j);
            const bool mirrored = mat_->node_mirrored(j);
            const T w = mat_->node_weight(j), gamma = mat_->node_gamma(j);
            for (int p = 0; p <= kLobes; ++p) r.a[p] += (w * (mirrored ? T(2) : T(1))) * nd.att.a[p];
            if constexpr (!kBackward) continue;
            for (int p = 0; p < kLobes; ++p) {
                T mass = wrapped_gaussian_backward_mass(sigma, exit_azimuth(p, gamma, nd.gamma_t) - centre);
                if (mirrored) mass += wrapped_gaussian_backward_mass(sigma, exit_azimuth(p, -gamma, -nd.gamma_t) - centre);
                back[p] += w * mass * (nd.att.a[p].x + nd.att.a[p].y + nd.att.a[p].z);
            }
        }
        for (int p = 0; p < kLobes; ++p) {
            const T total = r.a[p].x + r.a[p].y + r.a[p].z;
            r.backward[p] = total > T(0) ? back[p] / total : T(0.5);
        }
        r.backward[kLobes] = T(0.5);  // the residual is uniform in φ
        return r;
    }

    // The same terms serve eval and pdf (pdf = mean(f) / mean(albedo) in one loop).
    template <bool kW> HAIRSCATTER_HD Outgoing outgoing(const V3& wo) const {
        const FiberParams<T>& prm = mat_->params();
        Outgoing o;
        o.sin_o = clamp(wo.x, T(-1), T(1));
        o.cos_o = cos_from_sin(o.sin_o);
        o.refraction = FiberRefraction<T>(o.sin_o, o.cos_o, prm.eta);
        mat_->tilt_all(o.sin_o, o.cos_o, o.sin_p, o.cos_p);
        mat_->template condition<LobeSet::kAll>(o.m, o.sin_o, o.cos_o);
        return o;
    }

    template <bool kF, bool kPdf> HAIRSCATTER_HD HairEvalPdf<T> query(const Outgoing& o, const V3& wo, const V3& wi) const {
        const T sin_i = clamp(wi.x, T(-1), T(1));
        const T phi = relative_azimuth(wo, wi);
        return combine(o, sin_i, cos_from_sin(sin_i), phi);
    }

    // u.x picks the node, its sign and the lobe (each choice rescales the leftover of u.x
    // into a fresh uniform, which then drives the Box–Muller angle), (u.y, u.z) sample θi
    // from M_p, u.w the Box–Muller radius (or φ for the residual).
    HAIRSCATTER_HD HairSample<T> sample_from(const Outgoing& o, const V3& wo, const V4& u) const {
        const int n = mat_->half_nodes();

        // Node probabilities ∝ (multiplicity) ŵ_j mean(Σ_p A_p(h_j)); all > 0, since
        // A_0 = F ≥ ((η - 1)/(η + 1))² and every ŵ_j > 0.
        T t[Material::kMaxHalfNodes] = {};  // zeroed: GCC cannot see that half_nodes() ≥ 1
        T total = T(0);
        for (int j = 0; j < n; ++j) {
            const Node nd = node(o, j);
            T s = T(0);
            for (int p = 0; p <= kLobes; ++p) s += nd.att.a[p].x + nd.att.a[p].y + nd.att.a[p].z;
            t[j] = s * mat_->node_weight(j) * (mat_->node_mirrored(j) ? T(2) : T(1));
            total += t[j];
        }
        const DiscreteChoice<T> node_choice = sample_discrete(t, n, u.x, total);
        const int j = node_choice.index;
        T v = node_choice.rescaled;
        T sign = T(1);
        if (mat_->node_mirrored(j)) {
            sign = v < T(0.5) ? T(1) : T(-1);
            v = v < T(0.5) ? T(2) * v : T(2) * v - T(1);
        }

        // The lobe ∝ mean(A_p(h_j)) (w[0] ∝ F > 0).
        const Node nd = node(o, j);
        T w[kLobes + 1], wsum = T(0);
        for (int p = 0; p <= kLobes; ++p) {
            w[p] = nd.att.a[p].x + nd.att.a[p].y + nd.att.a[p].z;
            wsum += w[p];
        }
        const DiscreteChoice<T> lobe = sample_discrete(w, kLobes + 1, v, wsum);
        const int p = lobe.index;
        v = lobe.rescaled;

        const T sin_i = mat_->longitudinal(p).sample_sin_theta(o.sin_p[p], o.cos_p[p], u.y, u.z);
        const T cos_i = cos_from_sin(sin_i);
        const T phi = p < kLobes ? wrap_pi(exit_azimuth(p, sign * mat_->node_gamma(j), sign * nd.gamma_t) +
                                           mat_->azimuthal().sample(u.w, v))
                                 : wrap_pi(kTwoPi<T> * u.w - kPi<T>);

        return make_sample(direction_from_azimuth(wo, sin_i, phi), lobe_tag(p), combine(o, sin_i, cos_i, phi));
    }

    // A_p(h_j) for all lobes (even in h, so shared with the mirror node) and γt(h_j).
    HAIRSCATTER_HD Node node(const Outgoing& o, int j) const {
        const FiberParams<T>& prm = mat_->params();
        const auto path = o.refraction.at(mat_->node_h(j), prm.sigma_a);
        Node nd;
        nd.att = attenuation<T, kLobes>(fresnel_dielectric(o.cos_o * mat_->node_cos_gamma(j), prm.eta),
                                        path.transmittance);
        nd.gamma_t = path.gamma_t;
        return nd;
    }

    // f and pdf at (θi, φ): the four M_p once, then per node A_p · D for both signs of h.
    HAIRSCATTER_HD HairEvalPdf<T> combine(const Outgoing& o, T sin_i, T cos_i, T phi) const {
        T m[kLobes + 1];
        o.m.eval_all(sin_i, cos_i, m);
        const WrappedGaussian<T>& d = mat_->azimuthal();
        V3 f(T(0)), alb(T(0));
        for (int j = 0; j < mat_->half_nodes(); ++j) {
            const Node nd = node(o, j);
            const bool mirrored = mat_->node_mirrored(j);
            const T w = mat_->node_weight(j), gamma = mat_->node_gamma(j);
            for (int p = 0; p < kLobes; ++p) {
                // N_p's two quadrature terms: h_j and -h_j (Φ is odd in h about pπ).
                T np = d.pdf(wrap_pi(phi - exit_azimuth(p, gamma, nd.gamma_t)));
                if (mirrored) np += d.pdf(wrap_pi(phi - exit_azimuth(p, -gamma, -nd.gamma_t)));
                f += (w * m[p] * np) * nd.att.a[p];
            }
            // The residual lumps all higher orders: uniform in φ.
            const T mult = mirrored ? T(2) : T(1);
            f += (w * mult * m[kLobes] * kInvTwoPi<T>) * nd.att.a[kLobes];
            for (int p = 0; p <= kLobes; ++p) alb += (w * mult) * nd.att.a[p];
        }
        HairEvalPdf<T> r;
        r.f = f;
        // alb ≥ F > 0 in every channel (see sample), so the division is safe.
        r.pdf = (f.x + f.y + f.z) / (alb.x + alb.y + alb.z);
        return r;
    }

    const Material* mat_;
};

static_assert(is_fiber_model_v<DeonFarFieldFiber<float>> && is_fiber_model_v<DeonFarFieldFiber<double>>);

}  // namespace hairscatter
