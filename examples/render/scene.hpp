// render — scene description (what the user builds: camera, diffuse surfaces, hair,
// lights) and the built Scene: geometry only (Embree BVHs over the hair and the meshes).
// How the hair scatters light (the fiber model, its material, the dual-scattering tables
// and the density grid) is the ShadingSetup's (shading.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include "hair_gen.hpp"

namespace render {

class Environment;  // environment.hpp

struct Camera {
    glm::vec3 eye{0, 2.5f, 14}, target{0, 2.5f, 0}, up{0, 1, 0};
    float fov_y_deg = 35.0f;  // vertical field of view
};

// Throws std::invalid_argument naming the options (--eye, --look-at, --up, --fov) when
// the camera has no view: a non-finite vector, the eye on the target, an up vector of
// zero length or along the view direction, a field of view outside [1, 170] degrees.
void validate(const Camera& camera);

// A triangle mesh with one Lambertian albedo (or, for the area light, an emitter).
// normals, when given, are per vertex (smooth shading, e.g. the sphere).
struct Mesh {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
    std::vector<glm::vec3> normals;
    glm::vec3 albedo{0.5f};
};

// A one-sided rectangle emitting `radiance` toward the side of cross(edge_u, edge_v).
struct AreaLight {
    glm::vec3 corner{-1, 9, -1}, edge_u{2, 0, 0}, edge_v{0, 0, 2};
    glm::vec3 radiance{10.0f};
    glm::vec3 normal() const { return glm::normalize(glm::cross(edge_u, edge_v)); }
    float area() const { return glm::length(glm::cross(edge_u, edge_v)); }
};

struct SceneDescription {
    std::string name;
    Camera camera;
    std::vector<Mesh> meshes;
    Hair hair;
    std::optional<AreaLight> light;
    glm::vec3 environment{0.0f};  // constant radiance of every direction that escapes
    // When set, the radiance of the directions that escape instead of `environment`.
    std::shared_ptr<const Environment> environment_map;
};

// Sizes of what the Scene holds, for memory studies.
struct SceneStats {
    std::size_t strands = 0, hair_segments = 0, triangles = 0;
    std::size_t embree_bytes = 0;  // peak bytes Embree allocated (BVHs and buffers)
    double bvh_seconds = 0;
};

// What a ray hit.
struct Hit {
    enum Kind { kMiss, kHair, kSurface, kLight } kind = kMiss;
    float t = 0;
    glm::vec3 p{0};
    // hair: the segment's axis point at the hit's curve parameter, its tangent (root to
    // tip) and radius; the shading point (shading.hpp) turns them into the frame and h.
    glm::vec3 axis{0}, tangent{0};
    float radius = 0;
    std::uint32_t strand = 0;
    // surface and light
    glm::vec3 n{0};  // shading normal, facing the ray's origin side
    bool front = true;  // for the light: hit on its emitting side
    glm::vec3 albedo{0};
};

inline constexpr std::uint32_t kNoStrand = 0xffffffffu;

class Scene {
  public:
    // Builds the BVHs; throws std::invalid_argument for bad geometry (a mesh index out of
    // range, a zero-area light, a non-positive hair radius).
    explicit Scene(SceneDescription description);
    ~Scene();
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    const SceneDescription& description() const { return d_; }
    const SceneStats& stats() const { return stats_; }
    bool has_hair() const { return !strand_of_segment_.empty(); }  // O(1): asked per shadow ray

    // The closest hit along o + t d, t in (tmin, tmax); hits on strand `ignore` closer than
    // a few fiber radii are skipped (the fiber a path leaves, whose own passage the BCSDF
    // already accounts for).
    Hit intersect(const glm::vec3& o, const glm::vec3& d, float tmax, std::uint32_t ignore = kNoStrand) const;
    // Whether anything (hair, surfaces or the light) blocks o + t d for t < tmax.
    bool occluded(const glm::vec3& o, const glm::vec3& d, float tmax, std::uint32_t ignore = kNoStrand) const;
    // Only the surfaces and the light (no hair): the first such hit.
    Hit intersect_opaque(const glm::vec3& o, const glm::vec3& d, float tmax) const;
    // Only hair.
    bool hair_occluded(const glm::vec3& o, const glm::vec3& d, float tmax, std::uint32_t ignore = kNoStrand) const;
    // The number of distinct hair strands whose fibre the segment o + t d, t in (0, tmax),
    // passes through (enters or leaves: a segment wholly inside a fibre does not count it),
    // each strand counted once however many of its curve segments report a hit. Strand
    // `ignore` is skipped by the rule of intersect: its hits closer than a few fibre radii.
    // Hair only: surfaces and the light are not seen. count_hair(...) > 0 exactly when
    // hair_occluded(...) with the same arguments. Costs a traversal to tmax (about 5
    // hair_occluded calls through hair 10 fibres deep). With a limit, the count's minimum
    // with it, and the traversal stops once that many are found (limits above 64 are
    // counted in full).
    std::uint32_t count_hair(const glm::vec3& o, const glm::vec3& d, float tmax, std::uint32_t ignore = kNoStrand,
                             std::uint32_t limit = 0xffffffffu, float* last_t = nullptr) const;

  private:
    Hit hit_from(const RTCRayHit& rh, const glm::vec3& o, const glm::vec3& d) const;

    SceneDescription d_;
    SceneStats stats_;
    RTCDevice device_ = nullptr;
    RTCScene all_ = nullptr, opaque_ = nullptr, hair_ = nullptr;
    unsigned hair_geom_ = RTC_INVALID_GEOMETRY_ID, light_geom_ = RTC_INVALID_GEOMETRY_ID;
    std::vector<unsigned> mesh_of_geom_;            // geomID → mesh index (or -1)
    std::vector<std::uint32_t> strand_of_segment_;  // hair primID → strand
    std::vector<std::uint32_t> segment_start_;      // hair primID → first vertex
    std::vector<glm::vec4> curve_vertices_;         // (x, y, z, radius), kept for shading
};

}  // namespace render
