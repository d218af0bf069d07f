// A brute-force double-precision reference of Huang et al. 2022's fiber as
// include/hairscatter/models/huang.hpp defines it (docs/theory.md §3.6), for tests and the
// speed/accuracy study: Monte Carlo over the cross-section and every microfacet normal,
// written independently of the library —
//   the offset γ by stratified uniform samples (not Gauss–Legendre), weighted by the
//   intercepted beam max(0, v·m)|A⁻¹c| and normalised by the same samples' sum;
//   microfacet normals drawn from D(h)(h·m) (not the visible-normal sampler) and weighted
//   by G1(v) max(0, v·h) / ((v·m)(h·m)), so that their mean is the visible-normal
//   average;
//   the interfaces' reflectances by those random normals' Fresnel factors (no tables);
//   chords by the quadratic of the ellipse x² + y²/b² = 1 in real space (not through the
//   unit circle), normals by its gradient;
//   R, TT and TRT's last interface by next-event evaluation at wi, M with Boost's I0.
// Unbiased for the continuous model (the library's quadrature is what it checks); its noise
// is that of `paths` samples (the tests state their tolerances from it).
#pragma once

#include <cmath>
#include <random>

#include <boost/math/special_functions/bessel.hpp>
#include <glm/glm.hpp>

namespace ref_huang {

constexpr double kPi = 3.14159265358979323846;

struct Params {
    double eta = 1.55, roughness = 0.3, alpha = 0.0349065850398866, aspect = 1, orientation = 0;
    glm::dvec3 sigma_a{0.0};
};

// The reference's parameters from the library's HuangParams (any type with its fields).
template <typename P> Params params_of(const P& p) {
    Params r;
    r.eta = double(p.eta);
    r.roughness = double(p.roughness);
    r.alpha = double(p.alpha);
    r.aspect = double(p.aspect_ratio);
    r.orientation = double(p.orientation);
    r.sigma_a = glm::dvec3(p.sigma_a);
    return r;
}

inline double sq(double x) { return x * x; }

// Fresnel equations for unpolarised light at cos_i, relative index n = η_t/η_i; 1 past the
// critical angle.
inline double fresnel(double cos_i, double n) {
    cos_i = std::min(1.0, std::max(0.0, cos_i));
    const double sin_t2 = (1 - cos_i * cos_i) / (n * n);
    if (sin_t2 >= 1) return 1;
    const double cos_t = std::sqrt(1 - sin_t2);
    const double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t), rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

struct Reference {
    Params p;

    double ggx_d(double cos_h) const {
        if (cos_h <= 0) return 0;
        const double a2 = sq(p.roughness), t2 = (1 - cos_h * cos_h) / (cos_h * cos_h);
        return a2 / (kPi * sq(sq(cos_h)) * sq(a2 + t2));
    }
    double g1(double cos_v) const {
        const double a2 = sq(p.roughness);
        return 2 * cos_v / (cos_v + std::sqrt(a2 + (1 - a2) * cos_v * cos_v));
    }
    // M of d'Eon et al. 2011 with variance 4β (the residual's), its csch form.
    double residual_m(double sin_i, double sin_o) const {
        const double v = 4 * p.roughness, cos_i = std::sqrt(std::max(0.0, 1 - sin_i * sin_i)),
                     cos_o = std::sqrt(std::max(0.0, 1 - sin_o * sin_o));
        return 1 / (2 * v * std::sinh(1 / v)) * std::exp(-sin_i * sin_o / v) *
               boost::math::cyl_bessel_i(0, cos_i * cos_o / v);
    }

    // The mesonormal at the real-space section point (x, y): the gradient of x² + y²/b²,
    // tilted by α toward the fiber's axis; directions are (axis, major, minor).
    glm::dvec3 mesonormal(double x, double y) const {
        glm::dvec2 n(x, y / sq(p.aspect));
        n /= glm::length(n);
        return {std::sin(p.alpha), std::cos(p.alpha) * n.x, std::cos(p.alpha) * n.y};
    }
    // A normal from D(h)(h·m) about m, and its weight toward the visible-normal average.
    struct Normal {
        glm::dvec3 h;
        double weight;
    };
    template <typename Rng> Normal draw_normal(const glm::dvec3& m, const glm::dvec3& v, Rng& rng) const {
        std::uniform_real_distribution<double> uni(0, 1);
        const double u1 = uni(rng);
        const double u2 = uni(rng);
        const double t2 = sq(p.roughness) * u1 / (1 - u1), cos_t = 1 / std::sqrt(1 + t2), sin_t = std::sqrt(t2) * cos_t;
        const glm::dvec3 a = std::abs(m.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        const glm::dvec3 s = glm::normalize(glm::cross(a, m)), t = glm::cross(m, s);
        const glm::dvec3 h = sin_t * std::cos(2 * kPi * u2) * s + sin_t * std::sin(2 * kPi * u2) * t + cos_t * m;
        const double vh = glm::dot(v, h), vm = glm::dot(v, m);
        return {h, vh > 0 ? g1(vm) * vh / (vm * cos_t) : 0.0};
    }
    // Refraction out through a rough exit from v (inside, index η) toward o, next-event value.
    double exit_value(const glm::dvec3& v, const glm::dvec3& m, const glm::dvec3& o) const {
        const glm::dvec3 sum = p.eta * v + o;
        const glm::dvec3 h = glm::normalize(sum);
        const double hm = glm::dot(h, m), oh = glm::dot(o, h), vh = glm::dot(v, h), vm = glm::dot(v, m);
        if (!(hm > 0 && oh < 0 && vh > 0)) return 0;
        const double dv = g1(vm) * vh * ggx_d(hm) / vm;
        return (1 - fresnel(vh, 1 / p.eta)) * dv * (-oh) / glm::dot(sum, sum);
    }
    // The chord from the real-space point q along the unit 3D direction t: exit point and length.
    bool chord(const glm::dvec2& q, const glm::dvec3& t, glm::dvec2& exit, double& length) const {
        const double b2 = sq(p.aspect);
        const double a = t.y * t.y + t.z * t.z / b2, b = 2 * (q.x * t.y + q.y * t.z / b2);
        if (!(a > 1e-12)) return false;
        const double s = -b / a;
        if (!(s > 0)) return false;
        exit = q + s * glm::dvec2(t.y, t.z);
        length = s;
        return true;
    }

    // f(wo, wi), RGB, from `paths` stratified offsets, one random path each.
    template <typename Rng> glm::dvec3 f(const glm::dvec3& wo_fiber, const glm::dvec3& wi_fiber, int paths, Rng& rng) const {
        std::uniform_real_distribution<double> uni(0, 1);
        const double cp = std::cos(p.orientation), sp = std::sin(p.orientation);
        auto to_section = [&](const glm::dvec3& w) { return glm::dvec3(w.x, cp * w.y + sp * w.z, -sp * w.y + cp * w.z); };
        const glm::dvec3 v = to_section(wo_fiber), wi = to_section(wi_fiber);
        const double b = p.aspect;
        // The visible half: in circle space d' ∝ A⁻¹ d, the offset direction e' ⟂ d'.
        glm::dvec2 d(v.y, v.z);
        if (glm::dot(d, d) == 0) d = glm::dvec2(cp, -sp);
        glm::dvec2 dc(d.x, d.y / b);
        dc /= glm::length(dc);
        const glm::dvec2 ec(-dc.y, dc.x);
        auto attenuation = [&](double len) {
            return glm::dvec3(std::exp(-p.sigma_a.x * len), std::exp(-p.sigma_a.y * len), std::exp(-p.sigma_a.z * len));
        };

        glm::dvec3 sum(0.0), residual(0.0);
        double norm = 0;
        for (int i = 0; i < paths; ++i) {
            const double gamma = -kPi / 2 + kPi * (i + uni(rng)) / paths;
            const glm::dvec2 c = std::sin(gamma) * ec + std::cos(gamma) * dc;
            const glm::dvec2 q(c.x, b * c.y);
            const glm::dvec3 m = mesonormal(q.x, q.y);
            const double vm = glm::dot(v, m);
            const double x = std::max(0.0, vm) * std::sqrt(sq(c.x) + sq(c.y / b));
            norm += x;
            if (!(x > 0)) continue;
            glm::dvec3 path(0.0), res(0.0);
            // R: F D G1(v) / (4 v·m) at the half vector (= F D_v/(4 v·h)).
            const glm::dvec3 hr = glm::normalize(v + wi);
            if (glm::dot(hr, m) > 0) path += glm::dvec3(fresnel(glm::dot(v, hr), p.eta) * ggx_d(glm::dot(hr, m)) * g1(vm) / (4 * vm));
            // Into the fiber through a random normal.
            const Normal n1 = draw_normal(m, v, rng);
            if (n1.weight > 0) {
                const double ci = glm::dot(v, n1.h), e = 1 / p.eta;
                const double ct = std::sqrt(1 - e * e * (1 - ci * ci));
                const glm::dvec3 t = glm::normalize((e * ci - ct) * n1.h - e * v);
                const glm::dvec3 thr1(n1.weight * (1 - fresnel(ci, p.eta)));
                glm::dvec2 q2;
                double len1;
                if (!chord(q, t, q2, len1)) {
                    res += thr1;
                } else {
                    const glm::dvec3 a1 = attenuation(len1), at2 = thr1 * a1;
                    const glm::dvec3 m2 = -mesonormal(q2.x, q2.y), v2 = -t;
                    const double c2 = glm::dot(v2, m2);
                    if (!(c2 > 0)) {
                        res += at2;
                    } else {
                        path += at2 * exit_value(v2, m2, wi);
                        const Normal n2 = draw_normal(m2, v2, rng);
                        const glm::dvec3 r = glm::normalize(2 * glm::dot(v2, n2.h) * n2.h - v2);
                        const glm::dvec3 thr2 = at2 * (n2.weight * fresnel(glm::dot(v2, n2.h), 1 / p.eta));
                        glm::dvec2 q3;
                        double len2;
                        if (n2.weight > 0 && !chord(q2, r, q3, len2)) {
                            res += thr2;
                        } else if (n2.weight > 0) {
                            const glm::dvec3 a2 = attenuation(len2), at3 = thr2 * a2;
                            const glm::dvec3 m3 = -mesonormal(q3.x, q3.y), v3 = -r;
                            const double c3 = glm::dot(v3, m3);
                            if (!(c3 > 0)) {
                                res += at3;
                            } else {
                                path += at3 * exit_value(v3, m3, wi);
                                const Normal n3 = draw_normal(m3, v3, rng);
                                const double r3 = n3.weight * fresnel(glm::dot(v3, n3.h), 1 / p.eta);
                                const double rbar = fresnel(c3, 1 / p.eta);
                                glm::dvec3 series;
                                for (int ch = 0; ch < 3; ++ch) {
                                    const double a3 = std::sqrt(a1[ch] * a2[ch]), den = 1 - a3 * rbar;
                                    series[ch] = den > 1e-6 ? a3 * (1 - rbar) / den : 1.0;
                                }
                                res += at3 * r3 * series;
                            }
                        }
                    }
                }
            }
            sum += x * path;
            residual += x * res;
        }
        return (sum + residual * residual_m(wi_fiber.x, wo_fiber.x) / (2 * kPi)) / norm;
    }
};

}  // namespace ref_huang
