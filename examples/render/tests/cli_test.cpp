// The renderer's command line: every bad option is refused up front with a message naming
// it (before the scene is built: the "render: building" line never appears), a .hair file
// without hair and an oversized density grid are refused with a reason, a view without
// hair is warned about, and every --model renders. Runs the render executable.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <vector>

#include <common/image_io.hpp>

#include "hair_file.hpp"

namespace {

struct Outcome {
    int status = -1;
    std::string output;  // stdout and stderr
};

Outcome run(const std::string& args) {
    const std::string cmd = std::string(RENDER_EXE) + " --quiet " + args + " 2>&1";
    Outcome r;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    char buf[4096];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof(buf), p)) > 0) r.output.append(buf, n);
    const int s = pclose(p);
    r.status = WIFEXITED(s) ? WEXITSTATUS(s) : 128 + WTERMSIG(s);
    return r;
}

std::string out_base(const std::string& name) { return std::string(TEST_OUT_DIR) + "/" + name; }
const std::string kTiny = " --width 16 --height 12 --spp 1 --hairs 200";

// args plus the tiny size's options it does not set itself (an option may be given once).
std::string tiny(const std::string& args) {
    std::string s = args;
    for (const char* o : {"--width 16", "--height 12", "--spp 1", "--hairs 200", "-o " TEST_OUT_DIR "/refused"}) {
        const std::string opt(o);
        if (args.find(opt.substr(0, opt.find(' ')) + " ") == std::string::npos) s += " " + opt;
    }
    return s;
}

// A refusal: non-zero exit (not a crash), the option named, nothing built.
void expect_refused(const std::string& args, const std::string& named) {
    const Outcome r = run(tiny(args));
    EXPECT_EQ(r.status, 1) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(named), std::string::npos) << args << "\n" << r.output;
    EXPECT_EQ(r.output.find("render: building"), std::string::npos) << "built the scene before refusing " << args;
}

TEST(RenderCli, RefusesBadValuesNamingTheOption) {
    expect_refused("--environment -1", "--environment");
    expect_refused("--environment nan", "--environment");
    expect_refused("--light-power -2", "--light-power");
    expect_refused("--light-size -1", "--light-size");
    expect_refused("--light-size 0", "--light-size");
    expect_refused("--scene scalp --scalp-hairs 100 --gravity nan", "--gravity");
    expect_refused("--scene scalp --scalp-hairs 100 --curl nan", "--curl");
    expect_refused("--scene scalp --scalp-hairs 100 --curl -0.1", "--curl");
    expect_refused("--eumelanin -1", "--eumelanin");
    expect_refused("--eumelanin nan", "--eumelanin");
    expect_refused("--eumelanin 1 --pheomelanin -1", "--pheomelanin");
    expect_refused("--rgb 0.5,0,0.5", "--rgb");
    expect_refused("--beta-m 0", "beta_m");
    expect_refused("--spp 0", "--spp");
    expect_refused("--max-depth 0", "--max-depth");
    expect_refused("--threads -1", "--threads");
    expect_refused("--d-f 2", "--d-f");
    expect_refused("--grid-cell -1", "--grid-cell");
    expect_refused("--model tabulated --lobes R", "--lobes");
    expect_refused("--model chiang --lobes R,XX", "--lobes");
    expect_refused("--integrator dual --model farfield", "--integrator dual");
    expect_refused("--integrator dual --lobes R", "--integrator dual");
    expect_refused("--integrator single --model marschner --alpha 20", "marschner");
}

// Out-of-range values (before: --block-size 2147483648 rendered an empty image and exited
// 0, --fur-length 1e30 tripped an Embree assertion, --curl 1e30 and a thickness of 1e30
// failed inside the density grid with "box diagonal / 16777216 = inf", --light-size 1e-20
// failed after the build): each is refused up front naming its option.
TEST(RenderCli, RefusesOutOfRangeValuesNamingTheOption) {
    expect_refused("--block-size 2147483648", "--block-size");
    expect_refused("--block-size 1e-30", "--block-size");
    expect_refused("--fiber-radius 1e-30", "--fiber-radius");
    expect_refused("--scene scalp --scalp-hairs 100 --curl 1e30", "--curl");
    expect_refused("--scene scalp --scalp-hairs 100 --curl 1e30 --dual improved", "--curl");
    expect_refused("--scene scalp --scalp-hairs 100 --gravity 1e30", "--gravity");
    expect_refused("--scene fur --fur-hairs 100 --fur-length 1e30", "--fur-length");
    expect_refused("--scene slab --fiber-radius 1e-30", "--fiber-radius");
    // Fibers that may not overlap cannot fill more than 45 % of the slab's section.
    expect_refused("--scene slab --slab-depth 20", "--slab-depth");
    expect_refused("--light-size 1e-20", "--light-size");
    expect_refused("--light-size 1e30", "--light-size");
    expect_refused("--light-power 1e30", "--light-power");
    expect_refused("--environment 1e30", "--environment");
    expect_refused("--eye 0,10,0 --look-at 0,0,0", "--up is along the view direction");
    expect_refused("--up 0,0,0", "--up must not be zero");
    expect_refused("--eye 1,2,3 --look-at 1,2,3", "--eye and --look-at are the same point");
    expect_refused("--fov 0", "--fov");
    expect_refused("--fov 171", "--fov");
    expect_refused("--crop 0,0,17,12", "--crop");
    expect_refused("--crop 4,4,4,8", "--crop");
    expect_refused("--crop 0.5,0,8,8", "--crop");
    expect_refused("--env-rotate 400", "--env-rotate");
    expect_refused("--env studio --env-intensity -1", "--env-intensity");
    expect_refused("--env studio --env-intensity 0", "--env studio: the map is black");
    expect_refused("--env " + out_base("no_such_map.exr"), "--env " + out_base("no_such_map.exr") + ": cannot open");
    expect_refused("--exposure 1e30", "--exposure");
    expect_refused("--spp 2000000", "--spp");
    expect_refused("--integrator path --max-depth 2000000000", "--max-depth");
    expect_refused("--dual improved --grid-cell 1e30", "--grid-cell");
    expect_refused("--dual-counts grid --grid-cell 1e30", "--grid-cell");
    // A .hair file: --thickness-scale out of range, or a file thickness that it turns into
    // a fiber wider than the scene.
    render::HairFile f;
    f.segments = {2};
    f.points = {{0, 0, 0}, {1, 0, 0}, {2, 0.5f, 0}};
    f.default_thickness = 0.001f;  // a fiber radius of 1.25e-3 in the 5-unit box
    const std::string thin = out_base("range_thin.hair"), thick = out_base("range_thick.hair");
    render::write_hair_file(thin, f);
    f.default_thickness = 1e30f;
    render::write_hair_file(thick, f);
    expect_refused("--hair-file " + thin + " --thickness-scale 1e30 --dual improved", "--thickness-scale");
    expect_refused("--hair-file " + thick + " --dual improved", "--thickness-scale");
    expect_refused("--hair-file " + thick + " --thickness-scale 0.001", "gives a fiber radius of");
    // The bounds themselves render (the negative control).
    for (const char* ok : {"--block-size 100", "--block-size 0.01 --fiber-radius 0.001", "--light-size 0.001",
                           "--exposure -64", "--dual improved --grid-cell 4", "--env studio --env-rotate -360",
                           "--env constant --env-intensity 0", "--eye 0,10,0 --look-at 0,0,0 --up 0,0,-1",
                           "--fov 170 --crop 0,0,16,12 --tone filmic"}) {
        const Outcome r = run(tiny(std::string("--integrator dual ") + ok));
        EXPECT_EQ(r.status, 0) << ok << "\n" << r.output;
    }
    EXPECT_EQ(run(tiny("--hair-file " + thin + " --thickness-scale 1000")).status, 0);
}

// The production-shader controls (docs/controls.md): each bad value names its option.
TEST(RenderCli, RefusesBadControlsNamingTheOption) {
    expect_refused("--melanin 1.5", "--melanin");
    expect_refused("--melanin 0.5 --redness -0.1", "--redness");
    expect_refused("--redness 0.5", "--melanin");
    expect_refused("--dye 0.5,0,0.5", "--dye");
    expect_refused("--gain-r -1", "--gain-r");
    expect_refused("--gain-tt nan", "--gain-tt");
    expect_refused("--gain-res 2e6", "--gain-res");
    expect_refused("--tint-trt 1,-1,1", "--tint-trt");
    expect_refused("--alpha-trt 30", "--alpha-trt");
    expect_refused("--strand-seed -1", "--strand-seed");
    expect_refused("--melanin-range 0.6,0.2", "--melanin-range");
    expect_refused("--redness-range 0,1.5 --melanin 0.5", "--redness-range");
    expect_refused("--roughness-range 0,2", "--roughness-range");
    expect_refused("--melanin-range 0.2,0.6 --colour brown", "--melanin-range");
    expect_refused("--integrator single --model huang --alpha-tt 3", "HuangParams::alpha");
    expect_refused("--integrator single --model marschner --gain-res 2", "no residual lobe");
    expect_refused("--integrator path --model marschner --strand-seed 3", "--model chiang");
}

// mean_hair_rgb's red value in a summary line (-1 when missing).
double mean_hair_red(const std::string& output) {
    const std::size_t at = output.find("mean_hair_rgb=");
    return at == std::string::npos ? -1.0 : std::atof(output.c_str() + at + 14);
}

// Gains, tints, tilts and per-strand variation render with every integrator; zero gains
// darken the hair pixels and doubled gains brighten them (the same seed, the same rays:
// the jittered rays that miss the hair see the same background).
TEST(RenderCli, ControlsRender) {
    const std::string controls = " --melanin-range 0.2,0.7 --redness-range 0,0.5 --roughness-range 0.8,1.2 "
                                 "--strand-seed 4 --gain-trt 2 --tint-tt 1,0.8,0.8 --alpha-r 4 --dye 1,0.9,0.9";
    for (const char* integrator : {"single", "dual", "path"}) {
        const Outcome r = run(std::string("--integrator ") + integrator + controls + kTiny + " -o " +
                              out_base(std::string("controls_") + integrator));
        EXPECT_EQ(r.status, 0) << integrator << "\n" << r.output;
        EXPECT_NE(r.output.find("nonfinite_pixels=0"), std::string::npos) << r.output;
    }
    const std::string single = "--integrator single --hair-only" + kTiny;
    const Outcome plain = run(single + " -o " + out_base("controls_plain"));
    const Outcome dark = run(single + " --gain-r 0 --gain-tt 0 --gain-trt 0 --gain-res 0 -o " + out_base("controls_dark"));
    const Outcome bright = run(single + " --gain-r 2 --gain-tt 2 --gain-trt 2 --gain-res 2 -o " + out_base("controls_bright"));
    const double m = mean_hair_red(plain.output), d = mean_hair_red(dark.output), b = mean_hair_red(bright.output);
    EXPECT_GT(m, 0.0) << plain.output;
    EXPECT_GE(d, 0.0) << dark.output;
    EXPECT_LT(d, m);  // same seed: without the gains reaching the fibers, d = m = b exactly
    EXPECT_GT(b, m);
}

// The lobe controls on the other models: each renders with gains, a tint and a tilt, and
// zero gains darken its hair pixels, doubled gains brighten them (Marschner has no residual).
TEST(RenderCli, ControlsRenderOnEveryModel) {
    for (const char* model : {"farfield", "tabulated", "marschner"}) {
        const bool residual = std::string(model) != "marschner";
        const std::string single = std::string("--integrator single --hair-only --model ") + model + kTiny;
        auto gains = [&](const char* g) {
            return std::string(" --gain-r ") + g + " --gain-tt " + g + " --gain-trt " + g +
                   (residual ? std::string(" --gain-res ") + g : std::string());
        };
        const Outcome plain = run(single + " -o " + out_base(std::string("controls_plain_") + model));
        const Outcome mixed = run(single + " --gain-r 2 --gain-trt 0.3 --tint-tt 1,0.7,0.5 --alpha-r 4 -o " +
                                  out_base(std::string("controls_mixed_") + model));
        const Outcome dark = run(single + gains("0") + " -o " + out_base(std::string("controls_dark_") + model));
        const Outcome bright = run(single + gains("2") + " -o " + out_base(std::string("controls_bright_") + model));
        for (const Outcome* r : {&plain, &mixed, &dark, &bright}) {
            EXPECT_EQ(r->status, 0) << model << "\n" << r->output;
            EXPECT_NE(r->output.find("nonfinite_pixels=0"), std::string::npos) << model << "\n" << r->output;
        }
        const double m = mean_hair_red(plain.output), d = mean_hair_red(dark.output), b = mean_hair_red(bright.output);
        EXPECT_GT(m, 0.0) << model << "\n" << plain.output;
        EXPECT_GE(d, 0.0) << model << "\n" << dark.output;
        EXPECT_LT(d, m) << model;  // same seed: without the gains reaching the fibers, d = m = b exactly
        EXPECT_GT(b, m) << model;
        EXPECT_NE(mean_hair_red(mixed.output), m) << model;
    }
}

// --model fur's medulla: each bad value refused naming its option, the knobs refused with
// another model, and the integrator and controls the fur fiber does not have.
TEST(RenderCli, RefusesBadFurValuesNamingTheOption) {
    const std::string fur = "--model fur --integrator path ";
    expect_refused(fur + "--kappa 1", "--kappa");
    expect_refused(fur + "--kappa -0.1", "--kappa");
    expect_refused(fur + "--kappa nan", "--kappa");
    expect_refused(fur + "--medulla-sigma-s -1", "--medulla-sigma-s");
    expect_refused(fur + "--medulla-sigma-s inf", "--medulla-sigma-s");
    expect_refused(fur + "--medulla-sigma-a -0.5", "--medulla-sigma-a");
    expect_refused(fur + "--medulla-sigma-a 1,2", "--medulla-sigma-a");
    expect_refused(fur + "--medulla-sigma-a 1,-2,3", "--medulla-sigma-a");
    expect_refused(fur + "--medulla-g 1", "--medulla-g");
    expect_refused(fur + "--medulla-g -1", "--medulla-g");
    expect_refused("--integrator path --kappa 0.5", "only --model fur");
    expect_refused("--integrator single --model farfield --medulla-g 0.3", "only --model fur");
    expect_refused("--integrator single --rough-cortex", "only --model fur");
    expect_refused("--integrator single --facet-alpha 0.2", "only --model fur");
    expect_refused(fur + "--facet-alpha 0.2", "only with --rough-cortex");
    expect_refused(fur + "--rough-cortex --facet-alpha 1.5", "--facet-alpha");
    expect_refused(fur + "--rough-cortex --facet-alpha nan", "--facet-alpha");
    expect_refused("--integrator dual --model huang", "--integrator dual");
    expect_refused(fur + "--gain-r -1", "--gain-r");  // fur takes the lobe controls, checked as for chiang
    expect_refused(fur + "--strand-seed 3", "--model chiang");
}

// The fur ball renders with the fur fiber under every integrator (dual scattering with the
// two-stream estimator and with the BCSDF), finite; a scattering medulla changes the hair
// pixels (the same seed and rays: without the knobs reaching the fiber the means would be
// equal), so does --rough-cortex, and a scalar --medulla-sigma-a is the grey R,G,B.
TEST(RenderCli, FurRendersWithAMedulla) {
    const std::string scene = " --scene fur --fur-hairs 400 --width 24 --height 18 --spp 2 --model fur";
    struct Run {
        const char *integrator, *args;
    };
    for (const Run& run_of : {Run{"single", "single"}, Run{"path", "path"}, Run{"dual", "dual"},
                              Run{"dual_bcsdf", "dual --dual improved"}}) {
        const std::string integrator = run_of.integrator;
        const std::string base = std::string("--integrator ") + run_of.args + scene;
        const Outcome bare = run(base + " -o " + out_base(std::string("fur_bare_") + integrator));
        const Outcome medulla = run(base + " --kappa 0.6 --medulla-sigma-s 10 --medulla-g 0.3 -o " +
                                    out_base(std::string("fur_medulla_") + integrator));
        const Outcome grey = run(base + " --kappa 0.6 --medulla-sigma-s 10 --medulla-sigma-a 0.5 -o " +
                                 out_base(std::string("fur_grey_") + integrator));
        const Outcome rgb = run(base + " --kappa 0.6 --medulla-sigma-s 10 --medulla-sigma-a 0.5,0.5,0.5 -o " +
                                out_base(std::string("fur_rgb_") + integrator));
        const Outcome rough = run(base + " --rough-cortex -o " + out_base(std::string("fur_rough_") + integrator));
        for (const Outcome* r : {&bare, &medulla, &grey, &rgb, &rough}) {
            EXPECT_EQ(r->status, 0) << integrator << "\n" << r->output;
            EXPECT_NE(r->output.find(" model=fur "), std::string::npos) << r->output;
            EXPECT_NE(r->output.find(" dropped=0 nonfinite_pixels=0 "), std::string::npos) << r->output;
        }
        const double b = mean_hair_red(bare.output), m = mean_hair_red(medulla.output);
        EXPECT_GT(b, 0.0) << bare.output;
        EXPECT_GT(m, 0.0) << medulla.output;
        EXPECT_NE(m, b) << integrator;
        EXPECT_NE(mean_hair_red(rough.output), b) << integrator;  // --rough-cortex reaches the fibre
        EXPECT_EQ(mean_hair_red(grey.output), mean_hair_red(rgb.output)) << integrator;
    }
}

// --facet-alpha reaches the rough cortex: its GGX facets change the hair pixels (the same seed
// and rays as the facets from β, GGX 0.182 at the default β_m 0.3).
TEST(RenderCli, FurFacetAlphaReachesTheRoughCortex) {
    const std::string base = "--integrator single --scene fur --fur-hairs 400 --width 24 --height 18 --spp 2 --model fur "
                             "--rough-cortex";
    const Outcome from_beta = run(base + " -o " + out_base("fur_facets_from_beta"));
    const Outcome ggx = run(base + " --facet-alpha 0.5 -o " + out_base("fur_facets_ggx"));
    for (const Outcome* r : {&from_beta, &ggx}) {
        EXPECT_EQ(r->status, 0) << r->output;
        EXPECT_NE(r->output.find(" dropped=0 nonfinite_pixels=0 "), std::string::npos) << r->output;
    }
    EXPECT_GT(mean_hair_red(ggx.output), 0.0) << ggx.output;
    EXPECT_NE(mean_hair_red(ggx.output), mean_hair_red(from_beta.output));
}

// --model fur takes the lobe controls (docs/controls.md) on R, TT, TRT and the residual: a
// gain of 0 on every one of them leaves only the medulla's light, darker than the whole.
TEST(RenderCli, FurTakesTheLobeControls) {
    const std::string base = "--integrator single --scene fur --fur-hairs 400 --width 24 --height 18 --spp 2 --model fur"
                             " --kappa 0.6 --medulla-sigma-s 10";
    const Outcome whole = run(base + " -o " + out_base("fur_controls_whole"));
    const Outcome medulla_only =
        run(base + " --gain-r 0 --gain-tt 0 --gain-trt 0 --gain-res 0 -o " + out_base("fur_controls_s"));
    for (const Outcome* r : {&whole, &medulla_only}) {
        EXPECT_EQ(r->status, 0) << r->output;
        EXPECT_NE(r->output.find(" dropped=0 nonfinite_pixels=0 "), std::string::npos) << r->output;
    }
    const double w = mean_hair_red(whole.output), s = mean_hair_red(medulla_only.output);
    EXPECT_GT(s, 0.0) << medulla_only.output;
    EXPECT_LT(s, w) << medulla_only.output;
}

// The EXR and the PNG of one render carry the summary's pair_id (docs: each file is atomic
// alone; the id tells whether two files belong together).
TEST(RenderCli, TheImagePairCarriesTheSummarysId) {
    const std::string base = out_base("pair");
    const Outcome r = run("--integrator single" + kTiny + " -o " + base);
    ASSERT_EQ(r.status, 0) << r.output;
    const std::size_t at = r.output.find(" pair_id=");
    ASSERT_NE(at, std::string::npos) << r.output;
    const std::string id = r.output.substr(at + 9, 16);
    EXPECT_EQ(hairscatter_examples::read_pair_id(base + ".exr"), id);
    EXPECT_EQ(hairscatter_examples::read_pair_id(base + ".png"), id);
    // Another exposure: another PNG, so another pair.
    const Outcome other = run("--integrator single --exposure 1" + kTiny + " -o " + base + "_other");
    ASSERT_EQ(other.status, 0) << other.output;
    EXPECT_NE(hairscatter_examples::read_pair_id(base + "_other.png"), id);
    EXPECT_EQ(hairscatter_examples::read_pair_id(base + "_other.exr"), hairscatter_examples::read_pair_id(base + "_other.png"));
}

TEST(RenderCli, PheomelaninNeedsEumelanin) {
    const Outcome r = run("--pheomelanin 0.5" + kTiny + " -o " + out_base("pheo"));
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("--eumelanin"), std::string::npos) << r.output;
}

TEST(RenderCli, UnwritableOutputIsFoundBeforeTheScene) {
    // A path under a regular file: no directory can be made there.
    const std::string file = out_base("a_file");
    std::ofstream(file) << "x";
    expect_refused("--hairs 100000 -o " + file + "/sub/render", "-o/--out");
    std::filesystem::create_directories(out_base("isdir.exr"));
    expect_refused("-o " + out_base("isdir"), "it is a directory");
}

TEST(RenderCli, OversizedImagesAreRefusedWithAMessage) {
    const Outcome r = run("--width 200000 --height 200000 --spp 1 --hairs 200 -o " + out_base("huge"));
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("--width 200000 --height 200000"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("bad_alloc"), std::string::npos) << r.output;
}

TEST(RenderCli, OversizedDensityGridIsRefusedWithTheReason) {
    // The grid is built where it is read: dual scattering from grid counts, or the BCSDF.
    const Outcome r = run("--dual-counts grid --grid-cell 0.0075" + kTiny + " -o " + out_base("grid"));
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("--grid-cell 0.0075: the density grid would be"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("use --grid-cell"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("render: building"), std::string::npos) << r.output;
    // Field counts (the default) read the grid too.
    EXPECT_EQ(run("--grid-cell 0.0075" + kTiny + " -o " + out_base("grid_field")).status, 1);
    // Exact counts read it for the stacks' turn limits (--dual-depth shape, the default).
    EXPECT_EQ(run("--dual-counts exact --grid-cell 0.0075" + kTiny + " -o " + out_base("grid_exact_shape")).status, 1);
    // Single scattering, and exact counts with a slab's limits, build no grid: the same cell
    // is no obstacle.
    EXPECT_EQ(run("--integrator single --grid-cell 0.0075" + kTiny + " -o " + out_base("grid_single")).status, 0);
    EXPECT_EQ(
        run("--dual-counts exact --dual-depth slab --grid-cell 0.0075" + kTiny + " -o " + out_base("grid_exact")).status,
        0);
}

TEST(RenderCli, OversizedCountFieldIsRefusedWithTheReason) {
    // A grid that fits (about 25 MB) whose count field at 64² directions would not (about 17 GiB).
    const Outcome r = run("--grid-cell 0.05 --field-side 64" + kTiny + " -o " + out_base("field"));
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("--field-spacing 1: the count field would be"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("use --field-spacing"), std::string::npos) << r.output;
    EXPECT_EQ(run("--grid-cell 0.05 --field-side 64 --field-spacing 16" + kTiny + " -o " + out_base("field_ok")).status, 0);
}

TEST(RenderCli, AHairFileWithoutHairSaysSo) {
    for (const std::vector<std::uint32_t>& segments : {std::vector<std::uint32_t>{}, std::vector<std::uint32_t>{0, 0}}) {
        render::HairFile f;
        f.segments = segments;
        f.points.assign(segments.size(), glm::vec3(0));  // a 0-segment strand has one point
        const std::string path = out_base("empty.hair");
        const std::vector<unsigned char> bytes = render::serialize_hair(f);
        std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
        const Outcome r = run("--hair-file " + path + " --width 16 --height 12 --spp 1 -o " + out_base("empty"));
        EXPECT_EQ(r.status, 1) << r.output;
        EXPECT_NE(r.output.find("has no hair"), std::string::npos) << r.output;
    }
}

TEST(RenderCli, TheRefusalsComeBeforeTheScene) {  // the negative control of expect_refused
    const Outcome r = run(tiny("--integrator single"));
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("render: building the scene (200 strands)"), std::string::npos) << r.output;
}

TEST(RenderCli, WarnsWhenNoHairIsInView) {
    const Outcome none = run("--integrator single --hairs 1 --fiber-radius 0.0001 --width 8 --height 6 --spp 1 -o " +
                         out_base("unseen"));
    EXPECT_EQ(none.status, 0) << none.output;
    EXPECT_NE(none.output.find("no hair in view"), std::string::npos) << none.output;
    const Outcome seen = run("--integrator single" + kTiny + " -o " + out_base("seen"));  // the negative control
    EXPECT_EQ(seen.status, 0) << seen.output;
    EXPECT_EQ(seen.output.find("no hair in view"), std::string::npos) << seen.output;
}

TEST(RenderCli, EveryIntegratorRendersUnderTheStudio) {
    for (const char* integrator : {"single", "dual", "path"}) {
        const std::string args = std::string("--env studio --env-rotate 30 --light-power 0 --integrator ") + integrator + kTiny;
        const Outcome r = run(args + " -o " + out_base(std::string("studio_") + integrator));
        EXPECT_EQ(r.status, 0) << args << "\n" << r.output;
        EXPECT_NE(r.output.find(" dropped=0 nonfinite_pixels=0 "), std::string::npos) << r.output;
    }
}

TEST(RenderCli, EveryModelRenders) {
    for (const char* model : {"chiang", "farfield", "tabulated", "marschner", "fur"})
        for (const char* integrator : {"single", "path"}) {
            const std::string args = std::string("--model ") + model + " --integrator " + integrator + kTiny;
            const Outcome r = run(args + " -o " + out_base(std::string("model_") + model));
            EXPECT_EQ(r.status, 0) << args << "\n" << r.output;
            EXPECT_NE(r.output.find(std::string(" model=") + model + " "), std::string::npos) << r.output;
            EXPECT_NE(r.output.find(" dropped=0 nonfinite_pixels=0 "), std::string::npos) << r.output;
        }
    const Outcome r = run("--lobes R,TRT --integrator path" + kTiny + " -o " + out_base("lobes"));
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find(" lobes=R,TRT "), std::string::npos) << r.output;
}

}  // namespace
