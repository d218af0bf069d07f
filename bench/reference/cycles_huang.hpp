// Blender Cycles' published scheme for Huang et al. 2022's fiber, written here from its
// description (Blender's intern/cycles/kernel/closure/bsdf_hair_huang.h, read to understand
// the scheme, not copied) so that bench/vs_cycles.cpp can time and measure it beside
// HuangFiber in one process. Not part of the library.
//
// The scheme, per eval (V toward the viewer, L toward the light, in the fiber's section
// frame: x the axis, u the major semi-axis 1, v the minor b; the point at γ is
// p(γ) = (sin γ, b cos γ), its outward normal ∝ (b sin γ, cos γ), its mesonormal tilted by
// α toward the tip):
//   R    a composite Simpson rule over the visible γ with intervals of at most 0.7 β:
//        0.125 F(V·h) ∫ D(m·h) G2(V, L) |p'(γ)| / E(V·m) dγ / radius, h = (V + L)/|V + L|,
//        E the rough dielectric's single-scattering albedo (energy compensation);
//   TT, TRT  a Simpson rule with intervals of at most 0.8 β; at each node ONE random visible
//        normal refracts V into the fibre (a linear congruential generator seeded per
//        shading point), the chord to the exit follows in closed form, TT is the refraction
//        lobe toward L there, and ONE more random normal reflects the ray for TRT;
//   ≥ TRRT  per node a geometric series T R² T̄ A³ / (1 − A (1 − T̄)) in Chiang et al.
//        2016's longitudinal lobe of variance 4β, uniform in azimuth;
//   eval = (R + (S_TT + S_TRT)/(η² radius) + S_TRRT M / π²) h_Simpson / 3 / cos θ_V.
// sample draws an offset uniformly, one normal per interface and returns the lobe's
// direction with weight f/pdf folded in and pdf = 1 (Cycles' own "TODO"), so that it cannot
// be used for MIS: its pdf is not a density. The energy tables are 1D in cos (Cycles
// interpolates a 3D table in roughness, cos and η: ours is cheaper, which favours Cycles
// in the timing).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include <hairscatter/hairscatter.hpp>

namespace bench_ref {

template <typename T> class CyclesHuang {
  public:
    using V3 = glm::vec<3, T>;
    using V2 = glm::vec<2, T>;
    static constexpr int kTable = 64;

    explicit CyclesHuang(const hairscatter::HuangParams<T>& p)
        : p_(p), ggx_(p.roughness), section_(p.aspect_ratio, p.orientation), m4_(T(4) * p.roughness) {
        using M = hairscatter::HuangMaterial<double>;
        const hairscatter::GaussLegendre<double> gl(24);
        for (int i = 0; i < kTable; ++i) {
            const double c = std::max(1e-3, double(i) / (kTable - 1));
            const auto out = M::interface_energies(double(p.roughness), c, double(p.eta), gl);
            const auto in = M::interface_energies(double(p.roughness), c, 1 / double(p.eta), gl);
            inv_e_out_[i] = T(1 / std::max(1e-3, out.reflect_single + out.transmit_single));
            inv_e_in_[i] = T(1 / std::max(1e-3, in.reflect_single + in.transmit_single));
        }
        sin_a_ = std::sin(p.alpha);
        cos_a_ = std::cos(p.alpha);
        e2_ = T(1) - p.aspect_ratio * p.aspect_ratio;
    }

    // f with the cosine, for the fiber-frame wo (viewer) and wi (light), the quadrature's
    // normals drawn from `seed` (one shading point).
    V3 eval(const V3& wo, const V3& wi, std::uint32_t seed) const {
        const V3 v = section_.to_section(wo), l = section_.to_section(wi);
        const T cos_v = cos_theta(v);
        const T tan_tilt = sin_a_ / cos_a_;
        if (tan_tilt * l.x / cos_theta(l) < T(-1)) return V3(T(0));
        const T c = -tan_tilt * v.x / cos_v;
        if (c > T(1)) return V3(T(0));
        const T half_span = std::acos(c > T(0) ? c : T(0));
        const T phi_v = std::atan2(v.y, v.z);
        T g_min = to_gamma(phi_v - half_span), g_max = to_gamma(phi_v + half_span);
        if (g_max < g_min) g_max += T(2) * hairscatter::kPi<T>;
        g_min += T(1e-3);
        g_max -= T(1e-3);
        const T radius = e2_ == T(0) ? T(1) : std::sqrt(T(1) - e2_ * v.y * v.y / (v.y * v.y + v.z * v.z));
        std::uint32_t rng = seed;
        return (eval_r(v, l, g_min, g_max, radius) + eval_paths(v, l, g_min, g_max, radius, rng)) / cos_v;
    }

    struct Sample {
        V3 wi{T(0)}, weight{T(0)};
        T pdf = T(0);
    };
    // u: lobe, offset, first normal's u1; the rest from the generator seeded with `seed`.
    Sample sample(const V3& wo, const V3& u, std::uint32_t seed) const {
        Sample s;
        std::uint32_t rng = seed;
        const V3 v = section_.to_section(wo);
        const T b = p_.aspect_ratio;
        const T phi_v = std::atan2(v.y, v.z);
        const T sp = std::sin(phi_v), cp = std::cos(phi_v);
        const T radius = e2_ == T(0) ? T(1) : std::sqrt(T(1) - e2_ * v.y * v.y / (v.y * v.y + v.z * v.z));
        const T h = T(2) * u.y - T(1);
        // The visible point at offset h across the projected width (the circle: asin h).
        const T gamma_i = b == T(1) ? phi_v + std::asin(h)
                                    : std::atan2(cp, -b * sp) - std::acos(h * radius / std::sqrt(cp * cp + b * b * sp * sp));
        const V3 mi_flat = normal(gamma_i, T(0), T(1)), mi = normal(gamma_i, sin_a_, cos_a_);
        const T cos_mi1 = glm::dot(mi, v);
        if (cos_mi1 < T(0) || glm::dot(mi_flat, v) < T(0)) return s;
        const V3 h1 = visible_normal(v, mi, u.z, next(rng));
        const V3 wr = glm::normalize(hairscatter::reflect_about(v, h1));
        if (!(glm::dot(v, h1) > T(0) && glm::dot(v, mi_flat) > T(0))) return s;
        const T eta = p_.eta, inv_eta = T(1) / eta;
        const T r1 = hairscatter::fresnel_any(glm::dot(v, h1), eta);
        const T scale1 = lookup(inv_e_out_, cos_mi1);
        const T r_energy = r1 * scale1 * T(visible(wr, mi_flat, h1)) * go(cos_mi1, glm::dot(mi, wr));
        V3 tt(T(0)), trt(T(0)), trrt(T(0)), w_tt(T(0)), w_trt(T(0)), w_trrt(T(0));
        const hairscatter::Refracted<T> rt = hairscatter::refract_through(v, h1, inv_eta);
        if (rt.ok) {
            const V3 t = glm::normalize(rt.o);  // propagation into the fibre
            const T phi_t = std::atan2(t.y, t.z);
            const T gamma_t = T(2) * to_phi(phi_t) - gamma_i;  // the exit's antipode: inward normal
            const V3 mt = normal(gamma_t, -sin_a_, cos_a_), mt_flat = normal(gamma_t, T(0), T(1));
            const T cos_mi2 = glm::dot(-t, mt);
            const V3 h2 = visible_normal(-t, mt, next(rng), next(rng));
            if (cos_mi2 > T(0) && visible(-t, mi_flat, h1) && visible(-t, mt_flat, h2)) {
                const V3 a_t = attenuation(chord(gamma_i, gamma_t + hairscatter::kPi<T>) / cos_theta(t));
                const T r2 = hairscatter::fresnel_any(glm::dot(-t, h2), inv_eta);
                const T t1 = (T(1) - r1) * scale1 * go(cos_mi1, glm::dot(mi, -t));
                const T t2 = T(1) - r2, scale2 = lookup(inv_e_in_, cos_mi2);
                const hairscatter::Refracted<T> out = hairscatter::refract_through(-t, h2, eta);
                if (out.ok) {
                    w_tt = glm::normalize(out.o);
                    if (glm::dot(mt, -w_tt) > T(0) && t2 > T(0) && visible(-w_tt, mt_flat, h2))
                        tt = t1 * a_t * t2 * scale2 * go(cos_mi2, glm::dot(mt, -w_tt));
                }
                const V3 tr = hairscatter::reflect_about(-t, h2);  // the second chord's propagation
                const T phi_tr = std::atan2(-tr.y, -tr.z);
                const T gamma_tr = gamma_i - T(2) * (to_phi(phi_t) - to_phi(phi_tr)) + hairscatter::kPi<T>;
                const V3 mtr = normal(gamma_tr, -sin_a_, cos_a_);
                const V3 h3 = visible_normal(-tr, mtr, next(rng), next(rng));
                const T cos_mi3 = glm::dot(mtr, -tr);
                if (cos_mi3 > T(0)) {
                    const V3 a_tr = attenuation(chord(gamma_tr, gamma_t) / cos_theta(tr));
                    const V3 tr_energy = t1 * r2 * scale2 * a_t * a_tr * lookup(inv_e_in_, cos_mi3) * go(cos_mi2, glm::dot(mt, tr));
                    const T r3 = hairscatter::fresnel_any(glm::dot(-tr, h3), inv_eta);
                    const hairscatter::Refracted<T> out3 = hairscatter::refract_through(-tr, h3, eta);
                    if (out3.ok) {
                        w_trt = glm::normalize(out3.o);
                        if (T(1) - r3 > T(0) && visible(-tr, -w_trt, normal(gamma_tr, T(0), T(1)), h3))
                            trt = tr_energy * (T(1) - r3) * go(cos_mi3, glm::dot(mtr, -w_trt));
                    }
                    // ≥ TRRT: θ from M(4β) about −θ_V, φ uniform.
                    const T u_theta = std::max(next(rng), T(1e-5));
                    const T beta = p_.roughness;
                    const T fac = T(1) + T(4) * beta * std::log(u_theta + (T(1) - u_theta) * std::exp(T(-0.5) / beta));
                    const T sin_o = -fac * v.x + hairscatter::cos_from_sin(fac) *
                                                     std::cos(T(2) * hairscatter::kPi<T> * next(rng)) * cos_theta(v);
                    const T cos_o = hairscatter::cos_from_sin(sin_o);
                    const T phi_o = T(2) * hairscatter::kPi<T> * next(rng);
                    w_trrt = V3(sin_o, cos_o * std::sin(phi_o), cos_o * std::cos(phi_o));
                    V3 a_avg;
                    for (int ch = 0; ch < 3; ++ch) a_avg[ch] = std::sqrt(a_t[ch] * a_tr[ch]);
                    const T t_avg = std::max(T(0.5) * (t2 + (T(1) - r3)), T(1e-5));
                    const V3 a_res = a_avg * t_avg / (V3(T(1)) - a_avg * (T(1) - t_avg));
                    trrt = tr_energy * r3 * a_res * go(cos_mi3, glm::dot(mtr, hairscatter::reflect_about(-tr, h3)));
                }
            }
        }
        const T e_tt = mean(tt), e_trt = mean(trt), e_trrt = mean(trrt);
        const T total = r_energy + e_tt + e_trt + e_trrt;
        if (!(total > T(0))) return s;
        const T x = u.x * total;
        V3 dir;
        if (x < r_energy) {
            dir = wr;
            s.weight = V3(total);
        } else if (x < r_energy + e_tt) {
            dir = w_tt;
            s.weight = tt / e_tt * total;
        } else if (x < r_energy + e_tt + e_trt) {
            dir = w_trt;
            s.weight = trt / e_trt * total;
        } else {
            dir = w_trrt;
            s.weight = trrt / e_trrt * total;
        }
        s.wi = section_.from_section(dir);
        s.pdf = T(1);
        return s;
    }

  private:
    static T mean(const V3& x) { return (x.x + x.y + x.z) / T(3); }
    static T cos_theta(const V3& w) { return std::sqrt(w.y * w.y + w.z * w.z); }
    // A generator of Cycles' kind: one multiply-add per number.
    static T next(std::uint32_t& state) {
        state = 1103515245u * state + 12345u;
        return T(state) * T(1.0 / 4294967296.0);
    }
    // The section's in-plane direction angle φ (atan2(u, v)) ↔ the ellipse parameter γ.
    T to_phi(T gamma) const {
        if (p_.aspect_ratio == T(1)) return gamma;
        return std::atan2(p_.aspect_ratio * std::sin(gamma), std::cos(gamma));
    }
    T to_gamma(T phi) const {
        if (p_.aspect_ratio == T(1)) return phi;
        return std::atan2(std::sin(phi), p_.aspect_ratio * std::cos(phi));
    }
    // The unit normal at p(γ) tilted by (sin, cos) toward the axis: (sin, cos n).
    V3 normal(T gamma, T sin_t, T cos_t) const {
        const T b = p_.aspect_ratio;
        const V2 n = glm::normalize(V2(b * std::sin(gamma), std::cos(gamma)));
        return V3(sin_t, cos_t * n.x, cos_t * n.y);
    }
    T arc_length(T gamma) const {
        const T s = std::sin(gamma);
        return e2_ == T(0) ? T(1) : std::sqrt(T(1) - e2_ * s * s);
    }
    T chord(T g0, T g1) const {
        const T b = p_.aspect_ratio;
        const V2 d(std::sin(g0) - std::sin(g1), b * (std::cos(g0) - std::cos(g1)));
        return std::sqrt(glm::dot(d, d));
    }
    V3 attenuation(T length) const {
        return V3(std::exp(-p_.sigma_a.x * length), std::exp(-p_.sigma_a.y * length), std::exp(-p_.sigma_a.z * length));
    }
    T lookup(const T* table, T c) const {
        const T x = hairscatter::clamp(c, T(0), T(1)) * T(kTable - 1);
        const int i = std::min(kTable - 2, int(x));
        return table[i] + (x - T(i)) * (table[i + 1] - table[i]);
    }
    // The visible normal about m from v at (u1, u2).
    V3 visible_normal(const V3& v, const V3& m, T u1, T u2) const {
        const hairscatter::TangentFrame<T> f(m, v);
        return f.to_world(ggx_.sample_visible_local(f.to_local(v), u1, u2));
    }
    static bool visible(const V3& v, const V3& m, const V3& h) { return glm::dot(v, h) > T(0) && glm::dot(v, m) > T(0); }
    static bool visible(const V3& a, const V3& b, const V3& m, const V3& h) { return visible(a, m, h) && visible(b, m, h); }
    // Height-correlated G2 and G2 / G1(first).
    T g2(T c1, T c2) const { return T(1) / (T(1) + ggx_.lambda(c1) + ggx_.lambda(c2)); }
    T go(T c1, T c2) const {
        const T l1 = ggx_.lambda(c1);
        return (T(1) + l1) / (T(1) + l1 + ggx_.lambda(c2));
    }
    static int intervals(T range, T res) { return 2 * int(std::ceil(range / res * T(0.5))); }
    static T simpson_weight(int i, int n) { return (i == 0 || i == n) ? T(0.5) : T(i % 2 + 1); }

    V3 eval_r(const V3& v, const V3& l, T g_min, T g_max, T radius) const {
        const int n = intervals(g_max - g_min, T(0.7) * p_.roughness);
        const T res = (g_max - g_min) / T(n);
        const V3 h = glm::normalize(v + l);
        T integral = T(0);
        for (int i = 0; i <= n; ++i) {
            const T g = g_min + T(i) * res;
            const V3 m = normal(g, sin_a_, cos_a_), flat(T(0), m.y, m.z);
            if (!visible(v, l, flat, h)) continue;
            const T cos_mi = glm::dot(m, v);
            integral += simpson_weight(i, n) * ggx_.d(glm::dot(m, h)) * g2(cos_mi, glm::dot(m, l)) * arc_length(g) *
                        lookup(inv_e_out_, cos_mi);
        }
        integral *= T(2) / T(3) * res;
        return V3(T(0.125) * hairscatter::fresnel_any(glm::dot(v, h), p_.eta) * integral / radius);
    }

    static V3 trrt_series(T t, T r, const V3& a) {
        const T t_avg = std::max(T(1) - r, T(1e-5));
        return t * r * r * t_avg * a * a * a / (V3(T(1)) - a * (T(1) - t_avg));
    }

    V3 eval_paths(const V3& v, const V3& l, T g_min, T g_max, T radius, std::uint32_t& rng) const {
        const T eta = p_.eta, inv_eta = T(1) / eta;
        const int n = intervals(g_max - g_min, T(0.8) * p_.roughness);
        const T res = (g_max - g_min) / T(n);
        V3 s_tt(T(0)), s_trt(T(0)), s_trrt(T(0));
        for (int i = 0; i <= n; ++i) {
            const T gi = g_min + T(i) * res;
            const V3 mi = normal(gi, sin_a_, cos_a_), mi_flat = normal(gi, T(0), T(1));
            const T u1 = next(rng), u2 = next(rng);
            const V3 h1 = visible_normal(v, mi, u1, u2);
            const T cos_hi1 = glm::dot(v, h1);
            if (!(cos_hi1 > T(0))) continue;
            const T cos_mi1 = glm::dot(v, mi);
            const hairscatter::Refracted<T> rt = hairscatter::refract_through(v, h1, inv_eta);
            const T t1 = T(1) - hairscatter::fresnel_any(cos_hi1, eta);
            const T scale1 = lookup(inv_e_out_, cos_mi1);
            const V3 t = glm::normalize(rt.o);  // propagation into the fibre
            const T phi_t = std::atan2(t.y, t.z);
            const T gt = T(2) * to_phi(phi_t) - gi;  // antipode of the exit: inward normal there
            const V3 mt = normal(gt, -sin_a_, cos_a_), mt_flat = normal(gt, T(0), T(1));
            const T cos_mo1 = glm::dot(-t, mi), cos_mi2 = glm::dot(-t, mt);
            const T g1o = go(cos_mi1, cos_mo1);
            if (!visible(v, -t, mi, h1) || !visible(v, -t, mi_flat, h1)) continue;
            const T w = simpson_weight(i, n);
            const V3 a_t = attenuation(chord(gi, gt + hairscatter::kPi<T>) / cos_theta(t));
            const T scale2 = lookup(inv_e_in_, cos_mi2);
            // TT: refraction out toward l at the exit.
            if (glm::dot(l, t) >= inv_eta - T(1e-5)) {
                V3 h2 = -t + inv_eta * l;  // the generalised half vector, on the inner side
                const T rcp = T(1) / std::sqrt(glm::dot(h2, h2));
                h2 *= rcp;
                const T cos_mh2 = glm::dot(mt, h2);
                if (cos_mh2 >= T(0)) {
                    const T cos_hi2 = glm::dot(-t, h2), cos_ho2 = glm::dot(-l, h2), cos_mo2 = glm::dot(-l, mt);
                    const T t2 = (T(1) - hairscatter::fresnel_any(cos_hi2, inv_eta)) * scale2;
                    const V3 r = w * t1 * scale1 * t2 * ggx_.d(cos_mh2) * g1o * g2(cos_mi2, cos_mo2) * a_t / cos_mo1 *
                                 cos_mi1 * cos_hi2 * cos_ho2 * rcp * rcp;
                    if (hairscatter::is_finite(r)) s_tt += r * arc_length(gt);
                }
            }
            // TRT and the series past it.
            const T u3 = next(rng), u4 = next(rng);
            const V3 h2 = visible_normal(-t, mt, u3, u4);
            const T cos_hi2 = glm::dot(-t, h2);
            if (!(cos_hi2 > T(0))) continue;
            const T r2 = hairscatter::fresnel_any(cos_hi2, inv_eta);
            const V3 tr = hairscatter::reflect_about(-t, h2);  // the second chord's propagation
            const V3 wtr = -tr;
            if (glm::dot(tr, l) < inv_eta - T(1e-5)) {
                s_trrt += w * trrt_series(t1, r2, a_t);
                continue;
            }
            if (!visible(-t, tr, mt, h2) || !visible(-t, tr, mt_flat, h2)) continue;
            const T phi_tr = std::atan2(wtr.y, wtr.z);
            const T gtr = gi - T(2) * (to_phi(phi_t) - to_phi(phi_tr)) + hairscatter::kPi<T>;
            const V3 mtr = normal(gtr, -sin_a_, cos_a_), mtr_flat = normal(gtr, T(0), T(1));
            V3 h3 = wtr + inv_eta * l;
            const T rcp3 = T(1) / std::sqrt(glm::dot(h3, h3));
            h3 *= rcp3;
            const T cos_mh3 = glm::dot(mtr, h3);
            if (cos_mh3 < T(0) || !visible(wtr, -l, mtr, h3) || !visible(wtr, -l, mtr_flat, h3)) {
                s_trrt += w * trrt_series(t1, r2, a_t);
                continue;
            }
            const T cos_hi3 = glm::dot(h3, wtr), cos_ho3 = glm::dot(h3, -l), cos_mi3 = glm::dot(mtr, wtr);
            const T t3 = (T(1) - hairscatter::fresnel_any(cos_hi3, inv_eta)) * lookup(inv_e_in_, cos_mi3);
            const V3 a_tr = attenuation(chord(gtr, gt) / cos_theta(wtr));
            const T cos_mo2 = glm::dot(mt, -wtr);
            const V3 r = w * t1 * scale1 * r2 * scale2 * t3 * ggx_.d(cos_mh3) * g1o * go(cos_mi2, cos_mo2) *
                         g2(cos_mi3, glm::dot(mtr, -l)) * a_t * a_tr / (cos_mo1 * cos_mo2) * cos_mi1 * cos_mi2 * cos_hi3 *
                         cos_ho3 * rcp3 * rcp3;
            if (hairscatter::is_finite(r)) s_trt += r * arc_length(gtr);
            s_trrt += w * trrt_series(t1, r2, a_t);
        }
        const T m = m4_.eval(l.x, cos_theta(l), v.x, cos_theta(v));
        const T inv_2pi = T(0.5) / hairscatter::kPi<T>, two_over_pi = T(2) / hairscatter::kPi<T>;
        return ((s_tt + s_trt) * (inv_eta * inv_eta) / radius + s_trrt * m * inv_2pi * two_over_pi) * res / T(3);
    }

    hairscatter::HuangParams<T> p_;
    hairscatter::Ggx<T> ggx_;
    hairscatter::EllipticalSection<T> section_;
    hairscatter::DeonLongitudinal<T> m4_;
    T sin_a_ = T(0), cos_a_ = T(1), e2_ = T(0);
    T inv_e_out_[kTable] = {}, inv_e_in_[kTable] = {};
};

}  // namespace bench_ref
