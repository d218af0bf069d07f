// hairscatter — the local fiber frame (docs/theory.md §1) and world ↔ fiber conversions.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../math/elementary.hpp"
#include "../math/functions.hpp"

namespace hairscatter {

// x = fiber tangent (root to tip), y = across the fiber's width (the h axis),
// z = x × y. Build it from the world tangent and a reference direction that is not
// parallel to it — usually wo, so that wo lies in the x–z plane and the offset h of a
// hit is h = dot(hit - axis point, frame.y) / radius — or a ribbon's normal.
//
// The sign of h is the frame's: the models read h in a frame whose z lies on wo's side
// (wo.z ≥ 0; wo.z > 0 with reference = wo). A reference facing away from the viewer (a
// ribbon's back-facing normal) flips y and so mirrors h: a mirror image of the right
// answer, which no furnace test shows. FiberFrame::facing(tangent, reference, wo) flips
// such a reference first.
template <typename T> struct FiberFrame {
    using V = glm::vec<3, T>;
    V x{T(1), T(0), T(0)}, y{T(0), T(1), T(0)}, z{T(0), T(0), T(1)};

    FiberFrame() = default;
    HAIRSCATTER_HD FiberFrame(const V& tangent, const V& reference) {
        x = glm::normalize(tangent);
        V zr = reference - glm::dot(reference, x) * x;
        // A reference along the tangent leaves no azimuth to fix: any normal will do.
        if (glm::dot(zr, zr) < T(1e-12) * glm::dot(reference, reference) + T(1e-30)) {
            const V a = (x.x * x.x < T(0.5)) ? V(T(1), T(0), T(0)) : V(T(0), T(1), T(0));
            zr = a - glm::dot(a, x) * x;
        }
        z = glm::normalize(zr);
        y = glm::cross(z, x);
    }

    // The frame with z on wo's side: reference is used as is when it faces the viewer
    // (dot(reference, wo) ≥ 0) and flipped when it faces away (a ribbon's normal seen from
    // behind), so that h measured along its y has the sign the models expect.
    static HAIRSCATTER_HD FiberFrame facing(const V& tangent, const V& reference, const V& wo) {
        return FiberFrame(tangent, glm::dot(reference, wo) < T(0) ? -reference : reference);
    }

    HAIRSCATTER_HD V to_local(const V& w) const { return V(glm::dot(w, x), glm::dot(w, y), glm::dot(w, z)); }
    HAIRSCATTER_HD V to_world(const V& w) const { return w.x * x + w.y * y + w.z * z; }
};

// The unit direction with inclination sinθ = sin_theta whose azimuth is φ = phi past wo's,
// in the fiber frame: rotates wo's azimuthal direction by φ (no atan2 round trip). A wo
// along the fiber has no azimuth; φ is then measured from the y axis, as atan2(0, 0) = 0.
template <typename T>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE glm::vec<3, T> direction_from_azimuth(const glm::vec<3, T>& wo, T sin_theta, T phi) {
    using std::sqrt;
    const T cos_theta = cos_from_sin(sin_theta);
    const T len = sqrt(wo.y * wo.y + wo.z * wo.z);
    const T ay = len > T(0) ? wo.y / len : T(1), az = len > T(0) ? wo.z / len : T(0);
    T s, c;
    elem::sincos(phi, s, c);
    return glm::vec<3, T>(sin_theta, cos_theta * (ay * c - az * s), cos_theta * (ay * s + az * c));
}

// The relative azimuth φ = φi - φo ∈ [-π, π] of two fiber-frame directions, from one atan2
// of the azimuthal cross and dot products (no wrap needed). A wo along the fiber has no
// azimuth: φ is then wi's own, from the y axis, as direction_from_azimuth measures it (so
// that pdf(wo, wi) is the density sample() draws from; with atan2(0, 0) = 0 it was the
// density at φ = 0 for every wi).
template <typename T> HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T relative_azimuth(const glm::vec<3, T>& wo, const glm::vec<3, T>& wi) {
    const bool on_axis = wo.y == T(0) && wo.z == T(0);
    const T oy = on_axis ? T(1) : wo.y, oz = wo.z;
    return elem::atan2(oy * wi.z - oz * wi.y, oy * wi.y + oz * wi.z);
}

// The azimuth that a query of wi = direction_from_azimuth(wo, sinθ, φ) reads back: φ itself
// (to rounding), except exactly at a pole (cosθ = 0), where wi has no azimuth and
// relative_azimuth's convention decides, and at |φ| = π as rounded (u at 0 or 1), which is
// past π: wi's azimuth then wraps to the float below π, a step a table's interpolation can
// see at a narrow lobe. A sampler evaluates its sample at this φ, so that the sample's pdf
// and weight are pdf(wo, wi) and eval / pdf there (before, at θi = ±90° a sample carried the
// density of the φ it drew while pdf(wo, wi) read another). In float cosθ is 0 or ≥ 3.4e-4
// (cos_from_sin of the largest float below 1): only those two edges take the second branch.
template <typename T>
HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE T queried_azimuth(const glm::vec<3, T>& wo, const glm::vec<3, T>& wi, T cos_theta, T phi) {
    return cos_theta > T(0) && phi < kPi<T> && phi > -kPi<T> ? phi : relative_azimuth(wo, wi);
}

}  // namespace hairscatter
