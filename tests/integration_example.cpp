// One straight fiber shaded as a pbrt-v4 or Mitsuba 3 path tracer would shade it: the
// program of docs/integration.md (tests/integration_example.cpp, run by the tests).
#include <hairscatter/dual.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>

namespace hs = hairscatter;
using glm::vec3;
using glm::vec4;

// The renderer's sampler: uniform numbers per path and dimension (here the library's hash).
struct Sampler {
    std::uint32_t path, dim = 0;
    float next() { return hs::hash_to_unit<float>(hs::pcg_hash(hs::pcg_hash(path) + dim++)); }
    vec4 next4() {
        const float a = next(), b = next(), c = next();
        return vec4(a, b, c, next());
    }
};

constexpr float kPi = 3.14159265f;
constexpr float kSkyPdf = 1 / (4 * kPi);  // the sky's light sampler: uniform on the sphere
vec3 uniform_sphere(float u1, float u2) {
    const float z = 1 - 2 * u1, r = std::sqrt(std::fmax(0.0f, 1 - z * z));
    return vec3(r * std::cos(2 * kPi * u2), r * std::sin(2 * kPi * u2), z);
}
float power_heuristic(float a, float b) { return a * a / (a * a + b * b); }
float mean(const vec3& v) { return (v.x + v.y + v.z) / 3; }

// The scene: one straight fiber of radius 0.05 along y through the origin, under a sky of
// constant radiance and a sun (a directional light: its irradiance and direction).
const vec3 kTangent(0, 1, 0);
constexpr float kRadius = 0.05f;
struct Sky {
    vec3 env, sun, to_sun;
    vec3 radiance(const vec3&) const { return env; }  // what a ray leaving the fiber finds
};

// A camera ray's hit as a curve intersector reports it: the direction toward the viewer,
// v ∈ [0, 1] across the fiber, dp/dv (the direction in which v grows; pbrt-v4: si.uv[1]
// and si.dpdv) and the hit point on the tube.
struct CurveHit {
    vec3 wo_world, dpdv, p;
    float v;
};
CurveHit camera_ray(Sampler& s) {
    CurveHit c;
    c.wo_world = uniform_sphere(s.next(), s.next());
    c.v = s.next();
    c.dpdv = glm::normalize(glm::cross(kTangent, c.wo_world));  // across a ribbon facing the ray
    const vec3 n = glm::normalize(c.wo_world - glm::dot(c.wo_world, kTangent) * kTangent);
    const float x = 2 * c.v - 1;
    c.p = kRadius * (x * c.dpdv + std::sqrt(1 - x * x) * n);
    return c;
}
//--8<--
// One camera path: the fiber hit, light sampling (the sun without MIS, as a delta light;
// the sky uniformly, with MIS against the fiber's pdf) and a BCSDF sample that continues
// the path. `expected` gathers what the estimate averages to: f · sun + albedo · sky.
vec3 trace(const hs::ChiangMaterial<float>& material, const Sky& sky, Sampler& s, vec3& expected, int& mirrored) {
    const CurveHit c = camera_ray(s);
    const auto hit = hs::FiberHit<float>::from_v(kTangent, c.wo_world, c.v, c.dpdv);
    // The same h from the hit point and an axis point (the origin). Here v grows along
    // -hit.frame.y: pbrt-v4's h = -1 + 2v, taken as it is, would be mirrored.
    if (std::abs(hit.h - hs::FiberHit<float>(c.p, vec3(0), kTangent, c.wo_world, kRadius).h) > 1e-4f) ++mirrored;
    const auto fiber = hs::ChiangFiber<float>(material, hit.h).at(hit.wo);  // the wo terms, once per hit

    vec3 L(0), beta(1);
    const vec3 f_sun = fiber.eval(hit.frame.to_local(sky.to_sun));  // cosine inside: no |cos θ| factor
    L += beta * f_sun * sky.sun;
    const vec3 wl = uniform_sphere(s.next(), s.next());
    const hs::HairEvalPdf<float> e = fiber.eval_pdf(hit.frame.to_local(wl));  // f and the BCSDF's pdf
    L += beta * e.f * sky.radiance(wl) * power_heuristic(kSkyPdf, e.pdf) / kSkyPdf;

    const hs::HairSample<float> b = fiber.sample(s.next4());  // four uniform numbers
    if (b.pdf > 0) {
        beta *= b.weight;                         // f / pdf
        const vec3 d = hit.frame.to_world(b.wi);  // the next ray; it leaves the lone fiber
        L += beta * sky.radiance(d) * power_heuristic(b.pdf, kSkyPdf);
    }
    expected += f_sun * sky.sun + fiber.albedo() * sky.env;
    return L;
}
//--8<--
// The renderer's own density source (its grid, BVH or volume): here a slab of hair |z| < half
// in which a ray crosses k fibers per unit length, asked from points inside it. Any type
// with this member plugs in.
struct HairSlab {
    float k, half;
    float fibers_crossed(const vec3& o, const vec3& d, float t_max) const {
        const float to_face = (half - (d.z > 0 ? o.z : -o.z)) / std::abs(d.z);  // +inf along the slab
        return k > 0 ? k * std::fmin(t_max, to_face) : 0;
    }
};

// What dual scattering needs to know along wi (world) at x: a shadow ray through the hair
// (drawn here: blocked with the probability 1 - e^-n of a Poisson count of mean n) and the
// density source's counts toward the light and beyond x.
hs::DualScatteringLight<float> light_along(const HairSlab& slab, const vec3& x, const vec3& wi, float u) {
    const float n = slab.fibers_crossed(x, wi, hs::kUnbounded<float>);
    return hs::dual_light(slab, x, wi, u < std::exp(-n) ? 1.0f : 0.0f);
}

// A camera path's hit on a fiber inside the slab, under the sky alone, shaded twice: by the
// dual BCSDF (a light sample with MIS, then a sample that continues the path with its
// weight) and by the two-stream estimator (an arrival direction from the fiber's sampler,
// the light along it from the fibers on either side of the point).
struct DualEstimate {
    vec3 bcsdf{0}, two_stream{0};
};
DualEstimate trace_dual(const hs::ChiangMaterial<float>& material, const hs::DualScatteringTables<float>& tables,
                        const HairSlab& slab, const Sky& sky, Sampler& s) {
    const CurveHit c = camera_ray(s);
    const auto hit = hs::FiberHit<float>::from_v(kTangent, c.wo_world, c.v, c.dpdv);
    const hs::ChiangFiber<float> fiber(material, hit.h);
    DualEstimate r;

    const auto at = hs::DualScatteringBcsdf<hs::ChiangFiber<float>>(fiber, tables).at(hit.wo);
    const vec3 wl = uniform_sphere(s.next(), s.next()), wl_local = hit.frame.to_local(wl);
    r.bcsdf = at.eval(wl_local, light_along(slab, c.p, wl, s.next())) * sky.radiance(wl) *
              power_heuristic(kSkyPdf, at.pdf(wl_local)) / kSkyPdf;
    const float u_shadow = s.next();
    const hs::DualSample<float> d = at.sample_with(s.next4(), [&](const vec3& wi) {  // asked once, for d.wi
        return light_along(slab, c.p, hit.frame.to_world(wi), u_shadow);
    });
    if (d.pdf > 0) r.bcsdf += d.weight * sky.radiance(hit.frame.to_world(d.wi)) * power_heuristic(d.pdf, kSkyPdf);

    const hs::HairSample<float> a = fiber.at(hit.wo).sample(s.next4());  // the light's arrival direction
    if (!(a.pdf > 0)) return r;
    const vec3 aw = hit.frame.to_world(a.wi);
    const float n = hs::poisson_fiber_count(slab.fibers_crossed(c.p, aw, hs::kUnbounded<float>), s.next(), false);
    if (n == 0) {
        r.two_stream = a.weight * sky.radiance(aw);  // no hair along a: the sky itself
    } else {
        const float m = hs::poisson_fiber_count(slab.fibers_crossed(c.p, -aw, hs::kUnbounded<float>), s.next(), false);
        const hs::DualSourceKernel<float> k(a.wi, hs::dual_streams(tables.view(), a.wi.x, n, m));
        const auto ks = k.sample(s.next4());  // where that light entered the hair
        if (ks.pdf > 0) r.two_stream = a.weight * ks.f / ks.pdf * sky.radiance(hit.frame.to_world(ks.s));
    }
    return r;
}
//--8<--
int main() {
    hs::FiberParams<float> params;                          // η 1.55, βm = βn = 0.3, α 2°: pbrt-v4's defaults
    const hs::ChiangMaterial<float> white(params);          // σa = 0: a lossless fiber
    params.sigma_a = hs::sigma_a_from_concentrations(1.3f, 0.0f);  // pbrt-v4's default eumelanin concentration
    const hs::ChiangMaterial<float> brown(params);
    const Sky furnace{vec3(1), vec3(0), vec3(0, 0, 1)};
    const Sky outdoors{vec3(0.2f, 0.3f, 0.5f), vec3(3), glm::normalize(vec3(0.3f, 0.4f, 1))};
    int failures = 0;
    const auto expect_one = [&](const char* what, float value, float tolerance) {
        const bool ok = std::abs(value - 1) < tolerance;
        std::printf("%-48s %.4f (1 within %g)%s\n", what, value, tolerance, ok ? "" : "  FAILED");
        failures += ok ? 0 : 1;
    };

    constexpr std::uint32_t kPaths = 1u << 16;
    vec3 white_sum(0), white_expected(0), brown_sum(0), brown_expected(0);
    int mirrored = 0;
    for (std::uint32_t i = 0; i < kPaths; ++i) {
        Sampler s{i}, t{kPaths + i};
        white_sum += trace(white, furnace, s, white_expected, mirrored);
        brown_sum += trace(brown, outdoors, t, brown_expected, mirrored);
    }
    expect_one("single fiber, white furnace", mean(white_sum) / kPaths, 0.01f);
    const char* channel[3] = {"brown fiber, sun and sky: estimate / expected, r", "g", "b"};
    for (int c = 0; c < 3; ++c) expect_one(channel[c], brown_sum[c] / brown_expected[c], 0.02f);

    // Dual scattering: tables once per material (host); a lone fiber (no hair around it)
    // and the same fiber inside a slab of hair 2 deep, 20 fibers per unit length.
    const auto tables = hs::DualScatteringTables<float>::build<hs::ChiangFiber<float>>(white);
    DualEstimate lone, slab;
    for (std::uint32_t i = 0; i < kPaths; ++i) {
        Sampler s{2 * kPaths + i}, t{3 * kPaths + i};
        lone.bcsdf += trace_dual(white, tables, HairSlab{0, 1}, furnace, s).bcsdf;
        const DualEstimate e = trace_dual(white, tables, HairSlab{20, 1}, furnace, t);
        slab.bcsdf += e.bcsdf, slab.two_stream += e.two_stream;
    }
    expect_one("dual BCSDF, lone fiber, white furnace", mean(lone.bcsdf) / kPaths, 0.02f);
    expect_one("two-stream, fiber in the slab, white furnace", mean(slab.two_stream) / kPaths, 0.005f);
    std::printf("%-48s %.4f (not energy conserving)\n", "dual BCSDF, fiber in the slab, white furnace",
                mean(slab.bcsdf) / kPaths);

    // Spectral use: a channel of f depends on that channel's σa alone.
    hs::FiberParams<float> other = brown.params();
    other.sigma_a.g = 5.0f, other.sigma_a.b = 0.0f;
    const hs::ChiangMaterial<float> mixed(other);
    int coupled = 0;
    for (std::uint32_t i = 0; i < 1024; ++i) {
        Sampler s{4 * kPaths + i};
        const vec3 wo = uniform_sphere(s.next(), s.next()), wi = uniform_sphere(s.next(), s.next());
        const float h = 2 * s.next() - 1;
        coupled += hs::ChiangFiber<float>(brown, h).eval(wo, wi).r != hs::ChiangFiber<float>(mixed, h).eval(wo, wi).r;
    }
    std::printf("mirrored h: %d of %u hits; channels coupled: %d of 1024 pairs\n", mirrored, 2 * kPaths, coupled);
    return failures == 0 && mirrored == 0 && coupled == 0 ? 0 : 1;
}
