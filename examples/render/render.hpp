// render — the renderer as a library: render(scene, shading, options) → image, hair mask,
// timings. The integrators are in integrators/, one file each.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scene.hpp"
#include "shading.hpp"

namespace render {

enum class Integrator {
    kSingle,  // single scattering: light sampling with shadow rays (hair shadows are opaque)
    kDual,    // dual scattering (Zinke 2008) with the library's tables and density grid
    kPath,    // path tracing through fibers (any model): the multiple-scattering reference
};
// How dual and path choose incident directions at hair (path also at surfaces: only mis
// adds light sampling; surfaces always sample the cosine).
enum class Sampling {
    kUniform,     // uniform on the sphere (hairscatter::UniformSphereSampling)
    kImportance,  // the library's samplers (DualScatteringFiber / the model's sample)
    kMis,         // MIS (power heuristic) of BCSDF sampling and light sampling
};

const char* to_string(Integrator);
const char* to_string(Sampling);

// A window of the image, in pixels of the whole --width × --height frame: columns
// [x0, x1), rows [y0, y1) from the top. Empty (x1 = 0): the whole frame.
struct Crop {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x1 == 0 && y1 == 0 && x0 == 0 && y0 == 0; }
};

struct RenderOptions {
    Integrator integrator = Integrator::kDual;
    Sampling sampling = Sampling::kMis;
    int width = 480, height = 360;  // the defaults render in seconds on 2 cores
    int spp = 32;
    int max_depth = 4096;        // path: a safety cap only (paths end by Russian roulette)
    std::uint64_t seed = 1;      // pixel (x, y)'s generator depends on seed, x and y only
    bool hair_only = false;      // render only pixels whose primary (centre) ray hits hair
    bool progress = false;       // progress bar with ETA on stderr (for runs over a second)
    int tile = 16;               // tile side in pixels (tiles are rendered in parallel)
    int threads = 0;             // worker threads for the tiles; 0: TBB's default (one per core)
    // Renders only this window of the frame (the image is the window; each pixel is the
    // frame's, with its own random numbers: a crop of the whole render, to the bit).
    Crop crop;
};

struct RenderResult {
    int width = 0, height = 0;  // the crop's, when there is one
    std::vector<float> rgb;              // linear RGB, row-major from the top, 3 floats per pixel
    std::vector<std::uint8_t> hair_mask; // 1 where the pixel-centre primary ray hits hair
    double seconds = 0;                  // wall-clock time of the rendering (scene build excluded)
    std::uint64_t samples = 0;           // camera samples taken
    std::uint64_t dropped = 0;           // samples discarded as non-finite (should be 0)
    std::size_t hair_pixels = 0;
    // Time spent on the hair pixels' samples, summed over threads (per-pixel clock reads):
    // the cost per sample where integrators differ, free of the background's.
    double hair_seconds = 0;
    // hair_seconds per sample of a hair pixel, in microseconds (0 without hair pixels).
    double hair_us_per_sample(int spp) const {
        return hair_pixels > 0 && spp > 0 ? hair_seconds * 1e6 / (double(hair_pixels) * double(spp)) : 0.0;
    }
};

// Throws std::invalid_argument naming the first bad option (as its command-line flag).
void validate(const RenderOptions& options);

// Renders the scene. Deterministic: the same scene, options and seed give the same image
// whatever the thread count. Throws std::invalid_argument for bad options.
RenderResult render(const Scene& scene, const ShadingSetup& shading, const RenderOptions& options);

// Peak and current resident set size of this process in bytes (VmHWM and VmRSS of
// /proc/self/status); 0 where unavailable.
std::size_t peak_rss_bytes();
std::size_t current_rss_bytes();

// A one-line, space-separated key=value summary of a render (for scripts).
// One hair point seen by the camera and one arrival direction a from its fiber's sampler:
// the light arriving along a by the dual estimator and by the path tracer (channel means,
// each averaged over its samples), the sample's weight f cos / pdf (channel mean), cos of a
// with the camera ray (> 0: a points away from the camera), and the fibers along ±a
// (exact counts). A diagnostic of the dual estimator, direction by direction.
struct ArrivalRecord {
    float dual = 0, path = 0, weight = 0, cos_view = 0, count = 0, behind = 0;
    float cos_light = 0;  // cos of a with the direction to the area light's centre (0: none)
};
std::vector<ArrivalRecord> arrival_profile(const Scene& scene, const ShadingSetup& shading, const RenderOptions& o,
                                           int points, int dual_samples, int path_samples);

std::string summary_line(const Scene& scene, const ShadingSetup& shading, const RenderOptions& options,
                         const RenderResult& result);

}  // namespace render
