// hairscatter examples — the shared command-line vocabulary.
#include "options.hpp"

#include <algorithm>
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
        case FiberModel::kFur: return "fur";
    }
    return "?";
}

FiberModel parse_model(const std::string& name) {
    for (FiberModel m : {FiberModel::kChiang, FiberModel::kFarField, FiberModel::kTabulated, FiberModel::kMarschner,
                         FiberModel::kHuang, FiberModel::kFur})
        if (name == to_string(m)) return m;
    throw std::invalid_argument("--model: unknown model '" + name +
                                "' (chiang | farfield | tabulated | marschner | huang | fur)");
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

namespace {
const char* const kLobeOption[4] = {"r", "tt", "trt", "res"};

void add_control_options(CLI::App& app, ControlOptions& c) {
    for (int p = 0; p < 4; ++p) {
        const std::string lobe = kLobeNames[p];
        app.add_option(std::string("--gain-") + kLobeOption[p], c.gain[p],
                       "gain of the " + lobe + " lobe, in [0, 1e6] (default 1; every model but huang" +
                           (p == 3 ? ", and marschner has no residual)" : ")"));
        app.add_option(std::string("--tint-") + kLobeOption[p], c.tint[p],
                       "tint of the " + lobe + " lobe, R,G,B in [0, 1e6] (default 1,1,1; every model but huang" +
                           (p == 3 ? ", and marschner has no residual)" : ")"))
            ->delimiter(',')
            ->expected(3)
            ->type_name("R,G,B");
    }
    for (int p = 0; p < 3; ++p)
        app.add_option(std::string("--alpha-") + kLobeOption[p], c.alpha_deg[p],
                       std::string("cuticle tilt of the ") + kLobeNames[p] +
                           " lobe in degrees, |alpha| <= 22.5, instead of --alpha (every model but huang)");
    app.add_option("--strand-seed", c.strand_seed,
                   "vary melanin, redness and roughness per strand (renderer; lobe_explorer: --strand) with this "
                   "seed, within the --*-range intervals");
    const std::pair<std::vector<double>*, const char*> ranges[3] = {
        {&c.melanin_range, "--melanin-range|per-strand melanin amount LO,HI within [0, 1] (instead of --melanin)"},
        {&c.redness_range, "--redness-range|per-strand redness LO,HI within [0, 1] (instead of --redness)"},
        {&c.roughness_range, "--roughness-range|per-strand factor LO,HI on --beta-m and --beta-n, within (0, 1000]"}};
    for (const auto& r : ranges) {
        const std::string text = r.second;
        const std::size_t bar = text.find('|');
        app.add_option(text.substr(0, bar), *r.first, text.substr(bar + 1))->delimiter(',')->expected(2)->type_name(
            "LO,HI");
    }
}
}  // namespace

void add_fiber_options(CLI::App& app, FiberOptions& o, const std::string& default_colour,
                       const std::string& model_note) {
    app.add_option("--model", o.model, "fiber model: chiang | farfield | tabulated | marschner | huang | fur" + model_note)
        ->check(CLI::IsMember({"chiang", "farfield", "tabulated", "marschner", "huang", "fur"}))
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
    auto* mel = app.add_option("--melanin", o.colour.melanin,
                               "melanin amount in [0, 1] (Cycles' parameterisation: 0 white, 1 black; instead of "
                               "--colour)");
    app.add_option("--redness", o.colour.redness, "pheomelanin fraction of --melanin, in [0, 1] (default 0)");
    app.add_option("--dye", o.colour.dye,
                   "dye colour R,G,B in (0, 1]: its absorption (Chiang et al. 2016 eq. 9) is added to the hair's")
        ->delimiter(',')
        ->expected(3)
        ->type_name("R,G,B");
    preset->excludes(eu)->excludes(rgb)->excludes(sa)->excludes(mel);
    eu->excludes(rgb)->excludes(sa)->excludes(mel);
    rgb->excludes(sa)->excludes(mel);
    sa->excludes(mel);
    app.add_option("--beta-m", o.beta_m, "longitudinal roughness, (0, 1]")->capture_default_str();
    app.add_option("--beta-n", o.beta_n, "azimuthal roughness, (0, 1]")->capture_default_str();
    app.add_option("--alpha", o.alpha_deg, "cuticle tilt in degrees, |alpha| <= 22.5")->capture_default_str();
    app.add_option("--eta", o.eta, "index of refraction, > 1")->capture_default_str();
    add_control_options(app, o.controls);
    app.add_option("--aspect", o.section.aspect, "huang: cross-section minor/major axis ratio, [0.5, 1]")
        ->capture_default_str();
    app.add_option("--orientation", o.section.orientation_deg,
                   "huang: the major axis' angle about the fiber in degrees, [-180, 180]")
        ->capture_default_str();
    app.add_option("--kappa", o.kappa, "fur: the medulla's radius over the fiber's, [0, 1) (default 0: no medulla)");
    app.add_option("--medulla-sigma-s", o.medulla_sigma_s,
                   "fur: the medulla's scattering coefficient per unit fiber radius, >= 0 (default 0)");
    app.add_option("--medulla-sigma-a", o.medulla_sigma_a,
                   "fur: the medulla's absorption per unit fiber radius, one value or R,G,B, >= 0 (default 0)")
        ->delimiter(',')
        ->expected(1, 3)
        ->type_name("S|R,G,B");
    app.add_option("--medulla-g", o.medulla_g, "fur: the medulla's Henyey-Greenstein anisotropy, (-1, 1) (default 0)");
    app.add_flag("--rough-cortex", o.rough_cortex,
                 "fur: a rough cortex, whose light inside walks over tilted microfacets (total internal reflection "
                 "feeds the orders past TRT; docs/models.md)");
    app.add_option("--facet-alpha", o.facet_alpha,
                   "fur, with --rough-cortex: the cortex's microsurface as GGX of this roughness, [0, 1] "
                   "(default 0: the roughness whose reflections spread R as --beta-m does; docs/models.md)");
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

namespace {
// σa of the colour source (without the dye).
glm::dvec3 source_sigma_a(const HairColourOptions& c, const std::string& default_preset, double beta_n,
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
    if (c.melanin != none || c.redness != none) {
        hs::HairPigments<double> p;
        require(c.melanin != none, "--redness needs --melanin (or --melanin-range)");
        p.melanin = c.melanin;
        p.redness = c.redness == none ? 0.0 : c.redness;
        const std::string m = hs::validate(p);
        require(m.empty(), "--melanin/--redness: " + m);
        set_source("--melanin " + num(p.melanin) + " --redness " + num(p.redness));
        return hs::sigma_a_from_melanin_amount(p.melanin, p.redness);
    }
    if (c.eumelanin != none || c.pheomelanin != none) {
        require(c.eumelanin != none, "--pheomelanin needs --eumelanin (the preset fixes both)");
        require(std::isfinite(c.eumelanin) && c.eumelanin >= 0,
                "--eumelanin: " + num(c.eumelanin) + " is not a finite concentration >= 0");
        const double pheo = c.pheomelanin == none ? 0.0 : c.pheomelanin;
        require(std::isfinite(pheo) && pheo >= 0, "--pheomelanin: " + num(pheo) + " is not a finite concentration >= 0");
        set_source("eumelanin " + num(c.eumelanin) + ", pheomelanin " + num(pheo));
        return hs::sigma_a_from_concentrations(c.eumelanin, pheo);
    }
    const std::string name = c.preset.empty() ? default_preset : c.preset;
    for (const ColourPreset& p : colour_presets())
        if (name == p.name) {
            set_source("--colour " + name + " (eumelanin " + num(p.eumelanin) + ", pheomelanin " + num(p.pheomelanin) +
                       ")");
            return hs::sigma_a_from_concentrations(p.eumelanin, p.pheomelanin);
        }
    throw std::invalid_argument("--colour: unknown preset '" + name + "' (" + colour_preset_names() + ")");
}

// The --dye colour (white when not given), validated.
glm::dvec3 dye_of(const HairColourOptions& c) {
    if (c.dye.empty()) return glm::dvec3(1.0);
    require(c.dye.size() == 3, "--dye needs three values R,G,B");
    hs::HairPigments<double> p;
    p.dye = glm::dvec3(c.dye[0], c.dye[1], c.dye[2]);
    const std::string m = hs::validate(p);
    require(m.empty(), "--dye: " + m);
    return p.dye;
}
}  // namespace

glm::dvec3 sigma_a_of(const HairColourOptions& c, const std::string& default_preset, double beta_n,
                      std::string* source) {
    glm::dvec3 s = source_sigma_a(c, default_preset, beta_n, source);
    if (!c.dye.empty()) {
        const glm::dvec3 dye = dye_of(c);
        s += hs::sigma_a_from_dye(dye, beta_n);
        if (source) *source += " + --dye " + num(dye.r) + "," + num(dye.g) + "," + num(dye.b);
    }
    return s;
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
    // With per-strand colour, the base fiber (the dual-scattering tables') has the
    // intervals' midpoints; strand_setup checks the intervals first.
    HairColourOptions colour = o.colour;
    const StrandSetup strands = strand_setup(o);
    if (strands.vary_colour) {
        const hs::StrandVariation<double>& v = strands.variation;
        colour.melanin = 0.5 * (v.melanin.lo + v.melanin.hi);
        colour.redness = 0.5 * (v.redness.lo + v.redness.hi);
    }
    p.sigma_a = sigma_a_of(colour, default_colour, o.beta_n, sigma_a_source);
    if (strands.vary_colour && sigma_a_source) *sigma_a_source += " (the midpoints of the per-strand intervals)";
    const std::string m = hs::validate(p);
    if (!m.empty())
        throw std::invalid_argument("invalid fiber (--eta, --beta-m, --beta-n, --alpha in degrees, colour): " + m);
    return p;
}

MedullaShape medulla_shape(const FiberOptions& o) {
    const double none = HairColourOptions::kNotGiven;
    const bool given = o.kappa != none || o.medulla_sigma_s != none || o.medulla_g != none ||
                       !o.medulla_sigma_a.empty() || o.rough_cortex || o.facet_alpha != none;
    require(!given || o.model == "fur",
            "--kappa, --medulla-sigma-s, --medulla-sigma-a, --medulla-g, --rough-cortex, --facet-alpha: "
            "only --model fur has a medulla (not --model " + o.model + ")");
    MedullaShape m;
    m.rough_cortex = o.rough_cortex;
    require(o.facet_alpha == none || o.rough_cortex, "--facet-alpha: only with --rough-cortex (the smooth cortex has no facets)");
    if (o.facet_alpha != none) m.facet_alpha = o.facet_alpha;
    require(std::isfinite(m.facet_alpha) && m.facet_alpha >= 0 && m.facet_alpha <= 1,
            "--facet-alpha: " + num(m.facet_alpha) + " is outside [0, 1]");
    if (o.kappa != none) m.kappa = o.kappa;
    if (o.medulla_sigma_s != none) m.sigma_s = o.medulla_sigma_s;
    if (o.medulla_g != none) m.g = o.medulla_g;
    require(std::isfinite(m.kappa) && m.kappa >= 0 && m.kappa < 1, "--kappa: " + num(m.kappa) + " is outside [0, 1)");
    require(std::isfinite(m.sigma_s) && m.sigma_s >= 0,
            "--medulla-sigma-s: " + num(m.sigma_s) + " is not a finite value >= 0");
    require(std::isfinite(m.g) && m.g > -1 && m.g < 1, "--medulla-g: " + num(m.g) + " is outside (-1, 1)");
    const std::vector<double>& sa = o.medulla_sigma_a;
    require(sa.empty() || sa.size() == 1 || sa.size() == 3, "--medulla-sigma-a needs one value or three values R,G,B");
    for (double v : sa)
        require(std::isfinite(v) && v >= 0, "--medulla-sigma-a: " + num(v) + " is not a finite value >= 0");
    for (int c = 0; c < 3 && !sa.empty(); ++c) m.sigma_a[c] = sa[sa.size() == 3 ? std::size_t(c) : 0];
    return m;
}

hs::LobeControls<double> lobe_controls(const FiberOptions& o) {
    const ControlOptions& c = o.controls;
    hs::LobeControls<double> r;
    const double max = hs::kMaxLobeGain<double>;
    auto in_range = [](double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; };
    for (int p = 0; p < 4; ++p) {
        const std::string lobe = kLobeOption[p];
        require(in_range(c.gain[p], 0, max), "--gain-" + lobe + ": " + num(c.gain[p]) + " is outside [0, 1e6]");
        r.gain[p] = c.gain[p];
        if (!c.tint[p].empty()) {
            require(c.tint[p].size() == 3, "--tint-" + lobe + " needs three values R,G,B");
            for (double v : c.tint[p])
                require(in_range(v, 0, max), "--tint-" + lobe + ": " + num(v) + " is outside [0, 1e6]");
            r.tint[p] = glm::dvec3(c.tint[p][0], c.tint[p][1], c.tint[p][2]);
        }
    }
    for (int p = 0; p < 3; ++p)
        if (c.alpha_deg[p] != HairColourOptions::kNotGiven) {
            require(in_range(c.alpha_deg[p], -22.5, 22.5),
                    std::string("--alpha-") + kLobeOption[p] + ": " + num(c.alpha_deg[p]) +
                        " degrees is outside [-22.5, 22.5]");
            r.override_alpha(p, hs::radians(c.alpha_deg[p]));
        }
    const std::string m = hs::validate(r);
    if (!m.empty())
        throw std::invalid_argument("invalid lobe controls (--gain-r/tt/trt/res, --tint-r/tt/trt/res, "
                                    "--alpha-r/tt/trt in degrees): " + m);
    return r;
}

bool has_lobe_controls(const FiberOptions& o) {
    const ControlOptions& c = o.controls;
    bool any = false;
    for (int p = 0; p < 4; ++p) any = any || c.gain[p] != 1.0 || !c.tint[p].empty();
    for (int p = 0; p < 3; ++p) any = any || c.alpha_deg[p] != HairColourOptions::kNotGiven;
    return any;
}

StrandSetup strand_setup(const FiberOptions& o) {
    const ControlOptions& c = o.controls;
    const HairColourOptions& colour = o.colour;
    StrandSetup s;
    s.enabled = c.strand_seed != ControlOptions::kNoSeed || !c.melanin_range.empty() || !c.redness_range.empty() ||
                !c.roughness_range.empty();
    if (!s.enabled) return s;
    const bool seeded = c.strand_seed != ControlOptions::kNoSeed;
    require(!seeded || (c.strand_seed >= 0 && c.strand_seed <= 0xffffffffLL),
            "--strand-seed: " + std::to_string(c.strand_seed) + " is outside [0, 4294967295]");
    s.variation.seed = std::uint32_t(seeded ? c.strand_seed : 0);
    auto interval = [](const std::vector<double>& v, double fixed) { return v.empty() ? hs::Interval<double>{fixed, fixed}
                                                                                      : hs::Interval<double>{v[0], v[1]}; };
    const double none = HairColourOptions::kNotGiven;
    s.vary_colour = !c.melanin_range.empty() || !c.redness_range.empty();
    if (s.vary_colour) {
        require(colour.preset.empty() && colour.eumelanin == none && colour.rgb.empty() && colour.sigma_a.empty(),
                "--melanin-range/--redness-range colour each strand from melanin: drop --colour, --eumelanin, "
                "--rgb and --sigma-a (use --melanin, --redness, --dye)");
        require(!c.melanin_range.empty() || colour.melanin != none, "--redness-range needs --melanin or --melanin-range");
        require(c.melanin_range.empty() || colour.melanin == none, "--melanin-range replaces --melanin: give one");
        require(c.redness_range.empty() || colour.redness == none, "--redness-range replaces --redness: give one");
        s.dye = dye_of(colour);
    }
    auto check = [](const std::vector<double>& v, const char* option, double lo, double hi, bool open_lo) {
        if (v.empty()) return;
        require(v.size() == 2, std::string(option) + " needs two values LO,HI");
        const bool ok = std::isfinite(v[0]) && std::isfinite(v[1]) && (open_lo ? v[0] > lo : v[0] >= lo) &&
                        v[0] <= v[1] && v[1] <= hi;
        require(ok, std::string(option) + ": " + num(v[0]) + "," + num(v[1]) + " is not an interval LO <= HI within " +
                        (open_lo ? "(" : "[") + num(lo) + ", " + num(hi) + "]");
    };
    check(c.melanin_range, "--melanin-range", 0, 1, false);
    check(c.redness_range, "--redness-range", 0, 1, false);
    check(c.roughness_range, "--roughness-range", 0, hs::kMaxRoughnessScale<double>, true);
    s.variation.melanin = interval(c.melanin_range, colour.melanin == none ? 0.0 : colour.melanin);
    s.variation.redness = interval(c.redness_range, colour.redness == none ? 0.0 : colour.redness);
    s.variation.roughness_scale = interval(c.roughness_range, 1.0);
    const std::string m = hs::validate(s.variation);
    if (!m.empty())
        throw std::invalid_argument("invalid per-strand variation (--melanin-range, --redness-range, "
                                    "--roughness-range, or --melanin/--redness held fixed): " + m);
    return s;
}

hs::FiberParams<double> strand_fiber_params(const hs::FiberParams<double>& base, const StrandSetup& s,
                                            std::uint32_t strand) {
    if (!s.enabled) return base;
    const hs::StrandTraits<double> t = s.variation.at(strand);
    return s.vary_colour ? hs::strand_params(base, t, s.dye) : hs::strand_roughness(base, t.roughness_scale);
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

std::vector<std::uint8_t> tone_map(const std::vector<float>& rgb, double exposure, ToneCurve curve) {
    std::vector<std::uint8_t> out(rgb.size());
    const double gain = std::exp2(exposure);
    // Narkowicz 2015, "ACES Filmic Tone Mapping Curve": x (a x + b) / (x (c x + d) + e),
    // with its input scaled by 0.6 as the fit expects (so mid grey stays about mid grey).
    auto filmic = [](double x) {
        x = std::max(0.0, x) * 0.6;
        return x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14);
    };
    for (std::size_t i = 0; i < rgb.size(); ++i) {
        const double x = gain * double(rgb[i]);
        out[i] = srgb8(curve == ToneCurve::kFilmic ? filmic(x) : x);
    }
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
