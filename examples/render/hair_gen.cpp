// render — procedural hair generators.
#include "hair_gen.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
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
    const double across = vertical ? double(width) : double(height);  // the side the axes are spread over
    return int(std::lround(double(depth) * across / (2.0 * double(radius))));
}

double SlabOptions::packing() const {
    return double(depth) * 3.14159265358979323846 * double(radius) / (2.0 * double(thickness));
}

Hair make_slab(const SlabOptions& o) {
    if (o.vertical) {
        // The horizontal slab of the swapped sides, turned a quarter about z into the same
        // box: its fibers' x (along them) becomes y, their height becomes x.
        SlabOptions h = o;
        h.vertical = false;
        std::swap(h.width, h.height);
        Hair hair = make_slab(h);
        for (std::vector<glm::vec3>& strand : hair.strands)
            for (glm::vec3& q : strand) q = glm::vec3(q.y - 0.5f * o.width, q.x + 0.5f * o.height, q.z);
        return hair;
    }
    if (!(o.width > 0) || !(o.height > 0) || !(o.thickness > 0) || !(o.depth > 0) || !(o.radius > 0) || o.segments < 1)
        throw std::invalid_argument("make_slab: width, height, thickness, depth, radius and segments must be positive");
    const int count = o.strand_count();
    if (count < 1) throw std::invalid_argument("make_slab: depth · height / (2 radius) rounds to no strand");
    if (!o.overlap && !(o.packing() <= kSlabMaxPacking))
        throw std::invalid_argument("make_slab: fibers without overlap cannot cover more than " +
                                    std::to_string(int(std::lround(100 * kSlabMaxPacking))) + " % of the section (" +
                                    std::to_string(int(std::lround(100 * o.packing()))) + " % asked)");
    Hair hair;
    hair.radius = o.radius;
    Pcg32 rng(o.seed, 7);
    hair.strands.reserve(std::size_t(count));
    // Axes already placed, binned in cells one diameter wide: a new axis need only be checked
    // against the 3 × 3 cells around its own.
    const float diameter = 2 * o.radius;
    const int cells_y = std::max(1, int(o.height / diameter)), cells_z = std::max(1, int(o.thickness / diameter));
    std::vector<std::vector<glm::vec2>> placed(o.overlap ? 0 : std::size_t(cells_y) * std::size_t(cells_z));
    const auto cell_of = [&](float y, float z) {
        return glm::ivec2(std::min(cells_y - 1, int(y / diameter)), std::min(cells_z - 1, int((z + 0.5f * o.thickness) / diameter)));
    };
    const auto free_at = [&](float y, float z) {
        const glm::ivec2 c = cell_of(y, z);
        for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -1; dz <= 1; ++dz) {
                const int iy = c.x + dy, iz = c.y + dz;
                if (iy < 0 || iz < 0 || iy >= cells_y || iz >= cells_z) continue;
                for (const glm::vec2& q : placed[std::size_t(iy) * std::size_t(cells_z) + std::size_t(iz)])
                    if ((q.x - y) * (q.x - y) + (q.y - z) * (q.y - z) < diameter * diameter) return false;
            }
        return true;
    };
    for (int i = 0; i < count; ++i) {
        // Uniform positions, not the even count of a grid: the number of axes within r of a
        // ray varies as in real hair (binomial with overlap; a little less without).
        float y = 0, z = 0;
        for (int tries = 0;; ++tries) {
            y = o.height * rng.uniform();
            z = o.thickness * (rng.uniform() - 0.5f);
            if (o.overlap || free_at(y, z)) break;
            if (tries > 100000)
                throw std::runtime_error("make_slab: no room for fiber " + std::to_string(i) + " of " +
                                         std::to_string(count) + " without overlap");
        }
        if (!o.overlap) {
            const glm::ivec2 c = cell_of(y, z);
            placed[std::size_t(c.x) * std::size_t(cells_z) + std::size_t(c.y)].push_back({y, z});
        }
        std::vector<glm::vec3> s(std::size_t(o.segments) + 1);
        for (int k = 0; k <= o.segments; ++k)
            s[std::size_t(k)] = glm::vec3(o.width * (float(k) / float(o.segments) - 0.5f), y, z);
        hair.strands.push_back(std::move(s));
    }
    return hair;
}

glm::vec3 Ellipsoid::push_out(const glm::vec3& p, float margin) const {
    // In the ellipsoid's unit-sphere space the test and the projection are a sphere's.
    const glm::vec3 grown = radii + margin;
    const glm::vec3 q = (p - center) / grown;
    const float r = glm::length(q);
    if (r >= 1 || !(r > 0)) return p;
    return center + grown * (q / r);
}

std::vector<Ellipsoid> HeadOptions::body() const {
    return {
        {center, {0.92f, 1.05f, 1.0f}},                                  // head
        {center + glm::vec3(0.0f, -1.25f, -0.1f), {0.42f, 0.75f, 0.42f}},  // neck
        {center + glm::vec3(0.0f, -2.55f, -0.1f), {2.1f, 0.95f, 0.95f}},   // shoulders
    };
}

namespace {

// p pushed out of every ellipsoid: where two overlap (head and neck, neck and shoulders)
// leaving one can enter the other, so a few rounds.
glm::vec3 keep_outside(glm::vec3 p, float margin, const std::vector<Ellipsoid>& body) {
    for (int round = 0; round < 4; ++round)
        for (const Ellipsoid& e : body) p = e.push_out(p, margin);
    return p;
}

// One strand grown from root p along d: follow-the-leader steps bent by gravity and kept
// outside the body. Above the head's lower half a strand also stays within `layer` of the
// scalp (the stiffness and the other strands that hold real hair down: without it, hair
// leaves the crown along its tangent and stands off the head like a helmet).
std::vector<glm::vec3> grow_strand(glm::vec3 p, glm::vec3 d, float length, float layer, const HeadOptions& o,
                                   const std::vector<Ellipsoid>& body) {
    const float step = length / float(o.segments), margin = 2 * o.radius;
    const Ellipsoid& head = body[0];
    const Ellipsoid shell{head.center, head.radii + layer};
    std::vector<glm::vec3> s;
    s.reserve(std::size_t(o.segments) + 1);
    s.push_back(p);
    for (int k = 1; k <= o.segments; ++k) {
        d = glm::normalize(d + glm::vec3(0, -o.gravity * step, 0));
        glm::vec3 q = p + step * d;
        if (q.y > head.center.y - 0.3f * head.radii.y) {
            const glm::vec3 u = (q - shell.center) / shell.radii;
            if (const float r = glm::length(u); r > 1) q = shell.center + shell.radii * (u / r);
        }
        q = keep_outside(q, margin, body);
        d = glm::normalize(q - p);
        p = q;
        s.push_back(p);
    }
    return s;
}

}  // namespace

Hair make_head(const HeadOptions& o) {
    if (o.count < 1 || o.segments < 2 || !(o.length > 0) || !(o.radius > 0) || o.clumps < 1 ||
        !(o.clump >= 0 && o.clump <= 1) || !(o.frizz >= 0) || !(o.length_variation >= 0 && o.length_variation < 1))
        throw std::invalid_argument("make_head: count, segments, length, radius and clumps must be positive, clump in "
                                    "[0, 1], frizz >= 0, length_variation in [0, 1)");
    // The strands keep out of the body and of the face: an invisible ellipsoid in front of
    // it, around which the hair parts to frame it (gravity alone would slide the strands
    // that leave the parting down the forehead, where stiffness holds real hair back).
    std::vector<Ellipsoid> body = o.body();
    const Ellipsoid head = body[0];
    body.push_back({head.center + glm::vec3(0.0f, -0.2f, 0.45f), {0.62f, 0.8f, 0.7f}});
    Pcg32 rng(o.seed, 9);
    // A root on the scalp: area-uniform on the unit sphere (then stretched to the head)
    // above the hairline, which runs from the nape (y = -0.45) over the ears to the brow
    // (y = 0.55 at the front).
    struct Root {
        glm::vec3 p, d;
    };
    auto root = [&]() {
        glm::vec3 n;
        for (;;) {
            const float y = 1 - 2 * rng.uniform(), phi = 2 * kPi * rng.uniform();
            const float r = std::sqrt(std::max(0.0f, 1 - y * y));
            n = glm::vec3(r * std::sin(phi), y, r * std::cos(phi));
            const float hairline = n.z > 0 ? -0.1f + 0.65f * n.z : -0.1f + 0.35f * n.z;
            if (n.y > hairline) break;
        }
        const glm::vec3 p = head.center + head.radii * n;
        const glm::vec3 normal = glm::normalize(n / head.radii);
        // In front of the crown the hair leaves the parting sideways and a little back,
        // swept further back toward the brow (so that it frames the face instead of
        // falling over it); behind the crown it leaves the crown.
        const float side = p.x - head.center.x >= o.parting ? 1.0f : -1.0f;
        glm::vec3 away = n.z > -0.3f ? glm::vec3(side, 0.0f, -0.35f - 2.0f * std::max(0.0f, n.z - 0.2f))
                                     : glm::vec3(n.x, 0.0f, n.z);
        away -= glm::dot(away, normal) * normal;
        if (!(glm::length(away) > 1e-4f)) away = glm::vec3(0, -1, 0) - normal.y * normal;
        return Root{p, glm::normalize(glm::normalize(away) + 0.15f * normal)};
    };
    // Guide strands first (one per clump), then the strands, each pulled toward the guide
    // whose root is nearest its own.
    std::vector<std::vector<glm::vec3>> guides;
    guides.reserve(std::size_t(o.clumps));
    for (int g = 0; g < o.clumps; ++g) {
        const Root r = root();
        guides.push_back(grow_strand(r.p, r.d, o.length, 0.08f, o, body));
    }
    Hair hair;
    hair.radius = o.radius;
    hair.strands.reserve(std::size_t(o.count));
    for (int i = 0; i < o.count; ++i) {
        const Root r = root();
        const float length = o.length * (1 + o.length_variation * (2 * rng.uniform() - 1));
        // Strands lie in layers up to 0.15 head radii deep.
        std::vector<glm::vec3> s = grow_strand(r.p, r.d, length, 0.02f + 0.13f * rng.uniform(), o, body);
        const std::vector<glm::vec3>* guide = &guides[0];
        float nearest = std::numeric_limits<float>::max();
        for (const auto& g : guides) {
            const glm::vec3 e = g[0] - r.p;
            if (const float d2 = glm::dot(e, e); d2 < nearest) nearest = d2, guide = &g;
        }
        // Clumping: toward the guide's shape moved to this root, the offset fading to the
        // tip, so that with clump = 1 the tips meet; it grows from none at the root. The
        // frizz's random walk grows with the distance along the strand. Both keep the body
        // outside.
        glm::vec3 walk(0.0f);
        const float step = length / float(o.segments);
        for (std::size_t k = 1; k < s.size(); ++k) {
            const float t = float(k) / float(o.segments);
            const glm::vec3 target = (*guide)[k] + (1 - t) * (r.p - (*guide)[0]);
            glm::vec3 q = glm::mix(s[k], target, o.clump * t);
            const glm::vec3 u(2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1);
            walk += o.frizz * step * u;
            q += t * walk;
            s[k] = keep_outside(q, 2 * o.radius, body);
        }
        hair.strands.push_back(std::move(s));
    }
    return hair;
}

}  // namespace render
