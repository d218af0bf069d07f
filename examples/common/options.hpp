// hairscatter examples — the command-line vocabulary the example programs share (one
// spelling of each option across programs): the fiber model and its lobes, hair colour
// (presets, melanin, RGB or σa), the fiber parameters, and the output pair <out>.exr +
// <out>.png. Every value is validated before any work with a message naming its option.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/glm.hpp>
#include <hairscatter/hairscatter.hpp>

#include "fiber_models.hpp"

namespace hairscatter_examples {

// Hair colour presets: eumelanin and pheomelanin concentrations (Chiang et al. 2016 §4.2;
// white is lossless, σa = 0).
struct ColourPreset {
    const char* name;
    double eumelanin, pheomelanin;
};
const std::vector<ColourPreset>& colour_presets();
std::string colour_preset_names();  // "white | blond | brown | dark | red | black"

// Where σa comes from: a preset (--colour), melanin (--eumelanin, --pheomelanin), a melanin
// amount and redness (--melanin, --redness: Cycles' parameterisation), a colour (--rgb,
// Chiang et al. 2016 eq. 9) or σa itself (--sigma-a); all but the first exclude a preset.
// A dye (--dye) adds its absorption to any of them.
struct HairColourOptions {
    static constexpr double kNotGiven = -1e300;
    std::string preset;  // the program's default preset when empty
    double eumelanin = kNotGiven, pheomelanin = kNotGiven;
    double melanin = kNotGiven, redness = kNotGiven;
    std::vector<double> rgb, sigma_a, dye;
};

// The production-shader controls (docs/controls.md): per-lobe gains, tints and tilts of
// Chiang's model, and the per-strand variation of melanin, redness and roughness.
struct ControlOptions {
    double gain[4] = {1, 1, 1, 1};          // --gain-r, --gain-tt, --gain-trt, --gain-res
    std::vector<double> tint[4];            // --tint-r … --tint-res, R,G,B
    double alpha_deg[3] = {HairColourOptions::kNotGiven, HairColourOptions::kNotGiven,
                           HairColourOptions::kNotGiven};  // --alpha-r, --alpha-tt, --alpha-trt
    static constexpr long long kNoSeed = std::numeric_limits<long long>::min();
    long long strand_seed = kNoSeed;        // --strand-seed
    std::vector<double> melanin_range, redness_range, roughness_range;
};

// The fiber: model, lobes, colour and the roughness / tilt / index parameters.
struct FiberOptions {
    std::string model = "chiang", lobes = "all";
    HairColourOptions colour;
    double beta_m = 0.3, beta_n = 0.3, alpha_deg = 2.0, eta = 1.55;
    ControlOptions controls;
    SectionShape section;  // --model huang's cross-section
    // --model fur's medulla (--kappa, --medulla-sigma-s, --medulla-sigma-a, --medulla-g);
    // kNotGiven where the option was not given (then medulla_shape's default).
    double kappa = HairColourOptions::kNotGiven, medulla_sigma_s = HairColourOptions::kNotGiven,
           medulla_g = HairColourOptions::kNotGiven;
    std::vector<double> medulla_sigma_a;  // one value (grey) or R,G,B
    bool rough_cortex = false;            // --rough-cortex (FurParams::rough_cortex)
    double facet_alpha = HairColourOptions::kNotGiven;  // --facet-alpha (FurParams::facet_alpha)
};

// Adds --model, --lobes, --colour/--color, --eumelanin, --pheomelanin, --melanin,
// --redness, --rgb, --sigma-a, --dye, --beta-m, --beta-n, --alpha, --eta, --aspect,
// --orientation, the fur medulla (--kappa, --medulla-sigma-s, --medulla-sigma-a,
// --medulla-g) and the controls (--gain-*, --tint-*, --alpha-r/-tt/-trt, --strand-seed,
// --*-range). model_note is appended to --model's help.
void add_fiber_options(CLI::App& app, FiberOptions& o, const std::string& default_colour,
                       const std::string& model_note = "");

// σa from the colour options (validated; throws std::invalid_argument naming the option)
// and a description of where it came from.
glm::dvec3 sigma_a_of(const HairColourOptions& c, const std::string& default_preset, double beta_n,
                      std::string* source = nullptr);
// The FiberParams of the options (validated by the library, the message prefixed with the
// options' names), the model and the lobe set.
hairscatter::FiberParams<double> fiber_params(const FiberOptions& o, const std::string& default_colour,
                                              std::string* sigma_a_source = nullptr);

// The medulla of --model fur (validated: κ in [0, 1), σ finite and >= 0, |g| < 1; throws
// std::invalid_argument naming the option, or naming the options given with another model).
MedullaShape medulla_shape(const FiberOptions& o);

// The lobe controls of the options (validated; throws std::invalid_argument naming the
// options), and whether any differs from its default.
hairscatter::LobeControls<double> lobe_controls(const FiberOptions& o);
bool has_lobe_controls(const FiberOptions& o);

// The per-strand variation: enabled by --strand-seed or a range. vary_colour when a
// melanin or redness range is given (σa then comes from the strand's pigments and the dye);
// otherwise only the roughness varies and σa is the base's.
struct StrandSetup {
    bool enabled = false, vary_colour = false;
    hairscatter::StrandVariation<double> variation;
    glm::dvec3 dye{1.0};
};
// Validated; throws std::invalid_argument naming the option.
StrandSetup strand_setup(const FiberOptions& o);
// Strand `strand`'s parameters from the base (fiber_params) under the setup.
hairscatter::FiberParams<double> strand_fiber_params(const hairscatter::FiberParams<double>& base,
                                                     const StrandSetup& s, std::uint32_t strand);

// The parameters and controls in another precision (the renderer shades in float).
template <typename T> hairscatter::FiberParams<T> params_as(const hairscatter::FiberParams<double>& p) {
    return {T(p.eta), T(p.beta_m), T(p.beta_n), T(p.alpha), glm::vec<3, T>(p.sigma_a)};
}
template <typename T> hairscatter::LobeControls<T> controls_as(const hairscatter::LobeControls<double>& c) {
    hairscatter::LobeControls<T> r;
    for (int p = 0; p < 4; ++p) r.gain[p] = T(c.gain[p]), r.tint[p] = glm::vec<3, T>(c.tint[p]);
    for (int p = 0; p < 3; ++p) r.alpha[p] = T(c.alpha[p]);
    r.alpha_override = c.alpha_override;
    return r;
}

// The output pair: "-o,--out" names <out>.exr and <out>.png (an .exr/.png extension on
// the name is dropped).
std::string strip_image_extension(std::string base);
// Creates <base>'s directory and checks that <base>.exr and <base>.png can be written
// there (before any long work); throws std::runtime_error naming the path and the reason.
void prepare_output(const std::string& base);

// How the preview maps linear radiance to [0, 1] before the sRGB curve: clamp (the
// default: 1 and above show white) or filmic (a shoulder that keeps highlights' colour
// and detail: Narkowicz's 2015 fit of the ACES reference rendering transform).
enum class ToneCurve { kClamp, kFilmic };

// Linear RGB times 2^exposure, through the tone curve, to 8-bit sRGB.
std::vector<std::uint8_t> tone_map(const std::vector<float>& rgb, double exposure,
                                   ToneCurve curve = ToneCurve::kClamp);

// Refuses images whose buffers would not fit: width × height × bytes_per_pixel above
// max_bytes (default 4 GiB) throws std::invalid_argument naming --width and --height.
void check_image_size(long long width, long long height, long long bytes_per_pixel,
                      long long max_bytes = 4LL << 30);

}  // namespace hairscatter_examples
