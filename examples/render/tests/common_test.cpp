// The examples' shared vocabulary (examples/common): the lobe list ↔ lobe set ↔ template
// argument mapping for every subset, the model names, and where σa comes from.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <common/fiber_models.hpp>
#include <common/image_io.hpp>
#include <common/options.hpp>

// stb_image's decoder, to check that the PNG with its text chunk still decodes.
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb_image.h>

namespace {

namespace ex = hairscatter_examples;
namespace hs = hairscatter;

TEST(ExamplesCommon, EveryLobeSetMapsToItsTemplateArgument) {
    for (unsigned set = 1; set <= ex::LobeBits::kAll; ++set) {
        const std::string list = ex::lobes_to_string(set);
        EXPECT_EQ(ex::parse_lobes(list), set) << list;
        const unsigned kept = ex::with_chiang_lobes(set, [](auto s) {
            using Fiber = hs::BasicChiangFiber<float, decltype(s)::value>;
            unsigned k = 0;
            for (int p = 0; p < 4; ++p) k |= Fiber::keeps(p) ? 1u << p : 0u;
            return k;
        });
        EXPECT_EQ(kept, set) << list;
        unsigned sum = 0;
        for (unsigned lobe : ex::each_lobe(set)) sum += lobe;
        EXPECT_EQ(sum, set) << list;
    }
    EXPECT_EQ(ex::parse_lobes("all"), ex::LobeBits::kAll);
    EXPECT_EQ(ex::parse_lobes("primary"), ex::LobeBits::kPrimary);
    EXPECT_EQ(ex::parse_lobes("trt,r"), ex::LobeBits::kR | ex::LobeBits::kTRT);
    EXPECT_THROW(ex::with_chiang_lobes(0u, [](auto) { return 0; }), std::invalid_argument);
    EXPECT_THROW(ex::with_chiang_lobes(16u, [](auto) { return 0; }), std::invalid_argument);
    for (const char* bad : {"", "R,", "R,XX", "TTT", "R;TT"}) EXPECT_THROW(ex::parse_lobes(bad), std::invalid_argument) << bad;
}

TEST(ExamplesCommon, ModelNames) {
    for (const char* name : {"chiang", "farfield", "tabulated", "marschner", "huang", "fur"})
        EXPECT_STREQ(ex::to_string(ex::parse_model(name)), name);
    EXPECT_THROW(ex::parse_model("pbrt"), std::invalid_argument);
    hs::FiberParams<float> p;
    EXPECT_THROW(ex::FiberModels<float>(ex::FiberModel::kTabulated, ex::LobeBits::kR, p), std::invalid_argument);
    EXPECT_NO_THROW(ex::FiberModels<float>(ex::FiberModel::kChiang, ex::LobeBits::kR, p));
}

// --model fur's medulla: the options' defaults are no medulla, a scalar σa is grey, each bad
// value names its option, and the knobs need --model fur.
TEST(ExamplesCommon, FurMedulla) {
    ex::FiberOptions o;
    o.model = "fur";
    ex::MedullaShape m = ex::medulla_shape(o);
    EXPECT_EQ(m.kappa, 0.0);
    EXPECT_EQ(m.sigma_s, 0.0);
    EXPECT_EQ(m.g, 0.0);
    o.kappa = 0.6;
    o.medulla_sigma_s = 10;
    o.medulla_g = -0.2;
    o.medulla_sigma_a = {0.25};
    m = ex::medulla_shape(o);
    EXPECT_EQ(m.kappa, 0.6);
    EXPECT_EQ(m.g, -0.2);
    for (double v : m.sigma_a) EXPECT_EQ(v, 0.25);
    const hs::FurParams<float> fp = ex::fur_params(hs::FiberParams<float>(), m);
    EXPECT_TRUE(hs::validate(fp).empty()) << hs::validate(fp);
    EXPECT_NO_THROW(ex::FiberModels<float>(ex::FiberModel::kFur, ex::LobeBits::kAll, hs::FiberParams<float>(), {}, {}, m));
    auto refused = [](ex::FiberOptions bad, const char* named) {
        try {
            ex::medulla_shape(bad);
            ADD_FAILURE() << "accepted " << named;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
        }
    };
    ex::FiberOptions bad = o;
    bad.kappa = 1;
    refused(bad, "--kappa");
    bad = o, bad.medulla_sigma_s = -1;
    refused(bad, "--medulla-sigma-s");
    bad = o, bad.medulla_sigma_a = {1, 2};
    refused(bad, "--medulla-sigma-a");
    bad = o, bad.medulla_g = 1;
    refused(bad, "--medulla-g");
    bad = o, bad.model = "chiang";
    refused(bad, "only --model fur");
    ex::FiberExtras<float> controls;
    controls.has_controls = true;
    // The fur fiber takes the lobe controls on its unscattered lobes (R, TT, TRT, residual).
    EXPECT_NO_THROW(ex::FiberModels<float>(ex::FiberModel::kFur, ex::LobeBits::kAll, hs::FiberParams<float>(), controls));
}

TEST(ExamplesCommon, WhereSigmaAComesFrom) {
    ex::HairColourOptions c;
    const glm::dvec3 blond = hs::sigma_a_from_concentrations(0.3, 0.0);
    EXPECT_EQ(ex::sigma_a_of(c, "blond", 0.3), blond);  // the program's default preset
    c.preset = "white";
    EXPECT_EQ(ex::sigma_a_of(c, "blond", 0.3), glm::dvec3(0.0));
    c.preset = "purple";
    EXPECT_THROW(ex::sigma_a_of(c, "blond", 0.3), std::invalid_argument);
    c = ex::HairColourOptions{};
    c.eumelanin = 1.3;
    EXPECT_EQ(ex::sigma_a_of(c, "blond", 0.3), hs::sigma_a_from_concentrations(1.3, 0.0));
    c.pheomelanin = 0.5;
    EXPECT_EQ(ex::sigma_a_of(c, "blond", 0.3), hs::sigma_a_from_concentrations(1.3, 0.5));
    for (double bad : {-1.0, std::nan("")}) {
        c.eumelanin = bad;
        EXPECT_THROW(ex::sigma_a_of(c, "blond", 0.3), std::invalid_argument) << bad;
    }
    c = ex::HairColourOptions{};
    c.pheomelanin = 0.5;  // without eumelanin
    EXPECT_THROW(ex::sigma_a_of(c, "blond", 0.3), std::invalid_argument);
    c = ex::HairColourOptions{};
    c.sigma_a = {0.1, 0.2, 0.3};
    EXPECT_EQ(ex::sigma_a_of(c, "blond", 0.3), glm::dvec3(0.1, 0.2, 0.3));
    c.sigma_a = {0.1, -0.2, 0.3};
    EXPECT_THROW(ex::sigma_a_of(c, "blond", 0.3), std::invalid_argument);
}

// The controls' options become the library's values: σa from melanin, redness and dye,
// the lobe controls, and one deterministic fiber per strand.
TEST(ExamplesCommon, ControlsFromOptions) {
    ex::HairColourOptions c;
    c.melanin = 0.6;
    c.redness = 0.25;
    EXPECT_EQ(ex::sigma_a_of(c, "blond", 0.3), hs::sigma_a_from_melanin_amount(0.6, 0.25));
    c.dye = {0.9, 0.8, 0.7};
    EXPECT_EQ(ex::sigma_a_of(c, "blond", 0.3),
              hs::sigma_a_from_melanin_amount(0.6, 0.25) + hs::sigma_a_from_color(glm::dvec3(0.9, 0.8, 0.7), 0.3));

    ex::FiberOptions o;
    o.controls.gain[2] = 1.5;
    o.controls.tint[1] = {1.0, 0.5, 0.25};
    o.controls.alpha_deg[0] = 4.0;
    EXPECT_TRUE(ex::has_lobe_controls(o));
    EXPECT_FALSE(ex::has_lobe_controls(ex::FiberOptions{}));
    const hs::LobeControls<double> lc = ex::lobe_controls(o);
    EXPECT_EQ(lc.gain[2], 1.5);
    EXPECT_EQ(lc.tint[1], glm::dvec3(1.0, 0.5, 0.25));
    EXPECT_EQ(lc.lobe_alpha(0, 0.0), hs::radians(4.0));
    EXPECT_EQ(lc.lobe_alpha(1, 0.1), 0.1);

    o.colour.melanin = 0.4;
    o.controls.strand_seed = 9;
    o.controls.redness_range = {0.1, 0.6};
    o.controls.roughness_range = {0.5, 2.0};
    const ex::StrandSetup s = ex::strand_setup(o);
    ASSERT_TRUE(s.enabled && s.vary_colour);
    const hs::FiberParams<double> base = ex::fiber_params(o, "blond");
    ex::FiberExtras<float> extras;
    for (std::uint32_t k = 0; k < 8; ++k)
        extras.strand_params.push_back(ex::params_as<float>(ex::strand_fiber_params(base, s, k)));
    const ex::FiberModels<float> models(ex::FiberModel::kChiang, ex::LobeBits::kAll, ex::params_as<float>(base), extras);
    EXPECT_NE(models.chiang(1).params().sigma_a, models.chiang(2).params().sigma_a);
    EXPECT_EQ(models.chiang(3).params().sigma_a, models.chiang(11).params().sigma_a);  // strand % count
    EXPECT_EQ(ex::strand_fiber_params(base, s, 5).sigma_a, ex::strand_fiber_params(base, s, 5).sigma_a);
    EXPECT_EQ(hs::validate(ex::strand_fiber_params(base, s, 5)), "");
    EXPECT_THROW(ex::FiberModels<float>(ex::FiberModel::kTabulated, ex::LobeBits::kAll, ex::params_as<float>(base), extras),
                 std::invalid_argument);
    // Huang varies the colour per strand (the base material with the strand's σa, which is
    // the material built with it) and refuses a per-strand roughness.
    EXPECT_THROW(ex::FiberModels<float>(ex::FiberModel::kHuang, ex::LobeBits::kAll, ex::params_as<float>(base), extras),
                 std::invalid_argument);
    ex::FiberOptions colour_only = o;
    colour_only.controls.roughness_range = {1.0, 1.0};
    const ex::StrandSetup sc = ex::strand_setup(colour_only);
    ASSERT_TRUE(sc.enabled && sc.vary_colour);
    ex::FiberExtras<float> colours;
    for (std::uint32_t k = 0; k < 3; ++k)
        colours.strand_params.push_back(ex::params_as<float>(ex::strand_fiber_params(base, sc, k)));
    const ex::FiberModels<float> huang(ex::FiberModel::kHuang, ex::LobeBits::kAll, ex::params_as<float>(base), colours);
    const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, 0.8f, 0.2f)), wi = glm::normalize(glm::vec3(-0.2f, -0.7f, 0.4f));
    for (std::uint32_t k : {1u, 5u}) {
        const hs::HuangMaterial<float> own(ex::huang_params(colours.strand_params[k % 3], ex::SectionShape{}));
        const glm::vec3 f = huang.visit([&](auto make) { return make(0.0f, k).eval(wo, wi); });
        EXPECT_EQ(f, hs::HuangFiber<float>(own).eval(wo, wi)) << "strand " << k;
    }
    EXPECT_NE(huang.visit([&](auto make) { return make(0.0f, 1u).eval(wo, wi); }),
              huang.visit([&](auto make) { return make(0.0f, 2u).eval(wo, wi); }));

    // The lobe controls reach every model; Huang's refuses a per-lobe tilt, naming itself.
    ex::FiberExtras<float> controls;
    controls.controls = ex::controls_as<float>(lc);
    controls.has_controls = true;
    for (ex::FiberModel model : {ex::FiberModel::kChiang, ex::FiberModel::kFarField, ex::FiberModel::kTabulated,
                                 ex::FiberModel::kMarschner})
        EXPECT_NO_THROW(ex::FiberModels<float>(model, ex::LobeBits::kAll, ex::params_as<float>(base), controls))
            << ex::to_string(model);
    ex::FiberExtras<float> gains = controls;
    gains.controls.alpha_override = 0u;  // the gains and tints without the R tilt
    EXPECT_NO_THROW(ex::FiberModels<float>(ex::FiberModel::kHuang, ex::LobeBits::kAll, ex::params_as<float>(base), gains));
    try {
        ex::FiberModels<float>(ex::FiberModel::kHuang, ex::LobeBits::kAll, ex::params_as<float>(base), controls);
        ADD_FAILURE() << "huang accepted a per-lobe tilt";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("--model huang"), std::string::npos) << e.what();
    }
}

// The filmic preview curve: black stays black, it rises monotonically, keeps 1.0 below
// white (a shoulder, where the clamp saturates) and reaches white only far above it.
TEST(ExamplesCommon, FilmicToneCurveHasAShoulder) {
    std::vector<float> ramp;
    for (int i = 0; i <= 400; ++i) ramp.push_back(0.05f * float(i));
    const std::vector<std::uint8_t> f = ex::tone_map(ramp, 0.0, ex::ToneCurve::kFilmic);
    const std::vector<std::uint8_t> c = ex::tone_map(ramp, 0.0);
    EXPECT_EQ(f[0], 0);
    for (std::size_t i = 1; i < f.size(); ++i) EXPECT_GE(f[i], f[i - 1]) << ramp[i];
    EXPECT_EQ(c[20], 255);  // 1.0 clamps to white ...
    EXPECT_LT(f[20], 230);  // ... and keeps headroom under the shoulder
    EXPECT_GT(f[20], 150);  // mid-to-bright stays bright
    EXPECT_GE(f[400], 250);  // 20 is white
    EXPECT_EQ(ex::tone_map({std::nanf("")}, 0.0, ex::ToneCurve::kFilmic)[0], 0);
}

// The EXR/PNG pair is atomic file by file, not as a pair (a kill between the two renames
// once left a new EXR beside the old PNG): both files carry the pair's id, so a reader can
// tell. The id is the content hash the writer returns, the PNG still decodes to its
// pixels, and a torn pair (the EXR of one render, the PNG of another) shows two ids.
TEST(ExamplesCommon, ExrPngPairCarriesOneId) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(::testing::TempDir()) / "hairscatter_pair_id";
    fs::create_directories(dir);
    const int w = 5, h = 3;
    std::vector<float> rgb(std::size_t(w * h * 3));
    for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = float(i) / float(rgb.size());
    const std::vector<std::uint8_t> png = ex::tone_map(rgb, 0.0), brighter = ex::tone_map(rgb, 1.0);
    const std::string a = (dir / "a").string(), b = (dir / "b").string();
    const std::string id_a = ex::write_exr_png_pair(a + ".exr", a + ".png", w, h, rgb, {{"note", "a"}}, png);
    const std::string id_b = ex::write_exr_png_pair(b + ".exr", b + ".png", w, h, rgb, {}, brighter);
    EXPECT_EQ(id_a.size(), 16u);
    EXPECT_EQ(id_a, ex::pair_id(rgb, png));
    EXPECT_EQ(ex::read_pair_id(a + ".exr"), id_a);
    EXPECT_EQ(ex::read_pair_id(a + ".png"), id_a);
    EXPECT_EQ(ex::read_pair_id(b + ".png"), id_b);
    EXPECT_NE(id_a, id_b);  // the same pixels with another preview: another pair
    EXPECT_NE(ex::read_pair_id(a + ".exr"), ex::read_pair_id(b + ".png"));  // a torn pair shows
    int dw = 0, dh = 0, channels = 0;
    unsigned char* decoded = stbi_load((a + ".png").c_str(), &dw, &dh, &channels, 3);
    ASSERT_NE(decoded, nullptr) << stbi_failure_reason();
    EXPECT_EQ(std::vector<std::uint8_t>(decoded, decoded + w * h * 3), png);
    EXPECT_EQ(dw, w);
    EXPECT_EQ(dh, h);
    stbi_image_free(decoded);
    // A lone PNG or EXR has no id.
    ex::write_png_rgb8(b + "_lone.png", w, h, png);
    ex::write_exr_rgb(b + "_lone.exr", w, h, rgb, {});
    EXPECT_EQ(ex::read_pair_id(b + "_lone.png"), "");
    EXPECT_EQ(ex::read_pair_id(b + "_lone.exr"), "");
    EXPECT_THROW(ex::read_pair_id(b + "_missing.png"), std::runtime_error);
    fs::remove_all(dir);
}

}  // namespace
