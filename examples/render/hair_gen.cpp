// render — procedural hair generators.
#include "hair_gen.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rng.hpp"

namespace render {

std::size_t Hair::point_count() const {
    std::size_t n = 0;
    for (const auto& s : strands) n += s.size();
    return n;
}
std::size_t Hair::segment_count() const {
    std::size_t n = 0;
    for (const auto& s : strands) n += s.size() > 1 ? s.size() - 1 : 0;
    return n;
}

namespace {
constexpr float kPi = 3.14159265358979f;
}

Hair make_block(const BlockOptions& o) {
    if (o.count < 1 || o.segments < 1 || !(o.size > 0) || !(o.radius > 0))
        throw std::invalid_argument("make_block: count, segments, size and radius must be positive");
    Hair hair;
    hair.radius = o.radius;
    Pcg32 rng(o.seed, 1);
    // Roots jittered on an n × m grid over the y–z face (n·m ≥ count, cells kept square).
    const int cols = int(std::ceil(std::sqrt(double(o.count))));
    const int rows = (o.count + cols - 1) / cols;
    const float margin = o.radius + o.wave_amplitude;  // strands stay inside the box
    const float span = std::max(o.size - 2 * margin, 0.0f);
    hair.strands.reserve(std::size_t(o.count));
    for (int i = 0; i < o.count; ++i) {
        const int r = i / cols, c = i % cols;
        const float y0 = margin + span * (float(r) + rng.uniform()) / float(rows);
        const float z0 = -0.5f * o.size + margin + span * (float(c) + rng.uniform()) / float(cols);
        const float phase = 2 * kPi * rng.uniform();
        std::vector<glm::vec3> s(std::size_t(o.segments) + 1);
        for (int k = 0; k <= o.segments; ++k) {
            const float x = -0.5f * o.size + o.size * float(k) / float(o.segments);
            const float a = 2 * kPi * (x / o.wavelength) + phase;
            s[std::size_t(k)] = glm::vec3(x, y0 + o.wave_amplitude * std::sin(a), z0 + o.wave_amplitude * std::cos(a));
        }
        hair.strands.push_back(std::move(s));
    }
    return hair;
}

Hair make_scalp(const ScalpOptions& o) {
    if (o.count < 1 || o.segments < 1 || !(o.head_radius > 0) || !(o.length > 0) || !(o.radius > 0))
        throw std::invalid_argument("make_scalp: count, segments, head_radius, length and radius must be positive");
    Hair hair;
    hair.radius = o.radius;
    Pcg32 rng(o.seed, 3);
    const float step = o.length / float(o.segments);
    const float keep_out = o.head_radius * 1.01f + o.radius;
    hair.strands.reserve(std::size_t(o.count));
    for (int i = 0; i < o.count; ++i) {
        // Roots uniform in area over the cap y > -0.1 R, except a face region (z > 0, y < 0.5 R).
        glm::vec3 n;
        do {
            const float y = -0.1f + 1.1f * rng.uniform();
            const float phi = 2 * kPi * rng.uniform();
            const float r = std::sqrt(std::max(0.0f, 1 - y * y));
            n = glm::vec3(r * std::cos(phi), y, r * std::sin(phi));
        } while (n.z > 0.3f && n.y < 0.5f);
        glm::vec3 p = o.center + o.head_radius * n, d = n;
        // A frame around the growth direction for the curl offset.
        const glm::vec3 a = std::abs(d.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
        const float phase = 2 * kPi * rng.uniform();
        std::vector<glm::vec3> s;
        s.reserve(std::size_t(o.segments) + 1);
        glm::vec3 axis = p;
        s.push_back(p);
        for (int k = 1; k <= o.segments; ++k) {
            d = glm::normalize(d + glm::vec3(0, -o.gravity * step, 0));
            axis += step * d;
            // Keep the axis outside the head: project back onto the keep-out sphere.
            const glm::vec3 rel = axis - o.center;
            if (glm::length(rel) < keep_out) axis = o.center + keep_out * glm::normalize(rel);
            glm::vec3 q = axis;
            if (o.curl_radius > 0) {
                const glm::vec3 u = glm::normalize(glm::cross(d, a)), v = glm::cross(d, u);
                const float t = 2 * kPi * o.curl_turns * step * float(k) + phase;
                const float grow = std::min(1.0f, float(k) / 3.0f);  // no kink at the root
                q += grow * o.curl_radius * (std::cos(t) * u + std::sin(t) * v);
            }
            s.push_back(q);
        }
        hair.strands.push_back(std::move(s));
    }
    return hair;
}

Hair make_fur(const FurOptions& o) {
    if (o.count < 1 || o.segments < 1 || !(o.body_radius > 0) || !(o.length > 0) || !(o.radius > 0) ||
        !(o.length_variation >= 0 && o.length_variation < 1))
        throw std::invalid_argument(
            "make_fur: count, segments, body_radius, length and radius must be positive, length_variation in [0, 1)");
    Hair hair;
    hair.radius = o.radius;
    Pcg32 rng(o.seed, 5);
    const float deg = kPi / 180.0f;
    const float keep_out = o.body_radius + o.radius;
    const float comb_length = glm::length(o.comb);
    const glm::vec3 comb = comb_length > 0 ? o.comb / comb_length : glm::vec3(0);
    hair.strands.reserve(std::size_t(o.count));
    for (int i = 0; i < o.count; ++i) {
        // Area-uniform on the sphere: z uniform in [-1, 1] (Archimedes), azimuth uniform.
        const float z = 1 - 2 * rng.uniform();
        const float phi = 2 * kPi * rng.uniform();
        const float rz = std::sqrt(std::max(0.0f, 1 - z * z));
        const glm::vec3 n(rz * std::cos(phi), rz * std::sin(phi), z);
        // The combing direction in the tangent plane; where the comb is (nearly) normal
        // to the surface it has no tangent part, and a random tangent stands in.
        glm::vec3 t = comb - glm::dot(comb, n) * n;
        const float random_heading = 2 * kPi * rng.uniform();
        if (glm::length(t) < 1e-3f) {
            const glm::vec3 a = std::abs(n.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
            const glm::vec3 u = glm::normalize(glm::cross(n, a)), v = glm::cross(n, u);
            t = std::cos(random_heading) * u + std::sin(random_heading) * v;
        }
        t = glm::normalize(t);
        const glm::vec3 b = glm::cross(n, t);
        const float heading = o.tilt_jitter_deg * deg * (2 * rng.uniform() - 1);
        t = std::cos(heading) * t + std::sin(heading) * b;
        const float jitter = o.tilt_jitter_deg * (2 * rng.uniform() - 1);
        const float tilt = std::clamp((o.tilt_deg + jitter) * deg, 0.0f, 89.0f * deg);
        glm::vec3 d = std::cos(tilt) * n + std::sin(tilt) * t;
        const float length = o.length * (1 + o.length_variation * (2 * rng.uniform() - 1));
        const float step = length / float(o.segments);
        std::vector<glm::vec3> s;
        s.reserve(std::size_t(o.segments) + 1);
        glm::vec3 p = o.center + o.body_radius * n;
        s.push_back(p);
        for (int k = 1; k <= o.segments; ++k) {
            d = glm::normalize(d + glm::vec3(0, -o.gravity * step, 0));
            p += step * d;
            // Combed flat or bent by gravity, a strand could dip into the body: push it out.
            const glm::vec3 rel = p - o.center;
            if (glm::length(rel) < keep_out) p = o.center + keep_out * glm::normalize(rel);
            s.push_back(p);
        }
        hair.strands.push_back(std::move(s));
    }
    return hair;
}

int SlabOptions::strand_count() const {
    return int(std::lround(double(depth) * double(height) / (2.0 * double(radius))));
}

Hair make_slab(const SlabOptions& o) {
    if (!(o.width > 0) || !(o.height > 0) || !(o.thickness > 0) || !(o.depth > 0) || !(o.radius > 0) || o.segments < 1)
        throw std::invalid_argument("make_slab: width, height, thickness, depth, radius and segments must be positive");
    const int count = o.strand_count();
    if (count < 1) throw std::invalid_argument("make_slab: depth · height / (2 radius) rounds to no strand");
    Hair hair;
    hair.radius = o.radius;
    Pcg32 rng(o.seed, 7);
    hair.strands.reserve(std::size_t(count));
    for (int i = 0; i < count; ++i) {
        // Independent uniform positions: the number of axes within r of a ray is binomial
        // (Poisson in the limit), as in real hair, not the even count of a grid.
        const float y = o.height * rng.uniform();
        const float z = o.thickness * (rng.uniform() - 0.5f);
        std::vector<glm::vec3> s(std::size_t(o.segments) + 1);
        for (int k = 0; k <= o.segments; ++k)
            s[std::size_t(k)] = glm::vec3(o.width * (float(k) / float(o.segments) - 0.5f), y, z);
        hair.strands.push_back(std::move(s));
    }
    return hair;
}

}  // namespace render
