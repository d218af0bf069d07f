// hairscatter — Chiang et al. 2016's model with N channels: the wavelengths a spectral
// renderer samples per path (pbrt-v4 and Mitsuba 3 shade four), or any other channel count.
// The geometry (M_p, N_p, Φ, Fresnel, γt and the chord, the lobe choice) is the RGB model's,
// computed once per query by the same code (models/chiang.hpp); only the transmittance and
// A_p are per channel (docs/spectral.md).
#pragma once

#include <cstddef>
#include <type_traits>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../fiber/spectral.hpp"
#include "../lobes/attenuation.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"
#include "chiang.hpp"
#include "contract.hpp"

namespace hairscatter {

// f and pdf of one direction pair with N channels (HairEvalPdf's N-channel form).
template <typename T, int N> struct SpectralEvalPdf {
    SpectralValues<T, N> f = SpectralValues<T, N>::filled(T(0));
    T pdf = T(0);
};

// What sample() returns with N channels (HairSample's form): weight = f / pdf per channel.
template <typename T, int N> struct SpectralSample {
    glm::vec<3, T> wi{T(0)};
    SpectralValues<T, N> weight = SpectralValues<T, N>::filled(T(0));
    T pdf = T(0);
    SampledLobe lobe = SampledLobe::kNone;
};

// One fiber hit with N channels: the material's geometry (roughness, tilt, η, lobe
// controls) and σa per channel given per hit, e.g. at a path's sampled wavelengths
// (fiber/spectral.hpp: clamped_spectral_sigma_a). The material's own σa is not read.
// eval, pdf, eval_pdf, sample, albedo and at(wo) are the RGB model's (models/contract.hpp)
// with SpectralValues in place of vec3; the lobe is chosen ∝ Σ_c A_p,c over the N channels
// (pbrt-v4 averages A_p over its wavelengths the same way). With N = 3 and the material's
// σa it is the RGB model, bit for bit (tests/spectral_test.cpp).
//
// Lobe controls: with N = 3 the material's gains and tints apply per channel, as in RGB;
// with N ≠ 3 only the gains (a tint is an RGB colour, not a spectrum: a spectral renderer
// folds its tint into σa, or up-samples it and multiplies f).
//
// Refers to its material by pointer: the material must outlive the fiber.
template <typename T, int N = 3, LobeSet kKept = LobeSet::kAll> class BasicChiangSpectralFiber {
    using Geometry = BasicChiangFiber<T, kKept>;

  public:
    using Real = T;
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    using Material = ChiangMaterial<T>;
    using Values = SpectralValues<T, N>;
    using EvalPdf = SpectralEvalPdf<T, N>;
    using Sample = SpectralSample<T, N>;
    static constexpr int kChannels = N;
    static constexpr int kLobes = Material::kLobes;

    // Cheap, device-callable: h is clamped into [-1, 1]; σa below 0 or not finite is taken
    // as 0 (the lower end, as FiberParamBounds::clamp does: σa must be finite).
    HAIRSCATTER_HD BasicChiangSpectralFiber(const Material& material, T h, const Values& sigma_a) : geo_(material, h) {
        for (int c = 0; c < kStored; ++c) sigma_a_[c] = T(0);  // the padding: 0, so T = 1
        // (finiteness from the bits: under -ffast-math a NaN compares either way)
        for (int c = 0; c < N; ++c) sigma_a_[c] = is_finite(sigma_a[c]) && sigma_a[c] > T(0) ? sigma_a[c] : T(0);
    }
    BasicChiangSpectralFiber(const Material&&, T, const Values&) = delete;

    HAIRSCATTER_HD T h() const { return geo_.h(); }
    HAIRSCATTER_HD const Material& material() const { return geo_.material(); }

    class Bound;

    // Non-finite input gives 0 / no sample, finite directions of any non-zero length are
    // normalised and u is clamped into [0, 1], as in every model (models/contract.hpp).
    HAIRSCATTER_HD Values eval(V3 wo, V3 wi) const {
        if (!unit_directions(wo, wi)) return Values::filled(T(0));
        return query<true, false>(outgoing<false>(wo), wo, wi).f;
    }
    HAIRSCATTER_HD T pdf(V3 wo, V3 wi) const {
        if (!unit_directions(wo, wi)) return T(0);
        return query<false, true>(outgoing<true>(wo), wo, wi).pdf;
    }
    HAIRSCATTER_HD EvalPdf eval_pdf(V3 wo, V3 wi) const {
        if (!unit_directions(wo, wi)) return EvalPdf{};
        return query<true, true>(outgoing<true>(wo), wo, wi);
    }
    HAIRSCATTER_HD Sample sample(V3 wo, V4 u) const {
        if (!unit_direction_and_numbers(wo, u)) return Sample{};
        return sample_from<Geometry::kLaneSample>(outgoing<true>(wo), wo, u);
    }
    // Σ_p A_p(wo) per channel over the kept lobes: ∫ eval(wo, wi) dωi.
    HAIRSCATTER_HD Values albedo(V3 wo) const {
        if (!unit_direction(wo)) return Values::filled(T(0));
        return albedo_from(outgoing<false>(wo));
    }
    // The fiber at a fixed wo, the wo terms computed once (FiberModel::at's N-channel form).
    HAIRSCATTER_HD Bound at(const V3& wo) const { return Bound(*this, wo); }

  private:
    static constexpr int kLanes = Geometry::kLanes;
    static constexpr int kKeptLanes = Geometry::kKeptLanes;
    // The channels stored: in float a multiple of four, so that the transmittances' exps and
    // each lane's A_p are whole vectors (padding σa 0: T = 1, never read as a channel), and
    // N = 3 is the RGB model's layout (kChannelLanes), which makes it the same bits; in double
    // N (one libm exp per channel either way).
    static constexpr int kStored = std::is_same<T, float>::value ? (N + 3) / 4 * 4 : N;

    struct Outgoing {
        T a[std::size_t(kLanes)][std::size_t(kStored)];  // A_p per channel (past N: padding)
        T w[std::size_t(kLanes)];                        // lobe selection weights, Σ_c A_p,c
        T w_total, inv_w_total;
        DeonLanes<T, kLanes> m;
        T phi_p[std::size_t(kLanes)];
    };

    template <bool kW> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE Outgoing outgoing(const V3& wo) const {
        const Material& mat = geo_.material();
        Outgoing o;
        const T sin_o = clamp(wo.x, T(-1), T(1));
        const T cos_o = cos_from_sin(sin_o);
        const T fresnel = fresnel_dielectric(cos_o * geo_.cos_gamma_o_, mat.params().eta);
        T gamma_t = T(0);
        if constexpr (Geometry::kRefracts) {
            // The RGB model's FiberRefraction::at_channels, per stored channel.
            const auto path = FiberRefraction<T>(sin_o, cos_o, mat.params().eta).path(geo_.h_);
            gamma_t = elem::asin(path.sin_gamma_t);
            T t[std::size_t(kStored)];
            for (int c = 0; c < kStored; ++c) t[c] = -sigma_a_[c] * path.chord;
            if constexpr (std::is_same<T, float>::value) {
                elem::exp_each_nonpositive(t);  // (σa ≥ 0)
            } else {
                for (int c = 0; c < kStored; ++c) t[c] = elem::exp(t[c]);
            }
            if constexpr (kKept == LobeSet::kAll) {
                attenuation_channels<T, kLobes, kStored>(fresnel, fresnel, t, o.a);
            } else {
                T att[std::size_t(kLobes + 1)][std::size_t(kStored)];
                attenuation_channels<T, kLobes, kStored>(fresnel, fresnel, t, att);
                for (int k = 0; k < kLanes; ++k)
                    for (int c = 0; c < kStored; ++c) o.a[k][c] = k < kKeptLanes ? att[lane_lobe(kKept, k)][c] : T(0);
            }
        } else {
            for (int c = 0; c < kStored; ++c) o.a[0][c] = fresnel;  // R alone: one lane
        }
        geo_.outgoing_geometry(o, sin_o, cos_o, gamma_t);
        if (mat.has_lobe_weights()) {
            for (int k = 0; k < kKeptLanes; ++k) {
                const int p = lane_lobe(kKept, k);
                if constexpr (N == 3) {  // gain × tint per channel, as the RGB model
                    for (int c = 0; c < 3; ++c) o.a[k][c] *= mat.lobe_weight_lanes(p)[c];
                } else {  // the gain only: a tint is RGB
                    for (int c = 0; c < kStored; ++c) o.a[k][c] *= mat.controls().gain[p];
                }
            }
        }
        if constexpr (kW) Geometry::template selection_weights<N>(o);
        return o;
    }

    template <bool kF, bool kPdf>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE EvalPdf combine(const Outgoing& o, T sin_i, T cos_i, T phi) const {
        T mn[std::size_t(kLanes)];
        geo_.lobe_densities(o, sin_i, cos_i, phi, mn);
        EvalPdf r;
        if constexpr (kF) {
            T f[std::size_t(kStored)];
            Geometry::lobe_sum(o, mn, f);
            for (int c = 0; c < N; ++c) r.f[c] = f[c];
        }
        if constexpr (kPdf) r.pdf = Geometry::selection_pdf(o, mn);
        return r;
    }

    template <bool kF, bool kPdf>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE EvalPdf query(const Outgoing& o, const V3& wo, const V3& wi) const {
        const T sin_i = clamp(wi.x, T(-1), T(1));
        return combine<kF, kPdf>(o, sin_i, cos_from_sin(sin_i), relative_azimuth(wo, wi));
    }

    template <bool kEveryLane>
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE Sample sample_from(const Outgoing& o, const V3& wo, const V4& u) const {
        const auto d = geo_.template sample_direction<kEveryLane>(o, wo, u);
        const EvalPdf e = combine<true, true>(o, d.sin_i, d.cos_i, d.phi);
        Sample s;
        s.wi = d.wi;
        s.lobe = lobe_tag(d.lobe);
        s.pdf = e.pdf;
        for (int c = 0; c < N; ++c) s.weight[c] = e.pdf > T(0) ? e.f[c] / e.pdf : T(0);
        return s;
    }

    HAIRSCATTER_HD Values albedo_from(const Outgoing& o) const {
        Values a = Values::filled(T(0));
        for (int k = 0; k < kKeptLanes; ++k)
            for (int c = 0; c < N; ++c) a[c] += o.a[k][c];
        return a;
    }

    Geometry geo_;
    T sigma_a_[std::size_t(kStored)];
};

// What at(wo) returns: eval(wi), pdf(wi), eval_pdf(wi), sample(u) and albedo(), equal to
// the fiber's calls at the bound wo (a renderer that evaluates a light sample and draws a
// continuation pays for wo once). A non-finite or zero wo makes an empty object (0 / no sample).
template <typename T, int N, LobeSet kKept> class BasicChiangSpectralFiber<T, N, kKept>::Bound {
  public:
    HAIRSCATTER_HD Bound(const BasicChiangSpectralFiber& fiber, const V3& wo)
        : fiber_(fiber), wo_(wo), valid_(unit_or_stand_in(wo_)), o_(fiber.template outgoing<true>(wo_)) {}
    HAIRSCATTER_HD Values eval(V3 wi) const {
        if (!(valid_ && unit_direction(wi))) return Values::filled(T(0));
        return fiber_.template query<true, false>(o_, wo_, wi).f;
    }
    HAIRSCATTER_HD T pdf(V3 wi) const {
        if (!(valid_ && unit_direction(wi))) return T(0);
        return fiber_.template query<false, true>(o_, wo_, wi).pdf;
    }
    HAIRSCATTER_HD EvalPdf eval_pdf(V3 wi) const {
        if (!(valid_ && unit_direction(wi))) return EvalPdf{};
        return fiber_.template query<true, true>(o_, wo_, wi);
    }
    HAIRSCATTER_HD Sample sample(V4 u) const {
        if (!(valid_ && unit_numbers(u))) return Sample{};
        return fiber_.template sample_from<false>(o_, wo_, u);
    }
    HAIRSCATTER_HD Values albedo() const { return valid_ ? fiber_.albedo_from(o_) : Values::filled(T(0)); }
    HAIRSCATTER_HD const V3& wo() const { return wo_; }
    HAIRSCATTER_HD bool valid() const { return valid_; }

  private:
    // w made unit in place, or (non-finite or zero) replaced by a valid direction to bind
    // instead, the object then empty.
    static HAIRSCATTER_HD bool unit_or_stand_in(V3& w) {
        if (unit_direction(w)) return true;
        w = V3(T(0), T(1), T(0));
        return false;
    }

    BasicChiangSpectralFiber fiber_;
    V3 wo_;
    bool valid_;
    Outgoing o_;
};

// The full model with N channels (RGB's three by default): R, TT, TRT and the residual.
template <typename T, int N = 3> using ChiangSpectralFiber = BasicChiangSpectralFiber<T, N, LobeSet::kAll>;

}  // namespace hairscatter
