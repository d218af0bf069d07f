// hairscatter — Marschner et al. 2003's hair model: Gaussian longitudinal lobes on the half
// angle (with d'Eon et al. 2011's 2θh correction) and the smooth fiber's azimuthal
// function by root solving, with the TRT caustic replacement, eccentricity and a Gaussian
// azimuthal roughness. Far field: the fiber needs no h. Not energy conserving (docs/theory.md
// §3.5): its furnace value is a reported figure.
#pragma once

#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <string>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../fiber/frame.hpp"
#include "../fiber/params.hpp"
#include "../lobes/attenuation.hpp"
#include "../lobes/lobe_controls.hpp"
#include "../lobes/longitudinal.hpp"
#include "../lobes/marschner_azimuthal.hpp"
#include "../lobes/tilt.hpp"
#include "../math/constants.hpp"
#include "../math/distributions.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"
#include "../math/quadrature.hpp"
#include "../lobes/azimuthal.hpp"  // azimuthal_gaussian_width
#include "contract.hpp"

namespace hairscatter {

// Marschner's own parameters (their Table 1), angles in radians.
template <typename T> struct MarschnerParams {
    T eta = T(1.55);                      // index of refraction, > 1
    glm::vec<3, T> sigma_a{T(0)};         // absorption per unit fiber radius, RGB, ≥ 0
    T alpha_r = radians(T(-7.5));         // α_R, the R lobe's shift (Table 1: -10° to -5°)
    T beta_r = radians(T(7.5));           // β_R, the R lobe's width (5° to 10°), [1e-4, π/4]
    T beta_n = T(0.3);                    // azimuthal roughness, [1e-3, 1], Chiang's scale
    T eccentricity = T(1);                // a, major/minor axis ratio (0.85–1 for human hair), > 0
    T caustic_width = radians(T(15));     // w_c (10° to 25°), (0, π/2]
    T caustic_gain = T(0.5);              // k_G (0.5 to 5), ≥ 0
    T caustic_fade = T(0.3);              // Δη' (0.2 to 0.4), > 0
    T caustic_dh_max = T(0.5);            // Δh_M, the caustic's largest h extent, (0, 1]
};

// |α_R| ≤ π/6 keeps TRT's shift -3α_R/2 within 45°; β_R ≤ π/4 keeps β_TRT = 2β_R ≤ 90°.
template <typename T> inline constexpr T kMaxMarschnerShift = kPi<T> / T(6);
template <typename T> inline constexpr T kMaxMarschnerWidth = kPi<T> / T(4);
// β_R ≥ 1e-4 rad: finite in float and double far below (docs/robustness.md); a lobe 0.006°
// wide is already far narrower than any fiber's.
template <typename T> inline constexpr T kMinMarschnerWidth = T(1e-4);

// Empty when valid, else one message per bad field naming it, its value and its range.
template <typename T> std::string validate(const MarschnerParams<T>& p) {
    std::ostringstream msg;
    auto check = [&](bool ok, const char* name, double value, const char* range) {
        if (ok) return;
        if (msg.tellp() > 0) msg << "; ";
        msg << name << " = " << value << " is outside its range " << range;
    };
    // Every test is false for NaN and ±Inf, read from the bits (fast-math safe).
    auto finite = [](T x) { return is_finite(x); };
    auto within = [](T x, T lo, T hi) { return is_finite(x) && x >= lo && x <= hi; };
    check(finite(p.eta) && p.eta > T(1), "eta", double(p.eta), "(1, inf) (finite)");
    const char* channel[3] = {"sigma_a.r", "sigma_a.g", "sigma_a.b"};
    for (int c = 0; c < 3; ++c)
        check(finite(p.sigma_a[c]) && p.sigma_a[c] >= T(0), channel[c], double(p.sigma_a[c]), "[0, inf) (finite)");
    check(within(p.alpha_r, -kMaxMarschnerShift<T>, kMaxMarschnerShift<T>), "alpha_r", double(p.alpha_r),
          "[-pi/6, pi/6] radians");
    check(within(p.beta_r, kMinMarschnerWidth<T>, kMaxMarschnerWidth<T>), "beta_r", double(p.beta_r),
          "[1e-4, pi/4] radians");
    check(within(p.beta_n, kMinRoughness<T>, T(1)), "beta_n", double(p.beta_n), "[1e-3, 1]");
    check(finite(p.eccentricity) && p.eccentricity > T(0), "eccentricity", double(p.eccentricity),
          "(0, inf) (finite)");
    check(finite(p.caustic_width) && p.caustic_width > T(0) && p.caustic_width <= kHalfPi<T>, "caustic_width",
          double(p.caustic_width), "(0, pi/2] radians");
    check(finite(p.caustic_gain) && p.caustic_gain >= T(0), "caustic_gain", double(p.caustic_gain),
          "[0, inf) (finite)");
    check(finite(p.caustic_fade) && p.caustic_fade > T(0), "caustic_fade", double(p.caustic_fade),
          "(0, inf) (finite)");
    check(finite(p.caustic_dh_max) && p.caustic_dh_max > T(0) && p.caustic_dh_max <= T(1), "caustic_dh_max",
          double(p.caustic_dh_max), "(0, 1]");
    return msg.str();
}

// Everything that depends only on the parameters and the roughness node count, built on
// the host (the constructor throws std::invalid_argument naming a bad parameter).
// Trivially copyable (1152 bytes in double, 576 in float), so it can be passed to a kernel
// by value.
//
// Azimuthal roughness: N_p is convolved with a Gaussian of σ = azimuthal_gaussian_width(β_n)
// (the σ DeonFarField uses for the same β_n) by an n-point Gauss–Hermite rule,
//   Ñ_p(φ) = Σ_k ω_k N_p(φ - σ z_k)       (eval),
// and the sampler smears each node over its cell: the k-th piece of the roughness kernel
// is uniform on [σ z_k - b_k⁻, σ z_k + b_k⁺] (cell edges halfway between nodes) with mass
// ω_k. That kernel's convolution with the pushforward of a uniform h is available in
// closed form from the cubic's roots at the cell's two ends (MarschnerCubic::arc_mass), so
// the pdf is exact, bounded (no caustic spikes) and agrees with sample() to rounding.
//
// The optional lobe controls (lobes/lobe_controls.hpp): gain_p × tint_p multiplies lobe p's
// attenuations (its N_p, the TRT caustic included) in f and in the sampler's lobe
// probabilities; a cuticle tilt α_p overridden for lobe p replaces its shift by Marschner's
// relation to the scale tilt (§4.1; Table 1 with α_R = -2α): α_R = -2α_p, α_TT = α_p,
// α_TRT = 3α_p, so overriding every lobe with α = -α_R/2 changes nothing. The model has no
// residual: a residual gain or tint other than 1 is refused.
template <typename T> class MarschnerMaterial {
  public:
    static constexpr int kLobes = 3;  // R, TT, TRT; Marschner has no residual
    static constexpr int kMaxNodes = 16;
    static constexpr int kDefaultNodes = 7;

    explicit MarschnerMaterial(const MarschnerParams<T>& params, int azimuthal_nodes = kDefaultNodes,
                               const LobeControls<T>& controls = LobeControls<T>())
        : params_(params), controls_(controls), weights_(controls), nodes_(azimuthal_nodes) {
        const std::string m = validate(params);
        if (!m.empty()) HAIRSCATTER_THROW(std::invalid_argument("hairscatter: invalid Marschner parameters: " + m));
        require_valid(controls);
        if (controls.weighted(kLobes)) {
            std::ostringstream msg;
            msg << "hairscatter: MarschnerMaterial: gain_residual = " << double(controls.gain[kLobes])
                << ", tint_residual = (" << double(controls.tint[kLobes].x) << ", " << double(controls.tint[kLobes].y)
                << ", " << double(controls.tint[kLobes].z)
                << "): Marschner et al. 2003 has no residual lobe (R, TT, TRT only), so both must stay 1";
            HAIRSCATTER_THROW(std::invalid_argument(msg.str()));
        }
        if (!(azimuthal_nodes >= 1 && azimuthal_nodes <= kMaxNodes))
            HAIRSCATTER_THROW(std::invalid_argument("hairscatter: MarschnerMaterial: azimuthal_nodes = " +
                                        std::to_string(azimuthal_nodes) + " is outside its range [1, " +
                                        std::to_string(kMaxNodes) + "]"));
        // Table 1: α_TT = -α_R/2, α_TRT = -3α_R/2; β_TT = β_R/2, β_TRT = 2β_R.
        T alpha[kLobes] = {params.alpha_r, T(-0.5) * params.alpha_r, T(-1.5) * params.alpha_r};
        const T per_tilt[kLobes] = {T(-2), T(1), T(3)};  // α_p per unit of scale tilt (see above)
        for (int p = 0; p < kLobes; ++p)
            if (((controls.alpha_override >> p) & 1u) != 0u) alpha[p] = per_tilt[p] * controls.alpha[p];
        const T beta[kLobes] = {params.beta_r, T(0.5) * params.beta_r, T(2) * params.beta_r};
        for (int p = 0; p < kLobes; ++p) {
            m_[p] = MarschnerLongitudinal<T>(beta[p], alpha[p]);
            proposal_[p] = DeonLongitudinal<T>(beta[p] * beta[p]);
        }
        // The sampler's θi proposal is centred on θi = α_p - θo: θo rotated by -α_p.
        tilt_ = CuticleTilt<T>(-alpha[0], -alpha[1], -alpha[2]);
        eccentric_ = EccentricIndex<T>(params.eta, params.eccentricity);
        round_ = params.eccentricity == T(1);
        sigma_ = azimuthal_gaussian_width(params.beta_n);

        const GaussHermite<double> gh(azimuthal_nodes);
        const double sigma = double(sigma_);
        for (int k = 0; k < nodes_; ++k) {
            const double z = gh.nodes[std::size_t(k)];
            // Cell edges halfway to the neighbours; the outer cells are symmetric about
            // their node; a single node gets the box of standard deviation σ.
            const double left = k > 0 ? 0.5 * (z - gh.nodes[std::size_t(k - 1)]) : -1.0;
            const double right = k + 1 < nodes_ ? 0.5 * (gh.nodes[std::size_t(k + 1)] - z) : -1.0;
            const double bl = left > 0 ? left : (right > 0 ? right : std::sqrt(3.0));
            const double br = right > 0 ? right : bl;
            offset_[k] = T(sigma * z);
            weight_[k] = T(gh.weights[std::size_t(k)]);
            cell_lo_[k] = T(sigma * (z - bl));
            cell_len_[k] = T(sigma * (bl + br));
        }
    }

    MarschnerMaterial(const MarschnerParams<T>& params, const LobeControls<T>& controls)
        : MarschnerMaterial(params, kDefaultNodes, controls) {}

    HAIRSCATTER_HD const MarschnerParams<T>& params() const { return params_; }
    HAIRSCATTER_HD const LobeControls<T>& controls() const { return controls_; }
    // Lobe p's factor on A_p, gain_p × tint_p (1 without controls), and whether any differs from 1.
    HAIRSCATTER_HD glm::vec<3, T> lobe_weight(int p) const { return weights_[p]; }
    HAIRSCATTER_HD bool has_lobe_weights() const { return weights_.any(); }
    HAIRSCATTER_HD const MarschnerLongitudinal<T>& longitudinal(int p) const { return m_[p]; }
    HAIRSCATTER_HD const DeonLongitudinal<T>& proposal(int p) const { return proposal_[p]; }
    HAIRSCATTER_HD const CuticleTilt<T>& tilt() const { return tilt_; }
    HAIRSCATTER_HD const EccentricIndex<T>& eccentric_index() const { return eccentric_; }
    HAIRSCATTER_HD bool is_round() const { return round_; }
    HAIRSCATTER_HD T azimuthal_sigma() const { return sigma_; }
    HAIRSCATTER_HD int nodes() const { return nodes_; }
    HAIRSCATTER_HD T node_offset(int k) const { return offset_[k]; }
    HAIRSCATTER_HD T node_weight(int k) const { return weight_[k]; }
    HAIRSCATTER_HD const T* node_weights() const { return weight_; }
    HAIRSCATTER_HD T cell_lo(int k) const { return cell_lo_[k]; }
    HAIRSCATTER_HD T cell_len(int k) const { return cell_len_[k]; }
    // Lobe p peaks at θi = lobe_shift(p) - θo (Marschner's α_p), with width β_p; its
    // longitudinal variance is β_p² (that of the sampler's d'Eon proposal).
    HAIRSCATTER_HD T lobe_shift(int p) const { return m_[p].alpha(); }
    HAIRSCATTER_HD T lobe_width(int p) const { return m_[p].beta(); }
    HAIRSCATTER_HD T lobe_variance(int p) const { return proposal_[p].variance(); }

  private:
    MarschnerParams<T> params_;
    LobeControls<T> controls_;
    LobeWeights<T> weights_;
    int nodes_ = kDefaultNodes;
    MarschnerLongitudinal<T> m_[kLobes];
    DeonLongitudinal<T> proposal_[kLobes];
    CuticleTilt<T> tilt_;
    EccentricIndex<T> eccentric_;
    bool round_ = true;
    T sigma_ = T(1);
    T offset_[kMaxNodes] = {}, weight_[kMaxNodes] = {}, cell_lo_[kMaxNodes] = {}, cell_len_[kMaxNodes] = {};
};

// The fiber. Same frame and conventions as ChiangFiber (unit vectors in the fiber frame,
// x = tangent, wo toward the viewer, wi toward the light), and eval has the cosine inside:
//
//   f(wo, wi) = cosθi / cos²θd · Σ_p M_p(θh) Ñ_p(φ),      θh = (θi + θo)/2, θd = (θo - θi)/2
//
// (Marschner's S = Σ M_p N_p / cos²θd times the cosθi of the rendering integral). N_p uses
// the Bravais indices at θd (η' for the geometry and the perpendicular Fresnel term, η''
// for the parallel one) and absorption along the chord 2 cosγt / cosθt; with eccentricity
// the index is η*(φh) at Marschner's half azimuth φh = (φi + φo)/2 (only cos 2φh enters,
// so the π ambiguity of a half angle does not matter).
//
// sample (after d'Eon, Marschner & Hanika 2013 and Lemein 2019 §4.1): u.x picks lobe p
// with probability w_p (the mean over channels and four fixed offsets of A_p at θd = θo)
// and its leftover is a uniform h ∈ [-1, 1]; (u.y, u.z) draw θi from d'Eon's spherical
// Gaussian of variance β_p² around θi = α_p - θo; u.w picks a roughness cell and a
// uniform offset in it; φ = Φ̂(p, asin h) + offset. With eccentricity the sampler's cubic
// reads η* at φo instead of φh (φh depends on the φ being drawn). Its density is
//   pdf = Σ_p w_p M^d'Eon_p(θi) Σ_k ω_k P(Φ̂(p, ·) ∈ φ - cell_k) / |cell_k|,
// summing over every root of every lobe (through the cubic's pushforward). pdf() and
// sample() share that code, weight = f / pdf.
//
// Holds a pointer to the material, which must outlive the fiber and its at(wo) objects (a
// temporary material is rejected at compile time; on a GPU, a pointer to a device copy).
// kLobes = 3 explicit lobes and no residual: lobe index 3 never occurs.
template <typename T> class MarschnerFiber : public FiberModel<MarschnerFiber<T>, T> {
  public:
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    using Material = MarschnerMaterial<T>;
    static constexpr int kLobes = Material::kLobes;
    // The points of albedo()'s estimate.
    static constexpr int kAlbedoPoints = 4096;

    HAIRSCATTER_HD explicit MarschnerFiber(const Material& material) : mat_(&material) {}
    MarschnerFiber(const Material&&) = delete;

    HAIRSCATTER_HD const Material& material() const { return *mat_; }

    // ∫ eval dωi has no closed form here (M_p is not normalised on the sphere, 1/cos²θd):
    // estimated as the mean weight of kAlbedoPoints samples, u on a shifted rank-1 lattice
    // (Korobov, generator 1, a, a², a³ mod N), so the estimate is deterministic and, since
    // E[weight] = ∫ f dωi for any valid sampler, unbiased in the limit. A host-side or
    // occasional query (4096 samples), not one for the inner loop.
    // A non-finite or zero wo gives 0; any other length is normalised.
    HAIRSCATTER_HD V3 albedo(V3 wo) const {
        if (!unit_direction(wo)) return V3(T(0));
        const Outgoing o = outgoing<true>(wo);
        constexpr unsigned kN = unsigned(kAlbedoPoints), kA = 1487u;
        const unsigned g[4] = {1u, kA, (kA * kA) % kN, (((kA * kA) % kN) * kA) % kN};
        V3 sum(T(0));
        for (unsigned k = 0; k < kN; ++k) {
            V4 u;
            for (int d = 0; d < 4; ++d) u[d] = (T((k * g[d]) % kN) + T(0.5)) / T(kN);
            sum += sample_from(o, wo, u).weight;
        }
        return sum / T(kN);
    }

  private:
    friend class FiberModel<MarschnerFiber, T>;
    friend class BoundFiber<MarschnerFiber>;
    struct Outgoing;

    HAIRSCATTER_HD HairSample<T> sample_from(const Outgoing& o, const V3& wo, const V4& u) const {
        // The lobe ∝ w_p (normalised, w_R > 0); the leftover of u.x is h.
        const DiscreteChoice<T> lobe = sample_discrete(o.w, kLobes, u.x, T(1));
        const int p = lobe.index;
        const T h = T(2) * lobe.rescaled - T(1);

        const T sin_i = mat_->proposal(p).sample_sin_theta(o.sin_p[p], o.cos_p[p], u.y, u.z);
        const T cos_i = cos_from_sin(sin_i);
        const Section s = section(o, elem::asin(sin_i), sample_eta(o));
        const MarschnerCubic<T> cubic(p, s.inv_eta_perp);

        // The roughness cell ∝ its Gauss–Hermite weight ω_k (Σ ω_k = 1); the leftover of u.w
        // is the offset in it.
        const DiscreteChoice<T> cell = sample_discrete(mat_->node_weights(), mat_->nodes(), u.w, T(1));
        const int k = cell.index;
        const T v = cell.rescaled;
        const T phi = wrap_pi(cubic.exit_azimuth(elem::asin(h)) + mat_->cell_lo(k) + mat_->cell_len(k) * v);

        // Evaluated at the azimuth pdf(wo, wi) reads (one atan2, small beside the root
        // solving): the float density sums differences of arc masses, whose cancellation
        // turns the last-bit difference between φ and wi's azimuth into 1e-4 of the pdf.
        const V3 wi = direction_from_azimuth(wo, sin_i, phi);
        HairSample<T> r = make_sample(wi, lobe_tag(p), combine<true, true>(o, sin_i, cos_i, relative_azimuth(wo, wi)));
        // At a roughness cell's edge the density can round to a denormal in float while f does
        // not; with one lobe alone (the others' gains 0, so no other lobe's density backs it
        // up) f / pdf then overflows. Such a sample fails, as one whose pdf rounds to 0 does.
        if (!is_finite(r.weight)) r.pdf = T(0), r.weight = V3(T(0));
        return r;
    }

  public:
    // Marschner's smooth-fiber N_p(φ) (no roughness, no caustic replacement, no lobe
    // controls) at the inclinations of (wo, wi), RGB: exposed for tests and plots of the
    // root sum.
    HAIRSCATTER_HD V3 smooth_azimuthal(int p, const V3& wo, const V3& wi) const {
        const Outgoing o = outgoing<false>(wo);
        const T sin_i = clamp(wi.x, T(-1), T(1));
        const T phi = relative_azimuth(wo, wi);
        const Section s = section(o, elem::asin(sin_i), eval_eta(o, phi));
        return marschner_root_sum(MarschnerCubic<T>(p, s.inv_eta_perp), phi, LobeAttenuation{this, &s, p});
    }

  private:
    static constexpr int kTrt = lobe_index(SampledLobe::kTRT);

    // Terms of wo alone.
    struct Outgoing {
        T sin_o, cos_o, theta_o, phi_o;
        T sin_p[std::size_t(kLobes)], cos_p[std::size_t(kLobes)];  // θo rotated by -α_p (the sampler's proposal)
        T w[std::size_t(kLobes)];                     // lobe probabilities
    };
    // The cross-section's optics at one θd and index η*: Bravais η', η'', the chord.
    struct Section {
        FiberRefraction<T> refraction;
        T inv_eta_perp, eta_perp, eta_par, inv_eta_par, eta_star;
    };
    // A_p at one root (the functor marschner_root_sum calls).
    struct LobeAttenuation {
        const MarschnerFiber* fiber;
        const Section* s;
        int p;
        HAIRSCATTER_HD V3 operator()(T h, T cos_gamma) const { return fiber->attenuations(*s, h, cos_gamma).a[p]; }
    };


    // η* for eval (Marschner's φh = φo + φ/2) and for the sampler (φo).
    HAIRSCATTER_HD T eval_eta(const Outgoing& o, T phi) const {
        using std::cos;
        return mat_->is_round() ? mat_->params().eta : mat_->eccentric_index()(cos(T(2) * o.phi_o + phi));
    }
    HAIRSCATTER_HD T sample_eta(const Outgoing& o) const {
        using std::cos;
        return mat_->is_round() ? mat_->params().eta : mat_->eccentric_index()(cos(T(2) * o.phi_o));
    }

    HAIRSCATTER_HD Section section_at(T sin_d, T cos_d, T eta_star) const {
        Section s;
        s.eta_star = eta_star;
        s.refraction = FiberRefraction<T>(sin_d, cos_d, eta_star);
        // 1/η' = cosθd / √(η*² - sin²θd) → 0 as θd → ±90° (wo and wi opposite along the
        // axis): floored at ε so that η' and the Fresnel terms stay finite.
        s.inv_eta_perp = s.refraction.gamma_t_scale > kEpsilon<T> ? s.refraction.gamma_t_scale : kEpsilon<T>;
        s.eta_perp = T(1) / s.inv_eta_perp;
        s.eta_par = eta_star * eta_star * s.inv_eta_perp;  // η'' = η*² cosθd / √(η*² - sin²θd)
        s.inv_eta_par = T(1) / s.eta_par;
        return s;
    }
    HAIRSCATTER_HD Section section(const Outgoing& o, T theta_i, T eta_star) const {
        T sin_d, cos_d;
        elem::sincos(T(0.5) * (o.theta_o - theta_i), sin_d, cos_d);
        return section_at(sin_d, cos_d, eta_star);
    }

    // Marschner et al. 2003 eq. 9 (with the chord of docs/theory.md §3.2): A_0 = F(η', η'', γi),
    // A_1 = (1 - F)² T, A_2 = (1 - F)² F(1/η', 1/η'', γt) T².
    HAIRSCATTER_HD Attenuation<T, kLobes> attenuations(const Section& s, T h, T cos_gamma) const {
        const auto path = s.refraction.at(h, mat_->params().sigma_a);
        const T cos_t = cos_from_sin(h * s.inv_eta_perp);
        return attenuation<T, kLobes>(fresnel_bravais(cos_gamma, s.eta_perp, s.eta_par),
                                      fresnel_bravais(cos_t, s.inv_eta_perp, s.inv_eta_par), path.transmittance);
    }

    template <bool kW> HAIRSCATTER_HD Outgoing outgoing(const V3& wo) const {
        Outgoing o;
        o.sin_o = clamp(wo.x, T(-1), T(1));
        o.cos_o = cos_from_sin(o.sin_o);
        o.theta_o = elem::asin(o.sin_o);
        o.phi_o = mat_->is_round() ? T(0) : elem::atan2(wo.z, wo.y);
        for (int p = 0; p < kLobes; ++p) {
            const typename CuticleTilt<T>::Rotated r = mat_->tilt().rotate(p, o.sin_o, o.cos_o);
            o.sin_p[p] = r.sin_theta;
            o.cos_p[p] = r.cos_theta;
        }
        if constexpr (kW) {
            // Lobe probabilities ∝ the mean of A_p over h = 1/8, 3/8, 5/8, 7/8 (A_p is even
            // in h) at θd = θo, the specular θi. Any positive choice is exact; this one
            // follows the lobes' energies, times the lobe controls' gain × tint. w_R ≥ F > 0
            // without controls; zero gains can leave every w_p at 0 (then f and pdf are 0).
            const Section s = section_at(o.sin_o, o.cos_o, sample_eta(o));
            T total = T(0);
            for (int p = 0; p < kLobes; ++p) o.w[p] = T(0);
            for (int j = 0; j < 4; ++j) {
                const T h = (T(j) + T(0.5)) * T(0.25);
                const Attenuation<T, kLobes> a = attenuations(s, h, cos_from_sin(h));
                for (int p = 0; p < kLobes; ++p) {
                    V3 ap = a.a[p];
                    if (mat_->has_lobe_weights()) ap *= mat_->lobe_weight(p);
                    o.w[p] += ap.x + ap.y + ap.z;
                }
            }
            for (int p = 0; p < kLobes; ++p) total += o.w[p];
            if (total > T(0))
                for (int p = 0; p < kLobes; ++p) o.w[p] /= total;
        }
        return o;
    }

    template <bool kF, bool kPdf>
    HAIRSCATTER_HD HairEvalPdf<T> query(const Outgoing& o, const V3& wo, const V3& wi) const {
        const T sin_i = clamp(wi.x, T(-1), T(1));
        return combine<kF, kPdf>(o, sin_i, cos_from_sin(sin_i), relative_azimuth(wo, wi));
    }

    // N_p with the caustic replacement (TRT) at one azimuth, before roughness.
    HAIRSCATTER_HD V3 azimuthal(const MarschnerCubic<T>& cubic, const Section& s, const MarschnerCaustic<T>& caustic,
                                const V3& caustic_a, T phi) const {
        const int p = cubic.lobe();
        const V3 n = marschner_root_sum(cubic, phi, LobeAttenuation{this, &s, p});
        if (p != kTrt) return n;
        const T x = wrap_pi(phi);  // TRT is centred on 2π ≡ 0
        return n * caustic.smooth_factor(x) + caustic_a * caustic.lobes(x);
    }

    template <bool kF, bool kPdf>
    HAIRSCATTER_HD HairEvalPdf<T> combine(const Outgoing& o, T sin_i, T cos_i, T phi) const {
        const T theta_i = elem::asin(sin_i);
        HairEvalPdf<T> r;
        const int n = mat_->nodes();
        if constexpr (kF) {
            const Section s = section(o, theta_i, eval_eta(o, phi));
            const MarschnerParams<T>& prm = mat_->params();
            V3 f(T(0));
            for (int p = 0; p < kLobes; ++p) {
                const T m = mat_->longitudinal(p).eval(theta_i, o.theta_o);
                if (!(m > T(0))) continue;  // the lobe's Gaussian underflowed: skip its roots
                const MarschnerCubic<T> cubic(p, s.inv_eta_perp);
                MarschnerCaustic<T> caustic;
                V3 caustic_a(T(0));
                if (p == kTrt) {
                    caustic = MarschnerCaustic<T>(cubic, s.eta_perp, prm.caustic_width, prm.caustic_fade,
                                                  prm.caustic_dh_max);
                    using std::cos;
                    using std::sin;
                    caustic_a = prm.caustic_gain *
                                attenuations(s, sin(caustic.gamma_c), cos(caustic.gamma_c)).a[kTrt];
                }
                V3 np(T(0));
                for (int k = 0; k < n; ++k)
                    np += mat_->node_weight(k) * azimuthal(cubic, s, caustic, caustic_a, phi - mat_->node_offset(k));
                if (mat_->has_lobe_weights()) np *= mat_->lobe_weight(p);  // the lobe controls
                f += m * np;
            }
            // Marschner's 1/cos²θd, with cos²θd = (1 + cos(θo - θi))/2; it vanishes only for
            // wo and wi opposite along the axis, where the model diverges: floored at ε.
            const T cos2_d = T(0.5) * (T(1) + o.cos_o * cos_i + o.sin_o * sin_i);
            r.f = f * (cos_i / (cos2_d > kEpsilon<T> ? cos2_d : kEpsilon<T>));
        }
        if constexpr (kPdf) {
            const Section s = section(o, theta_i, sample_eta(o));
            T pdf = T(0);
            for (int p = 0; p < kLobes; ++p) {
                if (!(o.w[p] > T(0))) continue;
                const T m = mat_->proposal(p).eval(sin_i, cos_i, o.sin_p[p], o.cos_p[p]);
                if (!(m > T(0))) continue;
                const MarschnerCubic<T> cubic(p, s.inv_eta_perp);
                T np = T(0);
                for (int k = 0; k < n; ++k) {
                    const T len = mat_->cell_len(k);
                    np += mat_->node_weight(k) / len * cubic.arc_mass(phi - mat_->cell_lo(k) - len, len);
                }
                pdf += o.w[p] * m * np;
            }
            // Exactly at a pole f is 0 (its factor cosθi) and wi has no azimuth: the density
            // there, a set of measure 0, is taken as 0 too, so that a sample landing on it
            // fails instead of carrying weight 0 with a density that depends on φ.
            r.pdf = cos_i > T(0) ? pdf : T(0);
        }
        return r;
    }

    const Material* mat_;
};

static_assert(is_fiber_model_v<MarschnerFiber<float>> && is_fiber_model_v<MarschnerFiber<double>>);

}  // namespace hairscatter
