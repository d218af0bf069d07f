// render — the image loop: tiles in parallel with TBB, one PCG32 stream per pixel, the
// chosen integrator per camera sample; the summary line and the memory helpers.
#include "render.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "camera.hpp"
#include "integrators/integrator.hpp"
#include "progress.hpp"
#include "rng.hpp"

namespace render {
using glm::vec3;

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
std::size_t status_bytes(const char* key) {
    std::ifstream f("/proc/self/status");
    std::string line;
    const std::string k = std::string(key) + ":";
    while (std::getline(f, line))
        if (line.compare(0, k.size(), k) == 0) return std::size_t(std::stoull(line.substr(k.size()))) * 1024;  // kB
    return 0;
}

// ThreadSanitizer cannot see the happens-before edges of TBB's task spawn and join: they
// run inside the uninstrumented libtbb. In a TSan build (scripts/tsan.sh) the tile loop
// states them itself: everything the caller did before the loop happens before every tile
// (fork), and every tile happens before the caller reads the image (join). Tiles get no
// edge between each other, so a race between two tiles is still reported.
#if defined(__SANITIZE_THREAD__)
#define RENDER_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define RENDER_TSAN 1
#endif
#endif
#if defined(RENDER_TSAN)
extern "C" void __tsan_acquire(void* addr);
extern "C" void __tsan_release(void* addr);
void tsan_release(void* sync) { __tsan_release(sync); }
void tsan_acquire(void* sync) { __tsan_acquire(sync); }
#else
void tsan_release(void*) {}
void tsan_acquire(void*) {}
#endif
}  // namespace

std::size_t peak_rss_bytes() { return status_bytes("VmHWM"); }
std::size_t current_rss_bytes() { return status_bytes("VmRSS"); }

void validate(const RenderOptions& o) {
    auto require = [](bool ok, const std::string& m) {
        if (!ok) throw std::invalid_argument(m);
    };
    require(o.width >= 1 && o.height >= 1, "--width and --height must be >= 1");
    require(o.spp >= 1 && o.spp <= 1'000'000, "--spp must be in [1, 10^6] (got " + std::to_string(o.spp) + ")");
    require(o.max_depth >= 1 && o.max_depth <= 1'000'000,
            "--max-depth must be in [1, 10^6] (got " + std::to_string(o.max_depth) + ")");
    require(o.tile >= 1, "the tile size must be >= 1");
    require(o.threads >= 0 && o.threads <= 1024, "--threads must be in [0, 1024] (got " + std::to_string(o.threads) + ")");
    const Crop& c = o.crop;
    require(c.empty() || (c.x0 >= 0 && c.y0 >= 0 && c.x0 < c.x1 && c.y0 < c.y1 && c.x1 <= o.width && c.y1 <= o.height),
            "--crop " + std::to_string(c.x0) + "," + std::to_string(c.y0) + "," + std::to_string(c.x1) + "," +
                std::to_string(c.y1) + " must be a window x0,y0,x1,y1 with 0 <= x0 < x1 <= --width (" +
                std::to_string(o.width) + ") and 0 <= y0 < y1 <= --height (" + std::to_string(o.height) + ")");
}

RenderResult render(const Scene& scene, const ShadingSetup& shading, const RenderOptions& o) {
    validate(o);
    if (o.integrator == Integrator::kDual && shading.options().model != FiberModel::kFur &&
        (shading.options().model != FiberModel::kChiang || shading.options().lobes != hairscatter_examples::LobeBits::kAll))
        throw std::invalid_argument("--integrator dual shades with the full Chiang model or the fur model only (no "
                                    "other --model, no --lobes)");
    if (o.integrator == Integrator::kDual && scene.has_hair() &&
        (!shading.options().dual_scattering || (shading.needs_grid() && !shading.grid())))
        throw std::invalid_argument("--integrator dual needs a shading setup built with dual_scattering");
    validate(scene.description().camera);
    const auto t0 = std::chrono::steady_clock::now();
    const Crop win = o.crop.empty() ? Crop{0, 0, o.width, o.height} : o.crop;
    RenderResult r;
    r.width = win.x1 - win.x0;
    r.height = win.y1 - win.y0;
    r.rgb.assign(std::size_t(r.width) * std::size_t(r.height) * 3, 0.0f);
    r.hair_mask.assign(std::size_t(r.width) * std::size_t(r.height), 0);

    const CameraRays cam(scene.description().camera, o.width, o.height);
    const RenderContext context(scene, shading, o);
    const std::unique_ptr<PixelIntegrator> integrator = o.integrator == Integrator::kSingle ? make_single_integrator(context)
                                                        : o.integrator == Integrator::kDual ? make_dual_integrator(context)
                                                                                            : make_path_integrator(context);
    const int tiles_x = (r.width + o.tile - 1) / o.tile, tiles_y = (r.height + o.tile - 1) / o.tile;
    std::atomic<std::uint64_t> samples{0}, dropped{0};
    std::atomic<std::size_t> hair_pixels{0};
    std::atomic<std::int64_t> hair_ns{0};
    {
        Progress progress(std::size_t(r.width) * std::size_t(r.height), o.progress);
        char fork = 0, join = 0;  // TSan's sync objects (see tsan_release)
        auto tiles = [&](const tbb::blocked_range<int>& range) {
            tsan_acquire(&fork);
            for (int tile = range.begin(); tile < range.end(); ++tile) {
                // In frame pixels: the camera's rays and the random numbers are the frame's.
                const int x0 = win.x0 + (tile % tiles_x) * o.tile, y0 = win.y0 + (tile / tiles_x) * o.tile;
                const int x1 = std::min(x0 + o.tile, win.x1), y1 = std::min(y0 + o.tile, win.y1);
                std::uint64_t n = 0, bad = 0;
                std::size_t hair = 0;
                std::int64_t ns = 0;
                for (int y = y0; y < y1; ++y)
                    for (int x = x0; x < x1; ++x) {
                        const std::size_t i =
                            std::size_t(y - win.y0) * std::size_t(r.width) + std::size_t(x - win.x0);
                        const bool on_hair =
                            scene.intersect(cam.eye(), cam.direction(float(x) + 0.5f, float(y) + 0.5f), kInf).kind ==
                            Hit::kHair;
                        r.hair_mask[i] = on_hair ? 1 : 0;
                        hair += on_hair;
                        if (o.hair_only && !on_hair) continue;
                        Pcg32 gen = pixel_rng(o.seed, x, y);
                        Sampler rng{gen};
                        const auto pixel_start =
                            on_hair ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point();
                        vec3 sum(0);
                        for (int k = 0; k < o.spp; ++k) {
                            const float jx = rng.u(), jy = rng.u();
                            const vec3 L =
                                integrator->radiance(cam.eye(), cam.direction(float(x) + jx, float(y) + jy), rng);
                            if (finite3(L)) sum += L;
                            else ++bad;
                            ++n;
                        }
                        if (on_hair)
                            ns += std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() -
                                                                                       pixel_start)
                                      .count();
                        for (int c = 0; c < 3; ++c) r.rgb[3 * i + std::size_t(c)] = sum[c] / float(o.spp);
                    }
                samples += n;
                dropped += bad;
                hair_pixels += hair;
                hair_ns += ns;
                progress.add(std::size_t(x1 - x0) * std::size_t(y1 - y0));
            }
            tsan_release(&join);
        };
        const tbb::blocked_range<int> all(0, tiles_x * tiles_y, 1);
        tsan_release(&fork);
        if (o.threads == 0) {
            tbb::parallel_for(all, tiles);
        } else {
            // --threads N: an arena of N threads, more than the cores if asked (a race
            // detector wants threads to interleave even on a small machine).
            const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(o.threads));
            tbb::task_arena arena(o.threads);
            arena.execute([&] { tbb::parallel_for(all, tiles); });
        }
        tsan_acquire(&join);
    }
    r.samples = samples;
    r.dropped = dropped;
    r.hair_pixels = hair_pixels;
    r.hair_seconds = double(hair_ns.load()) * 1e-9;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

std::string summary_line(const Scene& scene, const ShadingSetup& shading, const RenderOptions& o,
                         const RenderResult& r) {
    const SceneStats& st = scene.stats();
    const ShadingStats& sh = shading.stats();
    std::ostringstream s;
    s.setf(std::ios::fixed);
    s.precision(3);
    const double mb = 1.0 / (1024.0 * 1024.0);
    std::size_t nonfinite = 0;
    for (std::size_t i = 0; i + 2 < r.rgb.size(); i += 3)
        nonfinite += !(std::isfinite(r.rgb[i]) && std::isfinite(r.rgb[i + 1]) && std::isfinite(r.rgb[i + 2]));
    s << "scene=" << scene.description().name << " integrator=" << to_string(o.integrator)
      << " sampling=" << to_string(o.sampling);
    if (o.integrator == Integrator::kDual) {
        const ShadingOptions& so = shading.options();
        s << " dual=" << (so.two_stream ? "two-stream" : so.dual.formulation == hairscatter::DualFormulation::kZinke2008 ? "zinke" : "improved");
        if (so.two_stream) s << " counts=" << to_string(so.counts) << " source=" << to_string(so.source);
    }
    s << " model=" << hairscatter_examples::to_string(shading.options().model)
      << " lobes=" << hairscatter_examples::lobes_to_string(shading.options().lobes) << " width=" << r.width
      << " height=" << r.height << " spp=" << o.spp << " seed=" << o.seed << " strands=" << st.strands
      << " segments=" << st.hair_segments << " time_s=" << r.seconds << " build_s=" << st.bvh_seconds + sh.seconds
      << " samples=" << r.samples << " dropped=" << r.dropped << " nonfinite_pixels=" << nonfinite
      << " hair_pixels=" << r.hair_pixels << " hair_us_per_sample=" << r.hair_us_per_sample(o.spp) << " embree_mb=" << st.embree_bytes * mb << " grid_mb=" << sh.grid_bytes * mb
      << " grid_res=" << sh.grid_resolution.x << "x" << sh.grid_resolution.y << "x" << sh.grid_resolution.z
      << " field_mb=" << sh.field_bytes * mb << " field_s=" << sh.field_seconds
      << " tables_kb=" << sh.table_bytes / 1024.0 << " peak_rss_mb=" << peak_rss_bytes() * mb;
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
