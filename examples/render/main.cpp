// render — the example renderer's command line: hair blocks, a Cornell box, a scalp, the
// showcase bust, a fur ball, a slab of parallel strands or a .hair file, under a constant,
// studio or OpenEXR environment; single, dual and path-traced hair with any of the
// library's fiber models; a camera to place, a crop to render; OpenEXR + PNG output and a
// summary line on stdout. Every option is checked before the scene is built, with a
// message naming it.
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <unistd.h>
#include <vector>

#include <CLI/CLI.hpp>
#include <common/image_io.hpp>
#include <common/options.hpp>

#include "hair_file.hpp"
#include "render.hpp"
#include "scenes.hpp"
#include "shading.hpp"

namespace hs = hairscatter;
namespace ex = hairscatter_examples;

int main(int argc, char** argv) {
    CLI::App app{"hairscatter example renderer: hair blocks, a Cornell box, a scalp, a bust with long hair, a fur ball "
                 "and a slab lit by an area light and a constant, studio or OpenEXR environment, shaded with single "
                 "scattering, dual scattering or a path tracer"};
    std::string scene_name = "block", hair_file, write_hair, out = "out/render";
    render::RenderOptions ro;
    render::BlockOptions block;
    render::ScalpOptions scalp;
    render::FurOptions fur;
    render::HeadOptions head;
    render::SlabOptions slab;
    render::LightingOptions lighting;
    ex::FiberOptions fiber;
    float exposure = 0.0f, grid_cell = 0.0f, thickness_scale = 1.0f;
    bool wavy = false, mask = false, quiet = false, no_ground = false;
    std::string integrator = "dual", sampling = "mis";

    app.add_option("--scene", scene_name,
                   "block | cornell | scalp | head (the showcase bust: studio environment, no area light and the "
                   "filmic preview unless --env, --light-power or --tone say otherwise) | fur | slab | file (with "
                   "--hair-file)")
        ->check(CLI::IsMember({"block", "cornell", "scalp", "head", "fur", "slab", "file"}))
        ->capture_default_str();
    app.add_option("--hair-file", hair_file, "a Cem Yuksel .hair file (implies --scene file)")->check(CLI::ExistingFile);
    app.add_option("--write-hair", write_hair, "also save the scene's strands as a .hair file");
    app.add_option("--thickness-scale", thickness_scale, "scene file: multiplies the file's fiber thickness")
        ->capture_default_str();
    app.add_option("--hairs", block.count, "block: number of strands (the study's: 1500, 3000, 6000, 12000)")
        ->capture_default_str();
    app.add_option("--block-size", block.size, "block: side of the cube")->capture_default_str();
    app.add_option("--fiber-radius", block.radius, "block and slab: fiber radius; fur and head: when given (defaults 0.004 and 0.003)")
        ->capture_default_str();
    app.add_flag("--wavy", wavy, "block: wavy strands instead of straight ones");
    app.add_option("--scalp-hairs", scalp.count, "scalp: number of strands")->capture_default_str();
    app.add_option("--curl", scalp.curl_radius, "scalp: curl radius (0: straight)")->capture_default_str();
    app.add_option("--gravity", scalp.gravity, "scalp: bend per unit length")->capture_default_str();
    app.add_option("--head-hairs", head.count, "head: number of strands, in [1, 10^7]")->capture_default_str();
    app.add_option("--hair-length", head.length, "head: mean strand length in head radii, in [0.05, 10] (each ±10 %)")
        ->capture_default_str();
    app.add_option("--clump", head.clump, "head: how far strands draw toward their clump's tip, in [0, 1]")
        ->capture_default_str();
    app.add_option("--frizz", head.frizz, "head: a random walk per unit length along the strands, in [0, 1]")
        ->capture_default_str();
    app.add_option("--fur-hairs", fur.count, "fur: number of strands")->capture_default_str();
    app.add_option("--fur-length", fur.length, "fur: mean strand length (each varies by ±30 %)")
        ->capture_default_str();
    app.add_option("--fur-tilt", fur.tilt_deg, "fur: degrees from the surface normal toward -y (combing)")
        ->capture_default_str();
    app.add_flag("--fur-body,!--no-fur-body", fur.body,
                 "fur: strands on a diffuse body sphere of albedo 0.4 (the default), or an empty shell of strands");
    app.add_option("--fur-seed", fur.seed, "fur: generator seed")->capture_default_str();
    app.add_option("--slab-depth", slab.depth, "slab: mean number of fibers a ray along the slab's normal crosses")
        ->capture_default_str();
    app.add_flag("--slab-overlap", slab.overlap,
                 "slab: independent fiber axes, fibers may interpenetrate (default: placed without overlap)");
    app.add_flag("--slab-vertical", slab.vertical,
                 "slab: fibers along y, so that the front light (above the camera) lies along them "
                 "rather than across them (default: along x)");
    app.add_flag("--back-lit", slab.back_lit,
                 "slab: the area light behind the slab, facing it and the camera (seen only through the gaps)");
    app.add_flag("--no-ground", no_ground, "remove the ground plane (block, scalp, fur, file)");
    app.add_option("--integrator", integrator,
                   "single | dual | path (dual scattering is Chiang's full model or --model fur: the other models "
                   "and --lobes apply to single and path)")
        ->check(CLI::IsMember({"single", "dual", "path"}))
        ->capture_default_str();
    app.add_option("--sampling", sampling, "dual and path: uniform | importance | mis")
        ->check(CLI::IsMember({"uniform", "importance", "mis"}))
        ->capture_default_str();
    ex::add_fiber_options(app, fiber, "blond", " (single and path; dual is chiang or fur)");
    app.add_option("--spp", ro.spp, "samples per pixel")->capture_default_str();
    app.add_option("--width", ro.width, "image width")->capture_default_str();
    app.add_option("--height", ro.height, "image height")->capture_default_str();
    app.add_option("--max-depth", ro.max_depth,
                   "path: a safety cap on bounces (paths end by Russian roulette; the default never matters)")
        ->capture_default_str();
    app.add_option("--seed", ro.seed, "random seed (each pixel's generator depends on it and the pixel only)")
        ->capture_default_str();
    app.add_option("--threads", ro.threads, "rendering threads (0: one per core; the image does not depend on it)")
        ->capture_default_str();
    std::string dual_formulation = "two-stream", dual_counts = "field", dual_source = "beyond-exit";
    float d_f = -1, d_b = -1;
    app.add_option("--dual", dual_formulation,
                   "dual: two-stream (the default: two-stream transport at the arrival direction, surfaces "
                   "traced) | improved (the dual-scattering BCSDF) | zinke (the BCSDF as Zinke et al. 2008 wrote it)")
        ->check(CLI::IsMember({"two-stream", "improved", "zinke"}))
        ->capture_default_str();
    app.add_option("--dual-counts", dual_counts,
                   "dual two-stream: fibers along a ray counted exactly on the hair (a ray per count), drawn from the "
                   "density grid (a march), or looked up in the directional count field (no ray)")
        ->check(CLI::IsMember({"exact", "grid", "field"}))
        ->capture_default_str();
    app.add_option("--dual-source", dual_source,
                   "dual two-stream: where a stack's source light is read: beyond its last fiber, through the hair "
                   "there (the default), or at the shading point with the hair ignored (point)")
        ->check(CLI::IsMember({"beyond-exit", "point"}))
        ->capture_default_str();
    int field_side = 12;
    float field_spacing = 1.0f;
    std::string dual_depth = "shape";
    std::string dual_stacks = "inclined";
    std::string dual_transport = "turned";
    std::string dual_kernels = "aligned";
    int dual_glow = 4;
    app.add_option("--dual-depth", dual_depth,
                   "dual two-stream: how many fibers turning light crosses per fiber of a stack, from the hair's "
                   "shape around the point (shape: the count field or the density grid, built for it with exact "
                   "counts) or a slab's (slab)")
        ->check(CLI::IsMember({"shape", "slab"}))
        ->capture_default_str();
    app.add_option("--dual-stacks", dual_stacks,
                   "dual two-stream: a fiber's backscatter returns along a stack only where it travels back "
                   "along it (inclined, the default: the tables' rho_b, a fiber keeping the light's travel along "
                   "its axis; dense white fur within 1 % of the path tracer, docs/dual.md) or always (planar: the "
                   "1D stack of Zinke et al. 2008)")
        ->check(CLI::IsMember({"inclined", "planar"}))
        ->capture_default_str();
    app.add_option("--dual-transport", dual_transport,
                   "dual two-stream: how light crosses a stack where it has spread over its half-circle: as along "
                   "the arrival (turned) or trading between the two half-circles as it turns (diffuse; docs/theory.md)")
        ->check(CLI::IsMember({"turned", "diffuse"}))
        ->capture_default_str();
    app.add_option("--dual-kernels", dual_kernels,
                   "dual two-stream: source kernels that assume the hair around a point parallel to it (aligned) "
                   "or widen in theta by the misalignment the density grid reads there (misaligned: curly hair; "
                   "docs/theory.md)")
        ->check(CLI::IsMember({"aligned", "misaligned"}))
        ->capture_default_str();
    app.add_option("--dual-glow", dual_glow,
                   "dual two-stream with grid or field counts: hair points per grid cell of the glow volume (the "
                   "hair's mean radiance, built before rendering; hair along a source direction is read as lit "
                   "hair); 0: none")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();
    int dual_vertices = 0;
    app.add_option("--dual-vertices", dual_vertices,
                   "dual two-stream: a path's first vertices traced as the path tracer traces them before the "
                   "estimator shades (0: the camera's hit; more: less bias, more noise and cost)")
        ->check(CLI::Range(0, 8))
        ->capture_default_str();
    app.add_option("--field-side", field_side,
                   "dual two-stream, field counts: the octahedral map's side, [2, 64] (side² directions)")
        ->check(CLI::Range(2, 64))
        ->capture_default_str();
    app.add_option("--field-spacing", field_spacing,
                   "dual two-stream, field counts: the field's lattice spacing in density-grid cells, [1, 64]")
        ->check(CLI::Range(1.0f, 64.0f))
        ->capture_default_str();
    app.add_option("--d-f", d_f, "dual improved and zinke: forward density factor in [0, 1] (default 1 improved, 0.7 zinke)");
    app.add_option("--d-b", d_b, "dual improved and zinke: backward density factor in [0, 1] (default 1 improved, 0.7 zinke)");
    app.add_option("--grid-cell", grid_cell, "dual: density grid cell size (0: 1/32 of the hair's extent)");
    app.add_option("--light-size", lighting.light_size, "side of the square area light")->capture_default_str();
    app.add_option("--light-power", lighting.light_power, "area light scale (0: no area light)")
        ->capture_default_str();
    app.add_option("--environment", lighting.environment, "constant environment radiance, in [0, 10^6]")
        ->capture_default_str();
    app.add_option("--env", lighting.env,
                   "environment: constant (--environment's radiance) | studio (procedural softboxes and a "
                   "gradient) | FILE (an OpenEXR lat-long map, width = 2 x height, RGB), importance-sampled")
        ->capture_default_str();
    app.add_option("--env-rotate", lighting.env_rotate_deg, "rotates the environment map about +y, degrees in [-360, 360]")
        ->capture_default_str();
    app.add_option("--env-intensity", lighting.env_intensity, "scales the environment (map or constant), in [0, 10^6]")
        ->capture_default_str();
    app.add_flag("--hair-only", ro.hair_only, "render only pixels whose primary ray hits hair");
    app.add_flag("--mask", mask, "also write <out>_mask.png, the hair-pixel mask");
    app.add_option("--exposure", exposure, "PNG preview exposure in stops, in [-64, 64]")->capture_default_str();
    std::string tone = "clamp";
    app.add_option("--tone", tone,
                   "PNG preview tone curve: clamp (values above 1 show white) | filmic (a highlight shoulder, ACES "
                   "fit); the EXR stays linear")
        ->check(CLI::IsMember({"clamp", "filmic"}))
        ->capture_default_str();
    std::vector<float> eye, look_at, up, crop;
    float fov = 0;
    app.add_option("--eye", eye, "camera position x,y,z (default: the scene's, which frames it)")
        ->delimiter(',')
        ->expected(3);
    app.add_option("--look-at", look_at, "the point the camera looks at, x,y,z (default: the scene's)")
        ->delimiter(',')
        ->expected(3);
    app.add_option("--up", up, "camera up vector x,y,z, not along the view direction (default 0,1,0)")
        ->delimiter(',')
        ->expected(3);
    app.add_option("--fov", fov, "vertical field of view in degrees, in [1, 170] (default: the scene's)");
    app.add_option("--crop", crop,
                   "render only the window x0,y0,x1,y1 of the --width x --height frame, in pixels from the top-left "
                   "(0 <= x0 < x1 <= width, 0 <= y0 < y1 <= height): a close-up, the same pixels as the whole frame's")
        ->delimiter(',')
        ->expected(4);
    app.add_option("-o,--out", out, "output path without extension: writes <out>.exr and <out>.png")
        ->capture_default_str();
    app.add_flag("-q,--quiet", quiet, "no progress bar");
    CLI11_PARSE(app, argc, argv);

    try {
        // Every option first, before anything is built or written.
        ro.integrator = integrator == "single" ? render::Integrator::kSingle
                        : integrator == "dual" ? render::Integrator::kDual
                                               : render::Integrator::kPath;
        ro.sampling = sampling == "uniform"      ? render::Sampling::kUniform
                      : sampling == "importance" ? render::Sampling::kImportance
                                                 : render::Sampling::kMis;
        ro.progress = !quiet && isatty(fileno(stderr));
        for (float c : crop)
            if (!(c == std::floor(c) && std::abs(c) < 1e9f))
                throw std::invalid_argument("--crop takes whole pixel numbers x0,y0,x1,y1");
        if (!crop.empty()) ro.crop = {int(crop[0]), int(crop[1]), int(crop[2]), int(crop[3])};
        render::validate(ro);
        // RGB floats, the PNG bytes, the mask and the pixel loop's copies: ~32 bytes a pixel.
        ex::check_image_size(ro.width, ro.height, 32);
        if (!(std::isfinite(exposure) && std::abs(exposure) <= 64))
            throw std::invalid_argument("--exposure must be a number of stops in [-64, 64]");
        if (!(std::isfinite(thickness_scale) && thickness_scale >= 1e-3f && thickness_scale <= 1e3f))
            throw std::invalid_argument("--thickness-scale must be a factor in [0.001, 1000]");
        if (!(std::isfinite(grid_cell) && grid_cell >= 0))
            throw std::invalid_argument("--grid-cell must be a size >= 0 (0: automatic)");
        render::validate(lighting);
        if (!hair_file.empty()) scene_name = "file";
        if (scene_name == "block" || scene_name == "cornell") render::validate(block);
        if (scene_name == "scalp") render::validate(scalp);
        // --fiber-radius is the block's (0.01), also the slab's; fur is finer unless it is given.
        slab.radius = block.radius;
        if (app.count("--fiber-radius")) fur.radius = block.radius;
        if (scene_name == "fur") render::validate(fur);
        if (app.count("--fiber-radius")) head.radius = block.radius;
        if (scene_name == "head") {
            render::validate(head);
            // The showcase's look, unless asked otherwise.
            if (!app.count("--env")) lighting.env = "studio";
            if (!app.count("--light-power")) lighting.light_power = 0;
            if (!app.count("--tone")) tone = "filmic";
        }
        if (scene_name == "slab") render::validate(slab, lighting);
        if (scene_name == "file" && hair_file.empty()) throw std::invalid_argument("--scene file needs --hair-file");
        const std::shared_ptr<const render::Environment> env_map = render::load_environment(lighting);

        render::ShadingOptions so;
        so.model = ex::parse_model(fiber.model);
        so.lobes = ex::parse_lobes(fiber.lobes);
        // The dual integrator's tables and its local scattering are the full Chiang fiber's or,
        // with --model fur, the fur fibre's.
        const bool dual_model = (so.model == ex::FiberModel::kChiang && so.lobes == ex::LobeBits::kAll) ||
                                so.model == ex::FiberModel::kFur;
        if (ro.integrator == render::Integrator::kDual && !dual_model)
            throw std::invalid_argument("--integrator dual shades with the full Chiang model or --model fur only: drop "
                                        "--lobes, pick one of those models, or use --integrator single or path");
        const hs::FiberParams<double> params = ex::fiber_params(fiber, "blond");
        so.fiber = ex::params_as<float>(params);
        so.fiber_extras.controls = ex::controls_as<float>(ex::lobe_controls(fiber));
        so.fiber_extras.has_controls = ex::has_lobe_controls(fiber);
        const ex::StrandSetup strands = ex::strand_setup(fiber);
        so.section = fiber.section;
        so.medulla = ex::medulla_shape(fiber);
        so.dual_scattering = ro.integrator == render::Integrator::kDual;
        so.two_stream = dual_formulation == "two-stream";
        so.counts = dual_counts == "exact" ? render::DualCounts::kExact
                    : dual_counts == "grid"  ? render::DualCounts::kGrid
                                             : render::DualCounts::kField;
        so.source = dual_source == "point" ? render::DualSource::kPoint : render::DualSource::kBeyondExit;
        so.shape_depth = dual_depth == "shape";
        so.inclined_stacks = dual_stacks == "inclined";
        so.transport = dual_transport == "diffuse" ? hairscatter::DualStackTransport::kDiffuse
                                                   : hairscatter::DualStackTransport::kTurned;
        so.misaligned_kernels = dual_kernels == "misaligned";
        so.glow_points = dual_glow;
        so.traced_vertices = dual_vertices;
        so.field_side = field_side;
        so.field_spacing = field_spacing;
        so.dual = dual_formulation == "zinke" ? hs::DualScatteringSettings<float>::zinke2008()
                                              : hs::DualScatteringSettings<float>::improved();
        if (app.count("--d-f")) so.dual.d_f = d_f;
        if (app.count("--d-b")) so.dual.d_b = d_b;
        if (!(so.dual.d_f >= 0 && so.dual.d_f <= 1)) throw std::invalid_argument("--d-f must lie in [0, 1]");
        if (!(so.dual.d_b >= 0 && so.dual.d_b <= 1)) throw std::invalid_argument("--d-b must lie in [0, 1]");
        so.grid_cell = grid_cell;
        out = ex::strip_image_extension(out);
        ex::prepare_output(out);

        if (wavy) block.wave_amplitude = 0.08f;
        render::SceneDescription desc;
        if (scene_name == "block") desc = render::make_block_scene(block, lighting);
        else if (scene_name == "cornell") desc = render::make_cornell_scene(block, lighting);
        else if (scene_name == "scalp") desc = render::make_scalp_scene(scalp, lighting);
        else if (scene_name == "fur") desc = render::make_fur_scene(fur, lighting);
        else if (scene_name == "head") desc = render::make_head_scene(head, lighting);
        else if (scene_name == "slab") desc = render::make_slab_scene(slab, lighting);
        else desc = render::make_file_scene(hair_file, thickness_scale, lighting);
        if (no_ground) render::remove_ground(desc);
        if (!eye.empty()) desc.camera.eye = {eye[0], eye[1], eye[2]};
        if (!look_at.empty()) desc.camera.target = {look_at[0], look_at[1], look_at[2]};
        if (!up.empty()) desc.camera.up = {up[0], up[1], up[2]};
        if (app.count("--fov")) desc.camera.fov_y_deg = fov;
        render::validate(desc.camera);
        desc.environment *= lighting.env_intensity;
        // The Cornell box is closed: no environment reaches inside.
        if (scene_name != "cornell") desc.environment_map = env_map;
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
        // One fiber per strand with --strand-seed or a --*-range (docs/controls.md).
        if (strands.enabled)
            for (std::size_t s = 0; s < desc.hair.strands.size(); ++s)
                so.fiber_extras.strand_params.push_back(
                    ex::params_as<float>(ex::strand_fiber_params(params, strands, std::uint32_t(s))));
        // The materials and the grid's size are checked before the BVH is built.
        { const hairscatter_examples::FiberModels<float> check(so.model, so.lobes, so.fiber, so.fiber_extras, so.section,
                                                                   so.medulla); }
        render::check_grid(desc.hair, so);
        std::fprintf(stderr, "render: building the scene (%zu strands)\n", desc.hair.strands.size());
        const render::Scene scene(std::move(desc));
        const render::ShadingSetup shading(scene, so);
        const render::SceneStats& st = scene.stats();
        const render::ShadingStats& sh = shading.stats();
        std::fprintf(stderr,
                     "render: scene %s, %zu strands, %zu segments, %zu triangles; BVH %.2f s; shading %s (%s) %.3f s "
                     "(tables %.3f s, grid %.3f s %dx%dx%d)\n",
                     scene.description().name.c_str(), st.strands, st.hair_segments, st.triangles, st.bvh_seconds,
                     ex::to_string(so.model), ex::lobes_to_string(so.lobes).c_str(), sh.seconds, sh.table_seconds,
                     sh.grid_seconds, sh.grid_resolution.x, sh.grid_resolution.y, sh.grid_resolution.z);

        const render::RenderResult r = render::render(scene, shading, ro);
        if (scene.has_hair() && r.hair_pixels == 0)
            std::fprintf(stderr, "render: warning: no hair in view (no pixel's primary ray hits hair; check the "
                                 "camera, --fiber-radius or the file's thickness)\n");

        // Each file is written to a temporary and renamed when both are complete; a kill
        // between the two renames can still pair a new EXR with an old PNG, so both carry
        // the pair's id (also the summary's pair_id=): differing ids, files of two renders.
        const std::vector<std::uint8_t> png =
            ex::tone_map(r.rgb, exposure, tone == "filmic" ? ex::ToneCurve::kFilmic : ex::ToneCurve::kClamp);
        const std::string summary = render::summary_line(scene, shading, ro, r) + " pair_id=" + ex::pair_id(r.rgb, png);
        ex::write_exr_png_pair(out + ".exr", out + ".png", r.width, r.height, r.rgb, {{"hairscatter:render", summary}}, png);
        if (mask) {
            std::vector<std::uint8_t> m(r.hair_mask.size() * 3);
            for (std::size_t i = 0; i < r.hair_mask.size(); ++i)
                m[3 * i] = m[3 * i + 1] = m[3 * i + 2] = r.hair_mask[i] ? 255 : 0;
            ex::write_png_rgb8(out + "_mask.png", r.width, r.height, m);
        }
        std::fprintf(stderr, "render: %.2f s, wrote %s.exr and %s.png\n", r.seconds, out.c_str(), out.c_str());
        std::printf("%s\n", summary.c_str());
        if (r.dropped > 0)
            std::fprintf(stderr, "render: warning: %llu non-finite samples dropped\n",
                         static_cast<unsigned long long>(r.dropped));
        return 0;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "render: error: out of memory (try a smaller image, fewer hairs or a larger --grid-cell)\n");
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "render: error: %s\n", e.what());
        return 1;
    }
}
