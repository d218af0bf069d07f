// hairscatter — the h integral of d'Eon et al. 2011's far field, written once for the models
// that integrate N_p over the offset h: the Gauss–Legendre rule in γ = asin h and the
// per-node terms A_p(h_j), γt(h_j) (docs/theory.md §3.4). models/deon_farfield.hpp evaluates
// the integral per call; models/tabulated/material.hpp tabulates it once per material.
#pragma once

#include <cmath>
#include <cstddef>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../fiber/params.hpp"
#include "../math/quadrature.hpp"
#include "attenuation.hpp"
#include "azimuthal.hpp"

namespace hairscatter {

// The h integral: nodes of an n-point Gauss–Legendre rule placed in γ = asin h rather than
// in h, because A_p and Φ go like √(1 - h²) at the rim and are smooth in γ:
//   ½ ∫_{-1}^{1} f(h) dh = ½ ∫_{-π/2}^{π/2} f(sin γ) cos γ dγ ≈ Σ_k ŵ_k f(sin γ_k),
//   ŵ_k ∝ (π/4) W_k cos γ_k,
// with the ŵ_k renormalised to sum to exactly 1 (the rule's estimate of ½∫ dh = 1 is off
// by 3e-2 at n = 2 and 1e-9 at n = 8): then the lossless fiber conserves energy exactly
// at every n, since Σ_p A_p(h) = 1 at every node. The rule is symmetric and A_p is even in
// h, so only the nodes with h ≥ 0 are stored and each carries its mirror image -h.
// Built on the host; trivially copyable and device-readable.
template <typename T> class FarFieldQuadrature {
  public:
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
    // limited instead by the smoothness of A_p and Φ in γ (tests/deon_farfield_test.cpp).
    static int auto_nodes(T beta_n) {
        const double sigma = double(azimuthal_gaussian_width(beta_n));
        const double n = std::ceil(9.8696044010893586188 / (1.45 * sigma));
        int k = n > double(kMaxNodes) ? kMaxNodes : int(n);
        k += k % 2;
        return k < 24 ? 24 : (k > kMaxNodes ? kMaxNodes : k);
    }

    FarFieldQuadrature() = default;
    // nodes ∈ [1, kMaxNodes] (the caller validates and resolves kAutoNodes).
    explicit FarFieldQuadrature(int nodes) : nodes_(nodes) {
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

    // n nodes in all, stored as half_nodes() nodes with h ≥ 0; node j stands for h_j and,
    // when mirrored(j), also for -h_j, each with weight weight(j).
    HAIRSCATTER_HD int nodes() const { return nodes_; }
    HAIRSCATTER_HD int half_nodes() const { return half_nodes_; }
    HAIRSCATTER_HD T node_h(int j) const { return h_[j]; }
    HAIRSCATTER_HD T node_gamma(int j) const { return gamma_[j]; }
    HAIRSCATTER_HD T node_cos_gamma(int j) const { return cos_gamma_[j]; }
    HAIRSCATTER_HD T node_weight(int j) const { return weight_[j]; }
    HAIRSCATTER_HD bool node_mirrored(int j) const { return mirrored_[j]; }

  private:
    int nodes_ = 0, half_nodes_ = 0;
    T h_[kMaxHalfNodes] = {}, gamma_[kMaxHalfNodes] = {}, cos_gamma_[kMaxHalfNodes] = {}, weight_[kMaxHalfNodes] = {};
    bool mirrored_[kMaxHalfNodes] = {};
};

// The terms of node j at one θo: A_p(h_j) for lobes 0 … P (even in h, so shared with the
// mirror node -h_j) and γt(h_j) (the mirror's is -γt). refraction is FiberRefraction's
// set-up at θo, cos_o = cosθo.
template <typename T, int P> struct FarFieldNode {
    Attenuation<T, P> att;
    T gamma_t;
};
template <int P, typename T>
HAIRSCATTER_HD HAIRSCATTER_INLINE FarFieldNode<T, P> far_field_node(const FarFieldQuadrature<T>& q, int j,
                                                                    const FiberRefraction<T>& refraction, T cos_o,
                                                                    const FiberParams<T>& params) {
    const auto path = refraction.at(q.node_h(j), params.sigma_a);
    FarFieldNode<T, P> nd;
    nd.att = attenuation<T, P>(fresnel_dielectric(cos_o * q.node_cos_gamma(j), params.eta), path.transmittance);
    nd.gamma_t = path.gamma_t;
    return nd;
}

}  // namespace hairscatter
