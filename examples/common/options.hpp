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

// Where σa comes from: a preset (--colour), melanin (--eumelanin, --pheomelanin), a colour
// (--rgb, Chiang et al. 2016 eq. 9) or σa itself (--sigma-a); the last three exclude a preset.
struct HairColourOptions {
    static constexpr double kNotGiven = -1e300;
    std::string preset;  // the program's default preset when empty
    double eumelanin = kNotGiven, pheomelanin = kNotGiven;
    std::vector<double> rgb, sigma_a;
};

// The fiber: model, lobes, colour and the roughness / tilt / index parameters.
struct FiberOptions {
    std::string model = "chiang", lobes = "all";
    HairColourOptions colour;
    double beta_m = 0.3, beta_n = 0.3, alpha_deg = 2.0, eta = 1.55;
    SectionShape section;  // --model huang's cross-section
};

// Adds --model, --lobes, --colour/--color, --eumelanin, --pheomelanin, --rgb, --sigma-a,
// --beta-m, --beta-n, --alpha, --eta, --aspect, --orientation. model_note is appended to --model's help.
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

// The output pair: "-o,--out" names <out>.exr and <out>.png (an .exr/.png extension on
// the name is dropped).
std::string strip_image_extension(std::string base);
// Creates <base>'s directory and checks that <base>.exr and <base>.png can be written
// there (before any long work); throws std::runtime_error naming the path and the reason.
void prepare_output(const std::string& base);

// Linear RGB times 2^exposure to 8-bit sRGB.
std::vector<std::uint8_t> tone_map(const std::vector<float>& rgb, double exposure);

// Refuses images whose buffers would not fit: width × height × bytes_per_pixel above
// max_bytes (default 4 GiB) throws std::invalid_argument naming --width and --height.
void check_image_size(long long width, long long height, long long bytes_per_pixel,
                      long long max_bytes = 4LL << 30);

}  // namespace hairscatter_examples
