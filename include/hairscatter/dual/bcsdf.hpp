// hairscatter — the dual-scattering BCSDF at a shading point (Zinke et al. 2008 §4,
// theory.md §5.2–5.4) with eval, pdf and sample, and the seed thesis's contribution:
// importance sampling it as one mixture of its lobes. Also the uniform-sphere sampler the
// thesis compares against, behind the same interface.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../fiber/frame.hpp"
#include "../lobes/longitudinal.hpp"
#include "../math/constants.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"
#include "../models/chiang.hpp"
#include "../models/contract.hpp"  // UniformSphereSampling
#include "tables.hpp"

namespace hairscatter {

// What the renderer knows about the light path at the shading point: either the number n
// of fibers crossed toward the light (dual/density.hpp), from which T_f = a_f(θi)^n and
// σ̄²_f = n β̄²_f(θi) follow (theory.md §5.2), or T_f and σ̄²_f themselves (from a deep
// opacity map that accumulated Π a_f and Σ β̄²_f along the way): set use_transmittance.
template <typename T> struct DualScatteringLight {
    T n = T(0);                // fibers crossed toward the light
    T direct_fraction = T(1);  // 1 if a shadow ray reaches the light, else 0
    T d_f = T(0.7);            // forward density factor (applied once, in F_scatter)
    T d_b = T(0.7);            // backward density factor
    bool use_transmittance = false;
    glm::vec<3, T> T_f{T(1)};  // with use_transmittance: the forward transmittance
    T sigma2_f = T(0);         // with use_transmittance: the summed forward variance
};

// F = F_direct + F_scatter of theory.md §5.3 in the library's eval convention (cosine
// inside: Lo = ∫ eval Li dωi):
//   F_direct  = df (f_s + d_b f_back)
//   F_scatter = max(0, T_f - df) d_f (f_s^G + π d_b f_back^G)
// with T_f = a_f(θi)^n, σ̄²_f = n β̄²_f(θi), f_s the single-fiber model, and
//   f_back   = A_b(θi) M(σ_b²; θi, θo - Δ_b) / π           backward azimuths only,
//   f_s^G    = Σ_p M(v_p + σ̄²_f; θi, θo'_p) G_p(θo)       forward azimuths only,
//   f_back^G = A_b(θi) M(σ_b² + σ̄²_f; θi, θo - Δ_b) / π   backward azimuths only,
// G_p the tables' h-averaged A_p N^G_p. Two deliberate changes from Zinke's text, both so
// that every lobe is a normalised density that the sampler can draw exactly: the
// longitudinal Gaussians are d'Eon's energy-conserving M (a Gaussian in θ for narrow
// lobes, normalised on the sphere for wide ones) instead of g(θh)/cos²θd, so f_back
// integrates to exactly A_b over the backward half; and the widening variances are the
// mean over the colour channels (the lobes' shapes are shared, their weights are not).
template <typename T> class DualScatteringFiber {
  public:
    using V3 = glm::vec<3, T>;
    using V4 = glm::vec<4, T>;
    static constexpr int kLobes = ChiangFiber<T>::kLobes;  // explicit lobes; +1 residual

    // tables must outlive this object (it keeps a pointer: tables are per material).
    DualScatteringFiber(const ChiangFiber<T>& fiber, const DualScatteringTables<T>& tables,
                        const DualScatteringLight<T>& light)
        : fiber_(fiber), tables_(&tables), light_(light) {
        light_.n = light_.n > T(0) ? light_.n : T(0);
        light_.direct_fraction = clamp(light_.direct_fraction, T(0), T(1));
        light_.sigma2_f = light_.sigma2_f > T(0) ? light_.sigma2_f : T(0);
        for (int c = 0; c < 3; ++c) light_.T_f[c] = clamp(light_.T_f[c], T(0), T(1));
    }

    const DualScatteringLight<T>& light() const { return light_; }

    V3 eval(const V3& wo, const V3& wi) const { return value(wo, wi, relative_azimuth(wo, wi), fiber_.eval(wo, wi)); }
    T pdf(const V3& wo, const V3& wi) const {
        return density(mixture(wo), wi, relative_azimuth(wo, wi), fiber_.pdf(wo, wi));
    }
    HairEvalPdf<T> eval_pdf(const V3& wo, const V3& wi) const {
        const T phi = relative_azimuth(wo, wi);
        const HairEvalPdf<T> single = fiber_.eval_pdf(wo, wi);
        HairEvalPdf<T> r;
        r.f = value(wo, wi, phi, single.f);
        r.pdf = density(mixture(wo), wi, phi, single.pdf);
        return r;
    }

    // u.x picks the component (single scattering, f_back, f_s^G, f_back^G) and is
    // rescaled to pick the lobe inside it; (u.y, u.z) sample θi, u.w the azimuth.
    HairSample<T> sample(const V3& wo, const V4& u) const {
        const Mixture mix = mixture(wo);
        T acc = T(0);
        int c = 0;
        for (; c < 3; ++c) {
            if (u.x < acc + mix.w[c]) break;
            acc += mix.w[c];
        }
        while (c > 0 && !(mix.w[c] > T(0))) --c;
        const T ux = mix.w[c] > T(0) ? clamp((u.x - acc) / mix.w[c], T(0), T(1)) : T(0);

        V3 wi;
        HairSample<T> r;
        if (c == 0) {
            const HairSample<T> s = fiber_.sample(wo, V4(ux, u.y, u.z, u.w));
            wi = s.wi;
            r.lobe = s.lobe;
        } else {
            T sin_i;
            bool forward = false;
            if (c == 2) {
                // pick lobe p of f_s^G by its forward energy
                int p = 0;
                T a = T(0);
                for (; p < kLobes; ++p) {
                    if (ux < a + mix.g[p]) break;
                    a += mix.g[p];
                }
                sin_i = mix.m_global[p].sample_sin_theta(mix.sin_o[p], mix.cos_o[p], u.y, u.z);
                forward = true;
                r.lobe = kDualGlobal;
            } else {
                const DeonLongitudinal<T>& m = c == 1 ? mix.m_back : mix.m_back_global;
                sin_i = m.sample_sin_theta(mix.sin_back, mix.cos_back, u.y, u.z);
                r.lobe = c == 1 ? kDualBack : kDualGlobalBack;
            }
            // φ uniform over the chosen half: backward |φ| < π/2, forward |φ| > π/2.
            const T half = kPi<T> * (u.w - T(0.5));
            const T phi = forward ? (half >= T(0) ? kPi<T> - half : -kPi<T> - half) : half;
            wi = direction_from_azimuth(wo, sin_i, phi);
        }
        const T phi = relative_azimuth(wo, wi);
        const HairEvalPdf<T> single = fiber_.eval_pdf(wo, wi);
        r.wi = wi;
        r.pdf = density(mix, wi, phi, single.pdf);
        r.weight = r.pdf > T(0) ? value(wo, wi, phi, single.f) / r.pdf : V3(T(0));
        return r;
    }

    // Sampled-lobe tags beyond the single-fiber ones (kR … kResidual).
    static constexpr SampledLobe kDualBack = SampledLobe::kDualBack, kDualGlobal = SampledLobe::kDualGlobal,
                                 kDualGlobalBack = SampledLobe::kDualGlobalBack;

  private:
    // Everything that depends on wo: the mixture weights of the four components, the
    // lobes' shapes (taken at the specular cone θi = -θo, where the scattered light is
    // concentrated) and the tilted θo' per lobe.
    struct Mixture {
        T w[4];                   // single, back, global, global back
        T g[kLobes + 1];          // lobe probabilities inside f_s^G
        T sin_o[kLobes + 1], cos_o[kLobes + 1];
        DeonLongitudinal<T> m_global[kLobes + 1];
        DeonLongitudinal<T> m_back, m_back_global;
        T sin_back, cos_back;     // θo - Δ_b
    };

    static T mean(const V3& v) { return (v.x + v.y + v.z) * T(1.0 / 3.0); }


    // T_f and σ̄²_f for light arriving with the table entry e of its inclination.
    V3 transmittance(const DualScatteringEntry<T>& e) const {
        using std::pow;
        if (light_.use_transmittance) return light_.T_f;
        return V3(pow(e.a_f.x, light_.n), pow(e.a_f.y, light_.n), pow(e.a_f.z, light_.n));
    }
    T forward_variance(const DualScatteringEntry<T>& e) const {
        return light_.use_transmittance ? light_.sigma2_f : light_.n * mean(e.beta2_f);
    }

    Mixture mixture(const V3& wo) const {
        using std::asin;
        using std::cos;
        using std::sin;
        Mixture m;
        const T sin_o = clamp(wo.x, T(-1), T(1)), cos_o = cos_from_sin(sin_o);
        const T theta_o = asin(sin_o);
        const DualScatteringEntry<T> eo = tables_->lookup(theta_o);
        const DualScatteringEntry<T> es = tables_->lookup(-theta_o);  // the specular cone
        const T s2f = forward_variance(es);
        const T scatter = light_.d_f * (mean(transmittance(es)) - light_.direct_fraction);
        const T df = light_.direct_fraction;
        const ChiangMaterial<T>& mat = fiber_.material();

        T total_g = T(0);
        for (int p = 0; p <= kLobes; ++p) {
            const auto r = mat.tilt().rotate(p, sin_o, cos_o);
            m.sin_o[p] = r.sin_theta;
            m.cos_o[p] = r.cos_theta;
            m.m_global[p] = DeonLongitudinal<T>(mat.lobe_variance(p) + s2f);
            m.g[p] = mean(eo.global[p]);
            total_g += m.g[p];
        }
        for (int p = 0; p <= kLobes; ++p) m.g[p] = total_g > T(0) ? m.g[p] / total_g : T(p == 0);

        const T delta = mean(es.delta_b);
        const T tb = theta_o - delta;
        m.sin_back = sin(tb);
        m.cos_back = cos(tb) < T(0) ? -cos(tb) : cos(tb);
        const T s2b = mean(es.sigma2_b);
        m.m_back = DeonLongitudinal<T>(s2b > T(1e-6) ? s2b : T(1e-6));
        m.m_back_global = DeonLongitudinal<T>((s2b > T(1e-6) ? s2b : T(1e-6)) + s2f);

        const T ab = mean(es.A_b);
        m.w[0] = df * mean(fiber_.albedo(wo));
        m.w[1] = df * light_.d_b * ab;
        m.w[2] = scatter > T(0) ? scatter * kPi<T> * total_g : T(0);
        m.w[3] = scatter > T(0) ? scatter * kPi<T> * light_.d_b * ab : T(0);
        const T sum = m.w[0] + m.w[1] + m.w[2] + m.w[3];
        if (sum > T(0)) {
            for (T& w : m.w) w /= sum;
        } else {
            m.w[0] = T(1);  // nothing to scatter: any valid density will do (f is 0)
            m.w[1] = m.w[2] = m.w[3] = T(0);
        }
        return m;
    }

    // F(wo, wi) given φ and the single-fiber f_s.
    V3 value(const V3& wo, const V3& wi, T phi, const V3& f_single) const {
        using std::asin;
        const T sin_i = clamp(wi.x, T(-1), T(1)), cos_i = cos_from_sin(sin_i);
        const T sin_o = clamp(wo.x, T(-1), T(1)), cos_o = cos_from_sin(sin_o);
        const bool forward = phi > kHalfPi<T> || phi < -kHalfPi<T>;
        const DualScatteringEntry<T> ei = tables_->lookup(asin(sin_i));
        const T df = light_.direct_fraction;
        const V3 tf = transmittance(ei);
        const T s2f = forward_variance(ei);
        T scatter_max = T(0);
        for (int c = 0; c < 3; ++c) scatter_max = tf[c] - df > scatter_max ? tf[c] - df : scatter_max;

        V3 f = df * f_single;
        if (!forward) {
            // f_back and its widened twin, shaped at this θi (the pdf's shape is fixed per wo).
            const T s2b = mean(ei.sigma2_b) > T(1e-6) ? mean(ei.sigma2_b) : T(1e-6);
            const T tb = asin(sin_o) - mean(ei.delta_b);
            const T sb = std::sin(tb), cb = std::abs(std::cos(tb));
            const V3 f_back = ei.A_b * DeonLongitudinal<T>(s2b).eval(sin_i, cos_i, sb, cb) * kInvPi<T>;
            f += df * light_.d_b * f_back;
            if (scatter_max > T(0)) {
                const V3 f_back_g = ei.A_b * DeonLongitudinal<T>(s2b + s2f).eval(sin_i, cos_i, sb, cb) * kInvPi<T>;
                for (int c = 0; c < 3; ++c)
                    if (tf[c] > df) f[c] += (tf[c] - df) * light_.d_f * kPi<T> * light_.d_b * f_back_g[c];
            }
        } else if (scatter_max > T(0)) {
            const DualScatteringEntry<T> eo = tables_->lookup(asin(sin_o));
            const ChiangMaterial<T>& mat = fiber_.material();
            V3 f_s_g(T(0));
            for (int p = 0; p <= kLobes; ++p) {
                const auto r = mat.tilt().rotate(p, sin_o, cos_o);
                f_s_g += DeonLongitudinal<T>(mat.lobe_variance(p) + s2f).eval(sin_i, cos_i, r.sin_theta, r.cos_theta) *
                         eo.global[p];
            }
            for (int c = 0; c < 3; ++c)
                if (tf[c] > df) f[c] += (tf[c] - df) * light_.d_f * f_s_g[c];
        }
        return f;
    }

    // The mixture's density: each component normalised on the sphere.
    T density(const Mixture& mix, const V3& wi, T phi, T pdf_single) const {
        const T sin_i = clamp(wi.x, T(-1), T(1)), cos_i = cos_from_sin(sin_i);
        const bool forward = phi > kHalfPi<T> || phi < -kHalfPi<T>;
        T pdf = mix.w[0] * pdf_single;
        if (!forward) {
            if (mix.w[1] > T(0)) pdf += mix.w[1] * mix.m_back.eval(sin_i, cos_i, mix.sin_back, mix.cos_back) * kInvPi<T>;
            if (mix.w[3] > T(0))
                pdf += mix.w[3] * mix.m_back_global.eval(sin_i, cos_i, mix.sin_back, mix.cos_back) * kInvPi<T>;
        } else if (mix.w[2] > T(0)) {
            T p_global = T(0);
            for (int p = 0; p <= kLobes; ++p)
                if (mix.g[p] > T(0))
                    p_global += mix.g[p] * mix.m_global[p].eval(sin_i, cos_i, mix.sin_o[p], mix.cos_o[p]) * kInvPi<T>;
            pdf += mix.w[2] * p_global;
        }
        return pdf;
    }

    ChiangFiber<T> fiber_;
    const DualScatteringTables<T>* tables_;
    DualScatteringLight<T> light_;
};

}  // namespace hairscatter
