// render — the integrators (single scattering, dual scattering, path tracing), tiles in
// parallel with TBB, a progress bar, and the memory helpers.
#include "render.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <limits>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "rng.hpp"

namespace render {
namespace hs = hairscatter;
using glm::vec3;
using glm::vec4;

const char* to_string(Integrator i) {
    switch (i) {
        case Integrator::kSingle: return "single";
        case Integrator::kDual: return "dual";
        case Integrator::kPath: return "path";
    }
    return "?";
}
const char* to_string(Sampling s) {
    switch (s) {
        case Sampling::kUniform: return "uniform";
        case Sampling::kImportance: return "importance";
        case Sampling::kMis: return "mis";
    }
    return "?";
}

namespace {

constexpr float kPi = 3.14159265358979f;
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kSurfaceOffset = 1e-4f;

float max3(const vec3& v) { return std::max({v.x, v.y, v.z}); }
bool finite3(const vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
float power_heuristic(float a, float b) { return a * a / (a * a + b * b); }

vec3 uniform_sphere(float u1, float u2) {
    const float z = 1 - 2 * u1, r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPi * u2;
    return vec3(r * std::cos(phi), r * std::sin(phi), z);
}

// An orthonormal basis around n (Duff et al. 2017).
void basis(const vec3& n, vec3& t, vec3& b) {
    const float s = std::copysign(1.0f, n.z);
    const float a = -1.0f / (s + n.z), c = n.x * n.y * a;
    t = vec3(1 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

vec3 cosine_hemisphere(const vec3& n, float u1, float u2) {
    const float r = std::sqrt(u1), phi = 2 * kPi * u2;
    vec3 t, b;
    basis(n, t, b);
    return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0f, 1 - u1)) * n);
}

struct Sampler {
    Pcg32& rng;
    float u() { return rng.uniform(); }
    vec4 u4() { return vec4(u(), u(), u(), u()); }
};

// The lights: the area light (picked with probability p_area) and the constant environment.
struct Lights {
    const AreaLight* area = nullptr;
    vec3 env{0};
    float p_area = 0;

    explicit Lights(const SceneDescription& d) {
        if (d.light && max3(d.light->radiance) > 0) area = &*d.light;
        env = d.environment;
        const bool has_env = max3(env) > 0;
        p_area = area ? (has_env ? 0.5f : 1.0f) : 0.0f;
    }
    bool any() const { return p_area > 0 || max3(env) > 0; }

    struct Sample {
        vec3 wi{0}, Le{0};
        float dist = 0, pdf = 0;  // pdf in solid angle, including the light selection
    };
    Sample sample(const vec3& x, float u0, float u1, float u2) const {
        Sample s;
        if (u0 < p_area) {
            const vec3 q = area->corner + u1 * area->edge_u + u2 * area->edge_v;
            vec3 d = q - x;
            const float dist = glm::length(d);
            if (!(dist > 0)) return s;
            d /= dist;
            const float cos_l = -glm::dot(d, area->normal());
            if (cos_l <= 0) return s;
            s.wi = d;
            s.dist = dist;
            s.Le = area->radiance;
            s.pdf = p_area * dist * dist / (area->area() * cos_l);
        } else {
            s.wi = uniform_sphere(u1, u2);
            s.dist = kInf;
            s.Le = env;
            s.pdf = (1 - p_area) / (4 * kPi);
        }
        return s;
    }
    // The pdf with which sample() picks the direction that reached the area light at
    // distance t (front side) / escaped to the environment.
    float pdf_area(const vec3& wi, float t) const {
        const float cos_l = -glm::dot(wi, area->normal());
        return cos_l > 0 ? p_area * t * t / (area->area() * cos_l) : 0.0f;
    }
    float pdf_env() const { return (1 - p_area) / (4 * kPi); }
};

class Renderer {
  public:
    Renderer(const Scene& scene, const RenderOptions& o) : s_(scene), o_(o), lights_(scene.description()) {}

    // Radiance along the camera ray o + t d.
    vec3 radiance(const vec3& o, const vec3& d, Sampler& rng) const {
        switch (o_.integrator) {
            case Integrator::kPath: return path(o, d, rng);
            default: return direct(o, d, rng);
        }
    }

  private:
    // --- single and dual scattering: the camera ray's first hit, lit directly -----------
    vec3 direct(const vec3& o, const vec3& d, Sampler& rng) const {
        const Hit hit = s_.intersect(o, d, kInf);
        switch (hit.kind) {
            case Hit::kMiss: return lights_.env;
            case Hit::kLight: return hit.front ? lights_.area->radiance : vec3(0);
            case Hit::kSurface: return surface_direct(hit, rng);
            case Hit::kHair:
                return o_.integrator == Integrator::kSingle ? hair_single(hit, -d, rng) : hair_dual(hit, -d, rng);
        }
        return vec3(0);
    }

    // Lambertian surface: one sample of the area light and one cosine-distributed sample of
    // the environment; everything (hair included) casts opaque shadows.
    vec3 surface_direct(const Hit& hit, Sampler& rng) const {
        const float u1 = rng.u(), u2 = rng.u(), u3 = rng.u(), u4 = rng.u();
        const vec3 x = hit.p + kSurfaceOffset * hit.n;
        vec3 L(0);
        if (lights_.area) {
            // sample() with u0 = 0 picks the area light; its pdf includes the selection p_area.
            const Lights::Sample ls = lights_.sample(hit.p, 0.0f, u1, u2);
            const float cos_i = glm::dot(hit.n, ls.wi);
            if (ls.pdf > 0 && cos_i > 0 && !s_.occluded(x, ls.wi, ls.dist * (1 - 1e-4f)))
                L += hit.albedo * (cos_i / kPi) * ls.Le * lights_.p_area / ls.pdf;
        }
        if (max3(lights_.env) > 0 && !s_.occluded(x, cosine_hemisphere(hit.n, u3, u4), kInf))
            L += hit.albedo * lights_.env;  // f cos / pdf = albedo
        return L;
    }

    // Single scattering: one light sample through ChiangFiber, hair shadows opaque.
    vec3 hair_single(const Hit& hit, const vec3& wo, Sampler& rng) const {
        if (!lights_.any()) return vec3(0);
        const hs::FiberFrame<float> frame(hit.tangent, wo);
        const hs::ChiangFiber<float> fiber(s_.material(), hit.h);
        const float u0 = rng.u(), u1 = rng.u(), u2 = rng.u();
        const Lights::Sample ls = lights_.sample(hit.p, u0, u1, u2);
        if (!(ls.pdf > 0)) return vec3(0);
        if (s_.occluded(hit.p, ls.wi, ls.dist * (1 - 1e-4f), hit.strand)) return vec3(0);
        return fiber.eval(frame.to_local(wo), frame.to_local(ls.wi)) * ls.Le / ls.pdf;
    }

    // What the light arriving along wi from the hair point x looks like to dual scattering.
    struct Incoming {
        bool visible = false;  // no wall, ground or sphere in the way
        vec3 Le{0};
        float light_pdf = 0;   // the pdf with which the light sampler picks wi (for MIS)
        hs::DualScatteringLight<float> state;
    };
    // dist: the light sample's distance, or 0 for a direction from the BCSDF sampler (then
    // the light it reaches, if any, is found here).
    Incoming incoming(const Hit& hit, const vec3& wi, float dist) const {
        Incoming in;
        if (dist == 0) {
            const Hit o = s_.intersect_opaque(hit.p, wi, kInf);
            if (o.kind == Hit::kLight && o.front) {
                in.Le = lights_.area->radiance;
                in.light_pdf = lights_.pdf_area(wi, o.t);
                dist = o.t;
            } else if (o.kind == Hit::kMiss) {
                in.Le = lights_.env;
                in.light_pdf = lights_.pdf_env();
                dist = kInf;
            } else {
                return in;
            }
        } else if (s_.intersect_opaque(hit.p, wi, std::isfinite(dist) ? dist * (1 - 1e-4f) : kInf).kind != Hit::kMiss) {
            return in;
        }
        in.visible = true;
        in.state.d_f = o_.d_f;
        in.state.d_b = o_.d_b;
        // Seed thesis §4.2: a shadow ray decides the direct fraction; only shadowed points
        // read the density grid for the number of fibers toward the light.
        if (s_.hair_occluded(hit.p, wi, dist, hit.strand)) {
            in.state.direct_fraction = 0;
            in.state.n = s_.grid()->fibers_crossed(hit.p, wi, std::isfinite(dist) ? dist : hs::kUnbounded<float>);
        } else {
            in.state.direct_fraction = 1;
            in.state.n = 0;
        }
        return in;
    }

    // Dual scattering at a hair hit: the estimator chosen by --sampling.
    vec3 hair_dual(const Hit& hit, const vec3& wo, Sampler& rng) const {
        if (!lights_.any()) return vec3(0);
        const hs::FiberFrame<float> frame(hit.tangent, wo);
        const vec3 wo_l = frame.to_local(wo);
        const hs::ChiangFiber<float> fiber(s_.material(), hit.h);
        const auto& tables = s_.tables();
        auto shade = [&](const hs::DualScatteringLight<float>& st, const vec3& wi) {
            return hs::DualScatteringFiber<float>(fiber, tables, st).eval(wo_l, frame.to_local(wi));
        };

        // The sampling density: an equal mixture of the dual BCSDF as seen by a directly lit
        // point and as seen by a point in the hair's shadow (n toward the main light), since
        // which applies is only known once a direction is chosen. Both cover the sphere.
        hs::DualScatteringLight<float> lit, shadowed;
        lit.d_f = shadowed.d_f = o_.d_f;
        lit.d_b = shadowed.d_b = o_.d_b;
        shadowed.direct_fraction = 0;
        const vec3 toward = lights_.area ? glm::normalize(lights_.area->corner + 0.5f * (lights_.area->edge_u + lights_.area->edge_v) - hit.p)
                                         : vec3(0, 1, 0);
        // (uniform sampling needs no mixture: skip the march)
        if (o_.sampling != Sampling::kUniform) shadowed.n = s_.grid()->fibers_crossed(hit.p, toward, hs::kUnbounded<float>);
        const hs::DualScatteringFiber<float> f_lit(fiber, tables, lit), f_shadowed(fiber, tables, shadowed);
        auto bcsdf_pdf = [&](const vec3& wi_l) {
            if (o_.sampling == Sampling::kUniform) return 1.0f / (4 * kPi);
            return 0.5f * f_lit.pdf(wo_l, wi_l) + 0.5f * f_shadowed.pdf(wo_l, wi_l);
        };

        vec3 L(0);
        if (o_.sampling == Sampling::kMis) {
            const float u0 = rng.u(), u1 = rng.u(), u2 = rng.u();
            const Lights::Sample ls = lights_.sample(hit.p, u0, u1, u2);
            if (ls.pdf > 0) {
                const Incoming in = incoming(hit, ls.wi, ls.dist);
                if (in.visible) {
                    const float w = power_heuristic(ls.pdf, bcsdf_pdf(frame.to_local(ls.wi)));
                    L += w * shade(in.state, ls.wi) * ls.Le / ls.pdf;
                }
            }
        }
        // One BCSDF (or uniform) sample.
        vec3 wi_l;
        float pdf;
        const vec4 u = rng.u4();
        if (o_.sampling == Sampling::kUniform) {
            const hs::HairSample<float> s = hs::UniformSphereSampling<hs::DualScatteringFiber<float>>(f_lit).sample(wo_l, u);
            wi_l = s.wi;
            pdf = s.pdf;
        } else {
            const bool first = u.x < 0.5f;
            const vec4 v(first ? 2 * u.x : 2 * u.x - 1, u.y, u.z, u.w);
            const hs::HairSample<float> s = first ? f_lit.sample(wo_l, v) : f_shadowed.sample(wo_l, v);
            wi_l = s.wi;
            pdf = bcsdf_pdf(wi_l);
        }
        if (!(pdf > 0)) return L;
        const vec3 wi = glm::normalize(frame.to_world(wi_l));
        const Incoming in = incoming(hit, wi, 0);
        if (!in.visible || max3(in.Le) <= 0) return L;
        const float w = o_.sampling == Sampling::kMis ? power_heuristic(pdf, in.light_pdf) : 1.0f;
        L += w * shade(in.state, wi) * in.Le / pdf;
        return L;
    }

    // --- path tracing -------------------------------------------------------------------
    vec3 path(vec3 o, vec3 d, Sampler& rng) const {
        vec3 L(0), beta(1);
        std::uint32_t ignore = kNoStrand;
        float prev_pdf = 0;  // pdf of the direction that led here (0: camera, no MIS)
        const bool mis = o_.sampling == Sampling::kMis;
        for (int depth = 0; depth < o_.max_depth; ++depth) {
            const Hit hit = s_.intersect(o, d, kInf, ignore);
            if (hit.kind == Hit::kMiss) {
                const float w = mis && prev_pdf > 0 ? power_heuristic(prev_pdf, lights_.pdf_env()) : 1.0f;
                L += beta * lights_.env * w;
                break;
            }
            if (hit.kind == Hit::kLight) {
                if (hit.front) {
                    const float w = mis && prev_pdf > 0 ? power_heuristic(prev_pdf, lights_.pdf_area(d, hit.t)) : 1.0f;
                    L += beta * lights_.area->radiance * w;
                }
                break;
            }
            const vec3 wo = -d;
            if (hit.kind == Hit::kHair) {
                const hs::FiberFrame<float> frame(hit.tangent, wo);
                const vec3 wo_l = frame.to_local(wo);
                const hs::ChiangFiber<float> fiber(s_.material(), hit.h);
                const auto at = fiber.at(wo_l);
                if (mis && lights_.any()) {
                    const float u0 = rng.u(), u1 = rng.u(), u2 = rng.u();
                    const Lights::Sample ls = lights_.sample(hit.p, u0, u1, u2);
                    if (ls.pdf > 0 && !s_.occluded(hit.p, ls.wi, ls.dist * (1 - 1e-4f), hit.strand)) {
                        const auto ep = at.eval_pdf(frame.to_local(ls.wi));
                        L += beta * ep.f * ls.Le * power_heuristic(ls.pdf, ep.pdf) / ls.pdf;
                    }
                }
                hs::HairSample<float> s;
                if (o_.sampling == Sampling::kUniform)
                    s = hs::UniformSphereSampling<hs::ChiangFiber<float>>(fiber).sample(wo_l, rng.u4());
                else
                    s = at.sample(rng.u4());
                if (!(s.pdf > 0)) break;
                beta *= s.weight;
                prev_pdf = s.pdf;
                o = hit.p;
                d = glm::normalize(frame.to_world(s.wi));
                ignore = hit.strand;
            } else {  // Lambertian surface
                const vec3 x = hit.p + kSurfaceOffset * hit.n;
                if (mis && lights_.any()) {
                    const float u0 = rng.u(), u1 = rng.u(), u2 = rng.u();
                    const Lights::Sample ls = lights_.sample(hit.p, u0, u1, u2);
                    const float cos_i = glm::dot(hit.n, ls.wi);
                    if (ls.pdf > 0 && cos_i > 0 && !s_.occluded(x, ls.wi, ls.dist * (1 - 1e-4f))) {
                        const float pdf_b = cos_i / kPi;
                        L += beta * hit.albedo * (cos_i / kPi) * ls.Le * power_heuristic(ls.pdf, pdf_b) / ls.pdf;
                    }
                }
                const float u1 = rng.u(), u2 = rng.u();
                d = cosine_hemisphere(hit.n, u1, u2);
                prev_pdf = std::max(glm::dot(hit.n, d), 0.0f) / kPi;
                if (!(prev_pdf > 0)) break;
                beta *= hit.albedo;  // f cos / pdf = albedo
                o = x;
                ignore = kNoStrand;
            }
            // Russian roulette after three bounces, keeping the estimate unbiased.
            if (depth >= 3) {
                const float q = std::min(0.95f, max3(beta));
                if (rng.u() >= q) break;
                beta /= q;
            }
            if (!finite3(beta)) break;
        }
        return L;
    }

    const Scene& s_;
    const RenderOptions& o_;
    Lights lights_;
};

struct CameraRays {
    vec3 eye, forward, right, up;
    float tan_half, aspect;
    int width, height;
    CameraRays(const Camera& c, int w, int h) : eye(c.eye), width(w), height(h) {
        forward = glm::normalize(c.target - c.eye);
        right = glm::normalize(glm::cross(forward, c.up));
        up = glm::cross(right, forward);
        tan_half = std::tan(0.5f * c.fov_y_deg * kPi / 180.0f);
        aspect = float(w) / float(h);
    }
    vec3 direction(float px, float py) const {
        const float sx = (2 * px / float(width) - 1) * tan_half * aspect;
        const float sy = (1 - 2 * py / float(height)) * tan_half;
        return glm::normalize(forward + sx * right + sy * up);
    }
};

// A progress bar on stderr, drawn from its own thread once the work has taken a second.
class Progress {
  public:
    Progress(std::size_t total, bool enabled) : total_(total), start_(Clock::now()) {
        if (enabled) thread_ = std::thread([this] { loop(); });
    }
    ~Progress() {
        {
            std::lock_guard<std::mutex> lock(m_);
            stop_ = true;
        }
        cv_.notify_all();
        if (thread_.joinable()) thread_.join();
        if (drawn_) {
            draw(total_);
            std::fputc('\n', stderr);
        }
    }
    void add(std::size_t n) { done_ += n; }

  private:
    using Clock = std::chrono::steady_clock;
    void loop() {
        std::unique_lock<std::mutex> lock(m_);
        while (!cv_.wait_for(lock, std::chrono::milliseconds(250), [this] { return stop_; })) {
            if (std::chrono::duration<double>(Clock::now() - start_).count() < 1.0) continue;
            draw(done_.load());
            drawn_ = true;
        }
    }
    void draw(std::size_t done) const {
        const double t = std::chrono::duration<double>(Clock::now() - start_).count();
        const double f = total_ ? double(done) / double(total_) : 1.0;
        const int width = 30, filled = int(f * width);
        char bar[width + 1];
        for (int i = 0; i < width; ++i) bar[i] = i < filled ? '#' : '.';
        bar[width] = 0;
        const double eta = f > 0 ? t * (1 - f) / f : 0.0;
        std::fprintf(stderr, "\r[%s] %5.1f%%  %6.1f s  ETA %6.1f s ", bar, 100 * f, t, eta);
        std::fflush(stderr);
    }
    std::size_t total_;
    std::atomic<std::size_t> done_{0};
    Clock::time_point start_;
    std::mutex m_;
    std::condition_variable cv_;
    bool stop_ = false, drawn_ = false;
    std::thread thread_;
};

std::size_t status_bytes(const char* key) {
    std::ifstream f("/proc/self/status");
    std::string line;
    const std::string k = std::string(key) + ":";
    while (std::getline(f, line))
        if (line.compare(0, k.size(), k) == 0) return std::size_t(std::stoull(line.substr(k.size()))) * 1024;  // kB
    return 0;
}

}  // namespace

std::size_t peak_rss_bytes() { return status_bytes("VmHWM"); }
std::size_t current_rss_bytes() { return status_bytes("VmRSS"); }

RenderResult render(const Scene& scene, const RenderOptions& o) {
    if (o.width < 1 || o.height < 1 || o.spp < 1 || o.max_depth < 1 || o.tile < 1)
        throw std::invalid_argument("render: width, height, spp, max_depth and tile must be ≥ 1");
    if (!(o.d_f >= 0 && o.d_f <= 1 && o.d_b >= 0 && o.d_b <= 1))
        throw std::invalid_argument("render: d_f and d_b must lie in [0, 1]");
    const auto t0 = std::chrono::steady_clock::now();
    RenderResult r;
    r.width = o.width;
    r.height = o.height;
    r.rgb.assign(std::size_t(o.width) * std::size_t(o.height) * 3, 0.0f);
    r.hair_mask.assign(std::size_t(o.width) * std::size_t(o.height), 0);

    const CameraRays cam(scene.description().camera, o.width, o.height);
    const Renderer renderer(scene, o);
    const int tiles_x = (o.width + o.tile - 1) / o.tile, tiles_y = (o.height + o.tile - 1) / o.tile;
    std::atomic<std::uint64_t> samples{0}, dropped{0};
    std::atomic<std::size_t> hair_pixels{0};
    {
        Progress progress(std::size_t(o.width) * std::size_t(o.height), o.progress);
        tbb::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y, 1), [&](const tbb::blocked_range<int>& range) {
            for (int tile = range.begin(); tile < range.end(); ++tile) {
                const int x0 = (tile % tiles_x) * o.tile, y0 = (tile / tiles_x) * o.tile;
                const int x1 = std::min(x0 + o.tile, o.width), y1 = std::min(y0 + o.tile, o.height);
                std::uint64_t n = 0, bad = 0;
                std::size_t hair = 0;
                for (int y = y0; y < y1; ++y)
                    for (int x = x0; x < x1; ++x) {
                        const std::size_t i = std::size_t(y) * std::size_t(o.width) + std::size_t(x);
                        const bool on_hair =
                            scene.intersect(cam.eye, cam.direction(float(x) + 0.5f, float(y) + 0.5f), kInf).kind ==
                            Hit::kHair;
                        r.hair_mask[i] = on_hair ? 1 : 0;
                        hair += on_hair;
                        if (o.hair_only && !on_hair) continue;
                        Pcg32 gen = pixel_rng(o.seed, x, y);
                        Sampler rng{gen};
                        vec3 sum(0);
                        for (int k = 0; k < o.spp; ++k) {
                            const float jx = rng.u(), jy = rng.u();
                            const vec3 L = renderer.radiance(cam.eye, cam.direction(float(x) + jx, float(y) + jy), rng);
                            if (finite3(L)) sum += L;
                            else ++bad;
                            ++n;
                        }
                        for (int c = 0; c < 3; ++c) r.rgb[3 * i + std::size_t(c)] = sum[c] / float(o.spp);
                    }
                samples += n;
                dropped += bad;
                hair_pixels += hair;
                progress.add(std::size_t(x1 - x0) * std::size_t(y1 - y0));
            }
        });
    }
    r.samples = samples;
    r.dropped = dropped;
    r.hair_pixels = hair_pixels;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

std::string summary_line(const Scene& scene, const RenderOptions& o, const RenderResult& r) {
    const SceneStats& st = scene.stats();
    std::ostringstream s;
    s.setf(std::ios::fixed);
    s.precision(3);
    const double mb = 1.0 / (1024.0 * 1024.0);
    std::size_t nonfinite = 0;
    for (std::size_t i = 0; i + 2 < r.rgb.size(); i += 3)
        nonfinite += !(std::isfinite(r.rgb[i]) && std::isfinite(r.rgb[i + 1]) && std::isfinite(r.rgb[i + 2]));
    s << "scene=" << scene.description().name << " integrator=" << to_string(o.integrator)
      << " sampling=" << to_string(o.sampling) << " width=" << r.width << " height=" << r.height << " spp=" << o.spp
      << " seed=" << o.seed << " strands=" << st.strands << " segments=" << st.hair_segments
      << " time_s=" << r.seconds << " build_s=" << st.build_seconds << " samples=" << r.samples
      << " dropped=" << r.dropped << " nonfinite_pixels=" << nonfinite << " hair_pixels=" << r.hair_pixels << " embree_mb=" << st.embree_bytes * mb
      << " grid_mb=" << st.grid_bytes * mb << " grid_res=" << st.grid_resolution.x << "x" << st.grid_resolution.y
      << "x" << st.grid_resolution.z << " tables_kb=" << st.table_bytes / 1024.0
      << " peak_rss_mb=" << peak_rss_bytes() * mb;
    // Mean radiance over the hair pixels (the mask), for quick comparisons of integrators.
    glm::dvec3 mean(0.0);
    for (std::size_t i = 0; i < r.hair_mask.size(); ++i)
        if (r.hair_mask[i])
            for (int c = 0; c < 3; ++c) mean[c] += double(r.rgb[3 * i + std::size_t(c)]);
    if (r.hair_pixels > 0) mean /= double(r.hair_pixels);
    s.precision(5);
    s << " mean_hair_rgb=" << mean.r << "," << mean.g << "," << mean.b;
    return s.str();
}

}  // namespace render
