// hairscatter — Chiang et al. 2016's near-field hair model with d'Eon et al. 2011's
// energy-conserving longitudinal lobes: R, TT, TRT and a residual for all higher orders.
// Same model as pbrt-v4's HairBxDF (including its θo tilt), evaluated accurately.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../fiber/frame.hpp"
#include "../fiber/params.hpp"
#include "../lobes/attenuation.hpp"
#include "../lobes/azimuthal.hpp"
#include "../lobes/deon_lobes.hpp"
#include "../lobes/lobe_controls.hpp"
#include "../lobes/lobe_set.hpp"
#include "../math/constants.hpp"
#include "../math/distributions.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"
#include "contract.hpp"

namespace hairscatter {

// Everything that depends only on the fiber parameters, computed once per material on
// the host (validated: the constructor throws std::invalid_argument with a message that
// names the bad parameter). Trivially copyable, so it can be copied to a GPU. Its d'Eon
// ingredients (longitudinal(p), tilt(), lobe_shift(p), lobe_variance(p)) are DeonLobes'.
// The optional lobe controls (lobes/lobe_controls.hpp) set per-lobe gains, tints and tilts;
// the tilts go into DeonLobes, the gains and tints into lobe_weight(p).
template <typename T> class ChiangMaterial : public DeonLobes<T> {
  public:
    static constexpr int kLobes = DeonLobes<T>::kLobes;  // R, TT, TRT explicit; index 3 is the residual

    explicit ChiangMaterial(const FiberParams<T>& params, const LobeControls<T>& controls = LobeControls<T>())
        : ChiangMaterial(Unchecked{}, validated(params), validated(controls)) {}

    // The material built per hit, on the host or the device: no validation, and bit for bit
    // the checked constructor's material. The caller guarantees valid parameters: params from
    // FiberParamBounds::clamp (fiber/params.hpp), whose bounds were checked once on the host,
    // and controls checked there (validate(controls)). Debug builds assert both.
    HAIRSCATTER_HD static ChiangMaterial unchecked(const FiberParams<T>& params,
                                                   const LobeControls<T>& controls = LobeControls<T>()) {
        return ChiangMaterial(Unchecked{}, params, controls);
    }

    // A material for one hit, from parameters that vary per hit (textures, strand variation:
    // fiber/strand_variation.hpp): no checks and no exceptions, device-callable. The
    // parameters are clamped into their ranges first (clamped_params, fiber/params.hpp: NaN
    // to the lower end), and the lobe controls are the defaults: unchecked() with every valid
    // range as the bounds. Forced inline, down to the lobes' constants, so that the default
    // controls fold away and the build interleaves with the caller's own work (its cost:
    // bench/results/vs_pbrt.md, build rows). From valid parameters it is bit for bit the
    // checked constructor's material (tests/per_hit_test.cpp).
    // The fiber refers to it: keep it alive while it is used,
    //   const auto m = ChiangMaterial<float>::per_hit(params_at_hit);
    //   const auto f = ChiangFiber<float>(m, h).at(wo);
    static HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE ChiangMaterial per_hit(const FiberParams<T>& params) {
        return ChiangMaterial(Unchecked{}, clamped_params(params), LobeControls<T>());
    }

    HAIRSCATTER_HD const FiberParams<T>& params() const { return params_; }
    HAIRSCATTER_HD const LobeControls<T>& controls() const { return controls_; }
    HAIRSCATTER_HD const TrimmedLogistic<T>& azimuthal() const { return n_; }
    // Lobe p's factor on A_p, gain_p × tint_p (1 without controls), and whether any differs
    // from 1 (without, the fiber skips the products: the default path costs one branch).
    HAIRSCATTER_HD glm::vec<3, T> lobe_weight(int p) const { return weights_[p]; }
    HAIRSCATTER_HD bool has_lobe_weights() const { return weights_.any(); }
    // lobe_weight(p) per channel lane (math/constants.hpp: kChannelLanes; padding 1).
    HAIRSCATTER_HD const T (&lobe_weight_lanes(int p) const)[kChannelLanes] { return weights_.channel_lanes(p); }
    // σa per channel lane (math/constants.hpp: kChannelLanes), the padding lane 0.
    HAIRSCATTER_HD const T (&sigma_a_lanes() const)[kChannelLanes] { return sigma_a_lanes_; }

  private:
    struct Unchecked {};
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE ChiangMaterial(Unchecked, const FiberParams<T>& params,
                                                      const LobeControls<T>& controls)
        : DeonLobes<T>(params.beta_m, controls, params.alpha), params_(params), controls_(controls),
          n_(logistic_scale(params.beta_n)), weights_(controls) {
        HAIRSCATTER_DCHECK(detail::params_in_range(params) && detail::controls_in_range(controls));
        // Written whole (elem::store4), as the fiber reads it; the padding 0.
        static_assert(kChannelLanes == 4, "σa's lanes: RGB and one padding lane");
        elem::store4(sigma_a_lanes_, params.sigma_a[0], params.sigma_a[1], params.sigma_a[2], T(0));
    }

    FiberParams<T> params_;
    LobeControls<T> controls_;
    TrimmedLogistic<T> n_;
    LobeWeights<T> weights_;
    T sigma_a_lanes_[kChannelLanes];
};

// What BasicChiangFiber::per_hit_vertex returns: f and pdf toward the light sample, and
// the continuation's sample.
template <typename T> struct PerHitVertex {
    HairEvalPdf<T> light;
    HairSample<T> next;
};

// One fiber hit: a material and the offset h ∈ [-1, 1] across the fiber. Directions are
// unit vectors in the fiber frame (fiber/frame.hpp): x = tangent, sinθ = w.x,
// φ = atan2(w.z, w.y); wo toward the viewer, wi toward the light.
// eval(wo, wi) has the cosine inside: Lo = ∫ eval(wo, wi) Li dωi, so ∫ eval dωi = 1 for
// σa = 0 (pbrt's HairBxDF::f is eval / |wi.z|). eval, pdf, eval_pdf, sample and at(wo)
// are the contract's (models/contract.hpp): sample is d'Eon, Marschner & Hanika 2013's,
// u.x picks the lobe with probability ∝ mean(A_p) (A_p times the material's lobe_weight),
// (u.y, u.z) sample θi from M_p, u.w samples φ from N_p.
//
// kKept selects the lobes at compile time (lobes/lobe_set.hpp); ChiangFiber<T> keeps all
// four. BasicChiangFiber<float, LobeSet::kR> is a one-lobe preview that never computes the
// refracted path: a dropped lobe costs nothing (bench/chiang_bench.cpp shows it).
//
// Refers to its material by pointer: the material must outlive the fiber (and every
// at(wo) made from it); a temporary material is rejected at compile time. On a GPU the
// material must be in device memory and the pointer a device pointer.
template <typename T, LobeSet kKept = LobeSet::kAll>
class BasicChiangFiber : public FiberModel<BasicChiangFiber<T, kKept>, T> {
  public:
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    using Material = ChiangMaterial<T>;
    using LobeSplit = hairscatter::LobeSplit<T, Material::kLobes>;
    static constexpr int kLobes = Material::kLobes;
    static constexpr LobeSet kKeptLobes = kKept;
    static_assert(kKept != LobeSet::kNone && (kKept & ~LobeSet::kAll) == LobeSet::kNone,
                  "keep at least one of R, TT, TRT, residual");
    HAIRSCATTER_HD static constexpr bool keeps(int p) { return keeps_lobe(kKept, p); }

    // Cheap, device-callable: h is clamped into [-1, 1] (hit offsets round slightly out).
    // Forced inline: kept a call (GCC -O3, with many instantiations), it took the material's
    // address out of the per-hit calls below, which then stored the whole material again.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE BasicChiangFiber(const Material& material, T h) : mat_(&material) {
        h_ = clamped_offset(h);
        gamma_o_ = elem::asin(h_);
        cos_gamma_o_ = cos_from_sin(h_);
    }
    BasicChiangFiber(const Material&&, T) = delete;

    // Host: the fiber at h, which must lie in [-1, 1] (throws std::invalid_argument).
    static BasicChiangFiber checked(const Material& material, T h) { return BasicChiangFiber(material, checked_offset(h)); }

    HAIRSCATTER_HD T h() const { return h_; }
    HAIRSCATTER_HD const Material& material() const { return *mat_; }

    // eval, pdf and sample at a hit whose parameters vary per hit (textures, strand
    // variation), the material built inside the call: the same values as
    //   const auto m = ChiangMaterial<T>::per_hit(params);
    //   BasicChiangFiber(m, h).eval(wo, wi);  // (or pdf, sample)
    // to a few ulp (the same arithmetic; only the compiler's FMA contraction may differ:
    // tests/per_hit_test.cpp). Cheaper than that composition: the material is a local of
    // the call, so the compiler keeps only the constants the query reads, in registers,
    // where a material built outside an out-of-line eval must be stored whole first
    // (bench/results/vs_pbrt.md, per-hit rows). No checks, no exceptions, device-callable;
    // the parameters are clamped as per_hit clamps them. Not forced inline: inlined into
    // the caller's loop, GCC spilled more than it saved (docs/performance.md).
    static HAIRSCATTER_HD V3 per_hit_eval(const FiberParams<T>& params, T h, V3 wo, V3 wi) {
        if (!unit_directions(wo, wi)) return V3(T(0));
        const Material m = Material::per_hit(params);
        const BasicChiangFiber fiber(m, h);
        return fiber.template query<true, false>(fiber.template outgoing<false>(wo), wo, wi).f;
    }
    static HAIRSCATTER_HD T per_hit_pdf(const FiberParams<T>& params, T h, V3 wo, V3 wi) {
        if (!unit_directions(wo, wi)) return T(0);
        const Material m = Material::per_hit(params);
        const BasicChiangFiber fiber(m, h);
        return fiber.template query<false, true>(fiber.template outgoing<true>(wo), wo, wi).pdf;
    }
    static HAIRSCATTER_HD HairSample<T> per_hit_sample(const FiberParams<T>& params, T h, V3 wo, V4 u) {
        if (!unit_direction_and_numbers(wo, u)) return HairSample<T>{};
        const Material m = Material::per_hit(params);
        const BasicChiangFiber fiber(m, h);
        return fiber.sample_fresh(fiber.template outgoing<true>(wo), wo, u);
    }
    // A path vertex at such a hit: f and pdf toward the light sample wi (its multiple
    // importance weight needs both) and the continuation sampled with u, with wo's terms
    // computed once, as at(wo) shares them: the same values as
    //   const auto at = BasicChiangFiber(ChiangMaterial<T>::per_hit(params), h).at(wo);
    //   {at.eval_pdf(wi), at.sample(u)}
    static HAIRSCATTER_HD PerHitVertex<T> per_hit_vertex(const FiberParams<T>& params, T h, const V3& wo, const V3& wi,
                                                        const V4& u) {
        const Material m = Material::per_hit(params);
        const auto at = BasicChiangFiber(m, h).at(wo);
        return {at.eval_pdf(wi), at.sample(u)};
    }

    // Per lobe: A_p(wo) and the fraction of N_p inside the half-circle of relative
    // azimuths |φ - centre| < π/2 (centre 0: the backward half). M_p integrates to 1, so
    // ∫ over that half of f_p = A_p · backward; the dual-scattering tables integrate these
    // (dual/tables.hpp: a_b at centre 0, a_f at centre π, the window W_p at every centre).
    // A non-finite or zero wo gives no energy (empty_lobe_split); any other length is
    // normalised, in albedo too.
    HAIRSCATTER_HD LobeSplit lobe_split(V3 wo, T centre = T(0)) const {
        if (!unit_direction(wo)) return empty_lobe_split<T, kLobes>();
        const Outgoing o = outgoing<false>(wo);
        LobeSplit r;
        for (int p = 0; p <= kLobes; ++p) {
            r.a[p] = V3(T(0));
            r.backward[p] = T(0);
        }
        for (int k = 0; k < kKeptLanes; ++k) {
            const int p = lane_lobe(kKept, k);
            r.a[p] = rgb(o.a[k]);
            r.backward[p] = k < kExplicit ? mat_->azimuthal().arc_mass(centre - kHalfPi<T> - o.phi_p[k], kPi<T>)
                                          : T(0.5);  // the residual is uniform in φ
        }
        if (!keeps(kLobes)) r.backward[kLobes] = T(0.5);
        return r;
    }

    // Σ_p A_p(wo) over the kept lobes, each times its lobe_weight(p) (gain × tint): the
    // directional albedo, exact for this model because every M_p and N_p is normalised.
    HAIRSCATTER_HD V3 albedo(V3 wo) const {
        if (!unit_direction(wo)) return V3(T(0));
        return albedo_from(outgoing<false>(wo));
    }

  private:
    friend class FiberModel<BasicChiangFiber, T>;
    friend class BoundFiber<BasicChiangFiber>;
    // The N-channel model (models/chiang_spectral.hpp) shares the geometry below: M_p, N_p,
    // Φ and the lobe choice, written once here for any channel count.
    template <typename, int, LobeSet> friend class BasicChiangSpectralFiber;

    // The kept lobes side by side: lane k holds lobe lane_lobe(kKept, k) (lobes/lobe_set.hpp).
    // The explicit lobes (R, TT, TRT) come first; the residual, if kept, is the last lane.
    static constexpr int kKeptLanes = lobe_count(kKept);
    // The lanes stored and computed: in float a power of two, so that the loops are whole
    // vectors (three lanes would leave them scalar); the extra lane is zero and adds
    // nothing. In double (scalar exps) the kept lobes only.
    static constexpr int kLanes = std::is_same<T, float>::value && kKeptLanes == 3 ? 4 : kKeptLanes;
    static constexpr int kExplicit = kKeptLanes - (keeps(kLobes) ? 1 : 0);
    // The N_p lanes computed per query: every lane in float, where the residual's is a
    // part of a whole vector that a select replaces; only the explicit ones in double (one
    // libm exp each).
    static constexpr int kAzimuthal = std::is_same<T, float>::value ? kLanes : kExplicit;
    // The stateless sample's θi of every lane at once (float: a vector log and square root),
    // or of the picked lobe only (double: a libm log each).
    static constexpr bool kLaneSample = std::is_same<T, float>::value && kLanes == 4;

    // The colour channels of A_p per lane: RGB and a padding channel (math/constants.hpp).
    static constexpr int kCh = kChannelLanes;

    // The terms that depend on wo only, shared by eval, pdf and sample, per lane.
    struct Outgoing {
        T a[std::size_t(kLanes)][std::size_t(kCh)];              // A_p per channel (channel 3 is padding)
        // The lobe selection weights, not normalised (only when asked for): lane p is chosen
        // with probability w_p / w_total, and pdf = Σ_p M_p N_p w_p · inv_w_total.
        T w[std::size_t(kLanes)];
        T w_total, inv_w_total;        // Σ_p w_p, and its reciprocal (0 where it is 0)
        DeonLanes<T, kLanes> m;        // M_p conditioned on the tilted θo'
        T phi_p[std::size_t(kLanes)];               // Φ(p, h), wrapped to [-π, π] (0 for the residual)
    };

    // The colour of one lane's channels (the padding channel dropped).
    HAIRSCATTER_HD static V3 rgb(const T (&channels)[kCh]) { return V3(channels[0], channels[1], channels[2]); }

    // Σ_p A_p of the bound terms (albedo(wo); BoundFiber::albedo()).
    HAIRSCATTER_HD V3 albedo_from(const Outgoing& o) const {
        V3 a(T(0));
        for (int k = 0; k < kKeptLanes; ++k) a += rgb(o.a[k]);
        return a;
    }

    // Only R needs no refracted path (no transmittance, no γt).
    static constexpr bool kRefracts = (kKept & ~LobeSet::kR) != LobeSet::kNone;

    // eval, pdf and eval_pdf: f and/or pdf at (wo, wi).
    template <bool kF, bool kPdf>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE HairEvalPdf<T> query(const Outgoing& o, const V3& wo, const V3& wi) const {
        // Finite wo and wi: FiberModel and BoundFiber (models/contract.hpp) check before calling.
        const T sin_i = clamp(wi.x, T(-1), T(1));
        const T phi = relative_azimuth(wo, wi);
        return combine<kF, kPdf>(o, sin_i, cos_from_sin(sin_i), phi);
    }

    // The bound sample (BoundFiber::sample): o is ready, so the branch on the lobe resolves
    // at once, and only the picked lobe's θi is sampled.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE HairSample<T> sample_from(const Outgoing& o, const V3& wo, const V4& u) const {
        return sample_lobe<false>(o, wo, u);
    }
    // The stateless sample (FiberModel::sample), whose o has just been computed.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE HairSample<T> sample_fresh(const Outgoing& o, const V3& wo, const V4& u) const {
        return sample_lobe<kLaneSample>(o, wo, u);
    }
    template <bool kEveryLane>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE HairSample<T> sample_lobe(const Outgoing& o, const V3& wo, const V4& u) const {
        const SampledDirection d = sample_direction<kEveryLane>(o, wo, u);
        return make_sample(d.wi, lobe_tag(d.lobe), combine<true, true>(o, d.sin_i, d.cos_i, d.phi));
    }

    // A sampled wi: the lobe p drawn, wi, and the sinθi, cosθi and azimuth a query of wi reads.
    struct SampledDirection {
        V3 wi;
        int lobe;
        T sin_i, cos_i, phi;
    };
    // The lobe and direction of a sample from the wo terms o (any channel count: o holds the
    // selection weights w, w_total, the conditioned M_p and Φ per lane).
    template <bool kEveryLane, typename O>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE SampledDirection sample_direction(const O& o, const V3& wo, const V4& u) const {
        // Finite wo and u: checked by the callers, as in query.
        // The lane ∝ w (normalised). All-zero weights (an opaque fiber without R) pick
        // lane 0, a kept lobe. The same lane and θi either way.
        T sin_i;
        int k;
        if constexpr (kEveryLane) {
            // Every lane's sinθi at once (DeonLongitudinal::sample_sin_theta_each: its log and
            // square root one vector each), then lane k's, k chosen as data (chosen_index).
            // In the stateless call w is the end of the wo terms' chain: a branch on the lobe
            // resolves only then, and where it guessed wrong (as often as the choice is
            // uncertain) the sample's own chain started over. Measured: 7 % off the stateless
            // sample, 8 % onto the bound one (whose branch resolves early).
            T v[std::size_t(kLanes)], e[std::size_t(kLanes)], lane_sin[std::size_t(kLanes)];
            for (int j = 0; j < kLanes; ++j) {
                const int q = lane_lobe(kKept, j < kKeptLanes ? j : 0);  // (the padding lane: a copy)
                v[j] = mat_->lobe_variance(q);
                e[j] = mat_->lobe_exp_m2_over_v(q);
            }
            DeonLongitudinal<T>::sample_sin_theta_each(v, e, o.m.sin_o, o.m.cos_o, u.y, u.z, lane_sin);
            k = chosen_index<kKeptLanes>(o.w, u.x * o.w_total);
            sin_i = lane_sin[k];
        } else {
            k = sample_discrete(o.w, kKeptLanes, u.x, o.w_total).index;
            sin_i = mat_->longitudinal(lane_lobe(kKept, k)).sample_sin_theta(o.m.sin_o[k], o.m.cos_o[k], u.y, u.z);
        }
        const int p = lane_lobe(kKept, k);
        const T cos_i = cos_from_sin(sin_i);
        T phi = kTwoPi<T> * u.w - kPi<T>;  // the residual: uniform
        if constexpr (kExplicit > 0) {  // (a residual-only set has no Φ lane to read)
            if constexpr (kEveryLane)  // (N's sample does not depend on the lobe: off the chain)
                phi = select(k < kExplicit, o.phi_p[k < kExplicit ? k : 0] + mat_->azimuthal().sample(u.w), phi);
            else if (k < kExplicit)
                phi = o.phi_p[k] + mat_->azimuthal().sample(u.w);
        }
        phi = wrap_pi(phi);

        const V3 wi = direction_from_azimuth(wo, sin_i, phi);
        return {wi, p, sin_i, cos_i, queried_azimuth(wo, wi, cos_i, phi)};
    }

    // kW: also the lobe selection probabilities w (pdf and sample need them, eval not).
    template <bool kW> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE Outgoing outgoing(const V3& wo) const {
        const FiberParams<T>& prm = mat_->params();
        Outgoing o;
        const T sin_o = clamp(wo.x, T(-1), T(1));
        const T cos_o = cos_from_sin(sin_o);
        const T fresnel = fresnel_dielectric(cos_o * cos_gamma_o_, prm.eta);
        T gamma_t = T(0);
        if constexpr (kRefracts) {
            const auto path = FiberRefraction<T>(sin_o, cos_o, prm.eta).at_channels(h_, mat_->sigma_a_lanes());
            gamma_t = path.gamma_t;
            if constexpr (kKept == LobeSet::kAll) {  // lane k is lobe k: straight into the lanes
                attenuation_channels<T, kLobes, kCh>(fresnel, fresnel, path.transmittance, o.a);
            } else {
                T att[std::size_t(kLobes + 1)][std::size_t(kCh)];
                attenuation_channels<T, kLobes, kCh>(fresnel, fresnel, path.transmittance, att);
                for (int k = 0; k < kLanes; ++k)
                    for (int c = 0; c < kCh; ++c) o.a[k][c] = k < kKeptLanes ? att[lane_lobe(kKept, k)][c] : T(0);
            }
        } else {
            for (int c = 0; c < kCh; ++c) o.a[0][c] = fresnel;  // R alone: one lane
        }
        outgoing_geometry(o, sin_o, cos_o, gamma_t);
        // The lobe controls, in this one place: f, the selection weights w, albedo and
        // lobe_split all read the scaled A_p, so sampling stays proportional to eval (the
        // per-lobe tilts are in the material's DeonLobes, which condition() rotates by).
        if (mat_->has_lobe_weights())
            for (int k = 0; k < kKeptLanes; ++k) elem::mul_each(o.a[k], mat_->lobe_weight_lanes(lane_lobe(kKept, k)));
        if constexpr (kW) selection_weights<3>(o);
        return o;
    }

    // M_p conditioned on θo and Φ(p, h) per lane: the wo terms that no channel changes.
    template <typename O>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void outgoing_geometry(O& o, T sin_o, T cos_o, T gamma_t) const {
        mat_->template condition<kKept>(o.m, sin_o, cos_o);
        // Φ(p, h) of every lane in one loop the compilers vectorise (select, not a branch).
        for (int k = 0; k < kLanes; ++k)
            o.phi_p[k] = select(k < kExplicit, exit_azimuth_wrapped(lane_lobe(kKept, k), gamma_o_, gamma_t), T(0));
    }

    // The lobe selection weights of o's A_p (its first kColours channels: the padding is
    // not colour), for pdf and sample.
    template <int kColours, typename O> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE static void selection_weights(O& o) {
        // w_p = Σ_c A_p,c: the normalisation is left to its two readers, so that no
        // division stands between the wo terms and w. The pdf multiplies its sum by
        // 1 / Σ_p w_p at the end, when the sum is ready (a division by the total first
        // made the weights the last of the pdf's inputs); sampling compares the cumulative
        // weights with u·Σ_p w_p. (w is built in a local array and written whole, once:
        // writing it lane by lane and then rescaling it made GCC reload it as a vector
        // from narrower stores, a store-forwarding stall on the sampling path.)
        T w[std::size_t(kLanes)];
        for (int k = 0; k < kLanes; ++k) {
            w[k] = o.a[k][0];
            for (int c = 1; c < kColours; ++c) w[k] += o.a[k][c];
        }
        T total = pairwise_sum<kLanes>(w);  // (a tree: the chain to the total is shorter)
        // With R kept at a gain above 0, total ≥ gain F > 0. Otherwise every kept lobe can
        // vanish (an opaque fiber, zero gains): then the total is 0, and so is the pdf. A
        // subnormal total (gains near 1e-39) has no finite reciprocal (a fuzzer found the
        // Inf and NaN weights it gave): its weights and total are scaled by 2^64, all
        // exactly (sums of non-negative numbers below the smallest normal one are exact,
        // so the scaled total is the sum of the scaled weights).
        if (!(total >= kMinNormal<T>)) {
            for (int k = 0; k < kLanes; ++k) w[k] *= T(18446744073709551616.0);
            total *= T(18446744073709551616.0);
        }
        for (int k = 0; k < kLanes; ++k) o.w[k] = w[k];
        o.w_total = total;
        o.inv_w_total = total > T(0) ? T(1) / total : T(0);
    }

    // f = Σ_p M_p A_p N_p and pdf = Σ_p M_p w_p N_p over the same lobe terms (kF, kPdf
    // select which).
    template <bool kF, bool kPdf>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE HairEvalPdf<T> combine(const Outgoing& o, T sin_i, T cos_i, T phi) const {
        T mn[std::size_t(kLanes)];
        lobe_densities(o, sin_i, cos_i, phi, mn);
        HairEvalPdf<T> r;
        if constexpr (kF) {
            T f[kCh];
            lobe_sum(o, mn, f);
            r.f = rgb(f);
        }
        if constexpr (kPdf) r.pdf = selection_pdf(o, mn);
        return r;
    }

    // M_p N_p of every lane at (sinθi, cosθi, φ), from the wo terms o (any channel count):
    // deon_logistic_densities (lobes/deon_lobes.hpp), every lane at once.
    template <typename O>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE void lobe_densities(const O& o, T sin_i, T cos_i, T phi,
                                                                T (&mn)[std::size_t(kLanes)]) const {
        deon_logistic_densities<kKeptLanes, kExplicit, kAzimuthal>(o.m, o.phi_p, mat_->azimuthal(), sin_i, cos_i, phi, mn);
    }

    // f = Σ_p (M_p N_p) A_p per channel of o's C channels.
    template <std::size_t C, typename O>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE static void lobe_sum(const O& o, const T (&mn)[std::size_t(kLanes)], T (&f)[C]) {
        for (std::size_t c = 0; c < C; ++c) f[c] = T(0);  // each lane's channels one vector FMA
#if HAIRSCATTER_HAS_VECTOR_EXT
        if constexpr (std::is_same<T, float>::value && C == 4) {
            // Spelled as vectors: at -O3 GCC split the loop below into pairs and singles.
            using V = elem::detail::F32x4;
            // A pairwise sum: two independent FMA chains, half as long as one.
            V acc[2] = {elem::detail::splat<V>(0.0f), elem::detail::splat<V>(0.0f)};
            HAIRSCATTER_UNROLL
            for (int k = 0; k < kLanes; ++k) {
                V a;
                std::memcpy(&a, o.a[k], sizeof a);
                acc[k & 1] += mn[k] * a;
            }
            const V sum = acc[0] + acc[1];
            std::memcpy(f, &sum, sizeof sum);
            return;
        }
#endif
        HAIRSCATTER_UNROLL
        for (int k = 0; k < kLanes; ++k)
            for (std::size_t c = 0; c < C; ++c) f[c] += mn[k] * o.a[k][c];
    }

    // pdf = Σ_p M_p N_p w_p / Σ_p w_p: as a tree (two dependent additions after the
    // products instead of four), then normalised.
    template <typename O>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE static T selection_pdf(const O& o, const T (&mn)[std::size_t(kLanes)]) {
        T terms[std::size_t(kLanes)];
        for (int k = 0; k < kLanes; ++k) terms[k] = mn[k] * o.w[k];
        return pairwise_sum<kLanes>(terms) * o.inv_w_total;
    }

    const Material* mat_;
    T h_ = T(0), gamma_o_ = T(0), cos_gamma_o_ = T(1);
};

// The full model: R, TT, TRT and the residual.
template <typename T> using ChiangFiber = BasicChiangFiber<T, LobeSet::kAll>;

static_assert(is_fiber_model_v<ChiangFiber<float>> && is_fiber_model_v<ChiangFiber<double>>);
static_assert(is_fiber_model_v<BasicChiangFiber<float, LobeSet::kR>>);

}  // namespace hairscatter
