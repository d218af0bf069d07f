// hairscatter — the GGX (Trowbridge–Reitz) microfacet distribution about a normal m and what
// a rough dielectric interface does with it: the visible-normal density and its sampler,
// reflection and refraction through one microfacet, and the densities of the reflected and
// refracted directions (Walter et al. 2007; Heitz 2014; Dupuy & Benyoub 2023). The Huang
// et al. 2022 fiber (models/huang.hpp) is built from these; they know nothing of fibers.
//
// Directions are unit vectors pointing away from the interface: v on the side the light
// comes from (v·m > 0), o the scattered direction.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../math/constants.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"
#include "attenuation.hpp"

namespace hairscatter {

// Unpolarised Fresnel reflectance at cos_i for the relative index n = η_t / η_i, either side
// of 1: total internal reflection (n < 1 past the critical angle) reflects everything.
// Written with s = n cos_t = sqrt(n² − sin²θi): r_s = (cos_i − s) / (cos_i + s) and
// r_p = (n² cos_i − s) / (n² cos_i + s), one square root and two divisions (the textbook
// form's cos_t = sqrt(1 − sin²θi / n²) takes a third); the same values up to rounding.
template <typename T> HAIRSCATTER_HD T fresnel_any(T cos_i, T n) {
    using std::sqrt;
    cos_i = clamp(cos_i, T(0), T(1));
    const T n2 = n * n, sin2_i = (T(1) - cos_i) * (T(1) + cos_i);
    // Total internal reflection, compared without dividing (n = 0 reflects, not NaN).
    if (sin2_i >= n2) return T(1);
    const T s = sqrt(n2 - sin2_i), n2c = n2 * cos_i;
    // cos_i = 0 with n > 1: both ratios are −1 (grazing reflects), no 0/0 since s > 0.
    return T(0.5) * (sqr((cos_i - s) / (cos_i + s)) + sqr((n2c - s) / (n2c + s)));
}

// An orthonormal basis (s, t, n) around a unit n with s along the part of `toward` that is
// orthogonal to n (any s when there is none): the deterministic normal nodes of the Huang
// fiber are then placed symmetrically about the plane of incidence.
template <typename T> struct TangentFrame {
    using V3 = glm::vec<3, T>;
    V3 s, t, n;

    HAIRSCATTER_HD TangentFrame(const V3& normal, const V3& toward) : n(normal) {
        using std::sqrt;
        V3 p = toward - glm::dot(toward, n) * n;
        T len2 = glm::dot(p, p);
        if (!(len2 > T(1e-12))) {
            // Duff et al. 2017's branch-free basis when `toward` is (anti)parallel to n.
            const T sign = n.z >= T(0) ? T(1) : T(-1);
            const T a = T(-1) / (sign + n.z), b = n.x * n.y * a;
            p = V3(T(1) + sign * n.x * n.x * a, sign * b, -sign * n.x);
            len2 = glm::dot(p, p);
        }
        s = p / sqrt(len2);
        t = glm::cross(n, s);
    }
    HAIRSCATTER_HD V3 to_local(const V3& w) const { return V3(glm::dot(w, s), glm::dot(w, t), glm::dot(w, n)); }
    HAIRSCATTER_HD V3 to_world(const V3& w) const { return w.x * s + w.y * t + w.z * n; }
};

// The GGX distribution of roughness α (Walter et al. 2007 eq. 33), about the normal m:
//   D(h) = α² / (π ((h·m)² (α² - 1) + 1)²)        for h·m > 0.
// Visible normals from v (Heitz 2014 eq. 2), with the Smith G1 of GGX folded in:
//   D_v(h) = G1(v) max(0, v·h) D(h) / (v·m) = 2 (v·h) D(h) / (v·m + sqrt(α² + (1 - α²)(v·m)²)).
// D_v integrates to 1 over the hemisphere of m for every v above it.
template <typename T> class Ggx {
  public:
    using V3 = glm::vec<3, T>;

    Ggx() = default;
    HAIRSCATTER_HD explicit Ggx(T alpha) : a_(alpha), a2_(alpha * alpha) {}

    HAIRSCATTER_HD T alpha() const { return a_; }

    // D at cos θh = h·m; 0 below the surface. (1 - c²) as (1 - c)(1 + c): the peak of a
    // smooth lobe sits where c² rounds to 1.
    HAIRSCATTER_HD T d(T cos_h) const {
        if (!(cos_h > T(0))) return T(0);
        const T c2 = cos_h * cos_h;
        return a2_ * kInvPi<T> / sqr((T(1) - cos_h) * (T(1) + cos_h) + a2_ * c2);
    }

    // 1 / (v·m + sqrt(α² + (1 - α²)(v·m)²)): the factor D_v carries for v.
    HAIRSCATTER_HD T visible_scale(T cos_v) const {
        using std::sqrt;
        return T(1) / (cos_v + sqrt(a2_ * (T(1) - cos_v) * (T(1) + cos_v) + cos_v * cos_v));
    }

    // Smith's G1 = 1 / (1 + Λ) at cos = w·m > 0: 2 cos · visible_scale(cos) (Heitz 2014
    // eq. 86); 0 at or below the surface (and for NaN), cosines above 1 read as 1.
    HAIRSCATTER_HD T g1(T cos_w) const {
        if (!(cos_w > T(0))) return T(0);
        const T c = cos_w < T(1) ? cos_w : T(1);
        return T(2) * c * visible_scale(c);
    }
    // Smith's Λ of GGX at cos = w·m > 0: (√(1 + α² tan²θ) − 1)/2 (Heitz 2014 eq. 72); 1e30
    // at or below the surface (and for NaN), where nothing escapes (finite in float).
    HAIRSCATTER_HD T lambda(T cos_w) const {
        using std::sqrt;
        if (!(cos_w > T(1e-30))) return T(1e30);
        const T c = cos_w < T(1) ? cos_w : T(1);
        return T(0.5) * (sqrt(a2_ * (T(1) - c) * (T(1) + c) + c * c) / c - T(1));
    }
    // The share of light scattered from v toward o that no microfacet shadows on its way out,
    // given v's G1 and o·m: for reflection (o on v's side) the height-correlated
    // G2 / G1(v) = 1 / (1 + Λ(o) G1(v)) (Heitz 2014 eq. 99); 0 where o is behind the surface.
    HAIRSCATTER_HD T unshadowed_reflection(T g1_v, T cos_o) const {
        return cos_o > T(0) ? T(1) / (T(1) + lambda(cos_o) * g1_v) : T(0);
    }

    // D_v(h) of the visible normals from v, given v·m (> 0), v·h and h·m.
    HAIRSCATTER_HD T visible(T cos_v, T v_dot_h, T cos_h) const {
        if (!(v_dot_h > T(0))) return T(0);
        return T(2) * v_dot_h * d(cos_h) * visible_scale(cos_v);
    }

    // A normal drawn from D_v, in the frame where m = (0, 0, 1) and v.z > 0: Dupuy & Benyoub
    // 2023's spherical cap. v is stretched to the α = 1 configuration, where visible normals
    // are a uniform point on the unit sphere's cap z ≥ -v.z offset by v; u1 the cap's
    // azimuth, u2 its height.
    HAIRSCATTER_HD V3 sample_visible_local(const V3& v, T u1, T u2) const {
        T s, c;
        elem::sincos(kTwoPi<T> * u1, s, c);
        return sample_visible_local(v, c, s, u2);
    }
    // The same with the cap's azimuth given by its cosine and sine (fixed nodes precompute them).
    HAIRSCATTER_HD V3 sample_visible_local(const V3& v, T cos_phi, T sin_phi, T u2) const {
        return sample_visible_stretched(stretch(v), cos_phi, sin_phi, u2);
    }
    // v stretched to the α = 1 configuration, and the sampler from it: several normals
    // drawn for one v stretch it once.
    HAIRSCATTER_HD V3 stretch(const V3& v) const { return glm::normalize(V3(a_ * v.x, a_ * v.y, v.z)); }
    HAIRSCATTER_HD V3 sample_visible_stretched(const V3& vs, T cos_phi, T sin_phi, T u2) const {
        const T z = (T(1) - u2) * (T(1) + vs.z) - vs.z;
        const T sin_theta = cos_from_sin(clamp(z, T(-1), T(1)));
        const V3 hs = V3(sin_theta * cos_phi, sin_theta * sin_phi, z) + vs;
        const V3 h(a_ * hs.x, a_ * hs.y, hs.z);
        const T len2 = glm::dot(h, h);
        // The cap's rim point opposite vs (u2 = 1) gives h = 0: a grazing normal, measure zero.
        using std::sqrt;
        return len2 > T(1e-30) ? h / sqrt(len2) : V3(T(0), T(0), T(1));
    }

  private:
    T a_ = T(1), a2_ = T(1);
};

// Mirror reflection of v about the microfacet normal h.
template <typename T> HAIRSCATTER_HD glm::vec<3, T> reflect_about(const glm::vec<3, T>& v, const glm::vec<3, T>& h) {
    return (T(2) * glm::dot(v, h)) * h - v;
}

// The direction v refracts into through the microfacet h (v·h > 0), for the relative index
// eta = η_i / η_t (incident over transmitted): Snell's law in vector form. `ok` is false on
// total internal reflection.
template <typename T> struct Refracted {
    glm::vec<3, T> o;
    bool ok;
};
template <typename T>
HAIRSCATTER_HD Refracted<T> refract_through(const glm::vec<3, T>& v, const glm::vec<3, T>& h, T eta) {
    const T cos_i = glm::dot(v, h);
    const T sin2_t = eta * eta * (T(1) - cos_i) * (T(1) + cos_i);
    if (!(sin2_t < T(1))) return {glm::vec<3, T>(T(0)), false};
    const T cos_t = safe_sqrt(T(1) - sin2_t);
    return {(eta * cos_i - cos_t) * h - eta * v, true};
}

// The microfacet lobes of one interface about the normal m, from v, as densities of the
// scattered direction o in solid angle (each equal to D_v(h) times the Jacobian dω_h/dω_o).
template <typename T> struct InterfaceLobes {
    using V3 = glm::vec<3, T>;
    const Ggx<T>* ggx;
    V3 v, m;
    T cos_v;  // v·m > 0

    // Reflection, h = (v + o)/|v + o|, dω_h/dω_o = 1/(4 v·h) (Walter et al. 2007 eq. 14):
    // q = D_v(h)/(4 v·h) = D(h) visible_scale / 2. Also returns v·h (0 where o is not a
    // reflection of v about a visible normal).
    struct Value {
        T q, v_dot_h;
    };
    HAIRSCATTER_HD Value reflection(const V3& o) const {
        const V3 sum = v + o;
        const T len2 = glm::dot(sum, sum);
        if (!(len2 > T(1e-20))) return {T(0), T(0)};
        using std::sqrt;
        const V3 h = sum / sqrt(len2);
        const T cos_h = glm::dot(h, m);
        if (!(cos_h > T(0))) return {T(0), T(0)};
        return {T(0.5) * ggx->d(cos_h) * ggx->visible_scale(cos_v), glm::dot(v, h)};
    }

    // Refraction from the side of index η_i into η_t, eta = η_i / η_t > 1 (leaving the
    // denser medium: the exits of a fiber): h = (eta v + o)/|eta v + o| — on v's side of
    // the microfacet since v·(eta v + o) ≥ eta - 1 > 0 — with o·h < 0, and
    // dω_h/dω_o = |o·h| / |eta v + o|² (Walter et al. 2007 eq. 17, η_t = 1 units).
    // Every such h refracts (its tangential part satisfies Snell's law), so v·h never
    // exceeds the critical angle.
    HAIRSCATTER_HD Value refraction(const V3& o, T eta) const {
        const V3 sum = eta * v + o;
        const T len2 = glm::dot(sum, sum);
        if (!(len2 > T(1e-20))) return {T(0), T(0)};
        using std::sqrt;
        const T inv_len = T(1) / sqrt(len2);
        const V3 h = sum * inv_len;
        const T cos_h = glm::dot(h, m), o_dot_h = glm::dot(o, h);
        if (!(cos_h > T(0) && o_dot_h < T(0))) return {T(0), T(0)};
        const T v_dot_h = glm::dot(v, h);
        return {ggx->visible(cos_v, v_dot_h, cos_h) * (-o_dot_h) * inv_len * inv_len, v_dot_h};
    }

    // The sampler of the refracted lobe leaving the denser side (eta > 1): a visible normal
    // from (u1, u2); refract through it, or reflect where it totally reflects. Its density
    // is exit_density(o, eta), which integrates to 1.
    HAIRSCATTER_HD V3 sample_exit(T eta, T u1, T u2) const {
        const TangentFrame<T> f(m, v);
        const V3 h = f.to_world(ggx->sample_visible_local(f.to_local(v), u1, u2));
        const Refracted<T> r = refract_through(v, h, eta);
        return glm::normalize(r.ok ? r.o : reflect_about(v, h));
    }
    // The reflection density of o through the normals sample_exit reflects at (past the
    // critical angle): exit_density = refraction(o, eta).q + total_reflection(o, eta).
    HAIRSCATTER_HD T total_reflection(const V3& o, T eta) const {
        const Value r = reflection(o);
        return r.q > T(0) && eta * eta * (T(1) - r.v_dot_h) * (T(1) + r.v_dot_h) >= T(1) ? r.q : T(0);
    }
    HAIRSCATTER_HD T exit_density(const V3& o, T eta) const { return refraction(o, eta).q + total_reflection(o, eta); }

    // The reflection sampler: a visible normal, and v mirrored about it; density reflection(o).q.
    HAIRSCATTER_HD V3 sample_reflection(T u1, T u2) const {
        const TangentFrame<T> f(m, v);
        const V3 h = f.to_world(ggx->sample_visible_local(f.to_local(v), u1, u2));
        return glm::normalize(reflect_about(v, h));
    }
};

}  // namespace hairscatter
