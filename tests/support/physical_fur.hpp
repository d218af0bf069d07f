// A physical reference for fur fibres: Monte-Carlo ray tracing of a double cylinder, a
// dielectric cortex around a scattering medulla, written independently of the library's
// models, for tests and for docs/fur_physical.md. The geometry is Yan, Tseng, Jensen &
// Ramamoorthi 2015 ("Physically-accurate fur reflectance: modeling, measurement and
// rendering") and Yan, Jensen & Ramamoorthi 2017 ("An efficient and practical near and far
// field fur reflectance model").
//
// What it models:
//   the cortex, an infinite round cylinder of radius 1 and relative index η, absorbing
//   σa^c per unit radius; its boundary, smooth or rough, exactly as physical_fiber.hpp's
//   (the Smith GGX random walk of Heitz et al. 2016 by default, the other Interface modes,
//   the cuticle tilt), whose code it calls;
//   the medulla, a concentric cylinder of radius κ ∈ [0, 1) of the cortex's refractive
//   index (no reflection or refraction at its boundary, Yan et al. 2015's assumption),
//   a homogeneous medium with scattering σs^m and absorption σa^m per unit radius and a
//   Henyey–Greenstein phase function of anisotropy g, in 3D: a scattered ray leaves the
//   section's cone of inclination, as light in a real medulla does;
//   every order: free flights in the medulla sampled exactly (exponential in the 3D
//   distance with σs^m; absorption as a weight exp(−σa^m ℓ), which is unbiased and lets the
//   lossless channel share the paths), cortex segments attenuated by σa^c over their 3D
//   length, until the ray leaves the fibre or a cap (boundary events, scatterings) counts
//   it as lost.
//
// What it leaves out: diffraction and polarisation (Fresnel averaged over polarisations),
// refraction and reflection at the medulla's boundary, non-concentric or elliptical
// medullas, the scales' steps.
//
// Conventions are physical_fiber.hpp's: fibre frame x = the axis, a far-field beam from wo
// spread uniformly over the projected width, f with the cosine inside, the same Histogram
// bins, channel 0 lossless and 1–3 RGB. Exiting light is classed R, TT, TRT, higher (by
// boundary events, as physical_fiber.hpp does) when it never scattered in the medulla, and
// scattered when it did at least once.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <thread>
#include <vector>

#include <glm/glm.hpp>

#include "physical_fiber.hpp"

namespace phys_fur {

using phys_fiber::kPi;
using phys_fiber::Rng;

struct Fur {
    // The cortex: η, roughness, tilt, interface, σa^c (per unit radius) and the cap on
    // boundary events. The section is round: aspect and orientation are not read.
    phys_fiber::Fiber cortex;
    double kappa = 0;                 // medulla radius over the cortex's, [0, 1)
    double sigma_s = 0;               // σs^m per unit radius
    glm::dvec3 sigma_a_medulla{0.0};  // σa^m per unit radius, RGB
    double g = 0;                     // Henyey–Greenstein anisotropy, (−1, 1)
    long long max_scatterings = 100000;  // medulla events per ray before it counts as lost
};

enum Class { kR = 0, kTT = 1, kTRT = 2, kHigher = 3, kScattered = 4, kClasses = 5 };

struct Histogram : phys_fiber::BasicHistogram<kClasses> {
    using BasicHistogram::BasicHistogram;
    // Energy per channel that scattered in the medulla at least once during the first
    // passage: between entering the fibre and meeting its boundary again.
    double first_passage_scattered[4] = {0, 0, 0, 0};
    double scatterings = 0;  // medulla scattering events, every ray
    void add(const Histogram& o) {
        BasicHistogram::add(o);
        for (int c = 0; c < 4; ++c) first_passage_scattered[c] += o.first_passage_scattered[c];
        scatterings += o.scatterings;
    }
};

// The Henyey–Greenstein phase function (Henyey & Greenstein 1941) of the cosine
// between the travel directions before and after scattering, per steradian.
inline double hg_phase(double cos_t, double g) {
    return (1 - g * g) / (4 * kPi * std::pow(1 + g * g - 2 * g * cos_t, 1.5));
}

// A cosine drawn from hg_phase by inverting its CDF.
inline double sample_hg_cos(double g, double u) {
    if (std::fabs(g) < 1e-6) return 1 - 2 * u;  // the inversion's 1/g: isotropic within 1e-6
    const double s = (1 - g * g) / (1 - g + 2 * g * u);
    return std::min(1.0, std::max(-1.0, (1 + g * g - s * s) / (2 * g)));
}

// A travel direction after scattering a ray travelling along d (unit).
inline glm::dvec3 scatter_direction(const glm::dvec3& d, double g, double u1, double u2) {
    const double c = sample_hg_cos(g, u1);
    const double s = std::sqrt(std::max(0.0, 1 - c * c));
    const double phi = 2 * kPi * u2;
    // An orthonormal basis around d (Duff et al. 2017, "Building an orthonormal basis,
    // revisited"), continuous except at d.z = 0's sign change.
    const double sign = std::copysign(1.0, d.z);
    const double a = -1 / (sign + d.z), b = d.x * d.y * a;
    const glm::dvec3 t(1 + sign * d.x * d.x * a, sign * b, -sign * d.x), bt(b, sign + d.y * d.y * a, -d.y);
    return glm::normalize(c * d + s * (std::cos(phi) * t + std::sin(phi) * bt));
}

// The line p + t d (d unit, in the section plane) against the circle of radius r about the
// axis: both roots, t0 ≤ t1, in the stable form.
inline bool circle_hit(const glm::dvec2& p, const glm::dvec2& d, double r, double& t0, double& t1) {
    const double b = glm::dot(p, d), c = glm::dot(p, p) - r * r;
    const double disc = b * b - c;
    if (!(disc > 0)) return false;
    const double q = -b - std::copysign(std::sqrt(disc), b);
    t0 = q;
    t1 = q != 0 ? c / q : 0;
    if (t0 > t1) std::swap(t0, t1);
    return true;
}

class Tracer {
  public:
    explicit Tracer(const Fur& f) : f_(f) {}

    // Traces `rays` rays from wo (fibre frame: x the axis), adding to hist.
    void trace(const glm::dvec3& wo, long long rays, std::uint64_t seed, Histogram& hist) const {
        Rng rng(seed);
        const glm::dvec3 d = -wo;
        const glm::dvec2 d2(d.y, d.z);
        const double len2 = glm::length(d2);
        if (!(len2 > 1e-9)) return;  // along the axis: the fibre has no width
        const glm::dvec2 dn = d2 / len2, e(-dn.y, dn.x);
        for (long long r = 0; r < rays; ++r) {
            hist.rays += 1;
            const double h = 2 * rng.uniform() - 1;
            trace_ray(h * e - std::sqrt(std::max(0.0, 1 - h * h)) * dn, d, rng, hist);
        }
    }

  private:
    // One ray arriving at p on the boundary, travelling along dir.
    void trace_ray(glm::dvec2 p, glm::dvec3 dir, Rng& rng, Histogram& hist) const {
        double w[4] = {1, 1, 1, 1};
        int transmissions = 0, internal_reflections = 0;
        long long scatterings = 0;
        bool inside = false;
        for (int event = 0; event < f_.cortex.max_events; ++event) {
            const std::optional<phys_fiber::Scatter> s = phys_fiber::boundary_event(dir, glm::dvec3(0, p), inside, f_.cortex, rng);
            if (!s) break;  // grazing the macro surface: stop (measure zero)
            for (int c = 0; c < 4; ++c) {
                hist.lost[c] += w[c] * (1 - s->weight);
                w[c] *= s->weight;
            }
            dir = s->dir;
            const bool first_passage = s->transmitted && transmissions == 0;  // entering for the first time
            if (s->transmitted) ++transmissions;
            else if (inside) ++internal_reflections;
            if (s->transmitted == inside) {
                // Left the fibre (a convex section: nothing is hit again).
                const int cls = scatterings > 0            ? kScattered
                                : transmissions == 0       ? kR
                                : internal_reflections == 0 ? kTT
                                : internal_reflections == 1 ? kTRT
                                                            : kHigher;
                const int bin = hist.bin_of(dir);
                for (int c = 0; c < 4; ++c) {
                    hist.energy[std::size_t((bin * kClasses + cls) * 4 + c)] += w[c];
                    hist.lobe_energy[cls][c] += w[c];
                }
                return;
            }
            inside = true;
            if (!pass(p, dir, w, scatterings, first_passage, rng, hist)) break;
        }
        for (int c = 0; c < 4; ++c) hist.lost[c] += w[c];
    }

    // Carries a ray from p on the boundary, heading in, to where it meets the boundary
    // again, through cortex and medulla. False when it never does: travelling along the
    // axis outside a scattering medulla, or past the scattering cap.
    bool pass(glm::dvec2& p, glm::dvec3& dir, double w[4], long long& scatterings, bool first_passage, Rng& rng,
              Histogram& hist) const {
        bool in_medulla = false, scattered = false;
        for (;;) {
            const glm::dvec2 t2(dir.y, dir.z);
            const double tl = glm::length(t2);  // in-plane length per unit 3D length
            const glm::dvec2 tn = tl > 1e-12 ? t2 / tl : glm::dvec2(0.0);
            if (in_medulla) {
                double a0 = 0, a1 = 0;
                const double s_exit = !(tl > 1e-12) ? HUGE_VAL : circle_hit(p, tn, f_.kappa, a0, a1) ? std::max(0.0, a1) : 0.0;
                const double t_exit = s_exit / std::max(tl, 1e-300);
                const double t_free = f_.sigma_s > 0 ? -std::log(1 - rng.uniform()) / f_.sigma_s : HUGE_VAL;
                if (t_free < t_exit) {
                    attenuate(w, f_.sigma_a_medulla, t_free, hist);
                    p += t_free * tl * tn;
                    if (first_passage && !scattered)
                        for (int c = 0; c < 4; ++c) hist.first_passage_scattered[c] += w[c];
                    scattered = true;
                    hist.scatterings += 1;
                    if (++scatterings > f_.max_scatterings) return false;
                    const double u1 = rng.uniform(), u2 = rng.uniform();
                    dir = scatter_direction(dir, f_.g, u1, u2);
                    continue;
                }
                if (std::isinf(t_exit)) return absorb_all(w, hist);  // along the axis, σs^m = 0
                attenuate(w, f_.sigma_a_medulla, t_exit, hist);
                p += s_exit * tn;
                in_medulla = false;
                continue;
            }
            if (!(tl > 1e-12)) return absorb_all(w, hist);  // along the axis in the cortex
            double m0 = 0, m1 = 0;
            if (f_.kappa > 0 && circle_hit(p, tn, f_.kappa, m0, m1) && m0 > 1e-12) {  // the medulla lies ahead
                attenuate(w, f_.cortex.sigma_a, m0 / tl, hist);
                p += m0 * tn;
                in_medulla = true;
                continue;
            }
            double a0 = 0, a1 = 0;
            if (!circle_hit(p, tn, 1.0, a0, a1)) a1 = 0;  // grazing the boundary from inside
            const double chord = std::max(0.0, a1);
            attenuate(w, f_.cortex.sigma_a, chord / tl, hist);
            p = glm::normalize(p + chord * tn);  // back on the boundary, against drift
            return true;
        }
    }

    static void attenuate(double w[4], const glm::dvec3& sigma, double length3d, Histogram& hist) {
        for (int c = 1; c < 4; ++c) {
            const double keep = std::exp(-sigma[c - 1] * length3d);
            hist.absorbed[c] += w[c] * (1 - keep);
            w[c] *= keep;
        }
    }
    // A ray that travels forever inside: the absorbing channels lose it all; the lossless
    // one is counted as lost by the caller.
    static bool absorb_all(double w[4], Histogram& hist) {
        for (int c = 1; c < 4; ++c) {
            hist.absorbed[c] += w[c];
            w[c] = 0;
        }
        return false;
    }

    Fur f_;
};

// Traces `rays` rays from wo on `threads` threads (independent streams from seed), adding
// to hist: for this tracer or physical_fiber.hpp's.
template <typename TracerT, typename HistogramT>
void trace_parallel(const TracerT& tracer, const glm::dvec3& wo, long long rays, std::uint64_t seed, int threads,
                    HistogramT& hist) {
    std::vector<HistogramT> part(std::size_t(threads), HistogramT(hist.n_u, hist.n_phi));
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            const long long n = rays / threads + (t < rays % threads ? 1 : 0);
            tracer.trace(wo, n, seed * 1000003u + std::uint64_t(t), part[std::size_t(t)]);
        });
    for (auto& th : pool) th.join();
    for (const HistogramT& h : part) hist.add(h);
}

}  // namespace phys_fur
