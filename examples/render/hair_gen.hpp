// render — procedural hair: a block of straight or wavy strands, a scalp with gravity and
// curl, a fur ball and a slab of parallel strands. Strands are polylines; all fibers share
// one radius.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace render {

struct Hair {
    std::vector<std::vector<glm::vec3>> strands;  // polylines, root first
    float radius = 0.01f;                         // fiber radius (scene units)

    std::size_t point_count() const;
    std::size_t segment_count() const;
};

// A block of `count` strands running along +x through the box [-size/2, size/2] ×
// [0, size] × [-size/2, size/2] (standing on y = 0), roots jittered on a grid over the
// x = -size/2 face. wave_amplitude > 0 makes each strand a helix-like wave of that
// amplitude (in scene units) and wavelength `wavelength` with a random phase.
struct BlockOptions {
    int count = 1500;
    float size = 5.0f;
    float radius = 0.01f;
    int segments = 24;
    float wave_amplitude = 0.0f;
    float wavelength = 1.5f;
    std::uint64_t seed = 7;
};
Hair make_block(const BlockOptions& options);

// `count` strands rooted on the upper part of a head sphere (centre `center`, radius
// head_radius): each grows along the scalp normal, is pulled down by `gravity` (bend per
// unit length) and kept outside the head, and curls around its growth direction with
// radius curl_radius and `curl_turns` turns per unit length.
struct ScalpOptions {
    int count = 10000;
    glm::vec3 center{0.0f, 0.0f, 0.0f};
    float head_radius = 1.0f;
    float length = 2.0f;
    float radius = 0.004f;
    int segments = 32;
    float gravity = 1.5f;
    float curl_radius = 0.0f;
    float curl_turns = 3.0f;
    std::uint64_t seed = 11;
};
Hair make_scalp(const ScalpOptions& options);

// A fur ball: `count` short strands rooted area-uniformly over a sphere (centre `center`,
// radius body_radius). Each leaves along the surface normal tilted by tilt_deg (± a
// uniform tilt_jitter_deg, clamped below 90°) toward `comb` projected on the surface (a
// random tangent where the comb is normal to the surface; the heading is jittered by the
// same amount), has a length of `length` times a uniform factor in [1 - length_variation,
// 1 + length_variation] and is bent by `gravity` (per unit length) toward -y, never
// entering the sphere: every point after the root is at least body_radius + radius from
// the centre.
struct FurOptions {
    int count = 20000;
    glm::vec3 center{0.0f, 0.0f, 0.0f};
    float body_radius = 1.5f;
    float length = 0.6f;
    float length_variation = 0.3f;
    float tilt_deg = 30.0f;
    float tilt_jitter_deg = 10.0f;
    glm::vec3 comb{0.0f, -1.0f, 0.0f};
    float radius = 0.004f;
    int segments = 8;
    float gravity = 0.5f;
    bool body = true;  // the scene's diffuse body sphere; without it, a shell of strands
    std::uint64_t seed = 13;
};
Hair make_fur(const FurOptions& options);

// An ellipsoid, the bust's building block: the head, the neck and the shoulders are each
// one, and strands are kept outside all of them.
struct Ellipsoid {
    glm::vec3 center{0.0f}, radii{1.0f};
    // p pushed out along the ellipsoid's radial direction to `margin` (in scene units,
    // approximately: the radii grow by it) outside, or p itself when already outside.
    glm::vec3 push_out(const glm::vec3& p, float margin) const;
};

// The showcase bust facing +z: a head (radius 1, centre `center`), a neck and shoulders.
// Its strands root area-uniformly on the scalp above a hairline (low at the nape, at the
// brow in front), grow away from a side parting at x = center.x + parting (in front of the
// crown) or away from the crown (behind it), then follow the head and fall under
// `gravity` (bend per unit length) onto the shoulders, kept outside every ellipsoid.
// `clump` in [0, 1] pulls each strand toward its clump's guide strand (1: tips meet);
// `frizz` ≥ 0 adds a random walk of that size per unit length, growing toward the tips.
struct HeadOptions {
    int count = 30000;
    glm::vec3 center{0.0f, 4.0f, 0.0f};
    float length = 3.2f;
    float length_variation = 0.1f;
    float radius = 0.003f;
    int segments = 40;
    float gravity = 1.5f;
    float parting = 0.3f;
    float clump = 0.4f;
    int clumps = 400;
    float frizz = 0.02f;
    std::uint64_t seed = 19;

    // The bust's ellipsoids: head, neck, shoulders (in that order).
    std::vector<Ellipsoid> body() const;
};
Hair make_head(const HeadOptions& options);

// A slab of straight strands along +x, filling x in [-width/2, width/2], y in [0, height],
// z in [-thickness/2, thickness/2] (strand axes; fibers reach out by their radius). The
// count is set by `depth`, the mean number of fibers a ray along z crosses: a ray crosses
// the strands whose axis lies within `radius` of it in the y–z cross-section, so
// count = depth · height / (2 radius) strands with axes uniform in the cross-section. By
// default no two fibers overlap (each axis is drawn again until it lies at least a diameter
// from every other: random sequential addition), as real fibers lie; the section they cover,
// depth · π · radius / (2 thickness), must then stay below kSlabMaxPacking. With `overlap`
// the axes are independent (per ray a binomial, nearly Poisson, count) and fibers may
// interpenetrate, which no real hair does. With `vertical` the strands run along +y through
// the same box (count = depth · width / (2 radius)): the scene's front light, above the
// camera, then lies along the fibers instead of across them. back_lit is the scene's.
struct SlabOptions {
    float width = 5.0f;
    float height = 5.0f;
    float thickness = 0.5f;
    float depth = 5.0f;
    float radius = 0.01f;
    int segments = 10;  // straight, but short segments keep Embree's boxes tight
    bool back_lit = false;  // the scene's area light behind the slab instead of in front
    bool overlap = false;   // independent axes: fibers may interpenetrate
    bool vertical = false;  // fibers along +y (the box unchanged) instead of along +x
    std::uint64_t seed = 17;

    int strand_count() const;
    // The share of the slab's y–z section its fibers cover: depth · π · radius / (2 thickness).
    double packing() const;
};
// The densest slab placed without overlap: random sequential addition of discs jams at
// about 0.547 of the plane, and slows down well before it.
inline constexpr double kSlabMaxPacking = 0.45;
Hair make_slab(const SlabOptions& options);

}  // namespace render
