#pragma once
// The longitudinal profile of Huang et al. 2022's residual (the orders past TRT), built with
// the material on the host (docs/theory.md §3.6, "The residual's profile").
//
// Light that stays inside a fiber after TRT meets the surface near grazing, where one
// microfacet turns it by far more than the roughness and where much of what a facet scatters
// is masked and scatters again. The profile follows that light as a Markov chain over two
// coordinates of a round section: u, the axial component of the light's direction, and h,
// the offset of its chord, which a smooth round section keeps from one interface to the next.
// Each interface is the rough dielectric's full microsurface: a random walk on the Smith GGX
// microsurface that scatters until the light leaves it [Heitz, Hanika, d'Eon & Dachsbacher
// 2016, "Multiple-scattering microfacet BSDFs with the Smith model", §4 and Algorithm 2, with
// uniform heights]. What it reflects goes on to another state; what it transmits leaves at
// sin θi = its direction's axial component. The chain starts where the beam from wo enters
// (through the same walk) and skips the interfaces TT and TRT leave by (their reflected light
// only), so that it holds the orders ≥ TRRT; the exits' distribution over sin θi is found by
// one linear solve. The section's aspect ratio and the absorption are left out: the profile
// is the lossless round fiber's, shared by every channel (the walk's energy split stays
// the model's own).
#include <cmath>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "../fiber/ellipse.hpp"
#include "../lobes/microfacet.hpp"
#include "../math/splitmix.hpp"

namespace hairscatter {
namespace huang_residual {

// The walks' generator: the profile is the same for the same parameters, run after run.
using Rng = SplitMix64;

// The microsurface: GGX of roughness α about z, heights uniform on [−1, 1] (C1(h) = (h + 1)/2;
// the walk's outcome does not depend on the heights' distribution, Heitz et al. 2016 §4.1).
class Microsurface {
  public:
    explicit Microsurface(double alpha) : ggx_(alpha), a2_(alpha * alpha) {}

    // Smith's Λ for any direction w (unit): Λ(w) above the surface, −1 − Λ(−w) below.
    double lambda(const glm::dvec3& w) const {
        const double z = w.z, s2 = std::max(0.0, 1 - z * z);
        const double l = 0.5 * (std::sqrt(1 + a2_ * s2 / (z * z)) - 1);
        return z > 0 ? l : -1 - l;
    }
    // The height at which a ray leaving height h along w meets the microsurface again
    // (Heitz et al. 2016 Algorithm 2, u uniform); false where it escapes. (No infinities, so
    // that -ffast-math keeps the test.)
    bool next_height(const glm::dvec3& w, double h, double u, double& next) const {
        if (w.z > 0.9999) return false;
        const double c1 = c1_of(h);
        next = h;
        const bool sloped = w.z >= -0.9999 && std::fabs(w.z) >= 1e-4;  // neither straight down nor level
        const double lam = sloped ? lambda(w) : 0.0;
        if (sloped && w.z > 0 && u > 1 - std::pow(c1, lam)) return false;
        next = descend(w, h, c1, lam, u);
        return true;
    }
    // The height met by a ray along w (w.z ≤ 0.9999) from h that does not escape, u uniform
    // (Algorithm 2's inversion): c1 = C1(h), lam = Λ(w) (read only where w is sloped).
    static double descend(const glm::dvec3& w, double h, double c1, double lam, double u) {
        if (w.z < -0.9999) return inv_c1(u * c1);
        if (std::fabs(w.z) < 1e-4) return h;
        const double p = std::pow(1 - u, 1 / lam);
        return p > 1e-300 ? inv_c1(c1 / p) : 1.0;
    }
    // One microfacet event seen from v (unit, any side of the mean surface): a visible normal
    // (the spherical-cap sampler draws D_v for v below the horizon too), then reflection with
    // Fresnel's probability, else refraction; n = η_t / η_i across the facet.
    glm::dvec3 event(const glm::dvec3& v, double n, Rng& rng, bool& refracted) const {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        const glm::dvec3 m = ggx_.sample_visible_local(v, u1, u2);
        const double c = glm::dot(v, m), f = fresnel_any(c, n);
        refracted = rng.uniform() >= f;
        if (!refracted) return 2 * c * m - v;
        const double k = 1 - (1 - c * c) / (n * n);
        return glm::normalize(-v / n + (c / n - std::sqrt(std::max(0.0, k))) * m);
    }
    // The whole interface for light arriving from wi (unit, wi.z > 0: the light is above),
    // n = η_below / η_above: the direction it leaves with (false: no exit within the events'
    // budget), and whether it left below.
    bool interact(const glm::dvec3& wi, double n, Rng& rng, glm::dvec3& out, bool& below) const {
        glm::dvec3 w = -wi;
        double h = 1 + inv_c1(0.999);
        bool above = true;
        for (int k = 0; k < kMaxEvents; ++k) {
            double next = 0;
            const bool hit = above ? next_height(w, h, rng.uniform(), next) : next_height(-w, -h, rng.uniform(), next);
            if (!hit) {
                out = w;
                below = !above;
                return true;
            }
            scatter_at(next, n, rng, w, h, above);
        }
        return false;
    }

    // The expected share of light from above (wi, wi.z > 0) that leaves above after two or
    // more events, along one walk: where the light could leave, the walk adds the chance
    // that it does (C1(h)^Λ, Algorithm 2's escape) and goes on with the rest to the next
    // height, so that only the facets and the Fresnel choices are drawn.
    double multiple_up(const glm::dvec3& wi, double n, Rng& rng) const {
        glm::dvec3 w = -wi;
        double h = 1 + inv_c1(0.999), weight = 1, up = 0;
        bool above = true;
        for (int k = 0; k < kMaxEvents && weight > 1e-9; ++k) {
            const glm::dvec3 d = above ? w : -w;
            const double hh = above ? h : -h;
            // Λ and C1^Λ once for the escape and the descent (next_height(d, hh, u (1 − escape))
            // would recompute both, and its escape test never passes: u (1 − e) ≤ 1 − e).
            const double c1 = c1_of(hh);
            const double lam = d.z > 0 || std::fabs(d.z) >= 1e-4 ? lambda(d) : 0.0;  // (level: unused)
            const double escape = d.z > 0 ? std::pow(c1, lam) : 0.0;
            if (above && k >= 2) up += weight * escape;
            weight *= 1 - escape;
            const double u = rng.uniform() * (1 - escape);
            if (d.z > 0.9999) break;
            scatter_at(descend(d, hh, c1, lam, u), n, rng, w, h, above);
        }
        return up;
    }

  private:
    // A walk's event at the height `next` it met (as next_height gives it, on the side the
    // light travels): the light along w (above or below) scatters there.
    void scatter_at(double next, double n, Rng& rng, glm::dvec3& w, double& h, bool& above) const {
        h = above ? next : -next;
        // Below, the microsurface is the mirror image (heights and directions negated).
        bool through = false;
        const glm::dvec3 o = above ? event(-w, n, rng, through) : -event(w, 1 / n, rng, through);
        w = o;
        if (through) above = !above;
    }
    static constexpr int kMaxEvents = 256;
    static double c1_of(double h) { return std::min(1.0, std::max(0.0, 0.5 * (h + 1))); }
    static double inv_c1(double u) { return std::min(1.0, std::max(-1.0, 2 * u - 1)); }
    Ggx<double> ggx_;
    double a2_;
};

// The share of light from above at cos c (n = η_below / η_above) that the microsurface
// reflects after two or more events: its total reflectance less the single scattering that
// no microfacet shadows, which the height-correlated Smith G2 gives in closed form (the
// walk's first event escapes with exactly that probability). `walks` walks from `seed`;
// the same seed at every c makes the estimate smooth in c. (Heitz et al. 2016's random
// walk, as the chain's interfaces.)
inline double multiple_reflectance(const Microsurface& surface, double c, double n, int walks, std::uint64_t seed) {
    Rng rng(seed);
    const double cc = std::max(c, 1e-3);
    const glm::dvec3 wi(std::sqrt(1 - cc * cc), 0, cc);
    double sum = 0;
    for (int k = 0; k < walks; ++k) sum += surface.multiple_up(wi, n, rng);
    return walks > 0 ? sum / walks : 0.0;
}

// One interface at the mesonormal m (unit, facing v) for light arriving from v (unit, the
// direction back toward where it came from), n = η beyond m's side / η on it: v in m's frame,
// the microsurface's walk, back. False where v does not face m or the walk does not end.
inline bool interface_walk(const Microsurface& surface, const glm::dvec3& v, const glm::dvec3& m, double n, Rng& rng,
                           glm::dvec3& out, bool& below) {
    const double c = glm::dot(v, m);
    if (!(c > 1e-6)) return false;
    const glm::dvec3 e1 = glm::normalize(v - c * m), e2 = glm::cross(m, e1);
    glm::dvec3 o;
    if (!surface.interact(glm::dvec3(glm::dot(v, e1), glm::dot(v, e2), c), n, rng, o, below)) return false;
    out = o.x * e1 + o.y * e2 + o.z * m;
    return true;
}

// The chain's size: u bins × h bins of states, walks per state and per entry offset, and the
// exits' bins in sin θi (measured against the physical fiber, docs/models.md: 36 × 8 states
// and 256 walks are as close as 72 × 16).
inline constexpr int kStatesU = 36;
inline constexpr int kStatesH = 8;
inline constexpr int kWalksPerState = 256;
inline constexpr int kEntryOffsets = 32;
inline constexpr int kWalksPerOffset = 64;

// The chain for a material (η, roughness α, cuticle tilt in radians), its exits in `bins`
// bins of sin θi. profile(sin_o) is the density of the orders ≥ TRRT over sin θi per bin,
// normalised to sum 1 over the bins (all zeros if nothing leaves).
class Chain {
  public:
    Chain(double eta, double alpha, double tilt, int bins)
        : eta_(eta), surface_(alpha), bins_(bins), m_out_(std::sin(tilt), std::cos(tilt), 0.0) {
        const int ns = kStatesU * kStatesH;
        reflect_.assign(std::size_t(ns * ns), 0.0);
        leave_.assign(std::size_t(ns * bins), 0.0);
        Rng rng(0x48756e67u);
        const glm::dvec3 m_in = -m_out_;
        for (int s = 0; s < ns; ++s) {
            const double u = -1 + (s / kStatesH + 0.5) * 2.0 / kStatesU, h = (s % kStatesH + 0.5) / kStatesH;
            const double r = std::sqrt(1 - u * u);
            // Travelling toward the surface point whose outward normal is +y.
            const glm::dvec3 d(u, r * std::sqrt(1 - h * h), r * h);
            glm::dvec3 out;
            bool below = false;
            for (int k = 0; k < kWalksPerState; ++k) {
                if (!walk(-d, m_in, 1 / eta, rng, out, below)) continue;
                if (below) leave_[std::size_t(s * bins + exit_bin(out.x))] += 1.0 / kWalksPerState;
                else reflect_[std::size_t(s * ns + state(out))] += 1.0 / kWalksPerState;
            }
        }
        // (I − K)ᵀ, factorised once (partial pivoting): the chain's light x solves x (I − K) = q.
        lu_.assign(std::size_t(ns * ns), 0.0);
        for (int i = 0; i < ns; ++i)
            for (int j = 0; j < ns; ++j) lu_[std::size_t(i * ns + j)] = (i == j ? 1.0 : 0.0) - reflect_[std::size_t(j * ns + i)];
        pivot_.resize(std::size_t(ns));
        for (int c = 0; c < ns; ++c) {
            int p = c;
            for (int i = c + 1; i < ns; ++i)
                if (std::fabs(lu_[std::size_t(i * ns + c)]) > std::fabs(lu_[std::size_t(p * ns + c)])) p = i;
            pivot_[std::size_t(c)] = p;
            if (p != c)
                for (int j = 0; j < ns; ++j) std::swap(lu_[std::size_t(c * ns + j)], lu_[std::size_t(p * ns + j)]);
            const double d = lu_[std::size_t(c * ns + c)];
            if (!(std::fabs(d) > 1e-300)) continue;
            for (int i = c + 1; i < ns; ++i) {
                const double f = lu_[std::size_t(i * ns + c)] / d;
                lu_[std::size_t(i * ns + c)] = f;
                if (f != 0)
                    for (int j = c + 1; j < ns; ++j) lu_[std::size_t(i * ns + j)] -= f * lu_[std::size_t(c * ns + j)];
            }
        }
    }

    std::vector<double> profile(double sin_o) const {
        const int ns = kStatesU * kStatesH;
        sin_o = std::min(0.999, std::max(-0.999, sin_o));
        const double cos_o = std::sqrt(1 - sin_o * sin_o);
        // The entry: the beam uniform over the offsets (h ≥ 0 by the section's symmetry).
        std::vector<double> q(std::size_t(ns), 0.0);
        Rng rng(0x456e747279u + std::uint64_t((sin_o + 1) * 1e6));
        glm::dvec3 out;
        bool below = false;
        for (int k = 0; k < kEntryOffsets; ++k) {
            const double h = (k + 0.5) / kEntryOffsets;
            const glm::dvec3 v(sin_o, cos_o * std::sqrt(1 - h * h), -cos_o * h);  // toward wo
            for (int j = 0; j < kWalksPerOffset; ++j)
                if (walk(v, m_out_, eta_, rng, out, below) && below) q[std::size_t(state(out))] += 1.0 / (kEntryOffsets * kWalksPerOffset);
        }
        // TT's and TRT's exits: only what they reflect goes on.
        for (int step = 0; step < 2; ++step) {
            std::vector<double> next(std::size_t(ns), 0.0);
            for (int i = 0; i < ns; ++i)
                if (q[std::size_t(i)] != 0)
                    for (int j = 0; j < ns; ++j) next[std::size_t(j)] += q[std::size_t(i)] * reflect_[std::size_t(i * ns + j)];
            q.swap(next);
        }
        // x (I − K) = q, by the factorisation of (I − K)ᵀ.
        for (int c = 0; c < ns; ++c) std::swap(q[std::size_t(c)], q[std::size_t(pivot_[std::size_t(c)])]);
        for (int i = 0; i < ns; ++i)
            for (int j = 0; j < i; ++j) q[std::size_t(i)] -= lu_[std::size_t(i * ns + j)] * q[std::size_t(j)];
        for (int i = ns - 1; i >= 0; --i) {
            for (int j = i + 1; j < ns; ++j) q[std::size_t(i)] -= lu_[std::size_t(i * ns + j)] * q[std::size_t(j)];
            const double d = lu_[std::size_t(i * ns + i)];
            q[std::size_t(i)] = std::fabs(d) > 1e-300 ? q[std::size_t(i)] / d : 0.0;
        }
        std::vector<double> exits(std::size_t(bins_), 0.0);
        double sum = 0;
        for (int i = 0; i < ns; ++i) {
            const double x = std::max(0.0, q[std::size_t(i)]);
            if (x > 0)
                for (int b = 0; b < bins_; ++b) exits[std::size_t(b)] += x * leave_[std::size_t(i * bins_ + b)];
        }
        for (double e : exits) sum += e;
        if (!(sum > 0 && sum < 1e300)) return std::vector<double>(std::size_t(bins_), 0.0);
        for (double& e : exits) e /= sum;
        return exits;
    }

  private:
    // One interface at the mesonormal m (unit, facing v): v in its frame, the walk, back.
    bool walk(const glm::dvec3& v, const glm::dvec3& m, double n, Rng& rng, glm::dvec3& out, bool& below) const {
        return interface_walk(surface_, v, m, n, rng, out, below);
    }
    int exit_bin(double x) const { return std::min(bins_ - 1, std::max(0, int((x + 1) * 0.5 * bins_))); }
    // The state of a ray leaving the surface point (outward normal +y) inward along r: its
    // axial component and its chord's offset.
    static int state(const glm::dvec3& r) {
        const double inplane = std::sqrt(r.y * r.y + r.z * r.z), h = inplane > 0 ? std::fabs(r.z) / inplane : 0.0;
        const int iu = std::min(kStatesU - 1, std::max(0, int((r.x + 1) * 0.5 * kStatesU)));
        return iu * kStatesH + std::min(kStatesH - 1, int(h * kStatesH));
    }

    double eta_;
    Microsurface surface_;
    int bins_;
    glm::dvec3 m_out_;
    std::vector<double> reflect_, leave_, lu_;
    std::vector<int> pivot_;
};

// The residual's azimuth (docs/theory.md §3.6, "The residual's azimuth"). The light that
// stays inside an elliptical section after TRT leaves with an azimuth that a round chain
// cannot give: an elongated section sends more of it across its long side, and the first
// orders past TRT remember where the beam came from (docs/models.md measures both against
// the physical fiber). So the section itself is traced: the beam from wo, uniform over the
// section's projected width, enters through the same microsurface walk as the chain, goes
// on in straight chords inside the ellipse (semi-axes 1 along y and b along z, the section
// frame of fiber/ellipse.hpp, whose geometry it uses), and at each interface meets the walk again at the mesonormal
// (the outward normal tilted toward the tip by the cuticle angle, as the chain's); what
// leaves after two or more internal reflections, the orders ≥ TRRT, is binned by its
// azimuth past wo's, φ = atan2(w.z, w.y) − atan2(wo.z, wo.y). Lossless, as the chain's
// profile (the shape is shared by every channel; the energy stays the model's own).
class AzimuthTrace {
  public:
    AzimuthTrace(double eta, double alpha, double tilt, double aspect)
        : eta_(eta), surface_(alpha), tilt_(tilt), b_(aspect) {}

    // The orders ≥ TRRT's density over φ ∈ [−π, π) in `bins` bins, normalised to sum 1
    // (all zeros if none leaves), for wo = (sin_o, cos_o cos a, cos_o sin a): `rays` rays,
    // stratified over the offset, from a generator seeded with `seed`.
    std::vector<double> profile(double sin_o, double a, int bins, int rays, std::uint64_t seed) const {
        std::vector<double> out(std::size_t(bins), 0.0);
        const double pi = 3.14159265358979323846;
        sin_o = std::min(0.999, std::max(-0.999, sin_o));
        const double cos_o = std::sqrt(1 - sin_o * sin_o);
        const glm::dvec3 wo(sin_o, cos_o * std::cos(a), cos_o * std::sin(a));
        // Points as the model's walk holds them: c on the unit circle, A c on the ellipse.
        const EllipticalSection<double> section(b_, 0.0);
        const EllipticalSection<double>::View view = section.view(wo);
        Rng rng(seed);
        double sum = 0;
        for (int k = 0; k < rays; ++k) {
            const double h = -1 + 2 * (k + rng.uniform()) / rays;
            glm::dvec2 c = EllipticalSection<double>::hit(view, h, std::sqrt(std::max(0.0, 1 - h * h)));
            glm::dvec3 dir, next;
            bool below = false;
            if (!interface_walk(surface_, wo, mesonormal(section.normal(c)), eta_, rng, next, below) || !below) continue;  // R
            dir = next;
            for (int reflections = 0, event = 0; event < kMaxInterfaces; ++event) {
                if (!(dir.y * dir.y + dir.z * dir.z > 1e-24)) break;  // along the axis
                // The next interface; a chord that points out (a facet behind the tilted
                // mesonormal) meets the surface again where it is.
                const EllipticalSection<double>::Chord chord = section.chord(c, glm::dvec2(dir.y, dir.z));
                if (chord.ok) c = chord.c;
                if (!interface_walk(surface_, -dir, -mesonormal(section.normal(c)), 1 / eta_, rng, next, below)) break;
                if (below) {
                    if (reflections >= 2) {
                        double phi = std::atan2(next.z, next.y) - a;
                        phi -= 2 * pi * std::floor((phi + pi) / (2 * pi));
                        out[std::size_t(std::min(bins - 1, std::max(0, int((phi + pi) / (2 * pi) * bins))))] += 1;
                        sum += 1;
                    }
                    break;
                }
                ++reflections;
                dir = next;
            }
        }
        if (!(sum > 0)) return std::vector<double>(std::size_t(bins), 0.0);
        for (double& x : out) x /= sum;
        return out;
    }

  private:
    static constexpr int kMaxInterfaces = 256;
    // The mesonormal at a point of the ellipse whose in-plane outward normal is n: n tilted
    // toward the tip (+x) by the cuticle angle.
    glm::dvec3 mesonormal(const glm::dvec2& n) const { return glm::dvec3(std::sin(tilt_), std::cos(tilt_) * n.x, std::cos(tilt_) * n.y); }

    double eta_;
    Microsurface surface_;
    double tilt_, b_;
};

}  // namespace huang_residual
}  // namespace hairscatter
