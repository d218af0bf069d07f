// lobe_explorer — an image of a hair BCSDF f(wo, wi) (any of the library's models:
// --model chiang|farfield|tabulated|marschner, Chiang's lobe subsets with --lobes) over the
// whole sphere of incident directions, for one outgoing direction and one set of fiber
// parameters. Writes the linear values as OpenEXR and a tone-mapped PNG preview (with
// --per-lobe also one pair per lobe), and prints the maximum and ∫ f dωi over the grid
// (the directional albedo: 1 for a lossless energy-conserving model).
//
//   lobe_explorer --theta-o 30 --beta-m 0.3 --beta-n 0.3 -o out/lobe_explorer
//
// Image layout: x = φ = φi - φo from -180° (left) to +180° (right), so φ = 0 (backward
// scattering: R, TRT) is the centre column and |φ| = 180° (forward: TT) the two edges;
// y = θi from +90° (top, along the fiber tangent) to -90° (bottom). Directions follow
// the library's fiber frame (docs/theory.md §1): w = (sinθ, cosθ cosφ, cosθ sinφ), φo = 0.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/glm.hpp>

#include <common/options.hpp>
#include <hairscatter/hairscatter.hpp>

#include "image.hpp"
#include "image_io.hpp"
#include "preview.hpp"

namespace hs = hairscatter;
namespace ex = hairscatter_examples;
using glm::dvec3;
using lobe_explorer::LinearImage;

namespace {

constexpr double kPi = hs::kPi<double>;

struct Options {
    double theta_o_deg = 30.0;
    double h = 0.0;
    int average_h = 0;  // 0: the single offset h
    ex::FiberOptions fiber;
    long long strand = -1;  // with per-strand variation: the strand shown (-1: strand 0)
    bool per_lobe = false;
    int width = 720, height = 360, supersample = 1, threads = 0;
    std::string tone = "log";
    double decades = 4.0, exposure = 0.0;
    bool no_annotate = false;
    std::string output = "out/lobe_explorer";
};

// What the image is of, after the options have been turned into library parameters.
struct Setup {
    hs::FiberParams<double> params;
    ex::FiberExtras<double> extras;  // the lobe controls
    std::string strand_text;  // which strand, with per-strand variation
    ex::FiberModel model = ex::FiberModel::kChiang;
    unsigned lobes = ex::LobeBits::kAll;
    ex::SectionShape section;     // --model huang's cross-section
    ex::MedullaShape medulla;     // --model fur's medulla
    std::string sigma_a_source;  // how σa was given, for the summary
    std::vector<double> offsets;  // the h that eval is averaged over (one for --h)
    dvec3 wo{0.0};
};

// Offsets for --average-h N: the midpoints of N equal cells of (-1, 1), so that the
// average is the midpoint rule for ½ ∫ f dh (a whole fiber seen from afar).
std::vector<double> uniform_offsets(int n) {
    std::vector<double> h(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) h[std::size_t(k)] = -1.0 + (2.0 * k + 1.0) / n;
    return h;
}

std::string fmt(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), format, v);
    return buf;
}

std::string rgb_string(const dvec3& c, const char* format = "%.4g") {
    return "(" + fmt(format, c.r) + ", " + fmt(format, c.g) + ", " + fmt(format, c.b) + ")";
}

// Fills s from the options; throws std::invalid_argument naming the bad option.
void make_setup(const Options& o, Setup& s) {
    s.params = ex::fiber_params(o.fiber, "brown", &s.sigma_a_source);
    s.extras.controls = ex::lobe_controls(o.fiber);
    s.extras.has_controls = ex::has_lobe_controls(o.fiber);
    const ex::StrandSetup strands = ex::strand_setup(o.fiber);
    if (o.strand >= 0 && !strands.enabled)
        throw std::invalid_argument("--strand needs per-strand variation (--strand-seed or a --*-range)");
    if (strands.enabled) {
        const std::uint32_t id = std::uint32_t(o.strand < 0 ? 0 : o.strand);
        s.params = ex::strand_fiber_params(s.params, strands, id);
        const hs::StrandTraits<double> t = strands.variation.at(id);
        s.strand_text = "strand " + std::to_string(id) + " of seed " + std::to_string(strands.variation.seed) +
                        ": melanin " + fmt("%.4g", t.melanin) + ", redness " + fmt("%.4g", t.redness) +
                        ", roughness x" + fmt("%.4g", t.roughness_scale) + (strands.vary_colour ? "" : " (colour fixed)");
        if (strands.vary_colour) s.sigma_a_source = "the strand's melanin and redness";
    }
    s.model = ex::parse_model(o.fiber.model);
    s.lobes = ex::parse_lobes(o.fiber.lobes);
    s.section = o.fiber.section;
    s.medulla = ex::medulla_shape(o.fiber);
    if (!(o.h >= -1 && o.h <= 1)) throw std::invalid_argument("--h: " + fmt("%g", o.h) + " is outside [-1, 1]");
    if (o.per_lobe && s.model != ex::FiberModel::kChiang)
        throw std::invalid_argument("--per-lobe needs --model chiang (the other models have no lobe subsets)");
    s.offsets = o.average_h > 0 ? uniform_offsets(o.average_h) : std::vector<double>{o.h};
    const double theta_o = hs::radians(o.theta_o_deg);
    s.wo = dvec3(std::sin(theta_o), std::cos(theta_o), 0.0);
}

// The model's albedo Σ_p A_p(wo) where it has one (Marschner's model has none).
template <class Fiber, class = void> struct HasAlbedo : std::false_type {};
template <class Fiber>
struct HasAlbedo<Fiber, std::void_t<decltype(std::declval<const Fiber&>().albedo(dvec3(0.0)))>> : std::true_type {};

struct Rendered {
    LinearImage image;
    dvec3 integral{0.0};  // Σ f dωi over the (sub-)pixels
    double seconds = 0.0;
};

// Column x covers φ ∈ [-π + xΔφ, -π + (x+1)Δφ]; row y covers θi from π/2 - yΔθ down to
// π/2 - (y+1)Δθ. Each pixel holds the mean of f at the centres of S × S sub-pixels; the
// integral weights each by its exact solid angle Δφ (sinθ_top - sinθ_bottom), the
// integral of cosθ dθ dφ over the sub-pixel.
template <class Fiber>
Rendered render(const std::vector<Fiber>& fibers, const dvec3& wo, int width, int height, int supersample,
                int threads) {
    const auto start = std::chrono::steady_clock::now();
    Rendered r{LinearImage(width, height), dvec3(0.0), 0.0};
    const int S = supersample;
    const double dphi = 2.0 * kPi / (double(width) * S), dtheta = kPi / (double(height) * S);
    const double inv_fibers = 1.0 / double(fibers.size()), inv_sub = 1.0 / (double(S) * S);
    std::vector<dvec3> row_integral(std::size_t(height), dvec3(0.0));

    auto render_row = [&](int y) {
        dvec3 acc(0.0);
        for (int b = 0; b < S; ++b) {
            const double theta_top = 0.5 * kPi - (double(y) * S + b) * dtheta;
            const double theta_bottom = theta_top - dtheta, theta = theta_top - 0.5 * dtheta;
            const double d_omega = dphi * (std::sin(theta_top) - std::sin(theta_bottom));
            const double sin_t = std::sin(theta), cos_t = std::cos(theta);
            for (int x = 0; x < width; ++x) {
                dvec3 pixel(0.0);
                for (int a = 0; a < S; ++a) {
                    const double phi = -kPi + (double(x) * S + a + 0.5) * dphi;
                    const dvec3 wi(sin_t, cos_t * std::cos(phi), cos_t * std::sin(phi));
                    dvec3 f(0.0);
                    for (const auto& fiber : fibers) f += fiber.eval(wo, wi);
                    f *= inv_fibers;
                    pixel += f;
                    acc += f * d_omega;
                }
                r.image.at(x, y) += pixel * inv_sub;
            }
        }
        row_integral[std::size_t(y)] = acc;
    };

    // Rows are independent: hand them out to the workers one at a time.
    std::atomic<int> next{0};
    auto worker = [&] {
        for (int y = next++; y < height; y = next++) render_row(y);
    };
    const int n = std::clamp(threads > 0 ? threads : int(std::thread::hardware_concurrency()), 1, height);
    std::vector<std::thread> pool;
    for (int t = 1; t < n; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();

    for (const dvec3& row : row_integral) r.integral += row;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

// The smallest S for which the S × S sub-pixel grid resolves the sharpest lobes, so that
// the integral is within about 1 %. By Poisson summation the midpoint rule's error for a
// lobe of width w sampled at pitch Δ decays like exp(-2π² w/Δ) (logistic of scale s,
// w = s) or exp(-2π² w²/Δ²) (the longitudinal lobes, w ≈ sqrt(v), sharpest for TT, v0/4),
// which is below 1 % for s ≥ 0.45 Δ and sqrt(v) ≥ 0.55 Δ.
int supersample_needed(const hs::FiberParams<double>& p, const Options& o) {
    const double s = hs::logistic_scale(p.beta_n);
    const double width_theta = std::sqrt(0.25 * hs::longitudinal_variance(p.beta_m));
    const double pixel_phi = 2.0 * kPi / o.width, pixel_theta = kPi / o.height;
    const double ratio = std::max(pixel_phi / (s / 0.45), pixel_theta / (width_theta / 0.55));
    return std::max(1, int(std::ceil(ratio)));
}

// The image of one lobe set of the chosen model: rendered, written to <base>.exr and
// <base>.png, and summarised on stdout. Returns the exit code.
int explore(const Options& o, const Setup& setup, unsigned lobes, const std::string& base) {
    const ex::FiberModels<double> models(setup.model, lobes, setup.params, setup.extras, setup.section, setup.medulla);
    const std::string model_text =
        setup.model == ex::FiberModel::kChiang
            ? "Chiang et al. 2016 (" + ex::lobes_to_string(lobes) + ")"
            : setup.model == ex::FiberModel::kFarField ? std::string("d'Eon et al. 2011 far field")
            : setup.model == ex::FiberModel::kTabulated ? std::string("tabulated far field")
            : setup.model == ex::FiberModel::kHuang     ? std::string("Huang et al. 2022 microfacet fiber")
            : setup.model == ex::FiberModel::kFur       ? std::string("Yan et al. 2015/2017 fur fiber")
                                                          : std::string("Marschner et al. 2003");
    Rendered r{LinearImage(1, 1), dvec3(0.0), 0.0};
    dvec3 albedo(-1.0);  // -1: the model reports none
    models.visit([&](auto make) {
        using Fiber = decltype(make(0.0));
        std::vector<Fiber> fibers;
        for (double h : setup.offsets) fibers.push_back(make(h));
        r = render(fibers, setup.wo, o.width, o.height, o.supersample, o.threads);
        if constexpr (HasAlbedo<Fiber>::value) {
            albedo = dvec3(0.0);
            for (const auto& fiber : fibers) albedo += fiber.albedo(setup.wo);
            albedo /= double(fibers.size());
        }
        return 0;
    });

    // Maximum of the image (any channel) and where it is.
    double max_f = -1.0;
    int max_x = 0, max_y = 0;
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x) {
            const dvec3& p = r.image.at(x, y);
            const double m = std::max({p.r, p.g, p.b});
            if (m > max_f) max_f = m, max_x = x, max_y = y;
        }
    const double max_phi = -180.0 + (max_x + 0.5) * 360.0 / o.width;
    const double max_theta = 90.0 - (max_y + 0.5) * 180.0 / o.height;

    const std::string h_text = o.average_h > 0 ? "h averaged over " + std::to_string(o.average_h) +
                                                     " uniformly spaced offsets in (-1, 1)"
                                               : "h = " + fmt("%g", o.h);
    const ex::FiberOptions& fo = o.fiber;
    const std::string fiber_text = "eta " + fmt("%g", fo.eta) + ", beta_m " + fmt("%g", setup.params.beta_m) +
                                   ", beta_n " + fmt("%g", setup.params.beta_n) + ", alpha " + fmt("%g", fo.alpha_deg) +
                                   " deg, sigma_a " + rgb_string(setup.params.sigma_a);
    std::string controls_text;  // the lobe controls that differ from their defaults
    const hs::LobeControls<double>& lc = setup.extras.controls;
    for (int p = 0; p < 4; ++p) {
        const char* names[4] = {"R", "TT", "TRT", "residual"};
        if (lc.gain[p] != 1.0) controls_text += std::string(" gain ") + names[p] + " " + fmt("%g", lc.gain[p]) + ";";
        if (lc.tint[p] != dvec3(1.0)) controls_text += std::string(" tint ") + names[p] + " " + rgb_string(lc.tint[p]) + ";";
        if (p < 3 && lc.lobe_alpha(p, -1e300) != -1e300)
            controls_text += std::string(" alpha ") + names[p] + " " + fmt("%g", lc.alpha[p] * 180 / kPi) + " deg;";
    }
    const std::string outgoing_text = "theta_o = " + fmt("%g", o.theta_o_deg) + " deg, phi_o = 0, " + h_text;

    // Outputs.
    const std::string exr_path = base + ".exr", png_path = base + ".png";
    lobe_explorer::PreviewOptions preview;
    preview.tone = o.tone == "log" ? lobe_explorer::ToneMap::kLog : lobe_explorer::ToneMap::kReinhard;
    preview.decades = o.decades;
    preview.exposure = o.exposure;
    preview.annotate = !o.no_annotate;
    preview.theta_o_deg = o.theta_o_deg;
    preview.title = {"hairscatter " + model_text + " f(wo, wi): " + outgoing_text, fiber_text};
    const std::string tone_text =
        preview.tone == lobe_explorer::ToneMap::kLog
            ? "log10 luminance false colour, " + fmt("%g", o.decades) + " decades below the maximum"
            : "Reinhard, exposure " + fmt("%+g", o.exposure) + " stops, sRGB";
    try {
        lobe_explorer::write_exr(
            exr_path, r.image,
            {{"hairscatter:model", model_text},
             {"hairscatter:values", "f(wo, wi) with the cosine inside: Lo = integral of f Li dwi"},
             {"hairscatter:axes", "x: phi = phi_i - phi_o, -180 deg (left edge) to +180 deg (right edge); "
                                  "y: theta_i, +90 deg (top edge) to -90 deg (bottom edge)"},
             {"hairscatter:outgoing", outgoing_text},
             {"hairscatter:fiber", fiber_text}});
        lobe_explorer::write_png(png_path, lobe_explorer::make_preview(r.image, preview));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lobe_explorer: %s\n", e.what());
        return 1;
    }

    std::printf("lobe_explorer: wrote %s (linear f, float RGB, %d x %d)\n", exr_path.c_str(), o.width, o.height);
    std::printf("               wrote %s (%s%s)\n", png_path.c_str(), tone_text.c_str(),
                preview.annotate ? ", annotated" : "");
    std::printf("  model     %s\n", model_text.c_str());
    std::printf("  outgoing  %s\n", outgoing_text.c_str());
    std::printf("  fiber     %s [from %s]\n", fiber_text.c_str(), setup.sigma_a_source.c_str());
    if (!setup.strand_text.empty()) std::printf("  strand    %s\n", setup.strand_text.c_str());
    if (!controls_text.empty())
        std::printf("  controls %s (the albedo below includes them: sum of gain x tint x A_p)\n", controls_text.c_str());
    std::printf("  grid      x: phi -180..180 deg, y: theta_i +90 (top)..-90 (bottom); %d x %d sub-samples "
                "per pixel; %.2f s\n",
                o.supersample, o.supersample, r.seconds);
    std::printf("  max f     %.5g at theta_i = %.2f deg, phi = %.2f deg\n", max_f, max_theta, max_phi);
    std::printf("  integral  of f dw_i over the grid = %s   (model albedo sum A_p = %s)\n",
                rgb_string(r.integral, "%.5f").c_str(),
                albedo.x < 0 ? "not reported by this model" : rgb_string(albedo, "%.5f").c_str());
    const int needed = supersample_needed(setup.params, o);
    if (needed > o.supersample)
        std::printf("  note      the grid is too coarse for these lobes: the integral is inaccurate and the image\n"
                    "            aliased; use --supersample %d (or a larger --width/--height)\n",
                    needed);
    return 0;
}

int run(const Options& o) {
    Setup setup;
    std::string base;
    try {
        make_setup(o, setup);
        ex::check_image_size(o.width, o.height, 3 * 8 + 3);
        base = ex::strip_image_extension(o.output);
        ex::prepare_output(base);
        // The materials validate too (Marschner's mapped parameters, the lobe set).
        const ex::FiberModels<double> check(setup.model, setup.lobes, setup.params, setup.extras, setup.section);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lobe_explorer: invalid parameters: %s\n", e.what());
        return 2;
    }
    int rc = explore(o, setup, setup.lobes, base);
    if (o.per_lobe)
        for (unsigned lobe : ex::each_lobe(setup.lobes))
            if (rc == 0) rc = explore(o, setup, lobe, base + "_" + ex::lobes_to_string(lobe));
    return rc;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app{
        "lobe_explorer: an image of a hair BCSDF f(wo, wi) (--model chiang | farfield | tabulated | marschner, "
        "Chiang's lobes with --lobes) over the sphere of incident directions wi.\n"
        "x axis: phi = phi_i - phi_o from -180 deg (left) to +180 deg (right); phi = 0 (centre) is "
        "backward scattering (R, TRT), |phi| = 180 (edges) forward scattering (TT).\n"
        "y axis: theta_i from +90 deg (top, along the fiber tangent) to -90 deg (bottom); the lobes sit "
        "near the specular cone theta_i = -theta_o.\n"
        "Writes <out>.exr (linear f, float RGB, one pixel per grid cell) and <out>.png (a preview: "
        "by default log10 of the luminance in false colour, with axes and a colour bar).\n"
        "Prints the maximum of f and the integral of f over the sphere (the albedo; 1 for a lossless "
        "fiber, e.g. --eumelanin 0)."};
    app.get_formatter()->column_width(34);

    app.add_option("--theta-o", o.theta_o_deg, "Outgoing inclination theta_o in degrees (phi_o = 0)")
        ->check(CLI::Range(-90.0, 90.0))
        ->capture_default_str();
    auto* h_opt = app.add_option("--h", o.h, "Offset across the fiber, in [-1, 1] (0 = centre)")->capture_default_str();
    app.add_option("--average-h", o.average_h,
                   "Instead of one h, average f over N uniformly spaced offsets in (-1, 1): a whole fiber")
        ->check(CLI::Range(1, 100000))
        ->excludes(h_opt);
    ex::add_fiber_options(app, o.fiber, "brown");
    app.add_option("--strand", o.strand,
                   "With per-strand variation (--strand-seed, --*-range): the strand whose fiber is shown (default 0)")
        ->check(CLI::Range(0LL, 4294967295LL));
    app.add_flag("--per-lobe", o.per_lobe,
                 "chiang: also one image per lobe of --lobes, <out>_R.exr/.png, <out>_TT..., <out>_residual...");
    app.add_option("--width", o.width, "Image width in pixels (phi)")->check(CLI::Range(1, 16384))->capture_default_str();
    app.add_option("--height", o.height, "Image height in pixels (theta_i)")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    app.add_option("--supersample", o.supersample,
                   "S x S samples per pixel (smoother image, more accurate integral for sharp lobes)")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    app.add_option("--threads", o.threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024))->capture_default_str();
    app.add_option("--tonemap", o.tone,
                   "PNG preview: 'log' = false colour (viridis) of log10 luminance over --decades below the "
                   "maximum, showing faint and sharp lobes together; 'reinhard' = f * 2^exposure, x/(1+x), "
                   "sRGB, showing the hair's hue")
        ->check(CLI::IsMember({"log", "reinhard"}))
        ->capture_default_str();
    app.add_option("--decades", o.decades, "log preview: decades of f shown below the maximum")
        ->check(CLI::Range(0.1, 30.0))
        ->capture_default_str();
    app.add_option("--exposure", o.exposure, "reinhard preview: exposure in stops")->capture_default_str();
    app.add_flag("--no-annotate", o.no_annotate, "PNG without axes, labels and colour bar (same size as the EXR)");
    app.add_option("-o,--out", o.output,
                   "Output basename: writes <out>.exr and <out>.png, creating the directory")
        ->capture_default_str();

    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {  // --help
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "lobe_explorer: %s\nRun with --help for the options.\n", e.what());
        return 2;
    }
    return run(o);
}
