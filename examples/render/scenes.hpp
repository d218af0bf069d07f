// render — the study's scenes (hair blocks on a ground plane, the Cornell box), a scalp, a
// fur ball and a slab of parallel strands, as SceneDescriptions.
#pragma once

#include <memory>
#include <string>

#include "environment.hpp"
#include "scene.hpp"

namespace render {

// Lighting shared by the presets: a small area light above and in front, and a constant
// environment (sky) radiance.
struct LightingOptions {
    float light_size = 2.0f;       // side of the square area light
    float light_power = 1.0f;      // multiplies the preset's light radiance; 0 removes it
    float environment = 0.15f;     // constant environment radiance (grey); 0 for none
    // --env: "constant" (the radiance above), "studio" (make_studio_map) or an OpenEXR
    // lat-long file; rotated about +y and scaled by env_intensity (the constant too).
    std::string env = "constant";
    float env_rotate_deg = 0.0f;
    float env_intensity = 1.0f;
};

// Throw std::invalid_argument naming the bad option by its command-line flag and its range
// (light size, power and environment; gravity, curl; counts, sizes and radii).
void validate(const LightingOptions& lighting);

// The environment map --env asks for (read or made once, before the scene is built); null
// for "constant". Throws std::invalid_argument naming --env and the file.
std::shared_ptr<const Environment> load_environment(const LightingOptions& lighting);
void validate(const BlockOptions& block);
void validate(const ScalpOptions& scalp);
// Fur: --fur-hairs, --fur-length, --fur-tilt (degrees in [0, 90)), --fiber-radius.
void validate(const FurOptions& fur);
// Slab: --slab-depth, --fiber-radius; with back_lit, --light-size: the back light must
// stay hidden behind the slab from the camera.
void validate(const SlabOptions& slab, const LightingOptions& lighting);

// The 5 × 5 × 5 hair block standing on a grey ground plane.
SceneDescription make_block_scene(const BlockOptions& block, const LightingOptions& lighting);

// The Cornell box: red left wall, green right wall, grey back, front (behind the camera),
// floor and ceiling; the hair block on the floor, a red diffuse sphere next to it, and the
// area light under the ceiling. The environment is not visible inside the closed box.
SceneDescription make_cornell_scene(const BlockOptions& block, const LightingOptions& lighting);

// A head (a skin-coloured diffuse sphere) with scalp hair, on the ground plane.
SceneDescription make_scalp_scene(const ScalpOptions& scalp, const LightingOptions& lighting);

// The showcase: a bust (head, neck and shoulders: HeadOptions::body) with long hair
// parted on the side, no ground, framed from the front right at head height. Lit by
// whatever `lighting` says (main gives it the studio environment and no area light unless
// asked otherwise); an area light, when there is one, is the scalp scene's key.
SceneDescription make_head_scene(const HeadOptions& head, const LightingOptions& lighting);
// --head-hairs, --hair-length, --clump, --frizz, --fiber-radius.
void validate(const HeadOptions& head);

// A fur ball (FurOptions::body: on a diffuse body sphere of albedo 0.4, or an empty shell
// of strands) floating above the ground plane, framed by the camera.
SceneDescription make_fur_scene(const FurOptions& fur, const LightingOptions& lighting);

// The slab (make_slab) standing vertically with its normal along z toward the camera, no
// ground plane. Front-lit by the usual light above and in front, or with slab.back_lit by
// a square light (side lighting.light_size) at z = -3 behind the slab's centre, facing it
// and the camera: the camera sees the light only through the gaps between fibers.
SceneDescription make_slab_scene(const SlabOptions& slab, const LightingOptions& lighting);

// The thinnest fiber the scenes accept: positions in a 5-unit scene resolve about 3e-7.
inline constexpr float kMinFiberRadius = 1e-6f;

// The back light's distance behind the slab's mid-plane.
inline constexpr float kSlabBackLightDistance = 3.0f;

// Removes the mesh named "ground" (block, scalp, fur, file); the others have none.
void remove_ground(SceneDescription& scene);

// Hair from a .hair file (thickness: the mean of the file's, times thickness_scale),
// scaled uniformly to fit a 5-unit box standing on the ground plane. Throws
// std::invalid_argument when the file has no hair (no strand with a segment) or when the
// fiber radius is outside [kMinFiberRadius, 5) (naming --thickness-scale).
SceneDescription make_file_scene(const std::string& path, float thickness_scale, const LightingOptions& lighting);

// Meshes used by the presets.
Mesh make_quad(const std::string& name, const glm::vec3& corner, const glm::vec3& u, const glm::vec3& v,
               const glm::vec3& albedo);
Mesh make_sphere(const std::string& name, const glm::vec3& center, float radius, const glm::vec3& albedo,
                 int rings = 48);
Mesh make_ellipsoid(const std::string& name, const Ellipsoid& ellipsoid, const glm::vec3& albedo, int rings = 48);

}  // namespace render
