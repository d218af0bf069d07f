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
#include "../lobes/farfield_quadrature.hpp"
#include "../lobes/lobe_controls.hpp"
#include "../math/constants.hpp"
#include "../math/distributions.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"
#include "../math/wrapped_gaussian.hpp"
#include "contract.hpp"

namespace hairscatter {

// Everything that depends only on the fiber parameters and the number of h nodes, computed
// once on the host (validated: the constructor throws std::invalid_argument naming the bad
// parameter). Trivially copyable (≈ 4.8 KB in double, over the 4 KB kernel-parameter
// limit of CUDA < 12.1): copy it to device memory once and pass the fiber a pointer.
//
// The h integral is lobes/farfield_quadrature.hpp's rule (nodes(), node_h(j), …, and
// auto_nodes(β_n) for the node count); its d'Eon ingredients (longitudinal(p), tilt(),
// lobe_shift(p), lobe_variance(p)) are DeonLobes'.
// The optional lobe controls (lobes/lobe_controls.hpp), as ChiangMaterial takes them: the
// per-lobe tilts go into DeonLobes, the gains and tints into lobe_weight(p), which the fiber
// multiplies into every A_p(h_j) (without controls it skips the products).
template <typename T> class DeonFarFieldMaterial : public DeonLobes<T>, public FarFieldQuadrature<T> {
  public:
    using Quadrature = FarFieldQuadrature<T>;
    static constexpr int kLobes = DeonLobes<T>::kLobes;  // R, TT, TRT explicit; index 3 is the residual
    using Quadrature::kAutoNodes;
    using Quadrature::kMaxHalfNodes;
    using Quadrature::kMaxNodes;

    // nodes: the Gauss–Legendre order of the h integral, 1 … kMaxNodes, or kAutoNodes for
    // auto_nodes(β_n) (the cost of eval, pdf and sample is linear in it).
    explicit DeonFarFieldMaterial(const FiberParams<T>& params, int nodes = kAutoNodes,
                                  const LobeControls<T>& controls = LobeControls<T>())
        : DeonLobes<T>(validated(params).beta_m, validated(controls), params.alpha),
          Quadrature(checked_nodes(nodes, params.beta_n)), params_(params), controls_(controls),
          n_(azimuthal_gaussian_width(params.beta_n)), weights_(controls) {}
    DeonFarFieldMaterial(const FiberParams<T>& params, const LobeControls<T>& controls)
        : DeonFarFieldMaterial(params, kAutoNodes, controls) {}

    HAIRSCATTER_HD const FiberParams<T>& params() const { return params_; }
    HAIRSCATTER_HD const LobeControls<T>& controls() const { return controls_; }
    // Lobe p's factor on A_p, gain_p × tint_p (1 without controls), and whether any differs from 1.
    HAIRSCATTER_HD glm::vec<3, T> lobe_weight(int p) const { return weights_[p]; }
    HAIRSCATTER_HD bool has_lobe_weights() const { return weights_.any(); }
    HAIRSCATTER_HD const WrappedGaussian<T>& azimuthal() const { return n_; }
    HAIRSCATTER_HD const Quadrature& quadrature() const { return *this; }

  private:
    static int checked_nodes(int nodes, T beta_n) {
        if (!(nodes >= 0 && nodes <= kMaxNodes))
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: DeonFarFieldMaterial: nodes = " + std::to_string(nodes) +
                                        " is outside its range [1, " + std::to_string(kMaxNodes) +
                                        "] (or 0 for the automatic choice)"));
        return nodes == kAutoNodes ? Quadrature::auto_nodes(beta_n) : nodes;
    }

    FiberParams<T> params_;
    LobeControls<T> controls_;
    WrappedGaussian<T> n_;
    LobeWeights<T> weights_;
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
// nodes) are recomputed per call, to keep the bound object small. Each call loops over the
// ⌈n/2⌉ stored nodes, so the cost is linear in n (docs/tradeoff.md measures it against the
// other models). Accuracy needs the nodes' exit azimuths closer than the Gaussian's σ; the
// automatic node count (FarFieldQuadrature::auto_nodes) gives ~1e-4 down to β_n ≈ 0.06.
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
    // A non-finite or zero wo gives 0 (and lobe_split no energy); other lengths are normalised.
    HAIRSCATTER_HD V3 albedo(V3 wo) const {
        if (!unit_direction(wo)) return V3(T(0));
        return split_albedo(split<false>(wo));
    }

    // Per lobe: ½ ∫ A_p(h) dh and the part of N_p in the backward half |φ| < π/2, each
    // node's wrapped Gaussian weighted by the channel sum of its A_p(h_j).
    // centre: the mass on |φ - centre| < π/2 instead (the dual-scattering window).
    HAIRSCATTER_HD LobeSplit lobe_split(V3 wo, T centre = T(0)) const {
        if (!unit_direction(wo)) return empty_lobe_split<T, kLobes>();
        return split<true>(wo, centre);
    }


  private:
    friend class FiberModel<DeonFarFieldFiber, T>;
    friend class BoundFiber<DeonFarFieldFiber>;

    // The terms that depend on wo only.
    struct Outgoing {
        T sin_o, cos_o;
        T sin_p[std::size_t(kLobes + 1)], cos_p[std::size_t(kLobes + 1)];  // tilted θo' per lobe
        DeonLanes<T, kLobes + 1> m;               // M_p at θo', side by side
        FiberRefraction<T> refraction;            // γt and the chord, per h
    };
    using Node = FarFieldNode<T, kLobes>;

    // lobe_split, with the backward fractions only when asked for (albedo needs none).
    template <bool kBackward> HAIRSCATTER_HD LobeSplit split(const V3& wo, T centre = T(0)) const {
        const Outgoing o = outgoing<false>(wo);
        const T sigma = mat_->azimuthal().sigma();
        LobeSplit r;
        T back[std::size_t(kLobes + 1)] = {};
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

        // Node probabilities ∝ (multiplicity) ŵ_j mean(Σ_p A_p(h_j)); all > 0 without lobe
        // controls, since A_0 = F ≥ ((η - 1)/(η + 1))² and every ŵ_j > 0. With zero gains
        // they can all vanish: node 0 and lobe 0 are then picked, and f and pdf are 0.
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

        // The lobe ∝ mean(A_p(h_j)).
        const Node nd = node(o, j);
        T w[std::size_t(kLobes + 1)], wsum = T(0);
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

        const V3 wi = direction_from_azimuth(wo, sin_i, phi);
        return make_sample(wi, lobe_tag(p), combine(o, sin_i, cos_i, queried_azimuth(wo, wi, cos_i, phi)));
    }

    // A_p(h_j) for all lobes (even in h, so shared with the mirror node) and γt(h_j).
    // The lobe controls, in this one place: f, the node and lobe choice, pdf, albedo and
    // lobe_split all read the scaled A_p(h_j), so sampling stays proportional to eval.
    HAIRSCATTER_HD Node node(const Outgoing& o, int j) const {
        Node nd = far_field_node<kLobes>(mat_->quadrature(), j, o.refraction, o.cos_o, mat_->params());
        if (mat_->has_lobe_weights())
            for (int p = 0; p <= kLobes; ++p) nd.att.a[p] *= mat_->lobe_weight(p);
        return nd;
    }

    // f and pdf at (θi, φ): the four M_p once, then per node A_p · D for both signs of h.
    HAIRSCATTER_HD HairEvalPdf<T> combine(const Outgoing& o, T sin_i, T cos_i, T phi) const {
        T m[std::size_t(kLobes + 1)];
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
        // alb ≥ F > 0 in every channel without controls (see sample); zero gains can make it 0.
        const T alb_sum = alb.x + alb.y + alb.z;
        r.pdf = alb_sum > T(0) ? (f.x + f.y + f.z) / alb_sum : T(0);
        return r;
    }

    const Material* mat_;
};

static_assert(is_fiber_model_v<DeonFarFieldFiber<float>> && is_fiber_model_v<DeonFarFieldFiber<double>>);

}  // namespace hairscatter
