// hairscatter — a ray's hit on a round fiber as the models want it: the fiber frame built
// from the tangent and wo, wo in that frame, and the offset h across the fiber.
#pragma once

#include <glm/glm.hpp>

#include "../config.hpp"
#include "frame.hpp"

namespace hairscatter {

// The offset h ∈ [-1, 1] of a hit point across a round fiber of the given radius, in the
// frame built with reference = wo (Chiang et al. 2016 §4; pbrt-v4's curve h):
//   h = dot(hit − axis, frame.y) / radius,
// where axis is any point of the fiber's axis next to the hit (the curve's centre at the
// hit's curve parameter): the component of hit − axis along the tangent is dropped by the
// dot product with y ⟂ x. Clamped to [-1, 1] (a ray-curve intersector reports points a
// rounding error outside the tube); 0 for a radius that is not positive or a non-finite
// result, so a degenerate hit shades as a centre hit instead of spreading NaN.
template <typename T>
HAIRSCATTER_HD T fiber_offset(const FiberFrame<T>& frame, const glm::vec<3, T>& hit, const glm::vec<3, T>& axis,
                              T radius) {
    if (!(radius > T(0))) return T(0);
    const T h = glm::dot(hit - axis, frame.y) / radius;
    if (!(h == h)) return T(0);  // NaN (a NaN point or an infinite radius)
    return h < T(-1) ? T(-1) : (h > T(1) ? T(1) : h);
}

// h from a curve intersector's coordinate v ∈ [0, 1] across the fiber (pbrt-v4's curves:
// h = -1 + 2v; Embree 3's normal-oriented curves report such a v, its flat curves one in
// [-1, 1]: pass (v + 1) / 2; its round and linear curves report v = 0: use fiber_offset
// with the hit point instead), given `across`,
// the world direction in which v grows at the hit (∂p/∂v, or any vector with its sign).
// Intersectors differ in which way v runs, and a v read the wrong way mirrors h; this
// takes the sign from dot(across, frame.y), so both ways give the same h. v is clamped to
// [0, 1]; a NaN v, or an `across` with no component along frame.y (or not finite), gives 0.
// Where the hit point and an axis point are known, fiber_offset needs no such care.
template <typename T>
HAIRSCATTER_HD T fiber_offset_from_v(const FiberFrame<T>& frame, T v, const glm::vec<3, T>& across) {
    if (!(v == v)) return T(0);
    const T h = T(2) * (v < T(0) ? T(0) : (v > T(1) ? T(1) : v)) - T(1);
    const T s = glm::dot(across, frame.y);
    if (!(s == s) || s == T(0)) return T(0);
    return s > T(0) ? h : -h;
}

// Everything a shading point on a fiber needs, made once per hit: the frame (x = tangent,
// wo in the x–z plane), wo in the frame, and h. The models take `wo` and `h` directly:
//   const FiberHit<float> hit(p, axis_point, tangent, -ray_dir, radius);
//   const auto fiber = ChiangFiber<float>(material, hit.h).at(hit.wo);
//   ... fiber.eval(hit.frame.to_local(to_light)), hit.frame.to_world(fiber.sample(u).wi)
template <typename T> struct FiberHit {
    using V = glm::vec<3, T>;
    FiberFrame<T> frame;
    V wo{T(0), T(0), T(1)};  // the outgoing direction in the fiber frame (unit, wo.y = 0)
    T h = T(0);

    FiberHit() = default;
    // hit: the hit point; axis: the fiber's axis point next to it; tangent: the fiber's
    // direction (root to tip, any length); wo_world: unit direction toward the viewer.
    HAIRSCATTER_HD FiberHit(const V& hit, const V& axis, const V& tangent, const V& wo_world, T radius)
        : frame(tangent, wo_world), wo(frame.to_local(wo_world)), h(fiber_offset(frame, hit, axis, radius)) {}

    // From a curve intersector's v instead of the hit point (fiber_offset_from_v: `across`
    // is the world direction in which v grows).
    static HAIRSCATTER_HD FiberHit from_v(const V& tangent, const V& wo_world, T v, const V& across) {
        FiberHit r;
        r.frame = FiberFrame<T>(tangent, wo_world);
        r.wo = r.frame.to_local(wo_world);
        r.h = fiber_offset_from_v(r.frame, v, across);
        return r;
    }
};

}  // namespace hairscatter
