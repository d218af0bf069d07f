// render — scene presets.
#include "scenes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include "hair_file.hpp"

namespace render {

Mesh make_quad(const std::string& name, const glm::vec3& corner, const glm::vec3& u, const glm::vec3& v,
               const glm::vec3& albedo) {
    Mesh m;
    m.name = name;
    m.positions = {corner, corner + u, corner + u + v, corner + v};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    m.albedo = albedo;
    return m;
}

Mesh make_sphere(const std::string& name, const glm::vec3& center, float radius, const glm::vec3& albedo, int rings) {
    return make_ellipsoid(name, {center, glm::vec3(radius)}, albedo, rings);
}

Mesh make_ellipsoid(const std::string& name, const Ellipsoid& e, const glm::vec3& albedo, int rings) {
    Mesh m;
    m.name = name;
    m.albedo = albedo;
    const int segs = 2 * rings;
    const float pi = 3.14159265358979f;
    for (int i = 0; i <= rings; ++i) {
        const float theta = pi * float(i) / float(rings);
        for (int j = 0; j <= segs; ++j) {
            const float phi = 2 * pi * float(j) / float(segs);
            const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
            m.positions.push_back(e.center + e.radii * n);
            // smooth shading: the exact normal at each vertex
            m.normals.push_back(glm::normalize(n / e.radii));
        }
    }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segs; ++j) {
            const unsigned a = unsigned(i * (segs + 1) + j), b = a + unsigned(segs + 1);
            m.triangles.push_back({a, b, a + 1});
            m.triangles.push_back({a + 1, b, b + 1});
        }
    return m;
}

namespace {

constexpr float kPi = 3.14159265358979f;

// The slab's camera distance: the default scene camera's 14 units for a 5-unit slab.
float slab_eye_distance(const SlabOptions& o) { return 14.0f * std::max(o.width, o.height) / 5.0f; }

void require(bool ok, const std::string& message) {
    if (!ok) throw std::invalid_argument(message);
}
// Six significant digits: 1e+30 and 1e-20 read as such (std::to_string gave 31 digits and
// 0.000000).
std::string num(double v) {
    char s[32];
    std::snprintf(s, sizeof s, "%.6g", v);
    return s;
}

}  // namespace

// The ranges keep the scenes' arithmetic in float and the picture in view: a light of side
// 1e-20 had zero area (its radiance scales with 1/side²), a --block-size of 2^31 or a
// --fur-length of 1e30 left the camera an empty frame or tripped an Embree assertion, and a
// --curl of 1e30 overflowed the density grid's box. Each names its flag and its range.
void validate(const LightingOptions& l) {
    require(std::isfinite(l.light_size) && l.light_size >= 1e-3f && l.light_size <= 1e3f,
            "--light-size: " + num(l.light_size) + " is not a size in [0.001, 1000]");
    require(std::isfinite(l.light_power) && l.light_power >= 0 && l.light_power <= 1e6f,
            "--light-power: " + num(l.light_power) + " is not a power in [0, 10^6]");
    require(std::isfinite(l.environment) && l.environment >= 0 && l.environment <= 1e6f,
            "--environment: " + num(l.environment) + " is not a radiance in [0, 10^6]");
    require(!l.env.empty(), "--env: expected constant, studio or an OpenEXR file");
    require(std::isfinite(l.env_rotate_deg) && std::abs(l.env_rotate_deg) <= 360,
            "--env-rotate: " + num(l.env_rotate_deg) + " is not an angle in [-360, 360] degrees");
    require(std::isfinite(l.env_intensity) && l.env_intensity >= 0 && l.env_intensity <= 1e6f,
            "--env-intensity: " + num(l.env_intensity) + " is not a factor in [0, 10^6]");
}

std::shared_ptr<const Environment> load_environment(const LightingOptions& l) {
    if (l.env == "constant") return nullptr;
    const LatLongMap map = l.env == "studio" ? make_studio_map() : read_lat_long_exr(l.env);
    return std::make_shared<const Environment>(map, l.env_rotate_deg, l.env_intensity);
}

void validate(const BlockOptions& b) {
    require(b.count >= 1 && b.count <= 10'000'000, "--hairs: " + std::to_string(b.count) + " is outside [1, 10^7]");
    require(std::isfinite(b.size) && b.size >= 0.01f && b.size <= 100,
            "--block-size: " + num(b.size) + " is not a size in [0.01, 100] (the camera frames the 5-unit block)");
    require(std::isfinite(b.radius) && b.radius >= kMinFiberRadius && b.radius < b.size,
            "--fiber-radius: " + num(b.radius) + " is not a radius in [10^-6, block size)");
}

void validate(const ScalpOptions& s) {
    require(s.count >= 1 && s.count <= 10'000'000, "--scalp-hairs: " + std::to_string(s.count) + " is outside [1, 10^7]");
    require(std::isfinite(s.gravity) && std::abs(s.gravity) <= 100,
            "--gravity: " + num(s.gravity) + " is not a bend per unit length in [-100, 100]");
    require(std::isfinite(s.curl_radius) && s.curl_radius >= 0 && s.curl_radius <= s.head_radius,
            "--curl: " + num(s.curl_radius) + " is not a radius in [0, " + num(s.head_radius) + "] (the head's radius)");
}

void validate(const FurOptions& f) {
    require(f.count >= 1 && f.count <= 10'000'000, "--fur-hairs: " + std::to_string(f.count) + " is outside [1, 10^7]");
    require(std::isfinite(f.length) && f.length > 0 && f.length <= 100,
            "--fur-length: " + num(f.length) + " is not a length in (0, 100]");
    require(std::isfinite(f.tilt_deg) && f.tilt_deg >= 0 && f.tilt_deg < 90,
            "--fur-tilt: " + num(f.tilt_deg) + " is not an angle in [0, 90) degrees");
    require(std::isfinite(f.radius) && f.radius >= kMinFiberRadius && f.radius < f.length,
            "--fiber-radius: " + num(f.radius) + " is not a radius in [10^-6, fur length)");
}

void validate(const SlabOptions& o, const LightingOptions& l) {
    require(std::isfinite(o.depth) && o.depth > 0, "--slab-depth: " + num(o.depth) + " is not a fiber count > 0");
    require(std::isfinite(o.radius) && o.radius >= kMinFiberRadius && o.radius < 0.5f * o.thickness,
            "--fiber-radius: " + num(o.radius) + " is not a radius in [10^-6, slab thickness / 2 = " +
                num(0.5 * o.thickness) + ")");
    const double across = o.vertical ? double(o.width) : double(o.height);  // as SlabOptions::strand_count
    const double strands = double(o.depth) * across / (2.0 * double(o.radius));
    require(strands >= 0.5 && strands <= 1e7, "--slab-depth: " + num(o.depth) + " with --fiber-radius " +
                                                   num(o.radius) + " makes " + num(std::round(strands)) +
                                                   " strands, outside [1, 10^7]");
    require(o.overlap || o.packing() <= kSlabMaxPacking,
            "--slab-depth: " + num(o.depth) + " fibers of radius " + num(o.radius) + " cover " +
                num(std::round(100 * o.packing())) + " % of the slab's section; without --slab-overlap at most " +
                num(100 * kSlabMaxPacking) + " % (thinner fibers: --fiber-radius)");
    if (o.back_lit && l.light_power > 0) {
        // Every sightline from the eye to the light must pass through the slab: the light's
        // half side, projected from the eye onto the slab's back face, stays inside it.
        const float eye = slab_eye_distance(o);
        const float shrink = (eye + 0.5f * o.thickness) / (eye + kSlabBackLightDistance);
        const float largest = std::min(o.width, o.height) / shrink;
        require(l.light_size < largest, "--light-size: " + num(l.light_size) +
                                            " makes the back light show beside the slab (it hides one below " +
                                            num(largest) + ")");
    }
}

void remove_ground(SceneDescription& scene) {
    auto& m = scene.meshes;
    m.erase(std::remove_if(m.begin(), m.end(), [](const Mesh& mesh) { return mesh.name == "ground"; }), m.end());
}

namespace {

Mesh ground() { return make_quad("ground", {-40, 0, 40}, {80, 0, 0}, {0, 0, -80}, glm::vec3(0.45f)); }

void add_lighting(SceneDescription& s, const LightingOptions& l, const glm::vec3& center, float radiance) {
    if (l.light_power > 0) {
        AreaLight a;
        const float h = 0.5f * l.light_size;
        a.corner = center + glm::vec3(-h, 0, -h);
        a.edge_u = {l.light_size, 0, 0};  // cross(u, v) = -y: emits downward
        a.edge_v = {0, 0, l.light_size};
        // Radiance scaled so the irradiance is independent of the light's size.
        a.radiance = glm::vec3(radiance * l.light_power * 4.0f / (l.light_size * l.light_size));
        s.light = a;
    }
    s.environment = glm::vec3(l.environment);
}

}  // namespace

SceneDescription make_block_scene(const BlockOptions& block, const LightingOptions& lighting) {
    SceneDescription s;
    s.name = "block";
    s.hair = make_block(block);
    s.meshes.push_back(ground());
    s.camera.eye = {0.0f, 5.5f, 15.0f};
    s.camera.target = {0.0f, 2.3f, 0.0f};
    s.camera.fov_y_deg = 30.0f;
    add_lighting(s, lighting, {-1.0f, 10.0f, 7.0f}, 80.0f);
    return s;
}

SceneDescription make_cornell_scene(const BlockOptions& block, const LightingOptions& lighting) {
    SceneDescription s;
    s.name = "cornell";
    const float w = 7.0f, H = 12.0f, back = -7.0f, front = 18.0f;
    s.meshes.push_back(make_quad("floor", {-w, 0, front}, {2 * w, 0, 0}, {0, 0, back - front}, glm::vec3(0.7f)));
    s.meshes.push_back(make_quad("ceiling", {-w, H, back}, {2 * w, 0, 0}, {0, 0, front - back}, glm::vec3(0.7f)));
    s.meshes.push_back(make_quad("back", {-w, 0, back}, {2 * w, 0, 0}, {0, H, 0}, glm::vec3(0.6f)));
    s.meshes.push_back(make_quad("front", {-w, 0, front}, {0, H, 0}, {2 * w, 0, 0}, glm::vec3(0.6f)));
    s.meshes.push_back(make_quad("left", {-w, 0, front}, {0, 0, back - front}, {0, H, 0}, {0.63f, 0.065f, 0.05f}));
    s.meshes.push_back(make_quad("right", {w, 0, back}, {0, 0, front - back}, {0, H, 0}, {0.14f, 0.45f, 0.091f}));
    s.meshes.push_back(make_sphere("sphere", {3.6f, 1.6f, 1.0f}, 1.6f, {0.7f, 0.1f, 0.08f}));
    BlockOptions b = block;
    s.hair = make_block(b);
    for (auto& strand : s.hair.strands)
        for (glm::vec3& p : strand) p += glm::vec3(-1.8f, 0, -1.0f);
    s.camera.eye = {0.0f, 6.0f, 17.0f};
    s.camera.target = {0.0f, 4.2f, 0.0f};
    s.camera.fov_y_deg = 42.0f;
    LightingOptions l = lighting;
    l.environment = 0;  // closed box
    add_lighting(s, l, {0.0f, H - 0.01f, 2.0f}, 30.0f);
    return s;
}

SceneDescription make_scalp_scene(const ScalpOptions& scalp, const LightingOptions& lighting) {
    SceneDescription s;
    s.name = "scalp";
    ScalpOptions o = scalp;
    o.center = {0.0f, 2.0f * o.head_radius + 0.5f, 0.0f};
    s.hair = make_scalp(o);
    s.meshes.push_back(ground());
    s.meshes.push_back(make_sphere("head", o.center, o.head_radius, {0.8f, 0.6f, 0.5f}));
    s.camera.eye = o.center + glm::vec3(4.0f, 2.0f, 10.0f) * o.head_radius;
    s.camera.target = o.center + glm::vec3(0, -0.4f, 0) * o.head_radius;
    s.camera.fov_y_deg = 38.0f;
    add_lighting(s, lighting, o.center + glm::vec3(3, 5, 6) * o.head_radius, 25.0f);
    return s;
}

void validate(const HeadOptions& h) {
    require(h.count >= 1 && h.count <= 10'000'000, "--head-hairs: " + std::to_string(h.count) + " is outside [1, 10^7]");
    require(std::isfinite(h.length) && h.length >= 0.05f && h.length <= 10,
            "--hair-length: " + num(h.length) + " is not a length in [0.05, 10] (head radii)");
    require(std::isfinite(h.clump) && h.clump >= 0 && h.clump <= 1, "--clump: " + num(h.clump) + " is not in [0, 1]");
    require(std::isfinite(h.frizz) && h.frizz >= 0 && h.frizz <= 1, "--frizz: " + num(h.frizz) + " is not in [0, 1]");
    require(std::isfinite(h.radius) && h.radius >= kMinFiberRadius && h.radius <= 0.05f,
            "--fiber-radius: " + num(h.radius) + " is not a radius in [10^-6, 0.05] for the head (radius 1)");
}

SceneDescription make_head_scene(const HeadOptions& head, const LightingOptions& lighting) {
    SceneDescription s;
    s.name = "head";
    s.hair = make_head(head);
    const std::vector<Ellipsoid> body = head.body();
    const glm::vec3 skin(0.72f, 0.53f, 0.43f), sweater(0.09f, 0.1f, 0.13f);
    s.meshes.push_back(make_ellipsoid("head", body[0], skin, 64));
    s.meshes.push_back(make_ellipsoid("neck", body[1], skin));
    s.meshes.push_back(make_ellipsoid("shoulders", body[2], sweater, 64));
    // Head and shoulders in a 16:9 frame, seen a little from the right and above.
    const glm::vec3 c = head.center;
    s.camera.eye = c + glm::vec3(2.0f, 0.5f, 7.2f);
    s.camera.target = c + glm::vec3(0.0f, -0.7f, 0.0f);
    s.camera.fov_y_deg = 32.0f;
    add_lighting(s, lighting, c + glm::vec3(-3, 5, 6), 25.0f);
    return s;
}

SceneDescription make_fur_scene(const FurOptions& fur, const LightingOptions& lighting) {
    SceneDescription s;
    s.name = "fur";
    FurOptions o = fur;
    // The longest strand reaches `outer` from the centre; the ball floats just above the
    // ground at the default camera's height.
    const float outer = o.body_radius + o.length * (1 + o.length_variation);
    o.center = {0.0f, std::max(2.5f, outer + 0.2f), 0.0f};
    s.hair = make_fur(o);
    s.meshes.push_back(ground());
    if (o.body) s.meshes.push_back(make_sphere("body", o.center, o.body_radius, glm::vec3(0.4f)));
    // The ball fills about 70 % of the image height, seen from slightly above.
    s.camera.fov_y_deg = 30.0f;
    const float distance = outer / (0.7f * std::tan(0.5f * s.camera.fov_y_deg * kPi / 180.0f));
    s.camera.eye = o.center + distance * glm::normalize(glm::vec3(0.0f, 0.15f, 1.0f));
    s.camera.target = o.center;
    // The scalp's light, scaled with the ball at constant irradiance.
    const float k = outer / 2.0f;
    add_lighting(s, lighting, o.center + glm::vec3(3, 5, 6) * k, 25.0f * k * k);
    return s;
}

SceneDescription make_slab_scene(const SlabOptions& slab, const LightingOptions& lighting) {
    SceneDescription s;
    s.name = "slab";
    s.hair = make_slab(slab);
    const float mid = 0.5f * slab.height;
    s.camera.eye = {0.0f, mid, slab_eye_distance(slab)};
    s.camera.target = {0.0f, mid, 0.0f};
    s.camera.fov_y_deg = 35.0f;
    if (!slab.back_lit) {
        add_lighting(s, lighting, {-1.0f, mid + 7.5f, 7.0f}, 80.0f);
        return s;
    }
    s.environment = glm::vec3(lighting.environment);
    if (lighting.light_power > 0) {
        AreaLight a;
        const float side = lighting.light_size;
        a.corner = {-0.5f * side, mid - 0.5f * side, -kSlabBackLightDistance};
        a.edge_u = {side, 0, 0};  // cross(u, v) = +z: toward the slab and the camera
        a.edge_v = {0, side, 0};
        // Facing the slab 3 units away, this gives about the irradiance the front light
        // gives the block's top (independent of the light's size, as add_lighting's).
        a.radiance = glm::vec3(10.0f * lighting.light_power * 4.0f / (side * side));
        s.light = a;
    }
    return s;
}

SceneDescription make_file_scene(const std::string& path, float thickness_scale, const LightingOptions& lighting) {
    const HairFile file = read_hair_file(path);
    SceneDescription s;
    s.name = "file";
    s.hair.strands = file.strands();
    if (s.hair.segment_count() == 0)
        throw std::invalid_argument(path + ": the file has no hair (" + std::to_string(file.strand_count()) +
                                    " strands, " + std::to_string(file.points.size()) + " points, no segment)");
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
    for (const glm::vec3& p : file.points) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const glm::vec3 e = hi - lo;
    const float extent = std::max({e.x, e.y, e.z});
    const float scale = extent > 0 ? 5.0f / extent : 1.0f;
    const glm::vec3 shift(-0.5f * (lo.x + hi.x), -lo.y, -0.5f * (lo.z + hi.z));
    for (auto& strand : s.hair.strands)
        for (glm::vec3& p : strand) p = (p + shift) * scale;
    double thickness = file.default_thickness;
    if (!file.thickness.empty()) {
        thickness = 0;
        for (float t : file.thickness) thickness += t;
        thickness /= double(file.thickness.size());
    }
    const double radius = 0.5 * thickness * scale * thickness_scale;
    if (!(radius >= kMinFiberRadius && radius < 5))
        throw std::invalid_argument(path + ": its mean thickness " + num(thickness) + " scaled to the 5-unit box and by " +
                                    "--thickness-scale " + num(thickness_scale) + " gives a fiber radius of " +
                                    num(radius) + ", outside [10^-6, 5)");
    s.hair.radius = float(radius);
    s.meshes.push_back(ground());
    s.camera.eye = {0.0f, 5.0f, 14.0f};
    s.camera.target = {0.0f, 0.5f * e.y * scale, 0.0f};
    s.camera.fov_y_deg = 32.0f;
    add_lighting(s, lighting, {3.0f, 10.0f, 6.0f}, 25.0f);
    return s;
}

}  // namespace render
