// render — the example renderer's command line: scenes from the seed thesis, single,
// dual and path-traced hair, OpenEXR + PNG output and a summary line on stdout.
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <common/image_io.hpp>

#include "hair_file.hpp"
#include "render.hpp"
#include "scenes.hpp"

namespace hs = hairscatter;

namespace {

struct HairColour {
    std::string preset = "blond";  // blond | brown | dark | rgb
    float eumelanin = -1, pheomelanin = 0;
    std::vector<float> rgb;
};

glm::vec3 sigma_a_of(const HairColour& c, float beta_n) {
    if (!c.rgb.empty()) return hs::sigma_a_from_color(glm::vec3(c.rgb[0], c.rgb[1], c.rgb[2]), beta_n);
    if (c.eumelanin >= 0) return hs::sigma_a_from_melanin(c.eumelanin, c.pheomelanin);
    static const std::map<std::string, glm::vec2> kPresets = {
        {"blond", {0.3f, 0.0f}}, {"brown", {1.3f, 0.0f}}, {"dark", {8.0f, 0.0f}}, {"red", {0.3f, 0.9f}}};
    const auto it = kPresets.find(c.preset);
    if (it == kPresets.end()) throw std::invalid_argument("unknown hair colour '" + c.preset + "'");
    return hs::sigma_a_from_melanin(it->second.x, it->second.y);
}

std::vector<std::uint8_t> tone_map(const render::RenderResult& r, float exposure) {
    std::vector<std::uint8_t> out(r.rgb.size());
    const float gain = std::exp2(exposure);
    for (std::size_t i = 0; i < r.rgb.size(); ++i) out[i] = hairscatter_examples::srgb8(double(gain * r.rgb[i]));
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"hairscatter example renderer: hair blocks, a Cornell box and a scalp lit by an area light and a "
                 "constant environment, shaded with single scattering, dual scattering or a path tracer"};
    std::string scene_name = "block", hair_file, write_hair, out = "out/render";
    render::RenderOptions ro;
    render::BlockOptions block;
    render::ScalpOptions scalp;
    render::LightingOptions lighting;
    HairColour colour;
    hs::FiberParams<float> fiber;
    float alpha_deg = 2.0f, exposure = 0.0f, grid_cell = 0.0f, thickness_scale = 1.0f;
    bool wavy = false, mask = false, quiet = false;
    std::string integrator = "dual", sampling = "mis";

    app.add_option("--scene", scene_name, "block | cornell | scalp | file (with --hair-file)")
        ->check(CLI::IsMember({"block", "cornell", "scalp", "file"}))
        ->capture_default_str();
    app.add_option("--hair-file", hair_file, "a Cem Yuksel .hair file (implies --scene file)")->check(CLI::ExistingFile);
    app.add_option("--write-hair", write_hair, "also save the scene's strands as a .hair file");
    app.add_option("--thickness-scale", thickness_scale, "scene file: multiplies the file's fiber thickness")
        ->capture_default_str();
    app.add_option("--hairs", block.count, "block: number of strands (the thesis: 1500, 3000, 6000, 12000)")
        ->capture_default_str();
    app.add_option("--block-size", block.size, "block: side of the cube")->capture_default_str();
    app.add_option("--fiber-radius", block.radius, "block: fiber radius")->capture_default_str();
    app.add_flag("--wavy", wavy, "block: wavy strands instead of straight ones");
    app.add_option("--scalp-hairs", scalp.count, "scalp: number of strands")->capture_default_str();
    app.add_option("--curl", scalp.curl_radius, "scalp: curl radius (0: straight)")->capture_default_str();
    app.add_option("--gravity", scalp.gravity, "scalp: bend per unit length")->capture_default_str();
    app.add_option("--integrator", integrator, "single | dual | path")
        ->check(CLI::IsMember({"single", "dual", "path"}))
        ->capture_default_str();
    app.add_option("--sampling", sampling, "dual and path: uniform | importance | mis")
        ->check(CLI::IsMember({"uniform", "importance", "mis"}))
        ->capture_default_str();
    app.add_option("--spp", ro.spp, "samples per pixel")->capture_default_str();
    app.add_option("--width", ro.width, "image width")->capture_default_str();
    app.add_option("--height", ro.height, "image height")->capture_default_str();
    app.add_option("--max-depth", ro.max_depth, "path: maximum bounces")->capture_default_str();
    app.add_option("--seed", ro.seed, "random seed (each pixel's generator depends on it and the pixel only)")
        ->capture_default_str();
    app.add_option("--colour,--color", colour.preset, "hair colour preset: blond | brown | dark | red")
        ->capture_default_str();
    app.add_option("--eumelanin", colour.eumelanin, "eumelanin concentration (overrides --colour)");
    app.add_option("--pheomelanin", colour.pheomelanin, "pheomelanin concentration (with --eumelanin)");
    app.add_option("--rgb", colour.rgb, "hair colour as linear RGB in (0, 1] (overrides the rest)")->expected(3);
    app.add_option("--beta-m", fiber.beta_m, "longitudinal roughness βm")->capture_default_str();
    app.add_option("--beta-n", fiber.beta_n, "azimuthal roughness βn")->capture_default_str();
    app.add_option("--alpha", alpha_deg, "cuticle tilt α in degrees")->capture_default_str();
    app.add_option("--eta", fiber.eta, "index of refraction")->capture_default_str();
    app.add_option("--d-f", ro.d_f, "dual: forward density factor")->capture_default_str();
    app.add_option("--d-b", ro.d_b, "dual: backward density factor")->capture_default_str();
    app.add_option("--grid-cell", grid_cell, "dual: density grid cell size (0: 1/32 of the hair's extent)");
    app.add_option("--light-size", lighting.light_size, "side of the square area light")->capture_default_str();
    app.add_option("--light-power", lighting.light_power, "area light scale (0: no area light)")
        ->capture_default_str();
    app.add_option("--environment", lighting.environment, "constant environment radiance")->capture_default_str();
    app.add_flag("--hair-only", ro.hair_only, "render only pixels whose primary ray hits hair");
    app.add_flag("--mask", mask, "also write <out>_mask.png, the hair-pixel mask");
    app.add_option("--exposure", exposure, "PNG preview exposure in stops")->capture_default_str();
    app.add_option("-o,--out", out, "output path without extension: writes <out>.exr and <out>.png")
        ->capture_default_str();
    app.add_flag("-q,--quiet", quiet, "no progress bar");
    CLI11_PARSE(app, argc, argv);

    try {
        ro.integrator = integrator == "single" ? render::Integrator::kSingle
                        : integrator == "dual" ? render::Integrator::kDual
                                               : render::Integrator::kPath;
        ro.sampling = sampling == "uniform"      ? render::Sampling::kUniform
                      : sampling == "importance" ? render::Sampling::kImportance
                                                 : render::Sampling::kMis;
        ro.progress = !quiet && isatty(fileno(stderr));
        fiber.alpha = hs::radians(alpha_deg);
        fiber.sigma_a = sigma_a_of(colour, fiber.beta_n);
        if (wavy) block.wave_amplitude = 0.08f;
        if (!hair_file.empty()) scene_name = "file";

        render::SceneDescription desc;
        if (scene_name == "block") desc = render::make_block_scene(block, lighting);
        else if (scene_name == "cornell") desc = render::make_cornell_scene(block, lighting);
        else if (scene_name == "scalp") desc = render::make_scalp_scene(scalp, lighting);
        else {
            if (hair_file.empty()) throw std::invalid_argument("--scene file needs --hair-file");
            desc = render::make_file_scene(hair_file, thickness_scale, lighting);
        }
        desc.hair_params = fiber;
        if (!write_hair.empty()) {
            render::HairFile file;
            for (const auto& strand : desc.hair.strands) {
                file.segments.push_back(std::uint32_t(strand.size() - 1));
                file.points.insert(file.points.end(), strand.begin(), strand.end());
            }
            file.default_thickness = 2 * desc.hair.radius;
            file.info = "hairscatter render --scene " + desc.name;
            render::write_hair_file(write_hair, file);
        }
        desc.grid_cell = grid_cell;
        const render::Scene scene(std::move(desc));
        const render::SceneStats& st = scene.stats();
        std::fprintf(stderr,
                     "render: scene %s, %zu strands, %zu segments, %zu triangles; built in %.2f s (BVH %.2f s, "
                     "tables %.3f s, grid %.3f s %dx%dx%d)\n",
                     scene.description().name.c_str(), st.strands, st.hair_segments, st.triangles, st.build_seconds,
                     st.bvh_seconds, st.table_seconds, st.grid_seconds, st.grid_resolution.x, st.grid_resolution.y,
                     st.grid_resolution.z);

        const render::RenderResult r = render::render(scene, ro);

        const std::filesystem::path parent = std::filesystem::path(out).parent_path();
        if (!parent.empty()) std::filesystem::create_directories(parent);
        const std::string summary = render::summary_line(scene, ro, r);
        hairscatter_examples::write_exr_rgb(out + ".exr", r.width, r.height, r.rgb,
                                            {{"hairscatter:render", summary}});
        hairscatter_examples::write_png_rgb8(out + ".png", r.width, r.height, tone_map(r, exposure));
        if (mask) {
            std::vector<std::uint8_t> m(r.hair_mask.size() * 3);
            for (std::size_t i = 0; i < r.hair_mask.size(); ++i) m[3 * i] = m[3 * i + 1] = m[3 * i + 2] = r.hair_mask[i] ? 255 : 0;
            hairscatter_examples::write_png_rgb8(out + "_mask.png", r.width, r.height, m);
        }
        std::fprintf(stderr, "render: %.2f s, wrote %s.exr and %s.png\n", r.seconds, out.c_str(), out.c_str());
        std::printf("%s\n", summary.c_str());
        if (r.dropped > 0) std::fprintf(stderr, "render: warning: %llu non-finite samples dropped\n",
                                        static_cast<unsigned long long>(r.dropped));
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "render: error: %s\n", e.what());
        return 1;
    }
}
