// render — procedural hair: a block of straight or wavy strands, and a scalp with gravity
// and curl. Strands are polylines; all fibers share one radius.
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

}  // namespace render
