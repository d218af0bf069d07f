// A brute-force double-precision reference of Huang et al. 2022's fiber as
// include/hairscatter/models/huang.hpp defines it (docs/theory.md §3.6), for tests and the
// speed/accuracy study: Monte Carlo over the cross-section and every microfacet normal,
// written independently of the library —
//   the offset γ by stratified uniform samples (not Gauss–Legendre), weighted by the
//   intercepted beam max(0, v·n)|A⁻¹c| (n the section's own normal: the silhouette stops
//   the beam, the tilt turns only the microfacets) and normalised by the same samples' sum;
//   where the tilted mesonormal turns away from v (v·m ≤ 0) the path is the residual's;
//   microfacet normals drawn from D(h)(h·m) (not the visible-normal sampler) and weighted
//   by G1(v) max(0, v·h) / ((v·m)(h·m)), so that their mean is the visible-normal
//   average;
//   each interface's single scattering shadowed as the model defines it (reflection by the
//   height-correlated G2, transmission by the scattered direction's G1) and scaled to the
//   interface's total, the microsurface's as the model's (docs/theory.md §3.6): the single
//   scattering by this file's own rule over normals drawn from D(h)(h·m) (not the
//   model's visible-normal tables) plus the share that physical_fiber.hpp's random walk
//   (not the library's) reflects after two or more events, 32768 walks at 33 cosines;
//   chords by the quadratic of the ellipse x² + y²/b² = 1 in real space (not through the
//   unit circle), normals by its gradient;
//   R, TT and TRT's last interface by next-event evaluation at wi, M with Boost's I0.
// Unbiased for the continuous model (the library's quadrature is what it checks); its noise
// is that of `paths` samples (the tests state their tolerances from it).
#pragma once

#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <vector>

#include <boost/math/special_functions/bessel.hpp>
#include <glm/glm.hpp>

#include "physical_fiber.hpp"

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

// One interface's energies for light from v at cos c to its mean normal (c in [0, 1]),
// relative index n = η_t/η_i: the shadowed single scattering and the two-event total
// reflectance; E(c') for c' in [−1, 1] the mean reflectance of one event (seen from below the
// horizon for c' < 0). Normals from D(h)(h·m) on a k × k grid of midpoints, weighted by
// max(0, v·h)/(h·m) and normalised by the weights' sum: D_v for any v.
struct InterfaceTables {
    static constexpr int kCos = 257, kHit = 513, kGrid = 256;
    std::vector<double> r_total, r_single, t_single;  // at c = i / (kCos - 1)
    std::vector<double> hit;                          // at c' = -1 + 2 i / (kHit - 1)

    static double lambda(double c, double a) {
        const double c2 = c * c;
        return 0.5 * (-1 + std::sqrt(1 + a * a * (1 - c2) / c2));
    }
    template <typename Visit> static void normals(double c, double a, Visit&& visit) {
        const glm::dvec3 v(std::sqrt(std::max(0.0, 1 - c * c)), 0.0, c);
        std::vector<std::pair<glm::dvec3, double>> hs;
        double total = 0;
        for (int i = 0; i < kGrid; ++i)
            for (int j = 0; j < kGrid; ++j) {
                const double u1 = (i + 0.5) / kGrid, u2 = (j + 0.5) / kGrid;
                const double t2 = a * a * u1 / (1 - u1), cos_t = 1 / std::sqrt(1 + t2), sin_t = std::sqrt(t2) * cos_t;
                const glm::dvec3 h(sin_t * std::cos(2 * kPi * u2), sin_t * std::sin(2 * kPi * u2), cos_t);
                const double w = std::max(0.0, glm::dot(v, h)) / cos_t;
                if (w > 0) hs.push_back({h, w});
                total += w;
            }
        for (const auto& hw : hs) visit(v, hw.first, hw.second / total);
    }
    static double interpolate(const std::vector<double>& t, double x) {
        const double y = std::min(1.0, std::max(0.0, x)) * double(t.size() - 1);
        const int i = std::min(int(t.size()) - 2, int(y));
        return t[std::size_t(i)] + (y - i) * (t[std::size_t(i) + 1] - t[std::size_t(i)]);
    }
    double e_hit(double c) const { return interpolate(hit, 0.5 * (c + 1)); }
    double at(const std::vector<double>& t, double c) const { return interpolate(t, c); }

    // Both sides at once: outside (n = η) needs inside's E for light shadowed below, and
    // the other way round.
    static void build(double a, double eta, InterfaceTables& out, InterfaceTables& in) {
        for (InterfaceTables* t : {&out, &in}) {
            const double n = t == &out ? eta : 1 / eta;
            t->hit.resize(kHit);
            for (int i = 0; i < kHit; ++i) {
                double e = 0;
                normals(-1 + 2.0 * i / (kHit - 1), a, [&](const glm::dvec3& v, const glm::dvec3& h, double w) {
                    e += w * fresnel(glm::dot(v, h), n);
                });
                t->hit[std::size_t(i)] = e;
            }
        }
        for (InterfaceTables* t : {&out, &in}) {
            const double n = t == &out ? eta : 1 / eta;
            const InterfaceTables& far = t == &out ? in : out;
            t->r_total.assign(kCos, 0.0);
            t->r_single.assign(kCos, 0.0);
            t->t_single.assign(kCos, 0.0);
            for (int i = 1; i < kCos; ++i) {
                const double c = double(i) / (kCos - 1), lv = lambda(c, a);
                normals(c, a, [&](const glm::dvec3& v, const glm::dvec3& h, double w) {
                    const double vh = glm::dot(v, h), f = fresnel(vh, n);
                    const glm::dvec3 o = 2 * vh * h - v;
                    const double keep_r = o.z > 0 ? (1 + lv) / (1 + lv + lambda(o.z, a)) : 0.0;
                    t->r_single[std::size_t(i)] += w * f * keep_r;
                    t->r_total[std::size_t(i)] += w * f * (keep_r + (1 - keep_r) * t->e_hit(-o.z));
                    if (f < 1) {
                        const double e = 1 / n, ct = std::sqrt(std::max(0.0, 1 - e * e * (1 - vh * vh)));
                        const glm::dvec3 tr = glm::normalize((e * vh - ct) * h - e * v);
                        const double keep_t = tr.z < 0 ? 1 / (1 + lambda(-tr.z, a)) : 0.0;
                        t->t_single[std::size_t(i)] += w * (1 - f) * keep_t;
                        t->r_total[std::size_t(i)] += w * (1 - f) * (1 - keep_t) * (1 - far.e_hit(tr.z));
                    }
                });
            }
            // The totals: the single scattering plus what the microsurface's random walk
            // reflects after two or more events, linear between kWalkCos cosines.
            constexpr int kWalkCos = 33, kWalks = 32768;
            std::vector<double> multiple(kWalkCos);
            for (int j = 0; j < kWalkCos; ++j) {
                const double c = std::max(1e-3, double(j) / (kWalkCos - 1));
                const glm::dvec3 wi(std::sqrt(1 - c * c), 0.0, c);
                phys_fiber::Rng rng(1234567);
                int up = 0;
                for (int k = 0; k < kWalks; ++k) {
                    const phys_fiber::Scatter sc = phys_fiber::interact(wi, a, n, phys_fiber::Interface::kRandomWalk, rng);
                    if (!sc.transmitted && sc.events > 1) ++up;
                }
                multiple[std::size_t(j)] = double(up) / kWalks;
            }
            for (int i = 1; i < kCos; ++i)
                t->r_total[std::size_t(i)] =
                    std::min(1.0, t->r_single[std::size_t(i)] + interpolate(multiple, double(i) / (kCos - 1)));
            // c = 0: the limit of the next cosine.
            t->r_total[0] = t->r_total[1];
            t->r_single[0] = t->r_single[1];
            t->t_single[0] = t->t_single[1];
        }
    }
};

struct Reference {
    Params p;
    // The interface tables, built on the first call of f.
    mutable std::shared_ptr<const std::pair<InterfaceTables, InterfaceTables>> tables_{};
    // The residual's density over sin θi given (sin θi, sin θo). The model's is a table its
    // material builds from a chain of the light inside (models/huang_residual.hpp), part of
    // its definition rather than of its quadrature: the tests pass the material's, so that
    // the comparison still measures the lattices alone. Empty: d'Eon's M of variance 4β.
    std::function<double(double, double)> residual_density{};
    // The residual's density over φi − φo (per radian) given (wo, wi) in the fiber frame: the
    // model's is a table its material traces through the section (AzimuthTrace in
    // models/huang_residual.hpp), passed by the tests for the same reason. Empty: uniform.
    std::function<double(const glm::dvec3&, const glm::dvec3&)> residual_azimuth{};
    const InterfaceTables& outside() const { return ensure().first; }
    const InterfaceTables& inside() const { return ensure().second; }
    const std::pair<InterfaceTables, InterfaceTables>& ensure() const {
        if (!tables_) {
            auto t = std::make_shared<std::pair<InterfaceTables, InterfaceTables>>();
            InterfaceTables::build(p.roughness, p.eta, t->first, t->second);
            tables_ = t;
        }
        return *tables_;
    }
    double lambda(double c) const { return InterfaceTables::lambda(c, p.roughness); }
    // Reflection from v to o (cosines to m): the height-correlated G2 / G1(v).
    double keep_reflected(double cv, double co) const { return co > 0 ? (1 + lambda(cv)) / (1 + lambda(cv) + lambda(co)) : 0.0; }
    // Transmission's shadowing: G1 of the scattered direction at cosine c to m.
    double keep_transmitted(double c) const { return c > 0 ? 1 / (1 + lambda(c)) : 0.0; }
    // The transmission lobe's scale leaving the fiber (model: exit_gain), with the nearest
    // cosine's value where almost nothing transmits singly.
    double transmit_gain(const InterfaceTables& t, double c) const {
        for (double x = c; x <= 1.0; x += 1.0 / (InterfaceTables::kCos - 1)) {
            const double single = t.at(t.t_single, x);
            if (single > 1e-4) return (1 - t.at(t.r_total, x)) / single;
        }
        return 1.0;
    }

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
        return (1 - fresnel(vh, 1 / p.eta)) * dv * (-oh) / glm::dot(sum, sum) * keep_transmitted(-glm::dot(o, m)) *
               transmit_gain(inside(), vm);
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
            const double vn = glm::dot(v, glm::dvec3(0.0, m.y, m.z)) / std::cos(p.alpha);
            const double x = std::max(0.0, vn) * std::sqrt(sq(c.x) + sq(c.y / b));
            norm += x;
            if (!(x > 0)) continue;
            if (!(vm > 0)) {
                residual += glm::dvec3(x);
                continue;
            }
            glm::dvec3 path(0.0), res(0.0);
            // R: F D G1(v) / (4 v·m) at the half vector (= F D_v/(4 v·h)).
            const glm::dvec3 hr = glm::normalize(v + wi);
            const InterfaceTables& out = outside();
            if (glm::dot(hr, m) > 0)
                path += glm::dvec3(fresnel(glm::dot(v, hr), p.eta) * ggx_d(glm::dot(hr, m)) * g1(vm) / (4 * vm) *
                                   keep_reflected(vm, glm::dot(wi, m)) * out.at(out.r_total, vm) / out.at(out.r_single, vm));
            // Into the fiber through a random normal.
            const Normal n1 = draw_normal(m, v, rng);
            if (n1.weight > 0) {
                const double ci = glm::dot(v, n1.h), e = 1 / p.eta;
                const double ct = std::sqrt(1 - e * e * (1 - ci * ci));
                const glm::dvec3 t = glm::normalize((e * ci - ct) * n1.h - e * v);
                const double t_gain = (1 - out.at(out.r_total, vm)) / out.at(out.t_single, vm);
                const glm::dvec3 thr1(n1.weight * (1 - fresnel(ci, p.eta)) * keep_transmitted(-glm::dot(t, m)) * t_gain);
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
                        const InterfaceTables& in = inside();
                        // F of the drawn normal (no masking of the reflected direction) in
                        // units of the mean reflectance E, times the total reflectance; the
                        // residual takes the difference from the total (zero on average).
                        const double total2 = in.at(in.r_total, c2);
                        const glm::dvec3 thr2 =
                            glm::dot(r, m2) > 0
                                ? at2 * (n2.weight * fresnel(glm::dot(v2, n2.h), 1 / p.eta) * total2 / in.e_hit(c2))
                                : glm::dvec3(0.0);
                        res += at2 * total2 - thr2;
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
                                const double r3 = in.at(in.r_total, c3), rbar = r3;
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
        const double m = residual_density ? residual_density(wi_fiber.x, wo_fiber.x) : residual_m(wi_fiber.x, wo_fiber.x);
        const double n_phi = residual_azimuth ? residual_azimuth(wo_fiber, wi_fiber) : 1 / (2 * kPi);
        return (sum + residual * m * n_phi) / norm;
    }
};

}  // namespace ref_huang
