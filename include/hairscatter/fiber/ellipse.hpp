// hairscatter — the elliptical cross-section of a fiber (Huang et al. 2022's shape):
// semi-axes 1 (major) and b ≤ 1 (minor), the major axis turned by ψ about the fiber axis.
// Everything is done through the affine map A = diag(1, b) from the unit circle, which
// keeps the far-field geometry exact and cheap:
//   a point p = A c (c on the unit circle) has the outward normal n ∝ A⁻¹ c;
//   seen from the in-plane direction d, the visible half is c·d' > 0 with d' ∝ A⁻¹ d, and
//   the offset across the projected width is c·e' (e' ⟂ d'), because A e ⟂ A⁻¹ d for e ⟂ d:
//   a far-field ray at offset h ∈ (-1, 1) hits c = h e' + sqrt(1 - h²) d', whatever b is;
//   a chord from p along the in-plane t leaves at the circle point c + s A⁻¹ t, s > 0 the
//   root of |c + s A⁻¹ t|² = 1, after the distance s per unit of |t|.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"

namespace hairscatter {

template <typename T> class EllipticalSection {
  public:
    using V2 = glm::vec<2, T>;
    using V3 = glm::vec<3, T>;

    EllipticalSection() = default;
    // b: the minor semi-axis over the major, (0, 1]; psi: the major axis' angle from the fiber
    // frame's y axis toward z, radians.
    HAIRSCATTER_HD EllipticalSection(T b, T psi) : b_(b), inv_b_(T(1) / b) { elem::sincos(psi, sin_psi_, cos_psi_); }

    HAIRSCATTER_HD T aspect() const { return b_; }
    HAIRSCATTER_HD T inv_aspect() const { return inv_b_; }  // 1 / b, as the section's formulas use it

    // Fiber frame (x axis, y, z) ↔ section frame (x axis, major u, minor v): a rotation about x.
    HAIRSCATTER_HD V3 to_section(const V3& w) const {
        return V3(w.x, cos_psi_ * w.y + sin_psi_ * w.z, -sin_psi_ * w.y + cos_psi_ * w.z);
    }
    HAIRSCATTER_HD V3 from_section(const V3& w) const {
        return V3(w.x, cos_psi_ * w.y - sin_psi_ * w.z, sin_psi_ * w.y + cos_psi_ * w.z);
    }

    // The far-field view from the section-frame direction w: d' and e' in circle space. A w
    // along the fiber axis has no in-plane part: the fiber frame's y axis stands in (the
    // convention of relative_azimuth, fiber/frame.hpp).
    struct View {
        V2 d, e;
    };
    HAIRSCATTER_HD View view(const V3& w) const {
        using std::sqrt;
        V2 dir(w.y, w.z);
        if (!(glm::dot(dir, dir) > T(0))) dir = V2(cos_psi_, -sin_psi_);
        V2 d(dir.x, dir.y * inv_b_);
        d /= sqrt(glm::dot(d, d));
        return {d, V2(-d.y, d.x)};
    }

    // The circle point hit at offset h = sin γ (cos_gamma = cos γ ≥ 0).
    HAIRSCATTER_HD static V2 hit(const View& view, T h, T cos_gamma) { return h * view.e + cos_gamma * view.d; }

    // |A⁻¹ c| and the unit outward normal at the circle point c.
    HAIRSCATTER_HD T normal_scale(const V2& c) const {
        using std::sqrt;
        return sqrt(c.x * c.x + sqr(c.y * inv_b_));
    }
    HAIRSCATTER_HD V2 normal(const V2& c) const { return V2(c.x, c.y * inv_b_) / normal_scale(c); }

    // The chord from the circle point c along the in-plane part t2 of a unit 3D direction:
    // the exit circle point and the 3D path length (s, in units of the major semi-axis).
    // ok is false when the ray does not run into the section (t2 along the axis, or
    // pointing out of it: s ≤ 0).
    struct Chord {
        V2 c;
        T length;
        bool ok;
    };
    HAIRSCATTER_HD Chord chord(const V2& c, const V2& t2) const {
        using std::sqrt;
        const V2 dc(t2.x, t2.y * inv_b_);
        const T dd = glm::dot(dc, dc);
        if (!(dd > T(1e-12))) return {c, T(0), false};
        const T s = T(-2) * glm::dot(c, dc) / dd;
        if (!(s > T(0))) return {c, T(0), false};
        V2 exit = c + s * dc;
        exit /= sqrt(glm::dot(exit, exit));  // back onto the circle after rounding
        return {exit, s, true};
    }

  private:
    T b_ = T(1), inv_b_ = T(1), sin_psi_ = T(0), cos_psi_ = T(1);
};

}  // namespace hairscatter
