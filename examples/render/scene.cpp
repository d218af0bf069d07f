// render — building the Scene: Embree BVHs over the hair (round linear curves) and the
// triangle meshes.
#include "scene.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <new>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace render {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Embree's allocations, through its memory monitor: current and peak bytes.
struct EmbreeMemory {
    std::atomic<long long> current{0}, peak{0};
};
EmbreeMemory& embree_memory() {
    static EmbreeMemory m;
    return m;
}
bool monitor_memory(void*, ssize_t bytes, bool) {
    EmbreeMemory& m = embree_memory();
    const long long now = m.current += (long long)bytes;
    long long p = m.peak.load();
    while (now > p && !m.peak.compare_exchange_weak(p, now)) {
    }
    return true;  // never veto an allocation
}

// An intersect context that skips hits on one strand closer than max_t: a ray leaving a
// fiber must not find that fiber again (the BCSDF already includes the passage through
// it), nor its neighbouring segments where the strand bends.
void ignore_strand_filter(const RTCFilterFunctionNArguments* args);

struct IgnoreStrandContext {
    RTCIntersectContext base;  // first member: Embree passes &base back to the filter
    std::uint32_t strand;
    float max_t;
    unsigned hair_geom;
    const std::uint32_t* strand_of_segment;

    IgnoreStrandContext(std::uint32_t s, float t, unsigned g, const std::uint32_t* of)
        : strand(s), max_t(t), hair_geom(g), strand_of_segment(of) {
        rtcInitIntersectContext(&base);
        base.filter = ignore_strand_filter;
    }
};

void ignore_strand_filter(const RTCFilterFunctionNArguments* args) {
    const auto* ctx = reinterpret_cast<const IgnoreStrandContext*>(args->context);
    if (ctx->strand == kNoStrand) return;
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        if (RTCHitN_geomID(args->hit, args->N, i) != ctx->hair_geom) continue;
        if (ctx->strand_of_segment[RTCHitN_primID(args->hit, args->N, i)] != ctx->strand) continue;
        if (RTCRayN_tfar(args->ray, args->N, i) < ctx->max_t) args->valid[i] = 0;
    }
}

// An intersect context that collects the distinct strands a ray crosses: its filter
// records each hit's strand and rejects the hit, so traversal runs on to tmax. Round
// curves report entry and exit, neighbouring segments of a strand (and spatial-split BVH
// references of one segment) may report the same crossing again: strands are deduped by
// id, in a fixed array scanned linearly (a ray rarely crosses more than a few dozen
// strands), then in a heap vector sorted at the end.
void count_strands_filter(const RTCFilterFunctionNArguments* args);

struct CountStrandsContext {
    static constexpr std::uint32_t kCapacity = 64;

    RTCIntersectContext base;  // first member: Embree passes &base back to the filter
    std::uint32_t ignore;
    float max_t;
    unsigned hair_geom;
    const std::uint32_t* strand_of_segment;
    std::vector<std::uint32_t>* overflow;  // strands past kCapacity, duplicates included
    bool failed = false;                   // an allocation threw (it must not cross Embree)
    std::uint32_t last = kNoStrand;        // the previous hit's: hits come in runs per strand
    std::uint32_t limit = 0xffffffffu;     // stop the traversal once this many are found
    std::uint32_t count = 0;
    float last_t = 0.0f;                   // the farthest counted hit
    std::uint32_t strands[kCapacity];

    CountStrandsContext(std::uint32_t s, float t, unsigned g, const std::uint32_t* of, std::vector<std::uint32_t>* spill)
        : ignore(s), max_t(t), hair_geom(g), strand_of_segment(of), overflow(spill) {
        rtcInitIntersectContext(&base);
        base.filter = count_strands_filter;
    }

    void add(std::uint32_t s) {
        if (s == last) return;
        last = s;
        for (std::uint32_t k = count; k-- > 0;)
            if (strands[k] == s) return;
        if (count < kCapacity) {
            strands[count++] = s;
            return;
        }
        try {
            overflow->push_back(s);
        } catch (...) {
            failed = true;
        }
    }
};
static_assert(std::is_standard_layout_v<CountStrandsContext>, "the filter casts &base back to the context");

void count_strands_filter(const RTCFilterFunctionNArguments* args) {
    auto* ctx = reinterpret_cast<CountStrandsContext*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        args->valid[i] = 0;
        if (RTCHitN_geomID(args->hit, args->N, i) != ctx->hair_geom) continue;
        const std::uint32_t s = ctx->strand_of_segment[RTCHitN_primID(args->hit, args->N, i)];
        const float t = RTCRayN_tfar(args->ray, args->N, i);
        if (s == ctx->ignore && t < ctx->max_t) continue;
        ctx->add(s);
        ctx->last_t = std::max(ctx->last_t, t);
        // Enough: accepting the hit ends an occlusion query (hits arrive in no order along
        // the ray, but any `limit` distinct strands make the count's minimum with it).
        if (ctx->count >= ctx->limit) {
            args->valid[i] = -1;
            return;
        }
    }
}

RTCRayHit make_ray(const glm::vec3& o, const glm::vec3& d, float tmin, float tmax) {
    RTCRayHit rh{};
    rh.ray.org_x = o.x, rh.ray.org_y = o.y, rh.ray.org_z = o.z;
    rh.ray.dir_x = d.x, rh.ray.dir_y = d.y, rh.ray.dir_z = d.z;
    rh.ray.tnear = tmin;
    rh.ray.tfar = tmax;
    rh.ray.mask = 0xffffffffu;
    rh.ray.flags = 0;
    rh.ray.time = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

// Self-intersection offsets: surfaces start rays a little off their plane (scaled with
// the scene), hair relies on the strand filter above.
constexpr float kRayEpsilon = 1e-4f;

}  // namespace

void validate(const Camera& c) {
    auto finite = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    if (!finite(c.eye) || !finite(c.target) || !finite(c.up))
        throw std::invalid_argument("--eye, --look-at and --up must be finite x,y,z");
    const glm::vec3 forward = c.target - c.eye;
    if (!(glm::length(forward) > 0)) throw std::invalid_argument("--eye and --look-at are the same point: no view direction");
    if (!(glm::length(c.up) > 0)) throw std::invalid_argument("--up must not be zero");
    // sin of the angle between them: below 1e-3 the image's horizontal axis is noise.
    const float s = glm::length(glm::cross(glm::normalize(forward), glm::normalize(c.up)));
    if (!(s > 1e-3f))
        throw std::invalid_argument("--up is along the view direction (--look-at minus --eye): the camera cannot tell "
                                    "up from forward; give an --up across the view");
    if (!(c.fov_y_deg >= 1 && c.fov_y_deg <= 170))
        throw std::invalid_argument("--fov must be a vertical field of view in [1, 170] degrees");
}

Scene::Scene(SceneDescription description) : d_(std::move(description)) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw std::runtime_error("cannot create an Embree device (error " +
                                           std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    embree_memory().current = 0;
    embree_memory().peak = 0;
    rtcSetDeviceMemoryMonitorFunction(device_, monitor_memory, nullptr);

    const auto t_bvh = Clock::now();
    all_ = rtcNewScene(device_);
    opaque_ = rtcNewScene(device_);
    hair_ = rtcNewScene(device_);
    rtcSetSceneFlags(all_, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    rtcSetSceneFlags(hair_, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);

    unsigned next_id = 0;
    auto attach = [&](RTCGeometry g, bool opaque, bool hair) {
        rtcCommitGeometry(g);
        const unsigned id = next_id++;
        rtcAttachGeometryByID(all_, g, id);
        if (opaque) rtcAttachGeometryByID(opaque_, g, id);
        if (hair) rtcAttachGeometryByID(hair_, g, id);
        rtcReleaseGeometry(g);
        return id;
    };
    auto add_triangles = [&](const std::vector<glm::vec3>& pos, const std::vector<glm::uvec3>& tri) {
        RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), pos.size()));
        for (std::size_t i = 0; i < pos.size(); ++i)
            for (int c = 0; c < 3; ++c) v[3 * i + std::size_t(c)] = pos[i][c];
        auto* idx = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), tri.size()));
        for (std::size_t i = 0; i < tri.size(); ++i)
            for (int c = 0; c < 3; ++c) idx[3 * i + std::size_t(c)] = tri[i][c];
        stats_.triangles += tri.size();
        return g;
    };

    for (std::size_t m = 0; m < d_.meshes.size(); ++m) {
        const Mesh& mesh = d_.meshes[m];
        for (const glm::uvec3& t : mesh.triangles)
            for (int c = 0; c < 3; ++c)
                if (t[c] >= mesh.positions.size())
                    throw std::invalid_argument("mesh '" + mesh.name + "' has a vertex index out of range");
        if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
            throw std::invalid_argument("mesh '" + mesh.name + "' needs one normal per vertex");
        attach(add_triangles(mesh.positions, mesh.triangles), true, false);
        mesh_of_geom_.push_back(unsigned(m));
    }
    if (d_.light) {
        const AreaLight& l = *d_.light;
        if (!(l.area() > 0)) throw std::invalid_argument("the area light has zero area");
        const std::vector<glm::vec3> pos = {l.corner, l.corner + l.edge_u, l.corner + l.edge_u + l.edge_v,
                                            l.corner + l.edge_v};
        light_geom_ = attach(add_triangles(pos, {{0, 1, 2}, {0, 2, 3}}), true, false);
        mesh_of_geom_.push_back(~0u);
    }
    if (d_.hair.segment_count() > 0) {
        const Hair& hair = d_.hair;
        if (!(hair.radius > 0) || !std::isfinite(hair.radius))
            throw std::invalid_argument("the hair radius must be a positive number");
        for (std::uint32_t s = 0; s < hair.strands.size(); ++s) {
            const auto& strand = hair.strands[s];
            const std::uint32_t first = std::uint32_t(curve_vertices_.size());
            for (const glm::vec3& p : strand) curve_vertices_.emplace_back(p, hair.radius);
            for (std::size_t k = 1; k < strand.size(); ++k) {
                segment_start_.push_back(first + std::uint32_t(k - 1));
                strand_of_segment_.push_back(s);
            }
        }
        RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, curve_vertices_.data(), 0,
                                   sizeof(glm::vec4), curve_vertices_.size());
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, segment_start_.data(), 0,
                                   sizeof(std::uint32_t), segment_start_.size());
        hair_geom_ = attach(g, false, true);
        mesh_of_geom_.push_back(~0u);
        stats_.strands = hair.strands.size();
        stats_.hair_segments = segment_start_.size();
    }
    rtcCommitScene(all_);
    rtcCommitScene(opaque_);
    rtcCommitScene(hair_);
    if (const RTCError e = rtcGetDeviceError(device_); e != RTC_ERROR_NONE)
        throw std::runtime_error("Embree failed to build the scene (error " + std::to_string(int(e)) + ")");
    stats_.bvh_seconds = seconds_since(t_bvh);
    stats_.embree_bytes = std::size_t(std::max(0LL, embree_memory().peak.load()));

}

Scene::~Scene() {
    if (all_) rtcReleaseScene(all_);
    if (opaque_) rtcReleaseScene(opaque_);
    if (hair_) rtcReleaseScene(hair_);
    if (device_) rtcReleaseDevice(device_);
}

Hit Scene::hit_from(const RTCRayHit& rh, const glm::vec3& o, const glm::vec3& d) const {
    Hit hit;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
    hit.t = rh.ray.tfar;
    hit.p = o + hit.t * d;
    const unsigned g = rh.hit.geomID;
    if (g == hair_geom_) {
        hit.kind = Hit::kHair;
        const std::uint32_t first = segment_start_[rh.hit.primID];
        const glm::vec4 a = curve_vertices_[first], b = curve_vertices_[first + 1];
        const float u = std::clamp(rh.hit.u, 0.0f, 1.0f);
        const glm::vec3 axis = glm::mix(glm::vec3(a), glm::vec3(b), u);
        const float radius = a.w + u * (b.w - a.w);
        hit.axis = axis;
        hit.radius = radius;
        hit.tangent = glm::normalize(glm::vec3(b) - glm::vec3(a));
        hit.strand = strand_of_segment_[rh.hit.primID];
        return hit;
    }
    glm::vec3 n(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    if (g == light_geom_) {
        hit.kind = Hit::kLight;
        hit.front = glm::dot(d, d_.light->normal()) < 0;
        hit.n = d_.light->normal();
        return hit;
    }
    const Mesh& mesh = d_.meshes[mesh_of_geom_[g]];
    if (!mesh.normals.empty()) {
        const glm::uvec3 t = mesh.triangles[rh.hit.primID];
        const float u = rh.hit.u, v = rh.hit.v;
        n = (1 - u - v) * mesh.normals[t.x] + u * mesh.normals[t.y] + v * mesh.normals[t.z];
    }
    n = glm::normalize(n);
    hit.kind = Hit::kSurface;
    hit.n = glm::dot(n, d) > 0 ? -n : n;
    hit.albedo = mesh.albedo;
    return hit;
}

Hit Scene::intersect(const glm::vec3& o, const glm::vec3& d, float tmax, std::uint32_t ignore) const {
    IgnoreStrandContext ctx(ignore, 8.0f * d_.hair.radius, hair_geom_, strand_of_segment_.data());
    RTCRayHit rh = make_ray(o, d, ignore == kNoStrand ? kRayEpsilon : 0.0f, tmax);
    rtcIntersect1(all_, &ctx.base, &rh);
    return hit_from(rh, o, d);
}

Hit Scene::intersect_opaque(const glm::vec3& o, const glm::vec3& d, float tmax) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh = make_ray(o, d, kRayEpsilon, tmax);
    rtcIntersect1(opaque_, &ctx, &rh);
    return hit_from(rh, o, d);
}

bool Scene::occluded(const glm::vec3& o, const glm::vec3& d, float tmax, std::uint32_t ignore) const {
    IgnoreStrandContext ctx(ignore, 8.0f * d_.hair.radius, hair_geom_, strand_of_segment_.data());
    RTCRayHit rh = make_ray(o, d, ignore == kNoStrand ? kRayEpsilon : 0.0f, tmax);
    rtcOccluded1(all_, &ctx.base, &rh.ray);
    return rh.ray.tfar < 0;
}

bool Scene::hair_occluded(const glm::vec3& o, const glm::vec3& d, float tmax, std::uint32_t ignore) const {
    if (!has_hair()) return false;
    IgnoreStrandContext ctx(ignore, 8.0f * d_.hair.radius, hair_geom_, strand_of_segment_.data());
    RTCRayHit rh = make_ray(o, d, ignore == kNoStrand ? kRayEpsilon : 0.0f, tmax);
    rtcOccluded1(hair_, &ctx.base, &rh.ray);
    return rh.ray.tfar < 0;
}

std::uint32_t Scene::count_hair(const glm::vec3& o, const glm::vec3& d, float tmax, std::uint32_t ignore,
                                std::uint32_t limit, float* last_t) const {
    if (last_t) *last_t = 0.0f;
    if (!has_hair() || limit == 0) return 0;
    std::vector<std::uint32_t> overflow;
    CountStrandsContext ctx(ignore, 8.0f * d_.hair.radius, hair_geom_, strand_of_segment_.data(), &overflow);
    // Only the fixed array counts toward the limit (the overflow keeps duplicates).
    ctx.limit = limit <= CountStrandsContext::kCapacity ? limit : 0xffffffffu;
    RTCRayHit rh = make_ray(o, d, ignore == kNoStrand ? kRayEpsilon : 0.0f, tmax);
    rtcOccluded1(hair_, &ctx.base, &rh.ray);
    if (ctx.failed) throw std::bad_alloc();
    if (last_t) *last_t = ctx.last_t;
    if (overflow.empty()) return std::min(ctx.count, limit);
    // The array holds none of the overflow's strands (add checked it first).
    std::sort(overflow.begin(), overflow.end());
    return std::min(limit, ctx.count + std::uint32_t(std::unique(overflow.begin(), overflow.end()) - overflow.begin()));
}

}  // namespace render
