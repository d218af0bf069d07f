// hairscatter examples — the shared command-line vocabulary.
#include "options.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include "image_io.hpp"

namespace hairscatter_examples {
namespace hs = hairscatter;

const char* to_string(FiberModel m) {
    switch (m) {
        case FiberModel::kChiang: return "chiang";
        case FiberModel::kFarField: return "farfield";
        case FiberModel::kTabulated: return "tabulated";
        case FiberModel::kMarschner: return "marschner";
        case FiberModel::kHuang: return "huang";
    }
    return "?";
}

FiberModel parse_model(const std::string& name) {
    for (FiberModel m : {FiberModel::kChiang, FiberModel::kFarField, FiberModel::kTabulated, FiberModel::kMarschner,
                         FiberModel::kHuang})
        if (name == to_string(m)) return m;
    throw std::invalid_argument("--model: unknown model '" + name + "' (chiang | farfield | tabulated | marschner | huang)");
}

namespace {
const char* const kLobeNames[4] = {"R", "TT", "TRT", "residual"};
std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}
}  // namespace

unsigned parse_lobes(const std::string& list) {
    const std::string l = lower(list);
    if (l == "all") return LobeBits::kAll;
    if (l == "primary") return LobeBits::kPrimary;
    unsigned set = 0;
    std::size_t start = 0;
    while (start <= l.size()) {
        const std::size_t end = std::min(l.find(',', start), l.size());
        const std::string name = l.substr(start, end - start);
        int p = -1;
        for (int k = 0; k < 4; ++k)
            if (name == lower(kLobeNames[k])) p = k;
        if (p < 0)
            throw std::invalid_argument("--lobes: unknown lobe '" + name +
                                        "' in '" + list + "' (R, TT, TRT, residual; or all, primary)");
        set |= 1u << p;
        start = end + 1;
    }
    return set;
}

std::string lobes_to_string(unsigned lobes) {
    std::string s;
    for (int p = 0; p < 4; ++p)
        if (keeps_lobe(lobes, p)) s += (s.empty() ? "" : ",") + std::string(kLobeNames[p]);
    return s;
}

std::vector<unsigned> each_lobe(unsigned lobes) {
    std::vector<unsigned> r;
    for (int p = 0; p < 4; ++p)
        if (keeps_lobe(lobes, p)) r.push_back(1u << p);
    return r;
}

const std::vector<ColourPreset>& colour_presets() {
    static const std::vector<ColourPreset> kPresets = {{"white", 0.0, 0.0}, {"blond", 0.3, 0.0},
                                                       {"brown", 1.3, 0.0}, {"dark", 8.0, 0.0},
                                                       {"red", 0.3, 0.9},   {"black", 20.0, 0.0}};
    return kPresets;
}

std::string colour_preset_names() {
    std::string s;
    for (const ColourPreset& p : colour_presets()) s += (s.empty() ? "" : " | ") + std::string(p.name);
    return s;
}

void add_fiber_options(CLI::App& app, FiberOptions& o, const std::string& default_colour,
                       const std::string& model_note) {
    app.add_option("--model", o.model, "fiber model: chiang | farfield | tabulated | marschner | huang" + model_note)
        ->check(CLI::IsMember({"chiang", "farfield", "tabulated", "marschner", "huang"}))
        ->capture_default_str();
    app.add_option("--lobes", o.lobes,
                   "chiang: the lobes kept, a list of R, TT, TRT, residual (e.g. R,TT), or all, primary")
        ->capture_default_str();
    auto* preset = app.add_option("--colour,--color", o.colour.preset,
                                  "hair colour preset: " + colour_preset_names() + " (default " + default_colour + ")");
    auto* eu = app.add_option("--eumelanin", o.colour.eumelanin, "eumelanin concentration, >= 0 (instead of --colour)");
    app.add_option("--pheomelanin", o.colour.pheomelanin, "pheomelanin concentration, >= 0 (with --eumelanin)")
        ->needs(eu);
    auto* rgb = app.add_option("--rgb", o.colour.rgb,
                               "hair colour as linear R,G,B in (0, 1] (Chiang et al. 2016 eq. 9; instead of --colour)")
                    ->delimiter(',')
                    ->expected(3)
                    ->type_name("R,G,B");
    auto* sa = app.add_option("--sigma-a", o.colour.sigma_a, "absorption per unit fiber radius R,G,B, >= 0")
                   ->delimiter(',')
                   ->expected(3)
                   ->type_name("R,G,B");
    preset->excludes(eu)->excludes(rgb)->excludes(sa);
    eu->excludes(rgb)->excludes(sa);
    rgb->excludes(sa);
    app.add_option("--beta-m", o.beta_m, "longitudinal roughness, (0, 1]")->capture_default_str();
    app.add_option("--beta-n", o.beta_n, "azimuthal roughness, (0, 1]")->capture_default_str();
    app.add_option("--alpha", o.alpha_deg, "cuticle tilt in degrees, |alpha| <= 22.5")->capture_default_str();
    app.add_option("--eta", o.eta, "index of refraction, > 1")->capture_default_str();
    app.add_option("--aspect", o.section.aspect, "huang: cross-section minor/major axis ratio, [0.5, 1]")
        ->capture_default_str();
    app.add_option("--orientation", o.section.orientation_deg,
                   "huang: the major axis' angle about the fiber in degrees, [-180, 180]")
        ->capture_default_str();
}

namespace {
std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%g", v);
    return buf;
}
void require(bool ok, const std::string& message) {
    if (!ok) throw std::invalid_argument(message);
}
}  // namespace

glm::dvec3 sigma_a_of(const HairColourOptions& c, const std::string& default_preset, double beta_n,
                      std::string* source) {
    auto set_source = [&](const std::string& s) {
        if (source) *source = s;
    };
    if (!c.sigma_a.empty()) {
        require(c.sigma_a.size() == 3, "--sigma-a needs three values R,G,B");
        for (double v : c.sigma_a)
            require(std::isfinite(v) && v >= 0, "--sigma-a: " + num(v) + " is not a finite value >= 0");
        set_source("--sigma-a");
        return glm::dvec3(c.sigma_a[0], c.sigma_a[1], c.sigma_a[2]);
    }
    if (!c.rgb.empty()) {
        require(c.rgb.size() == 3, "--rgb needs three values R,G,B");
        for (double v : c.rgb) require(v > 0 && v <= 1, "--rgb: " + num(v) + " is outside (0, 1]");
        set_source("--rgb " + num(c.rgb[0]) + "," + num(c.rgb[1]) + "," + num(c.rgb[2]));
        return hs::sigma_a_from_color(glm::dvec3(c.rgb[0], c.rgb[1], c.rgb[2]), beta_n);
    }
    const double none = HairColourOptions::kNotGiven;
    if (c.eumelanin != none || c.pheomelanin != none) {
        require(c.eumelanin != none, "--pheomelanin needs --eumelanin (the preset fixes both)");
        require(std::isfinite(c.eumelanin) && c.eumelanin >= 0,
                "--eumelanin: " + num(c.eumelanin) + " is not a finite concentration >= 0");
        const double pheo = c.pheomelanin == none ? 0.0 : c.pheomelanin;
        require(std::isfinite(pheo) && pheo >= 0, "--pheomelanin: " + num(pheo) + " is not a finite concentration >= 0");
        set_source("eumelanin " + num(c.eumelanin) + ", pheomelanin " + num(pheo));
        return hs::sigma_a_from_melanin(c.eumelanin, pheo);
    }
    const std::string name = c.preset.empty() ? default_preset : c.preset;
    for (const ColourPreset& p : colour_presets())
        if (name == p.name) {
            set_source("--colour " + name + " (eumelanin " + num(p.eumelanin) + ", pheomelanin " + num(p.pheomelanin) +
                       ")");
            return hs::sigma_a_from_melanin(p.eumelanin, p.pheomelanin);
        }
    throw std::invalid_argument("--colour: unknown preset '" + name + "' (" + colour_preset_names() + ")");
}

hs::FiberParams<double> fiber_params(const FiberOptions& o, const std::string& default_colour,
                                     std::string* sigma_a_source) {
    hs::FiberParams<double> p;
    p.eta = o.eta;
    p.beta_m = o.beta_m;
    p.beta_n = o.beta_n;
    p.alpha = hs::radians(o.alpha_deg);
    require(std::isfinite(o.beta_n) && o.beta_n > 0 && o.beta_n <= 1,
            "--beta-n: " + num(o.beta_n) + " is outside (0, 1]");
    p.sigma_a = sigma_a_of(o.colour, default_colour, o.beta_n, sigma_a_source);
    const std::string m = hs::validate(p);
    if (!m.empty())
        throw std::invalid_argument("invalid fiber (--eta, --beta-m, --beta-n, --alpha in degrees, colour): " + m);
    return p;
}

std::string strip_image_extension(std::string base) {
    for (const char* ext : {".exr", ".png", ".EXR", ".PNG"}) {
        const std::string e(ext);
        if (base.size() > e.size() && base.compare(base.size() - e.size(), e.size(), e) == 0)
            return base.substr(0, base.size() - e.size());
    }
    return base;
}

void prepare_output(const std::string& base) {
    namespace fs = std::filesystem;
    if (base.empty()) throw std::runtime_error("-o/--out: the output name is empty");
    const fs::path parent = fs::path(base).parent_path();
    std::error_code ec;
    if (!parent.empty()) fs::create_directories(parent, ec);
    if (ec) throw std::runtime_error("-o/--out: cannot create the directory " + parent.string() + ": " + ec.message());
    for (const char* ext : {".exr", ".png"}) {
        const fs::path target = base + ext;
        if (fs::is_directory(target, ec))
            throw std::runtime_error("-o/--out: cannot write " + target.string() + ": it is a directory");
        // A probe next to the target: the directory must accept a new file (the image
        // writers may replace the target through a temporary file and a rename).
        const fs::path probe = target.string() + ".probe";
        {
            std::ofstream f(probe);
            if (!f) throw std::runtime_error("-o/--out: cannot write " + target.string() + " (the directory " +
                                             (parent.empty() ? std::string(".") : parent.string()) +
                                             " is not writable or does not exist)");
        }
        fs::remove(probe, ec);
        if (fs::exists(target, ec)) {
            std::ofstream f(target, std::ios::app);
            if (!f) throw std::runtime_error("-o/--out: cannot write " + target.string() + ": the file is read-only");
        }
    }
}

std::vector<std::uint8_t> tone_map(const std::vector<float>& rgb, double exposure) {
    std::vector<std::uint8_t> out(rgb.size());
    const double gain = std::exp2(exposure);
    for (std::size_t i = 0; i < rgb.size(); ++i) out[i] = srgb8(gain * double(rgb[i]));
    return out;
}

void check_image_size(long long width, long long height, long long bytes_per_pixel, long long max_bytes) {
    require(width >= 1 && height >= 1, "--width and --height must be >= 1 (got " + std::to_string(width) + " x " +
                                           std::to_string(height) + ")");
    const long double bytes = (long double)width * (long double)height * (long double)bytes_per_pixel;
    if (bytes > (long double)max_bytes)
        throw std::invalid_argument("--width " + std::to_string(width) + " --height " + std::to_string(height) +
                                    ": the image buffers would take " + num(double(bytes) / (1 << 30)) +
                                    " GiB, above this program's limit of " + num(double(max_bytes) / (1 << 30)) +
                                    " GiB");
}

}  // namespace hairscatter_examples
