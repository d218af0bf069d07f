// study — the origin study's measurements with the example renderer:
//
//   study convergence     error against spp and against seconds for uniform and importance
//                         sampling of the dual-scattering BCSDF inside a hair-only region of
//                         interest, and the variance between consecutive spp levels;
//   study dual-vs-path    dual scattering (each formulation) and single scattering against
//                         the path tracer on hair blocks, a scalp, fur or a slab lit from
//                         behind (slab) or from the front (slab-front):
//                         relative error of the mean
//                         hair radiance, mean per-pixel error, error images, times;
//   study furnace         the white furnace (lossless hair, uniform environment) on any scene:
//                         every formulation and the path tracer against the exact answer 1;
//   study time-to-error   seconds for dual scattering and for the path tracer to reach a
//                         relative RMSE over the hair pixels against a converged reference.
//
// Each writes CSV files and images into --out; scripts/study.sh runs them, plots with
// gnuplot and writes docs/results/README.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <memory>
#include <tuple>
#include <vector>

#include <CLI/CLI.hpp>
#include <hairscatter/hairscatter.hpp>

#include "common/image_io.hpp"
#include "common/options.hpp"
#include "render.hpp"
#include "scenes.hpp"

namespace {

namespace io = hairscatter_examples;

struct Common {
    bool ground = true;  // dual-vs-path: keep the ground plane (its bounce light is only in path)
    int hairs = 1500;
    std::string lighting = "both";  // env | area | both
    int width = 160, height = 120;
    std::string colour = "blond";
    std::string out = "study-out";
};

// σa of a colour preset of the examples (common/options.hpp: "white" is lossless, σa = 0,
// the limit multiple scattering matters most in); throws std::invalid_argument naming the
// presets for an unknown one.
glm::vec3 melanin_sigma_a(const std::string& colour) {
    io::HairColourOptions c;
    c.preset = colour;
    return glm::vec3(io::sigma_a_of(c, colour, hairscatter::FiberParams<double>().beta_n));
}

// The origin study's hair block (5 × 5 × 5 on the ground plane), a scalp, fur (short strands
// on a body, or a shell of them with nothing inside) or a slab lit from behind (slab) or from
// the front, above the camera (slab-front); `hairs` is
// the strand count, or the slab's depth in fibers. Lighting: "env" a white environment of
// radiance 1 only (where BCSDF sampling is the only strategy; with lossless hair, the white
// furnace), "area" the preset's small area light only, "both" the preset's area light and
// dim environment.
render::SceneDescription block_scene(int hairs, const std::string& light, bool ground = true,
                                     const std::string& kind = "block") {
    render::BlockOptions block;
    block.count = hairs;
    render::LightingOptions lighting;
    if (light == "env") {
        lighting.light_power = 0;
        lighting.environment = 1;
    } else if (light == "area") {
        lighting.environment = 0;
    } else if (light != "both") {
        throw std::invalid_argument("unknown lighting '" + light + "' (env | area | both)");
    }
    render::SceneDescription d;
    if (kind == "scalp") {
        render::ScalpOptions scalp;
        scalp.count = hairs;
        d = render::make_scalp_scene(scalp, lighting);
    } else if (kind == "block") {
        d = render::make_block_scene(block, lighting);
    } else if (kind == "fur" || kind == "fur-shell" || kind == "fur-short" || kind == "fur-long" || kind == "fur-flat" ||
               kind == "fur-coarse") {
        // fur: strands on a body; fur-shell: the same strands with nothing inside. The shell's
        // variants, geometry no default was measured on: a short pelt (a quarter of the
        // length: the shell one or two density-grid cells thick), long fur (twice the length),
        // fur combed flat (70° from the normal instead of 30°) and fibers twice as thick.
        render::FurOptions fur;
        fur.count = hairs;
        fur.body = kind == "fur";
        if (kind == "fur-short") fur.length = 0.25f * fur.length;
        if (kind == "fur-long") fur.length = 2.0f * fur.length;
        if (kind == "fur-flat") fur.tilt_deg = 70.0f;
        if (kind == "fur-coarse") fur.radius = 2.0f * fur.radius;
        d = render::make_fur_scene(fur, lighting);
    } else if (kind == "slab" || kind == "slab-front") {
        render::SlabOptions slab;
        slab.depth = float(hairs);
        slab.back_lit = kind == "slab";
        // Fibers that do not overlap (as real ones) cover depth · π · radius / (2 thickness) of
        // the section: past 35 % (deeper than 11 fibers at the default radius) the fibers are
        // made thinner to keep it, rather than let them interpenetrate.
        constexpr double kPacking = 0.35;
        if (slab.packing() > kPacking) slab.radius = float(double(slab.radius) * kPacking / slab.packing());
        // The renderer's own checks (its strand limit): a depth of thousands, as the block's
        // strand count read as a depth, would otherwise build the slab until memory runs out.
        try {
            render::validate(slab, lighting);
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument("a slab " + std::to_string(hairs) + " fibers deep (--hairs or --hair-counts: the depth): " + e.what());
        }
        d = render::make_slab_scene(slab, lighting);
    } else {
        throw std::invalid_argument("unknown scene '" + kind +
                                    "' (block | scalp | fur | fur-shell | fur-short | fur-long | fur-flat | fur-coarse | slab | slab-front)");
    }
    // Without ground: the ground plane goes; a body or a head stays (it is part of the hair's
    // geometry, and the light it bounces onto the hair is part of what dual scattering must carry).
    if (!ground) render::remove_ground(d);
    return d;
}

// The hair's shading: the Chiang fiber of the colour, with dual scattering as `formulation`
// says: two-stream (the default: exact counts), two-stream-grid (counts from the density
// grid), improved or zinke (the dual-scattering BCSDF).
render::ShadingOptions shading_options(const std::string& colour, const std::string& formulation_in = "two-stream") {
    render::ShadingOptions o;
    o.fiber.sigma_a = melanin_sigma_a(colour);
    // A "-vN" suffix traces a path's first N vertices before the two-stream estimator
    // (--dual-vertices N), without the glow volume (--dual-glow 0: measured the better pairing).
    std::string formulation = formulation_in;
    const std::size_t v = formulation.rfind("-v");
    if (v != std::string::npos && v + 3 == formulation.size() && formulation[v + 2] >= '0' && formulation[v + 2] <= '8') {
        o.traced_vertices = formulation[v + 2] - '0';
        o.glow_points = 0;
        formulation = formulation.substr(0, v);
    }
    // A "-gN" suffix sets the glow volume's points per cell (--dual-glow N; 0: none).
    const std::size_t g = formulation.rfind("-g");
    if (g != std::string::npos && g + 2 < formulation.size() &&
        formulation.find_first_not_of("0123456789", g + 2) == std::string::npos && formulation.size() - g <= 5) {
        o.glow_points = std::stoi(formulation.substr(g + 2));
        formulation = formulation.substr(0, g);
    }
    // Drops `suffix` from the formulation's end if it is there, and says whether it was.
    const auto strip = [&formulation](const std::string& suffix) {
        const bool has = formulation.size() > suffix.size() &&
                         formulation.compare(formulation.size() - suffix.size(), suffix.size(), suffix) == 0;
        if (has) formulation.resize(formulation.size() - suffix.size());
        return has;
    };
    // A "-planar" suffix returns every backward event along the stacks (--dual-stacks planar,
    // the 1D stack of Zinke et al. 2008); without it the stacks are inclined (the default).
    if (strip("-planar")) o.inclined_stacks = false;
    // A "-diffuse" suffix trades light between the stacks' half-circles where it has spread
    // (--dual-transport diffuse, DualStackTransport::kDiffuse).
    if (strip("-diffuse")) o.transport = hairscatter::DualStackTransport::kDiffuse;
    // A "-point" suffix reads the stacks' sources at the shading point (DualSource::kPoint).
    const bool at_point = strip("-point");
    const std::string& base = formulation;
    o.two_stream = base == "two-stream" || base == "two-stream-grid" || base == "two-stream-field";
    o.counts = base == "two-stream-grid"    ? render::DualCounts::kGrid
               : base == "two-stream-field" ? render::DualCounts::kField
                                            : render::DualCounts::kExact;
    o.source = at_point ? render::DualSource::kPoint : render::DualSource::kBeyondExit;
    if (o.traced_vertices > 0 && !o.two_stream)
        throw std::invalid_argument("'-vN' applies to two-stream formulations only");
    if (at_point && !o.two_stream) throw std::invalid_argument("'-point' applies to two-stream formulations only");
    if (formulation == "zinke") o.dual = hairscatter::DualScatteringSettings<float>::zinke2008();
    else if (formulation == "improved") o.dual = hairscatter::DualScatteringSettings<float>::improved();
    else if (!o.two_stream)
        throw std::invalid_argument("unknown formulation '" + formulation +
                                    "' (two-stream | two-stream-grid | two-stream-field, each optionally with -point, -planar, -diffuse, -gN, -vN | "
                                    "improved | zinke)");
    return o;
}

// Relative RMSE over the region of interest: sqrt(mean (x - r)²) / mean r (channel mean).

// Statistics over the region of interest: pixels whose primary ray hits hair in the
// reference's mask (Lemein 2019 §4: the error is measured where the hair is, not the background).
struct Roi {
    std::vector<std::size_t> pixels;
    int width = 0;
    explicit Roi(const render::RenderResult& ref) : width(ref.width) {
        for (std::size_t i = 0; i < ref.hair_mask.size(); ++i)
            if (ref.hair_mask[i]) pixels.push_back(i);
        if (pixels.empty()) throw std::runtime_error("study: the region of interest is empty (no hair in view)");
    }
    // Mean squared error and relative MSE (per channel, (x - r)² / (r² + 1e-4), the 1e-4
    // keeping black reference pixels from dominating) against the reference.
    std::pair<double, double> mse(const std::vector<float>& img, const std::vector<float>& ref) const {
        double se = 0, rel = 0;
        for (std::size_t p : pixels)
            for (int c = 0; c < 3; ++c) {
                const double x = img[3 * p + std::size_t(c)], r = ref[3 * p + std::size_t(c)];
                se += (x - r) * (x - r);
                rel += (x - r) * (x - r) / (r * r + 1e-4);
            }
        const double n = 3.0 * double(pixels.size());
        return {se / n, rel / n};
    }
    // The mean squared error after averaging b × b blocks: each block's hair pixels averaged
    // (per channel) in the image and in the reference, the squared differences averaged over
    // the blocks that hold hair. Noise falls by up to b² in variance; bias stays.
    double block_mse(const std::vector<float>& img, const std::vector<float>& ref, int b) const {
        std::map<std::size_t, std::pair<glm::dvec3, glm::dvec3>> sums;
        std::map<std::size_t, int> counts;
        const std::size_t w = std::size_t(width), bw = (w + std::size_t(b) - 1) / std::size_t(b);
        for (std::size_t p : pixels) {
            const std::size_t key = (p / w) / std::size_t(b) * bw + (p % w) / std::size_t(b);
            auto& [si, sr] = sums[key];
            for (int c = 0; c < 3; ++c) {
                si[c] += img[3 * p + std::size_t(c)];
                sr[c] += ref[3 * p + std::size_t(c)];
            }
            ++counts[key];
        }
        double se = 0;
        for (const auto& [key, s] : sums) {
            const glm::dvec3 d = (s.first - s.second) / double(counts[key]);
            se += glm::dot(d, d);
        }
        return se / (3.0 * double(sums.size()));
    }
    glm::dvec3 mean(const std::vector<float>& img) const {
        glm::dvec3 m(0.0);
        for (std::size_t p : pixels)
            for (int c = 0; c < 3; ++c) m[c] += img[3 * p + std::size_t(c)];
        return m / double(pixels.size());
    }
    double mean_square(const std::vector<float>& img) const {
        double s = 0;
        for (std::size_t p : pixels)
            for (int c = 0; c < 3; ++c) s += double(img[3 * p + std::size_t(c)]) * img[3 * p + std::size_t(c)];
        return s / (3.0 * double(pixels.size()));
    }
};

bool all_finite(const std::vector<float>& img) {
    return std::all_of(img.begin(), img.end(), [](float v) { return std::isfinite(v); });
}

// PNG preview at a fixed exposure (so images of one study are comparable).
void write_png(const std::string& path, const render::RenderResult& r, float scale) {
    std::vector<std::uint8_t> px(r.rgb.size());
    for (std::size_t i = 0; i < r.rgb.size(); ++i) {
        const double v = double(r.rgb[i]) * scale;
        px[i] = io::srgb8(v / (1 + v));  // Reinhard, then sRGB
    }
    io::write_png_rgb8(path, r.width, r.height, px);
}

void write_images(const std::string& base, const render::RenderResult& r, float scale) {
    io::write_exr_rgb(base + ".exr", r.width, r.height, r.rgb, {});
    write_png(base + ".png", r, scale);
}

// A false-colour image of |x - r| / (r + 0.01) per pixel (channel mean), 0 black → ≥ 50 %
// white through red and yellow; outside the region of interest grey.
void write_error_png(const std::string& path, const render::RenderResult& x, const render::RenderResult& ref) {
    std::vector<std::uint8_t> px(ref.rgb.size(), 64);
    for (std::size_t i = 0; i < ref.hair_mask.size(); ++i) {
        if (!ref.hair_mask[i]) continue;
        double e = 0;
        for (int c = 0; c < 3; ++c) {
            const double a = x.rgb[3 * i + std::size_t(c)], b = ref.rgb[3 * i + std::size_t(c)];
            e += std::abs(a - b) / (std::abs(b) + 0.01) / 3;
        }
        const double t = std::min(1.0, e / 0.5);
        px[3 * i + 0] = std::uint8_t(255 * std::min(1.0, 3 * t));
        px[3 * i + 1] = std::uint8_t(255 * std::clamp(3 * t - 1, 0.0, 1.0));
        px[3 * i + 2] = std::uint8_t(255 * std::clamp(3 * t - 2, 0.0, 1.0));
    }
    io::write_png_rgb8(path, ref.width, ref.height, px);
}

render::RenderOptions options(const Common& c, render::Integrator integrator, render::Sampling sampling, int spp,
                              std::uint64_t seed) {
    render::RenderOptions o;
    o.integrator = integrator;
    o.sampling = sampling;
    o.width = c.width;
    o.height = c.height;
    o.spp = spp;
    o.seed = seed;
    return o;
}

// ---- Lemein 2019 §4.3–4.4 ---------------------------------------------------------------------

int convergence(const Common& c, int max_spp, int reference_spp, const std::string& reference_sampling,
                double threshold) {
    // The dual-scattering BCSDF's samplers (the two-stream integrator samples the fiber).
    const render::Scene scene(block_scene(c.hairs, c.lighting));
    const render::ShadingSetup shading(scene, shading_options(c.colour, "improved"));
    const render::Sampling ref_sampling =
        reference_sampling == "uniform" ? render::Sampling::kUniform : render::Sampling::kImportance;
    std::fprintf(stderr, "study: reference, dual scattering, %s sampling, %d spp\n", reference_sampling.c_str(),
                 reference_spp);
    render::RenderOptions ro = options(c, render::Integrator::kDual, ref_sampling, reference_spp, 1000003);
    ro.progress = true;
    const render::RenderResult ref = render::render(scene, shading, ro);
    if (!all_finite(ref.rgb)) throw std::runtime_error("study: the reference image has non-finite pixels");
    const Roi roi(ref);
    const double ref_ms = roi.mean_square(ref.rgb);
    write_images(c.out + "/convergence_" + c.lighting + "_reference", ref, 1.0f);

    std::ofstream csv(c.out + "/convergence_" + c.lighting + ".csv");
    csv << "sampler,spp,seconds,rmse,rel_mse,consecutive_var,consecutive_var_rel\n";
    std::ofstream reach(c.out + "/convergence_" + c.lighting + "_threshold.csv");
    reach << "sampler,threshold,spp_below\n";
    for (const auto& [name, sampling] : {std::pair<const char*, render::Sampling>{"uniform", render::Sampling::kUniform},
                                         {"importance", render::Sampling::kImportance}}) {
        std::vector<float> previous;
        int below = -1;
        for (int spp = 1; spp <= max_spp; spp *= 2) {
            const render::RenderResult r = render::render(scene, shading, options(c, render::Integrator::kDual, sampling, spp, 17));
            if (!all_finite(r.rgb)) throw std::runtime_error("study: non-finite pixels at " + std::to_string(spp) + " spp");
            const auto [mse, rel] = roi.mse(r.rgb, ref.rgb);
            // Lemein 2019 §4.4: the variance between consecutive levels, mean over the ROI of
            // (I_spp - I_spp/2)², and relative to the reference's mean square.
            double var = -1;
            if (!previous.empty()) var = roi.mse(r.rgb, previous).first;
            if (var >= 0 && below < 0 && var / ref_ms < threshold) below = spp;
            csv << name << ',' << spp << ',' << r.seconds << ',' << std::sqrt(mse) << ',' << rel << ',' << var << ','
                << (var >= 0 ? var / ref_ms : -1) << '\n';
            std::fprintf(stderr, "study: %-10s %5d spp  %7.2f s  RMSE %.4g  relMSE %.4g\n", name, spp, r.seconds,
                         std::sqrt(mse), rel);
            if (spp == 16) write_images(c.out + "/convergence_" + c.lighting + "_" + name + "_16spp", r, 1.0f);
            previous = r.rgb;
        }
        reach << name << ',' << threshold << ',' << below << '\n';
    }
    return 0;
}

// A path-traced reference as two independent halves of spp / 2 each (seeds a and b) and
// their mean: the halves' difference states the reference's own noise.
struct HalvedReference {
    render::RenderResult a, b, mean;
};
HalvedReference path_reference(const Common& c, const render::Scene& scene, const render::ShadingSetup& shading,
                               int spp, std::uint64_t seed_a, std::uint64_t seed_b) {
    render::RenderOptions po = options(c, render::Integrator::kPath, render::Sampling::kMis, spp / 2, seed_a);
    po.progress = true;
    HalvedReference r;
    r.a = render::render(scene, shading, po);
    po.seed = seed_b;
    r.b = render::render(scene, shading, po);
    r.mean = r.a;
    for (std::size_t i = 0; i < r.mean.rgb.size(); ++i) r.mean.rgb[i] = 0.5f * (r.a.rgb[i] + r.b.rgb[i]);
    r.mean.seconds = r.a.seconds + r.b.seconds;
    r.mean.hair_seconds = r.a.hair_seconds + r.b.hair_seconds;
    return r;
}

// ---- dual scattering against path tracing ------------------------------------------------

int dual_vs_path(const Common& c, const std::string& kind, const std::vector<int>& hair_counts,
                 const std::vector<std::string>& colours, const std::vector<std::string>& formulations, int dual_spp,
                 int path_spp) {
    const std::string tag = kind + "_" + c.lighting + (c.ground ? "" : "_noground");
    std::ofstream csv(c.out + "/dual_vs_path_" + tag + ".csv");
    csv << "colour,hairs,integrator,spp,seconds,ms_per_spp,mean,rel_error_mean,mean_abs_pixel_rel_error,path_noise,"
           "hair_us_per_sample\n";
    for (const std::string& colour : colours)
        for (int hairs : hair_counts) {
            const render::Scene scene(block_scene(hairs, c.lighting, c.ground, kind));
            const render::ShadingSetup path_shading(scene, shading_options(colour));
            const HalvedReference ref = path_reference(c, scene, path_shading, path_spp, 1, 7);
            const render::RenderResult &pa = ref.a, &pb = ref.b, &path = ref.mean;
            const Roi roi(path);
            const auto sum = [](const glm::dvec3& m) { return m.x + m.y + m.z; };
            const double mp = sum(roi.mean(path.rgb));
            const double noise = std::abs(sum(roi.mean(pa.rgb)) - sum(roi.mean(pb.rgb))) / 2 / mp;
            const std::string base = c.out + "/dvp_" + tag + "_" + colour + "_" + std::to_string(hairs);
            write_images(base + "_path", path, 1.0f);
            std::vector<std::tuple<std::string, render::RenderResult, int>> rows;
            rows.emplace_back("path", path, path_spp);
            for (const std::string& f : formulations) {
                const render::ShadingSetup shading(scene, shading_options(colour, f));
                std::string row = "dual_" + f;
                std::replace(row.begin(), row.end(), '-', '_');
                rows.emplace_back(row, render::render(scene, shading, options(c, render::Integrator::kDual,
                                                                                      render::Sampling::kMis, dual_spp, 2)),
                                  dual_spp);
            }
            rows.emplace_back("single",
                              render::render(scene, path_shading,
                                             options(c, render::Integrator::kSingle, render::Sampling::kMis, dual_spp, 3)),
                              dual_spp);
            for (const auto& [name, r, spp] : rows) {
                if (!all_finite(r.rgb)) throw std::runtime_error("study: non-finite pixels in " + name);
                if (name != "path") {
                    write_images(base + "_" + name, r, 1.0f);
                    write_error_png(base + "_" + name + "_error.png", r, path);
                }
                const double m = sum(roi.mean(r.rgb));
                const double rel = (m - mp) / mp;
                double pix = 0;
                for (std::size_t p : roi.pixels) {
                    double e = 0;
                    for (int ch = 0; ch < 3; ++ch) {
                        const double a = r.rgb[3 * p + std::size_t(ch)], b = path.rgb[3 * p + std::size_t(ch)];
                        e += std::abs(a - b) / (std::abs(b) + 0.01) / 3;
                    }
                    pix += e / double(roi.pixels.size());
                }
                csv << colour << ',' << hairs << ',' << name << ',' << spp << ',' << r.seconds << ','
                    << 1000 * r.seconds / spp << ',' << m / 3 << ',' << rel << ',' << pix << ',' << noise << ','
                    << r.hair_us_per_sample(spp) << '\n';
                csv.flush();
                std::fprintf(stderr, "study: %-6s %6d hairs %-14s %5d spp %8.2f s  mean %.4f  rel. error of mean %+.3f\n",
                             colour.c_str(), hairs, name.c_str(), spp, r.seconds, m / 3, rel);
            }
        }
    return 0;
}

// ---- the white furnace -----------------------------------------------------------------------

// Lossless hair (and white surfaces: a body or a head of albedo 1) under a uniform
// environment of radiance 1, no ground: the exact radiance is 1 at every hair pixel, on
// any geometry. Each scene "kind:hairs" with every dual formulation and the path tracer.
int furnace(const Common& c, const std::vector<std::string>& scenes, const std::vector<std::string>& formulations,
            int dual_spp, int path_spp) {
    std::ofstream csv(c.out + "/furnace.csv");
    csv << "scene,hairs,integrator,spp,seconds,mean,rel_error\n";
    for (const std::string& spec : scenes) {
        const std::size_t colon = spec.find(':');
        if (colon == std::string::npos) throw std::invalid_argument("furnace scene '" + spec + "' is not kind:hairs");
        const std::string kind = spec.substr(0, colon);
        const int hairs = std::stoi(spec.substr(colon + 1));
        render::SceneDescription d = block_scene(hairs, "env", false, kind);
        d.light.reset();
        for (render::Mesh& m : d.meshes) m.albedo = glm::vec3(1.0f);
        const render::Scene scene(std::move(d));
        std::vector<std::pair<std::string, render::RenderResult>> rows;
        for (const std::string& f : formulations) {
            const render::ShadingSetup shading(scene, shading_options("white", f));
            std::string row = "dual_" + f;
            std::replace(row.begin(), row.end(), '-', '_');
            rows.emplace_back(row, render::render(scene, shading, options(c, render::Integrator::kDual, render::Sampling::kMis, dual_spp, 2)));
        }
        const render::ShadingSetup path_shading(scene, shading_options("white"));
        rows.emplace_back("path", render::render(scene, path_shading, options(c, render::Integrator::kPath, render::Sampling::kMis, path_spp, 1)));
        const Roi roi(rows.back().second);
        for (const auto& [name, r] : rows) {
            if (!all_finite(r.rgb)) throw std::runtime_error("study: non-finite pixels in the furnace, " + name);
            const glm::dvec3 m = roi.mean(r.rgb);
            const double mean = (m.x + m.y + m.z) / 3;
            const int spp = name == "path" ? path_spp : dual_spp;
            csv << kind << ',' << hairs << ',' << name << ',' << spp << ',' << r.seconds << ',' << mean << ',' << mean - 1 << '\n';
            csv.flush();
            std::fprintf(stderr, "study: furnace %-9s %6d %-22s %8.2f s  mean %.4f\n", kind.c_str(), hairs, name.c_str(),
                         r.seconds, mean);
        }
    }
    return 0;
}

// ---- time to equal error ---------------------------------------------------------------------

// Seconds for dual scattering (the two-stream integrator) and the path tracer, both with MIS, to
// reach each relative RMSE over the hair pixels against a converged path-traced reference
// (rendered as two independent halves: their difference states its own RMSE).
// The process's CPU seconds so far (every thread's): unlike the wall clock, it does not grow
// when other processes share the cores, so runs on a busy machine still compare.
double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

int time_to_error(const Common& c, const std::string& kind, int reference_spp, int dual_max_spp, int path_max_spp,
                  const std::vector<std::string>& formulations, const std::string& tag_suffix) {
    const render::Scene scene(block_scene(c.hairs, c.lighting, c.ground, kind));
    const render::ShadingSetup shading(scene, shading_options(c.colour));
    const HalvedReference halves = path_reference(c, scene, shading, reference_spp, 1000003, 2000003);
    const render::RenderResult &ra = halves.a, &rb = halves.b, &ref = halves.mean;
    const Roi roi(ref);
    const glm::dvec3 mref = roi.mean(ref.rgb);
    const double mean_ref = (mref.x + mref.y + mref.z) / 3;
    // The reference's own relative RMSE: that of each half against the other, / 2.
    const double ref_rmse = std::sqrt(roi.mse(ra.rgb, rb.rgb).first) / 2 / mean_ref;
    const std::string tag = kind + "_" + c.colour + "_" + std::to_string(c.hairs) + tag_suffix;
    write_images(c.out + "/tte_" + tag + "_reference", ref, 1.0f);
    std::ofstream csv(c.out + "/time_to_error_" + tag + ".csv");
    csv << "integrator,spp,seconds,rel_rmse,reference_rel_rmse,rel_rmse_4x4,reference_rel_rmse_4x4,setup_seconds,"
           "cpu_seconds,setup_cpu_seconds\n";
    const double ref_rmse_4x4 = std::sqrt(roi.block_mse(ra.rgb, rb.rgb, 4)) / 2 / mean_ref;
    // Each formulation's rows (dual: the two-stream estimator with exact counts; dual_field:
    // with field counts; dual_<formulation> otherwise), then the path tracer's.
    std::vector<std::unique_ptr<render::ShadingSetup>> setups;
    // seconds: the render's, plus for dual scattering its setup (the tables, the density grid and
    // the count field: ShadingSetup's build, which the path tracer does not need); the
    // render's own part holds the glow volume's build. cpu_seconds: the same in the process's
    // CPU time (both threads' work, whatever else runs on the machine).
    std::vector<std::tuple<std::string, render::Integrator, int, const render::ShadingSetup*>> runs;
    std::map<const render::ShadingSetup*, double> setup_cpu;
    for (const std::string& f : formulations) {
        const double cpu0 = cpu_seconds();
        setups.push_back(std::make_unique<render::ShadingSetup>(scene, shading_options(c.colour, f)));
        setup_cpu[setups.back().get()] = cpu_seconds() - cpu0;
        std::string name = f == "two-stream" ? "dual" : f == "two-stream-field" ? "dual_field" : "dual_" + f;
        std::replace(name.begin(), name.end(), '-', '_');
        runs.emplace_back(name, render::Integrator::kDual, dual_max_spp, setups.back().get());
    }
    runs.emplace_back("path", render::Integrator::kPath, path_max_spp, &shading);
    for (const auto& [name, integrator, max_spp, setup] : runs) {
        for (int spp = 1; spp <= max_spp; spp *= 2) {
            const double cpu0 = cpu_seconds();
            const render::RenderResult r =
                render::render(scene, *setup, options(c, integrator, render::Sampling::kMis, spp, 17));
            const double render_cpu = cpu_seconds() - cpu0;
            const bool dual = integrator == render::Integrator::kDual;
            const double setup_s = dual ? setup->stats().seconds : 0.0;
            const double setup_cpu_s = dual ? setup_cpu.at(setup) : 0.0;
            const double seconds = r.seconds + setup_s;
            const double rel = std::sqrt(roi.mse(r.rgb, ref.rgb).first) / mean_ref;
            const double rel_4x4 = std::sqrt(roi.block_mse(r.rgb, ref.rgb, 4)) / mean_ref;
            csv << name << ',' << spp << ',' << seconds << ',' << rel << ',' << ref_rmse << ',' << rel_4x4 << ','
                << ref_rmse_4x4 << ',' << setup_s << ',' << render_cpu + setup_cpu_s << ',' << setup_cpu_s << '\n';
            csv.flush();
            std::fprintf(stderr, "study: %-5s %5d spp %8.2f s  relative RMSE %.4f (reference %.4f)\n", name.c_str(), spp, seconds,
                         rel, ref_rmse);
        }
    }
    return 0;
}


// The dual estimator's arrivals against the path tracer's, direction by direction
// (render::arrival_profile), binned by the fibers along the arrival direction a and whether
// a points away from the camera: per bin the share of the samples, the mean light of each
// (weighted by the fiber's sampling weight: the bin's part of the pixel's light) and their
// ratio. Which directions make the dual image too bright or too dark.
int arrivals(const Common& c, const std::string& kind, int hairs, const std::string& formulation, int points,
             int dual_samples, int path_samples) {
    const render::Scene scene(block_scene(hairs, c.lighting, c.ground, kind));
    const render::ShadingSetup shading(scene, shading_options(c.colour, formulation));
    render::RenderOptions o;
    o.width = c.width, o.height = c.height;
    const std::vector<render::ArrivalRecord> recs = render::arrival_profile(scene, shading, o, points, dual_samples, path_samples);
    const float edges[] = {0, 1, 2, 4, 8, 16, 32, 1e30f};
    constexpr int kEdges = 8;
    std::printf("%s %s %d %s %s: %d points, %d dual and %d path samples each\n", kind.c_str(), c.colour.c_str(), hairs,
                c.lighting.c_str(), formulation.c_str(), points, dual_samples, path_samples);
    std::printf("%-9s %-7s %7s %11s %11s %7s %9s\n", "count", "a", "share", "w·dual", "w·path", "ratio", "excess");
    double all_d = 0, all_p = 0;
    for (const auto& r : recs) all_d += r.weight * r.dual, all_p += r.weight * r.path;
    // One table of bins: the records of each group (group(r) = its index in names, −1 none)
    // by the fibers along a; the zero-fiber bin only when `open` (it is the same in both).
    const auto table = [&](auto group, const std::vector<const char*>& names, bool open, const char* format) {
        for (std::size_t g = 0; g < names.size(); ++g)
            for (int b = open ? 0 : 1; b + 1 < kEdges; ++b) {
                double n = 0, wd = 0, wp = 0;
                for (const auto& r : recs) {
                    if (!(r.weight > 0) || group(r) != int(g)) continue;
                    if (b == 0 ? r.count != 0 : !(r.count >= edges[b] && r.count < edges[b + 1])) continue;
                    n += 1, wd += r.weight * r.dual, wp += r.weight * r.path;
                }
                if (n == 0) continue;
                char label[32];
                if (b == 0) std::snprintf(label, sizeof label, "0");
                else std::snprintf(label, sizeof label, "%g-%g", double(edges[b]), double(edges[b + 1] > 1e29f ? 999 : edges[b + 1]));
                std::printf(format, label, names[g], n / double(recs.size()), wd / double(recs.size()),
                            wp / double(recs.size()), wp > 0 ? wd / wp : 0.0, all_p > 0 ? (wd - wp) / all_p : 0.0);
            }
    };
    table([](const render::ArrivalRecord& r) { return r.cos_view > 0 ? 0 : 1; }, {"away", "toward"}, true,
          "%-9s %-7s %7.3f %11.4g %11.4g %7.3f %+9.4f\n");
    // The same by the direction to the area light: a toward it (> 0.3), across, away (< −0.3).
    table([](const render::ArrivalRecord& r) { return r.cos_light > 0.3f ? 0 : r.cos_light < -0.3f ? 2 : 1; },
          {"to-light", "across", "off-light"}, false, "%-9s %-9s %5.3f %11.4g %11.4g %7.3f %+9.4f\n");
    std::printf("all: dual %.4g path %.4g ratio %.3f\n", all_d / double(recs.size()), all_p / double(recs.size()),
                all_p > 0 ? all_d / all_p : 0.0);
    return 0;
}
}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"hairscatter study: the origin study's convergence study, dual scattering against path tracing, time to equal error"};
    app.require_subcommand(1);
    Common c;
    auto common = [&](CLI::App* s) {
        s->add_option("--hairs", c.hairs, "strands in the block")->capture_default_str();
        s->add_option("--width", c.width, "image width")->capture_default_str();
        s->add_option("--height", c.height, "image height")->capture_default_str();
        s->add_option("--out", c.out, "output directory (must exist)")->capture_default_str();
        s->add_option("--lighting", c.lighting, "env | area | both")->capture_default_str();
    };

    CLI::App* conv = app.add_subcommand("convergence", "Lemein 2019 §4.3–4.4: error and variance against spp, uniform vs importance");
    common(conv);
    int max_spp = 256, reference_spp = 1024;
    std::string reference_sampling = "importance";
    double threshold = 1e-3;
    conv->add_option("--colour", c.colour, io::colour_preset_names())->capture_default_str();
    conv->add_option("--max-spp", max_spp, "largest spp level (levels 1, 2, 4, …)")->capture_default_str();
    conv->add_option("--reference-spp", reference_spp, "spp of the reference image")->capture_default_str();
    conv->add_option("--reference-sampling", reference_sampling, "uniform | importance")->capture_default_str();
    conv->add_option("--threshold", threshold, "relative consecutive-level variance to reach (Lemein 2019 §4.4)")
        ->capture_default_str();

    CLI::App* dvp = app.add_subcommand("dual-vs-path", "dual scattering against the path-traced reference");
    common(dvp);
    std::vector<int> hair_counts{1500};
    std::vector<std::string> colours{"blond", "dark"};
    std::vector<std::string> formulations{"two-stream", "two-stream-field", "improved", "zinke"};
    std::string kind = "block";
    int dual_spp = 64, path_spp = 256;
    dvp->add_option("--hair-counts", hair_counts, "block sizes")->capture_default_str();
    bool no_ground = false;
    dvp->add_flag("--no-ground", no_ground,
                  "remove the ground plane: the light it bounces onto the hair reaches only the path tracer, so "
                  "without it the difference is the hair's own multiple scattering");
    dvp->add_option("--colours", colours, "hair colours")->capture_default_str();
    dvp->add_option("--formulations", formulations,
                    "dual-scattering formulations: two-stream, two-stream-grid, two-stream-field (each also with "
                    "-point: sources read at the shading point), improved, zinke")
        ->capture_default_str();
    dvp->add_option("--scene", kind,
                    "block | scalp | fur | fur-shell | fur-short | fur-long | fur-flat | fur-coarse | slab | slab-front (--hair-counts: strands; the slab's depth in fibers)")
        ->capture_default_str();
    dvp->add_option("--dual-spp", dual_spp, "spp of the dual and single scattering images")->capture_default_str();
    dvp->add_option("--path-spp", path_spp, "spp of the path-traced reference")->capture_default_str();

    CLI::App* furn = app.add_subcommand("furnace", "the white furnace: lossless hair under a uniform environment");
    common(furn);
    std::vector<std::string> furnace_scenes{"block:1500", "fur-shell:20000"};
    std::vector<std::string> furnace_formulations{"two-stream", "two-stream-grid", "two-stream-field", "improved",
                                                  "zinke"};
    int furnace_dual_spp = 32, furnace_path_spp = 64;
    furn->add_option("--scenes", furnace_scenes, "kind:hairs (block, scalp, fur, fur-shell and its variants fur-short, fur-long, fur-flat, fur-coarse; slab, slab-front: its depth)")
        ->capture_default_str();
    furn->add_option("--formulations", furnace_formulations, "dual-scattering formulations")->capture_default_str();
    furn->add_option("--dual-spp", furnace_dual_spp, "spp of the dual images")->capture_default_str();
    furn->add_option("--path-spp", furnace_path_spp, "spp of the path-traced images")->capture_default_str();

    CLI::App* tte = app.add_subcommand("time-to-error", "seconds to a relative RMSE: dual scattering vs path tracing");
    common(tte);
    int tte_ref = 4096, tte_dual = 256, tte_path = 2048;
    bool tte_no_ground = false;
    tte->add_option("--colour", c.colour, io::colour_preset_names())->capture_default_str();
    tte->add_option("--reference-spp", tte_ref, "spp of the path-traced reference")->capture_default_str();
    tte->add_option("--dual-max-spp", tte_dual, "largest dual-scattering spp level")->capture_default_str();
    tte->add_option("--path-max-spp", tte_path, "largest path-tracing spp level")->capture_default_str();
    tte->add_flag("--no-ground", tte_no_ground, "remove the ground plane");
    std::string tte_kind = "block";
    tte->add_option("--scene", tte_kind, "block | scalp | fur | fur-shell | fur-short | fur-long | fur-flat | fur-coarse | slab | slab-front")->capture_default_str();
    std::vector<std::string> tte_formulations{"two-stream", "two-stream-field"};
    tte->add_option("--formulations", tte_formulations, "dual-scattering formulations (as dual-vs-path's)")
        ->capture_default_str();
    std::string tte_suffix;
    tte->add_option("--tag-suffix", tte_suffix, "appended to the files' names (time_to_error_<scene>_<colour>_<hairs><suffix>)");

    CLI::App* arr = app.add_subcommand("arrivals", "the dual estimator's arrivals against the path tracer's, binned");
    common(arr);
    std::string arr_kind = "slab", arr_formulation = "two-stream-field";
    int arr_points = 2000, arr_dual = 16, arr_path = 64;
    bool arr_no_ground = false;
    arr->add_option("--scene", arr_kind, "block | scalp | fur | fur-shell | fur-short | fur-long | fur-flat | fur-coarse | slab | slab-front")->capture_default_str();
    arr->add_option("--colour", c.colour, io::colour_preset_names())->capture_default_str();
    arr->add_option("--formulation", arr_formulation, "two-stream, two-stream-grid or two-stream-field")->capture_default_str();
    arr->add_option("--points", arr_points, "hair points seen by the camera")->capture_default_str();
    arr->add_option("--dual-samples", arr_dual, "dual estimates per point")->capture_default_str();
    arr->add_option("--path-samples", arr_path, "paths per point")->capture_default_str();
    arr->add_flag("--no-ground", arr_no_ground, "remove the ground plane");

    CLI11_PARSE(app, argc, argv);
    try {
        if (conv->parsed()) return convergence(c, max_spp, reference_spp, reference_sampling, threshold);
        c.ground = !no_ground;
        if (dvp->parsed()) return dual_vs_path(c, kind, hair_counts, colours, formulations, dual_spp, path_spp);
        if (furn->parsed()) return furnace(c, furnace_scenes, furnace_formulations, furnace_dual_spp, furnace_path_spp);
        if (arr->parsed()) {
            c.ground = !arr_no_ground;
            return arrivals(c, arr_kind, c.hairs, arr_formulation, arr_points, arr_dual, arr_path);
        }
        if (tte->parsed()) {
            c.ground = !tte_no_ground;
            return time_to_error(c, tte_kind, tte_ref, tte_dual, tte_path, tte_formulations, tte_suffix);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "study: %s\n", e.what());
        return 1;
    }
    return 1;
}
