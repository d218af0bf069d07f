// A physical reference for rough dielectric fibers of elliptical section: Monte-Carlo ray
// tracing of the fiber itself, written independently of the library's models, for tests
// and for the accuracy figures of docs/models.md.
//
// What it models:
//   the fiber, an infinite cylinder whose section is an ellipse of semi-axes 1 and b (the
//   major axis at ψ from the frame's y axis toward z), absorbing σa per unit length inside;
//   its boundary, a rough dielectric of relative index η whose microsurface is GGX of
//   roughness α [Walter et al. 2007] about the local surface normal (or, with a cuticle
//   tilt, the normal tilted toward the tip, as in Huang et al. 2022);
//   every interaction with the boundary as a random walk on the Smith microsurface
//   [Heitz, Hanika, d'Eon & Dachsbacher 2016, "Multiple-scattering microfacet BSDFs with
//   the Smith model"]: heights and visible normals are sampled, each microfacet reflects
//   or refracts with Fresnel's probability, and the walk ends when the ray leaves the
//   microsurface, above or below. Masking and shadowing are therefore physical: light
//   shadowed by the microsurface scatters again instead of vanishing, and energy is kept.
//   The walk's single-scattering part is the microfacet BSDF with height-correlated
//   Smith masking–shadowing (the test checks this against quadrature).
//   Every order until the ray leaves the fiber; absorption by the 3D path length inside.
//
// Switches (Interface):
//   kRandomWalk    the physical boundary above (the default);
//   kSmith         one microfacet event per interaction, weighted by the Smith masking of
//                  the scattered direction, G1(o) (Walter et al. 2007's BSDF with the
//                  separable G2; masked light is lost, so a lossless fiber keeps < 1);
//   kUnshadowed    one microfacet event per interaction whose scattered direction always
//                  leaves, masking ignored (the assumption of Huang et al. 2022's model as
//                  the library implements it; used to cross-check R in isolation).
//
// What it leaves out: diffraction and polarisation (Fresnel averaged over polarisations at
// every event), the medulla, and the scales' steps (a tilt turns the microfacets' mean
// normal, not the surface).
//
// The light is a far-field beam from wo, spread uniformly over the fiber's projected width;
// the histogram of exit directions over the sphere, divided by the rays launched and each
// bin's solid angle, estimates f(wo, wi) with the cosine inside (docs/theory.md §2), by
// reciprocity of the reversed paths. Bins are equal in solid angle: n_u in sin θ = w.x and
// n_phi in the absolute azimuth atan2(w.z, w.y).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

namespace phys_fiber {

constexpr double kPi = 3.14159265358979323846;

enum class Interface { kRandomWalk, kSmith, kUnshadowed };

struct Fiber {
    double eta = 1.55;
    double roughness = 0.3;  // GGX α
    double tilt = 0.0;       // cuticle tilt of the microfacets' mean normal toward the tip, radians
    double aspect = 1.0;     // minor / major semi-axis
    double orientation = 0;  // major axis' angle from y toward z, radians
    glm::dvec3 sigma_a{0.0}; // absorption per unit major semi-axis
    Interface interface = Interface::kRandomWalk;
    int max_events = 4096;   // boundary interactions per ray before it is counted as lost
};

// Path classes by what happened at the boundary: R (reflected at the first interaction),
// TT (entered, left at the next), TRT (one internal reflection), higher (more).
enum Lobe { kR = 0, kTT = 1, kTRT = 2, kHigher = 3, kLobes = 4 };

// A small, fast generator (SplitMix64 seeding a xoshiro256+): the reference's own.
class Rng {
  public:
    explicit Rng(std::uint64_t seed) {
        for (auto& s : s_) {
            seed += 0x9E3779B97F4A7C15ull;
            std::uint64_t z = seed;
            z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
            z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
            s = z ^ (z >> 31);
        }
    }
    double uniform() {  // [0, 1)
        const std::uint64_t r = s_[0] + s_[3];
        const std::uint64_t t = s_[1] << 17;
        s_[2] ^= s_[0];
        s_[3] ^= s_[1];
        s_[1] ^= s_[2];
        s_[0] ^= s_[3];
        s_[2] ^= t;
        s_[3] = (s_[3] << 45) | (s_[3] >> 19);
        return double(r >> 11) * 0x1.0p-53;
    }

  private:
    std::uint64_t s_[4];
};

// ---- The Smith GGX microsurface in a local frame (z the mean normal, heights uniform) ----

// Λ of GGX for a direction w (Heitz 2014 eq. 72; negative below the surface: Λ(−w) = −1 − Λ(w)).
inline double lambda(const glm::dvec3& w, double alpha) {
    const double c = w.z;
    if (c >= 1.0) return 0.0;
    if (c <= -1.0) return -1.0;
    const double s2 = std::max(0.0, 1 - c * c);
    const double t = std::sqrt(1 + alpha * alpha * s2 / (c * c));
    return c > 0 ? 0.5 * (-1 + t) : 0.5 * (-1 - t);
}

// Smith masking of a direction above the surface, G1 = 1/(1 + Λ).
inline double smith_g1(const glm::dvec3& w, double alpha) {
    return w.z > 0 ? 1.0 / (1.0 + lambda(w, alpha)) : 0.0;
}

// A microfacet normal from GGX's visible normals seen from w, D_w(m) ∝ max(0, w·m) D(m) over
// the facets (m.z > 0), for any w, including directions below the horizon that a ray
// bouncing on the microsurface takes: in the configuration stretched to α = 1 the
// normalised sum of w and a uniform point on the unit sphere has density ∝ max(0, w·m), and
// m.z > 0 is the spherical cap c.z > −w.z (Dupuy & Benyoub 2023, "Sound and complete
// visible-normal sampling with spherical caps").
inline glm::dvec3 sample_visible_normal(const glm::dvec3& w, double alpha, double u1, double u2) {
    const glm::dvec3 v = glm::normalize(glm::dvec3(alpha * w.x, alpha * w.y, w.z));
    const double phi = 2 * kPi * u1;
    const double z = (1 - u2) * (1 + v.z) - v.z;
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    const glm::dvec3 h = glm::dvec3(r * std::cos(phi), r * std::sin(phi), z) + v;
    return glm::normalize(glm::dvec3(alpha * h.x, alpha * h.y, std::max(1e-300, h.z)));
}

// Fresnel reflectance for unpolarised light arriving from wi at the microfacet m, the
// relative index n = η_t / η_i; 1 past the critical angle.
inline double fresnel(double cos_i, double n) {
    cos_i = std::fabs(cos_i);
    const double sin_t2 = (1 - cos_i * cos_i) / (n * n);
    if (sin_t2 >= 1) return 1;
    const double cos_t = std::sqrt(1 - sin_t2);
    const double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t), rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

// The refraction of wi (pointing away from the surface, wi·m > 0) through m, n = η_t / η_i.
inline glm::dvec3 refract(const glm::dvec3& wi, const glm::dvec3& m, double n) {
    const double c = glm::dot(wi, m);
    const double ct2 = 1 - (1 - c * c) / (n * n);
    const double ct = -std::sqrt(std::max(0.0, ct2));
    return glm::normalize(m * (c / n + ct) - wi / n);
}

// The heights' distribution: uniform on [−1, 1] (the walk's result does not depend on it).
inline double c1(double h) { return std::min(1.0, std::max(0.0, 0.5 * (h + 1))); }
inline double inv_c1(double u) { return std::min(1.0, std::max(-1.0, 2 * u - 1)); }

struct Scatter {
    glm::dvec3 dir;        // the direction the ray leaves the boundary with (local frame)
    bool transmitted;      // true: it left below (through the boundary)
    double weight = 1.0;   // kSmith's masking weight; 1 otherwise
    int events = 0;        // microfacet events
};

// One microfacet event seen from wi (pointing away from the side the light is on); n the
// relative index across the surface from that side.
inline Scatter microfacet_event(const glm::dvec3& wi, bool from_above, double alpha, double n, Rng& rng) {
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const glm::dvec3 m = from_above ? sample_visible_normal(wi, alpha, u1, u2)
                                    : -sample_visible_normal(-wi, alpha, u1, u2);
    const double f = fresnel(glm::dot(wi, m), n);
    Scatter s;
    s.events = 1;
    if (rng.uniform() < f) {
        s.dir = glm::normalize(2 * glm::dot(wi, m) * m - wi);
        s.transmitted = false;
    } else {
        s.dir = refract(wi, m, n);
        s.transmitted = true;
    }
    return s;
}

// The height of the next intersection of a ray leaving height h along w (Heitz et al. 2016,
// Algorithm 2), or +∞ when it leaves the microsurface.
inline double next_height(const glm::dvec3& w, double h, double alpha, double u) {
    if (w.z > 0.9999) return HUGE_VAL;
    if (w.z < -0.9999) return inv_c1(u * c1(h));
    if (std::fabs(w.z) < 1e-4) return h;
    const double lam = lambda(w, alpha);
    if (w.z > 0) {
        const double g1 = std::pow(c1(h), lam);
        if (u > 1 - g1) return HUGE_VAL;
    }
    return inv_c1(c1(h) / std::pow(1 - u, 1 / lam));
}

// The interaction of light arriving from wi (local frame, wi.z > 0: the light is above)
// with the boundary, n = η_below / η_above.
inline Scatter interact(const glm::dvec3& wi, double alpha, double n, Interface mode, Rng& rng) {
    if (mode != Interface::kRandomWalk) {
        Scatter s = microfacet_event(wi, true, alpha, n, rng);
        if (mode == Interface::kSmith) s.weight = smith_g1(s.transmitted ? -s.dir : s.dir, alpha);
        return s;
    }
    // Heitz et al. 2016's random walk: the side flips with every refraction; below, the
    // microsurface is seen mirrored (heights and directions negated).
    glm::dvec3 w = -wi;
    double h = 1 + inv_c1(0.999);
    bool above = true;
    Scatter s;
    for (int k = 0; k < 1000; ++k) {
        const double u = rng.uniform();
        h = above ? next_height(w, h, alpha, u) : -next_height(-w, -h, alpha, u);
        if (std::isinf(h)) break;
        const double nn = above ? n : 1 / n;
        const Scatter e = microfacet_event(-w, above, alpha, nn, rng);
        ++s.events;
        w = e.dir;
        if (e.transmitted) above = !above;
    }
    s.dir = w;
    s.transmitted = !above;
    return s;
}

// One interaction of a ray travelling along dir with the fiber's boundary at a point of
// outward normal n (x the fiber's axis), from inside or outside: the local frame and the
// walk of `interact`. The returned direction is in the same frame. Empty when the ray grazes the
// macro surface (measure zero).
inline std::optional<Scatter> boundary_event(const glm::dvec3& dir, const glm::dvec3& n, bool inside, const Fiber& f, Rng& rng) {
    // The microfacets' mean normal: n tilted toward the tip by the cuticle angle.
    const glm::dvec3 m = glm::normalize(glm::dvec3(std::sin(f.tilt), std::cos(f.tilt) * n.y, std::cos(f.tilt) * n.z));
    // The local frame's z faces the side the ray arrives from.
    glm::dvec3 z = inside ? -m : m;
    if (glm::dot(-dir, z) <= 0) z = inside ? -n : n;  // the tilt turned the facets away: untilted
    if (glm::dot(-dir, z) <= 0) return std::nullopt;
    glm::dvec3 x_axis = std::fabs(z.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    x_axis = glm::normalize(x_axis - z * glm::dot(x_axis, z));
    const glm::dvec3 y_axis = glm::cross(z, x_axis);
    const glm::dvec3 wi_local(glm::dot(-dir, x_axis), glm::dot(-dir, y_axis), glm::dot(-dir, z));
    const double rel = inside ? 1 / f.eta : f.eta;
    Scatter s = interact(wi_local, f.roughness, rel, f.interface, rng);
    s.dir = s.dir.x * x_axis + s.dir.y * y_axis + s.dir.z * z;
    return s;
}

// ---- The fiber ----

// The exit directions' histogram for `Lobes` path classes.
template <int Lobes>
struct BasicHistogram {
    int n_u = 0, n_phi = 0;
    // Energy per bin, class and channel (0: lossless, 1–3: RGB with σa): [bin][class][4].
    std::vector<double> energy;
    double lost[4] = {0, 0, 0, 0};      // rays stopped by max_events or masked (kSmith), per channel
    double absorbed[4] = {0, 0, 0, 0};  // energy absorbed inside
    double lobe_energy[Lobes][4] = {};
    double rays = 0;

    BasicHistogram() = default;
    BasicHistogram(int nu, int nphi) : n_u(nu), n_phi(nphi), energy(std::size_t(nu * nphi * Lobes * 4), 0.0) {}
    double bin_solid_angle() const { return (2.0 / n_u) * (2 * kPi / n_phi); }
    int bin_of(const glm::dvec3& w) const {
        const int iu = std::min(n_u - 1, std::max(0, int((w.x + 1) * 0.5 * n_u)));
        const double phi = std::atan2(w.z, w.y);
        const int ip = std::min(n_phi - 1, std::max(0, int((phi + kPi) / (2 * kPi) * n_phi)));
        return iu * n_phi + ip;
    }
    // f averaged over a bin (1/sr), channel c, every lobe or one.
    double f(int bin, int c, int lobe = -1) const {
        double e = 0;
        for (int l = 0; l < Lobes; ++l)
            if (lobe < 0 || lobe == l) e += energy[std::size_t((bin * Lobes + l) * 4 + c)];
        return rays > 0 ? e / (rays * bin_solid_angle()) : 0.0;
    }
    void add(const BasicHistogram& o) {
        for (std::size_t i = 0; i < energy.size(); ++i) energy[i] += o.energy[i];
        for (int c = 0; c < 4; ++c) {
            lost[c] += o.lost[c];
            absorbed[c] += o.absorbed[c];
            for (int l = 0; l < Lobes; ++l) lobe_energy[l][c] += o.lobe_energy[l][c];
        }
        rays += o.rays;
    }
};
using Histogram = BasicHistogram<kLobes>;

class Tracer {
  public:
    explicit Tracer(const Fiber& f) : f_(f) {
        cp_ = std::cos(f.orientation);
        sp_ = std::sin(f.orientation);
    }

    // Traces `rays` rays from wo (fiber frame: x the axis), adding to hist.
    void trace(const glm::dvec3& wo, long long rays, std::uint64_t seed, Histogram& hist) const {
        Rng rng(seed);
        // The section frame: u the major axis, v the minor; points (pu, pv) with
        // pu² + pv²/b² = 1.
        const glm::dvec3 d = to_section(-wo);
        const glm::dvec2 d2(d.y, d.z);
        const double len2 = glm::length(d2);
        if (!(len2 > 1e-9)) return;  // along the axis: the fiber has no width
        const glm::dvec2 dn = d2 / len2, e(-dn.y, dn.x);
        const double b = f_.aspect;
        const double half_width = std::sqrt(e.x * e.x + b * b * e.y * e.y);  // support of the ellipse along e
        for (long long r = 0; r < rays; ++r) {
            hist.rays += 1;
            const double h = 2 * rng.uniform() - 1;
            const glm::dvec2 start = h * half_width * e - 4.0 * dn;
            double t_near, t_far;
            if (!intersect(start, dn, t_near, t_far)) continue;  // grazing: measure zero
            glm::dvec2 p = start + t_near * dn;
            glm::dvec3 dir = d;
            double w[4] = {1, 1, 1, 1};
            int transmissions = 0, internal_reflections = 0;
            bool inside = false, done = false;
            for (int event = 0; event < f_.max_events; ++event) {
                const std::optional<Scatter> hit = boundary_event(dir, glm::dvec3(0, normal(p)), inside, f_, rng);
                if (!hit) break;  // grazing the macro surface: stop (measure zero)
                const Scatter& s = *hit;
                const glm::dvec3 out = s.dir;
                for (int c = 0; c < 4; ++c) {
                    hist.lost[c] += w[c] * (1 - s.weight);
                    w[c] *= s.weight;
                }
                dir = out;
                const bool now_inside = s.transmitted ? !inside : inside;
                if (s.transmitted) ++transmissions;
                else if (inside) ++internal_reflections;
                if (!now_inside) {
                    // Left the fiber (a convex section: nothing is hit again).
                    const int lobe = transmissions == 0 ? kR
                                     : internal_reflections == 0 ? kTT
                                     : internal_reflections == 1 ? kTRT
                                                                 : kHigher;
                    const int bin = hist.bin_of(from_section(dir));
                    for (int c = 0; c < 4; ++c) {
                        hist.energy[std::size_t((bin * kLobes + lobe) * 4 + c)] += w[c];
                        hist.lobe_energy[lobe][c] += w[c];
                    }
                    done = true;
                    break;
                }
                inside = true;
                // The chord to the next interface; its 3D length from the in-plane one.
                const glm::dvec2 t2(dir.y, dir.z);
                const double tl = glm::length(t2);
                if (!(tl > 1e-12)) {  // along the axis inside: travels forever
                    for (int c = 0; c < 4; ++c) hist.absorbed[c] += (c == 0 ? 0 : w[c]);
                    w[1] = w[2] = w[3] = 0;
                    break;
                }
                const glm::dvec2 tn = t2 / tl;
                double a0, a1;
                if (!intersect(p, tn, a0, a1)) break;
                const double chord = std::max(0.0, a1);
                const double length3d = chord / tl;
                for (int c = 1; c < 4; ++c) {
                    const double keep = std::exp(-f_.sigma_a[c - 1] * length3d);
                    hist.absorbed[c] += w[c] * (1 - keep);
                    w[c] *= keep;
                }
                p = p + chord * tn;
                p = snap(p);
            }
            if (!done)
                for (int c = 0; c < 4; ++c) hist.lost[c] += w[c];
        }
    }

  private:
    glm::dvec3 to_section(const glm::dvec3& w) const { return {w.x, cp_ * w.y + sp_ * w.z, -sp_ * w.y + cp_ * w.z}; }
    glm::dvec3 from_section(const glm::dvec3& w) const { return {w.x, cp_ * w.y - sp_ * w.z, sp_ * w.y + cp_ * w.z}; }
    // The outward unit normal at a point of the ellipse: the gradient of u² + v²/b².
    glm::dvec2 normal(const glm::dvec2& p) const {
        const glm::dvec2 g(p.x, p.y / (f_.aspect * f_.aspect));
        return g / glm::length(g);
    }
    // Puts a point back on the ellipse (radially, in the scaled space) against drift.
    glm::dvec2 snap(const glm::dvec2& p) const {
        const double r = std::sqrt(p.x * p.x + (p.y / f_.aspect) * (p.y / f_.aspect));
        return r > 0 ? p / r : p;
    }
    // The line p + t d (d unit, in-plane) against the ellipse: both roots, t0 ≤ t1.
    bool intersect(const glm::dvec2& p, const glm::dvec2& d, double& t0, double& t1) const {
        const double ib2 = 1 / (f_.aspect * f_.aspect);
        const double A = d.x * d.x + d.y * d.y * ib2;
        const double B = 2 * (p.x * d.x + p.y * d.y * ib2);
        const double C = p.x * p.x + p.y * p.y * ib2 - 1;
        const double disc = B * B - 4 * A * C;
        if (!(disc > 0)) return false;
        const double s = std::sqrt(disc);
        const double q = B < 0 ? -0.5 * (B - s) : -0.5 * (B + s);  // stable roots
        double r0 = q / A, r1 = q != 0 ? C / q : -B / A;
        if (r0 > r1) std::swap(r0, r1);
        t0 = r0;
        t1 = r1;
        return true;
    }

    Fiber f_;
    double cp_ = 1, sp_ = 0;
};

}  // namespace phys_fiber
