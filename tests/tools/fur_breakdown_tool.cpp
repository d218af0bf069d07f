// Where the fur model's error against the physical double cylinder comes from: per case,
// per lobe, lossless and blond (docs/models.md, "Fur with a medulla").
//
// For each case of the comparison (tests/support/physical_fur_cases.hpp: the rough, tilted
// cortex; or those whose name contains --only) it traces the reference with its path
// classes apart (R, TT, TRT, higher, scattered: physical_fur.hpp) over the cache's 16 × 32
// bins, and evaluates the model one lobe at a time (R, TT, TRT and the residual by their
// gains, S by its own), averaged over 48 offsets h as FurPhysical.AgainstThePhysicalFur
// does, with the rough cortex as that test sets it. Per lobe p it prints the model's and the
// reference's energy and the lobe's share of the error, Σ_bins |f_p − f_ref,p| dω over the
// reference's whole energy (the shares add up to at least the whole f's relative L1, which
// is printed next to them: lobes that overlap can cancel). Blond is the mean over RGB.
// With --marginals, per case and lobe instead: the lossless model's and reference's f
// integrated over φ per bin of sin θi, and over sin θi per bin of φ (the lobe's shape).
// With --regions, each lobe's share of the error and the whole f's, per region of incoming
// directions: four bands of sin θi (from −1) times four quarters of φ about wo's azimuth
// (back, toward wo; side; front; the other side), in per cent of the reference's energy.
// With --map L (0 R, 1 TT, 2 TRT, 3 higher, 4 S) and --marginals, that lobe's f per bin too.
// With --split, each lobe's share is split into its energy's part, |E_p − E_ref,p| over the
// reference's whole energy, and its shape's, Σ_bins |f_p E_ref,p / E_p − f_ref,p| dω over the
// same (the lobe scaled to the reference's energy first).
// The model's facets are those its β implies (FurParams::facet_alpha 0), as in the test, or
// with --facet-alpha A GGX of roughness A (the reference's own: 0.17).
// With --tt-exits, instead of the cases: TT's longitudinal shape, per θo (0°, 30°, 75°) and
// per band of |h|. The reference's cortex (no medulla: TT's directions are the cortex's) is
// met at offsets in the band, and the light that enters and leaves at the next meeting (TT)
// is kept with its weight; of its sin θi: the quartiles, the median's shift from the model's
// TT centre −sin(θo + α) (Chiang's tilt), the interquartile range (IQR), Bowley's quartile
// skewness (q3 + q1 − 2 q2)/(q3 − q1), the share beyond 1.5 IQR of the median (the tails),
// and the variance of the d'Eon lobe with the same quartiles over v(β_m) (deon_lobe_from_
// quartiles); then the same for the model's M_TT (the lobe of variance v/4 about θo + α) from
// its cdf, and K(c) = √(η² − 1 + c²) − c at the band's middle, c = cos θo cos γ: to first
// order a facet of slope a along the fibre at entry and b at exit move TT's sin θi by
// −K(c)(a + b) (docs/fur_breakdown.md).
// With --first-chord, instead of the cases: where the light that enters goes on its first
// chord, per θo (0°, 30°, 75°) and κ (0.3, 0.6, 0.9), over a beam uniform in h, through the
// smooth cortex (Snell's law, weighted by 1 − F) and through the rough one (the model's walk over its
// facets, RoughFacets, of --facet-alpha A or from β): the share of the entered light whose
// first chord meets the medulla (in the section the chord leaves the entry at γ' to the normal
// and meets the medulla where |sin γ'| < κ), and of those the mean 3D path through the cortex
// to the medulla, (cos γ' − √(κ² − sin²γ')) over the chord's in-section share, and the mean
// transmittance along it at the blond cortex's green σa^c.
//
//   fur_breakdown_tool [--rays N] [--threads T] [--only SUBSTRING] [--marginals [--map L]] [--split] [--regions]
//                      [--facet-alpha A]
//   fur_breakdown_tool --tt-exits [--rays N]
//   fur_breakdown_tool --first-chord [--rays N] [--facet-alpha A]
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <hairscatter/models/fur.hpp>

#include "support/fur_model_bins.hpp"
#include "support/physical_fur_cases.hpp"

namespace hs = hairscatter;

namespace {

constexpr int kNu = 16, kNphi = 32;

// The model's f of lobe `only` (0–3 Chiang's lobes, 4 the scattered one) per bin.
double g_facet_alpha = 0;  // --facet-alpha
int g_map = -1;            // --map L: with --marginals, lobe L's f per bin

std::vector<glm::dvec3> lobe_bins(const phys_fur::FurCase& fc, const glm::dvec3& sigma_a, int only,
                                  const phys_fiber::CachedCase& grid) {
    hs::FurParams<double> p;
    p.kappa = fc.kappa;
    p.sigma_s = fc.sigma_s;
    p.g = fc.g;
    p.cortex.sigma_a = sigma_a;
    p.cortex.alpha = fc.tilt_deg * phys_fiber::kPi / 180;
    p.rough_cortex = fc.roughness >= 0.1;
    p.facet_alpha = p.rough_cortex ? g_facet_alpha : 0;
    hs::FurControls<double> c;
    for (int l = 0; l < 4; ++l) c.lobes.gain[l] = l == only ? 1.0 : 0.0;
    c.gain_s = only == 4 ? 1.0 : 0.0;
    return phys_fur::fur_model_bins(hs::FurMaterial<double>(p, c), grid);
}

// Per lobe, the lossless model's and reference's f over sin θi (summed over φ) and over φ
// (summed over sin θi), each bin's energy.
void print_marginals(const phys_fur::FurCase& fc, const phys_fur::Histogram& h, const phys_fiber::CachedCase& grid) {
    static const char* kName[5] = {"R", "TT", "TRT", "higher", "S"};
    const double dw = (2.0 / kNu) * (2 * phys_fiber::kPi / kNphi);
    for (int l = 0; l < 5; ++l) {
        const std::vector<glm::dvec3> model = lobe_bins(fc, glm::dvec3(0.0), l, grid);
        double mu[2][kNu] = {}, mp[2][kNphi] = {};
        for (int b = 0; b < kNu * kNphi; ++b) {
            const double m = model[std::size_t(b)][0] * dw, r = h.f(b, 0, l) * dw;
            mu[0][b / kNphi] += m, mu[1][b / kNphi] += r;
            mp[0][b % kNphi] += m, mp[1][b % kNphi] += r;
        }
        std::printf("%s %s sin(theta_i) model/ref:", fc.name().c_str(), kName[l]);
        for (int i = 0; i < kNu; ++i) std::printf(" %.4f/%.4f", mu[0][i], mu[1][i]);
        std::printf("\n%s %s phi model/ref:", fc.name().c_str(), kName[l]);
        for (int i = 0; i < kNphi; ++i) std::printf(" %.4f/%.4f", mp[0][i], mp[1][i]);
        std::printf("\n");
        if (g_map == l)  // --map: the lobe's f per bin, model / ref, every row of sin θi
            for (int i = 0; i < kNu; ++i) {
                std::printf("%s %s row %d (sin θi from %+.3f):", fc.name().c_str(), kName[l], i, -1 + 2.0 * i / kNu);
                for (int j = 0; j < kNphi; ++j)
                    std::printf(" %.4f/%.4f", model[std::size_t(i * kNphi + j)][0] * dw, h.f(i * kNphi + j, 0, l) * dw);
                std::printf("\n");
            }
    }
    std::fflush(stdout);
}

// sin θi at which the d'Eon lobe of variance v about inclination θc has cdf p (bisection).
double deon_lobe_quantile(double p, double v, double theta_c) {
    double lo = -1, hi = 1;
    for (int i = 0; i < 40; ++i) {
        const double mid = 0.5 * (lo + hi);
        (hs::detail::deon_lobe_cdf(mid, v, std::sin(theta_c), std::cos(theta_c)) < p ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

// The cdf of s = a + b for two independent slopes along one axis of a GGX microsurface of
// roughness 1: each has the marginal of GGX's slope density 1/(π (1 + x² + y²)²), the density
// (1 + x²)^(−3/2) / 2 (Student's t with 2 degrees of freedom over √2), of cdf
// F(x) = (1 + x/√(1 + x²)) / 2. With a = tan t, whose density is cos t / 2 in t,
// P(s ≤ x) = ∫ F(x − tan t) cos t / 2 dt over (−π/2, π/2) (midpoint rule, 4,096 points: the
// integrand is smooth).
double ggx_slope_pair_cdf(double x) {
    constexpr int kN = 4096;
    const double pi = phys_fiber::kPi;
    double p = 0;
    for (int i = 0; i < kN; ++i) {
        const double t = -pi / 2 + (i + 0.5) * pi / kN, y = x - std::tan(t);
        p += 0.5 * (1 + y / std::sqrt(1 + y * y)) * std::cos(t) / 2;
    }
    return p * pi / kN;
}
double ggx_slope_pair_quantile(double p) {
    double lo = -100, hi = 100;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (ggx_slope_pair_cdf(mid) < p ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

// --tt-exits: TT's exits in sin θi, the reference's per band of |h| against the model's M_TT.
void print_tt_exits(long long rays) {
    const double beta_m = 0.3, v = hs::longitudinal_variance(beta_m), kPi = phys_fiber::kPi;
    std::printf("# fur_breakdown_tool --tt-exits --rays %lld: TT's exits in sin θi (lossless, no medulla), v(β_m 0.3) = %.4f\n\n",
                rays, v);
    // To first order TT's sin θi moves by −K(c)(a + b) (a, b the facets' slopes along the fibre
    // at entry and exit): the first-order IQR is K(c) α IQR(a + b), and its share beyond 1.5 IQR
    // of the median that of a + b.
    const double iqr_pair = ggx_slope_pair_quantile(0.75) - ggx_slope_pair_quantile(0.25);
    const double beyond_pair = 2 * ggx_slope_pair_cdf(-1.5 * iqr_pair);
    std::printf("First order (two GGX slopes summed): IQR(a + b) = %.3f α, %.1f %% beyond 1.5 IQR.\n\n", iqr_pair,
                100 * beyond_pair);
    std::printf("| θo | \\|h\\| | TT share | q1, q2, q3 | q2 − model's centre | IQR | first-order IQR | Bowley skew |"
                " beyond 1.5 IQR | quartile v / v | K(c) |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    constexpr int kBands = 5;
    for (double theta_deg : {0.0, 30.0, 75.0}) {
        phys_fur::FurCase fc{0.0, 0, 0, theta_deg};
        const phys_fiber::Fiber cortex = fc.fur().cortex;
        const double eta = cortex.eta, theta = theta_deg * kPi / 180, alpha = fc.tilt_deg * kPi / 180;
        const glm::dvec3 d(-std::sin(theta), 0, -std::cos(theta));
        const glm::dvec2 d2 = glm::normalize(glm::dvec2(d.y, d.z)), e(-d2.y, d2.x);
        const double centre = -std::sin(theta + alpha);
        for (int band = 0; band <= kBands; ++band) {  // the last: every |h|
            phys_fiber::Rng rng(0x77E5u + std::uint64_t(band) + std::uint64_t(theta_deg) * 16u);
            std::vector<std::pair<double, double>> exits;
            double total = 0;
            for (long long r = 0; r < rays; ++r) {
                const double u = rng.uniform(), h = band < kBands ? (band + u) / kBands : u;
                glm::dvec2 p = h * e - std::sqrt(std::max(0.0, 1 - h * h)) * d2;
                const std::optional<phys_fiber::Scatter> in = phys_fiber::boundary_event(d, glm::dvec3(0, p), false, cortex, rng);
                if (!in || !in->transmitted) continue;
                const glm::dvec2 t2(in->dir.y, in->dir.z);
                double a0 = 0, a1 = 0;
                if (!(glm::length(t2) > 1e-12) || !phys_fur::circle_hit(p, glm::normalize(t2), 1.0, a0, a1)) continue;
                p = glm::normalize(p + a1 * glm::normalize(t2));
                const std::optional<phys_fiber::Scatter> out = phys_fiber::boundary_event(in->dir, glm::dvec3(0, p), true, cortex, rng);
                if (!out || !out->transmitted) continue;
                exits.emplace_back(out->dir.x, in->weight * out->weight);
                total += in->weight * out->weight;
            }
            const std::array<double, 3> q = hs::detail::weighted_quartiles(exits);
            const double iqr = q[2] - q[0];
            double tail = 0;
            for (const auto& x : exits)
                if (std::fabs(x.first - q[1]) > 1.5 * iqr) tail += x.second;
            const hs::detail::DeonLobeFit fit = hs::detail::deon_lobe_from_quartiles(q[0], q[1], q[2]);
            const double hm = band < kBands ? (band + 0.5) / kBands : 0.5;  // (all: the middle of [0, 1])
            const double c = std::cos(theta) * std::sqrt(1 - hm * hm), k = std::sqrt(eta * eta - 1 + c * c) - c;
            char label[16] = "all";
            if (band < kBands) std::snprintf(label, sizeof(label), "%.1f–%.1f", double(band) / kBands, double(band + 1) / kBands);
            std::printf("| %.0f° | %s | %.3f | %.3f, %.3f, %.3f | %+.3f | %.3f | %.3f | %+.2f | %.1f %% | %.2f | %.2f |\n",
                        theta_deg, label, total / double(rays), q[0], q[1], q[2], q[1] - centre, iqr, k * cortex.roughness * iqr_pair,
                        (q[2] + q[0] - 2 * q[1]) / iqr, 100 * tail / total, fit.v / v, k);
        }
        // The model's M_TT: Chiang's lobe of variance v/4 about θo + α.
        const double vt = v / 4, tc = -(theta + alpha);
        const double m1 = deon_lobe_quantile(0.25, vt, tc), m2 = deon_lobe_quantile(0.5, vt, tc), m3 = deon_lobe_quantile(0.75, vt, tc);
        const double miqr = m3 - m1;
        const double lo = m2 - 1.5 * miqr, hi = m2 + 1.5 * miqr;
        const double beyond = hs::detail::deon_lobe_cdf(lo, vt, std::sin(tc), std::cos(tc)) +
                              1 - hs::detail::deon_lobe_cdf(hi, vt, std::sin(tc), std::cos(tc));
        std::printf("| %.0f° | model M_TT | — | %.3f, %.3f, %.3f | %+.3f | %.3f | — | %+.2f | %.1f %% | 0.25 | — |\n", theta_deg, m1,
                    m2, m3, m2 - centre, miqr, (m3 + m1 - 2 * m2) / miqr, 100 * beyond);
        std::fflush(stdout);
    }
}

// --first-chord (see the top).
void print_first_chord(long long rays) {
    constexpr double kEta = 1.55, kBeta = 0.3;
    const double tilt = 2 * phys_fiber::kPi / 180, sigma = phys_fiber::kBlond[1];
    const hs::detail::RoughFacets facets = hs::detail::RoughFacets::of(kEta, tilt, kBeta, g_facet_alpha);
    std::printf("# fur_breakdown_tool --first-chord --rays %lld --facet-alpha %g (GGX %.3f, tilt 2°)\n\n", rays, g_facet_alpha,
                facets.ggx);
    std::printf("| θo | κ | smooth: meets the medulla | path to it | transmittance | rough: meets the medulla | path to it |"
                " transmittance |\n|---|---|---|---|---|---|---|---|\n");
    for (double theta_deg : {0.0, 30.0, 75.0})
        for (double kappa : {0.3, 0.6, 0.9}) {
            const double theta = theta_deg * phys_fiber::kPi / 180;
            hs::detail::FurRng rng(0xF1257C40u);
            double entered[2] = {0, 0}, hits[2] = {0, 0}, path[2] = {0, 0}, kept[2] = {0, 0};
            for (long long k = 0; k < rays; ++k) {
                const double h = 2 * rng.uniform() - 1;
                // Toward the light in the entry point's frame (axis, normal, tangent), as
                // build_rough_cortex meets it.
                const glm::dvec3 out(std::sin(theta), std::cos(theta) * std::sqrt(1 - h * h), -std::cos(theta) * h);
                for (int rough = 0; rough < 2; ++rough) {
                    glm::dvec3 d;
                    double w = 1;  // (the smooth boundary's transmitted share; the walk's light enters or not)
                    if (rough) {
                        const double h1 = facets.next_height(-out, 2, rng.uniform());
                        const hs::detail::RoughFacets::Event e = facets.event(-out, true, kEta, rng);
                        const hs::detail::RoughFacets::Exit x = facets.walk_from(e.dir, e.outside, h1, kEta, rng);
                        if (x.outside) continue;
                        d = x.dir;
                    } else {
                        const double ci = out.y, ct = std::sqrt(1 - (1 - ci * ci) / (kEta * kEta));
                        d = -out / kEta + (ci / kEta - ct) * glm::dvec3(0, 1, 0);
                        w = 1 - hs::detail::fur_fresnel(ci, kEta);
                    }
                    entered[rough] += w;
                    const double in_plane = std::sqrt(d.y * d.y + d.z * d.z), cos_g = std::fabs(d.y) / in_plane, sin_g = d.z / in_plane;
                    if (!(std::fabs(sin_g) < kappa)) continue;
                    const double l = (cos_g - std::sqrt(kappa * kappa - sin_g * sin_g)) / in_plane;
                    hits[rough] += w, path[rough] += w * l, kept[rough] += w * std::exp(-sigma * l);
                }
            }
            std::printf("| %g° | %g |", theta_deg, kappa);
            for (int r = 0; r < 2; ++r)
                std::printf(" %.3f | %.3f | %.3f |", hits[r] / entered[r], path[r] / hits[r], kept[r] / hits[r]);
            std::printf("\n");
            std::fflush(stdout);
        }
}

}  // namespace

int main(int argc, char** argv) {
    long long rays = 1000000;
    int threads = 2;
    std::string only;
    bool marginals = false, split = false, regions = false, tt_exits = false, first_chord = false;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--rays") && i + 1 < argc) rays = std::atoll(argv[++i]);
        else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threads = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
        else if (!std::strcmp(argv[i], "--marginals")) marginals = true;
        else if (!std::strcmp(argv[i], "--split")) split = true;
        else if (!std::strcmp(argv[i], "--regions")) regions = true;
        else if (!std::strcmp(argv[i], "--map") && i + 1 < argc) g_map = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--tt-exits")) tt_exits = true;
        else if (!std::strcmp(argv[i], "--first-chord")) first_chord = true;
        else if (!std::strcmp(argv[i], "--facet-alpha") && i + 1 < argc) g_facet_alpha = std::atof(argv[++i]);
        else {
            std::fprintf(stderr, "usage: fur_breakdown_tool [--rays N] [--threads T] [--only SUBSTRING] [--marginals]"
                                 " [--split] [--regions] [--map L] [--facet-alpha A] [--tt-exits] [--first-chord]\n");
            return 2;
        }
    }
    if (rays < 2 || threads < 1) {
        std::fprintf(stderr, "fur_breakdown_tool: bad arguments\n");
        return 2;
    }
    if (tt_exits) {
        print_tt_exits(rays);
        return 0;
    }
    if (first_chord) {
        print_first_chord(rays);
        return 0;
    }
    const glm::dvec3 blond(phys_fiber::kBlond[0], phys_fiber::kBlond[1], phys_fiber::kBlond[2]);
    const double dw = (2.0 / kNu) * (2 * phys_fiber::kPi / kNphi);
    std::printf("# fur_breakdown_tool --rays %lld%s%s%s%s --facet-alpha %g\n\n", rays, only.empty() ? "" : " --only ", only.c_str(),
                split ? " --split" : "", regions ? " --regions" : "", g_facet_alpha);
    if (split)
        std::printf("| case | pigment | f L1 | R: energy, shape | TT | TRT | higher | S |\n|---|---|---|---|---|---|---|---|\n");
    else
        std::printf("| case | pigment | f L1 | R: model / ref, share | TT | TRT | higher | S |\n|---|---|---|---|---|---|---|---|\n");
    for (const phys_fur::FurCase& fc : phys_fur::fur_cases()) {
        if (fc.roughness < 0.1 || (!only.empty() && fc.name().find(only) == std::string::npos)) continue;
        const phys_fur::Tracer tracer(fc.fur());
        phys_fur::Histogram h(kNu, kNphi);
        phys_fiber::CachedCase grid;
        grid.c = fc.cortex_case();
        grid.n_u = kNu, grid.n_phi = kNphi;
        phys_fur::trace_parallel(tracer, grid.c.wo(), rays, 11, threads, h);
        if (marginals) {
            print_marginals(fc, h, grid);
            continue;
        }
        for (int pigment = 0; pigment < 2; ++pigment) {
            std::vector<glm::dvec3> lobe[5];
            for (int l = 0; l < 5; ++l) lobe[l] = lobe_bins(fc, pigment ? blond : glm::dvec3(0.0), l, grid);
            double energy[5][2] = {}, share[5] = {}, energy_part[5] = {}, shape_part[5] = {}, whole = 0;
            double region[6][16] = {};  // per lobe and the whole f (5), per region
            const int channels = pigment ? 3 : 1;
            for (int c = 0; c < channels; ++c) {
                const int mch = pigment ? c : 0, ch = pigment ? c + 1 : 0;
                double ref_total = 0, part[5] = {}, diff_whole = 0, e[5][2] = {}, reg[6][16] = {};
                for (int b = 0; b < kNu * kNphi; ++b) {
                    double m_sum = 0, r_sum = 0;
                    // wo's azimuth is bin 23.5 of 32 (φ = π/2): back, side, front, other side.
                    const int rq = ((b % kNphi - 20 + kNphi) % kNphi) / 8, rg = (b / kNphi) / 4 * 4 + rq;
                    for (int l = 0; l < 5; ++l) {
                        const double m = lobe[l][std::size_t(b)][mch], r = h.f(b, ch, l);
                        part[l] += std::fabs(m - r) * dw;
                        reg[l][rg] += std::fabs(m - r) * dw;
                        e[l][0] += m * dw;
                        e[l][1] += r * dw;
                        m_sum += m;
                        r_sum += r;
                    }
                    ref_total += r_sum * dw;
                    diff_whole += std::fabs(m_sum - r_sum) * dw;
                    reg[5][rg] += std::fabs(m_sum - r_sum) * dw;
                }
                for (int l = 0; l < 6; ++l)
                    for (int g = 0; g < 16; ++g) region[l][g] += reg[l][g] / ref_total / channels;
                for (int l = 0; l < 5; ++l) {  // the lobe scaled to the reference's energy: its shape's error
                    const double scale = e[l][0] > 0 ? e[l][1] / e[l][0] : 0;
                    double shape = 0;
                    for (int b = 0; b < kNu * kNphi; ++b)
                        shape += std::fabs(lobe[l][std::size_t(b)][mch] * scale - h.f(b, ch, l)) * dw;
                    energy_part[l] += std::fabs(e[l][0] - e[l][1]) / ref_total / channels;
                    shape_part[l] += shape / ref_total / channels;
                }
                for (int l = 0; l < 5; ++l) {
                    share[l] += part[l] / ref_total / channels;
                    energy[l][0] += e[l][0] / channels;
                    energy[l][1] += e[l][1] / channels;
                }
                whole += diff_whole / ref_total / channels;
            }
            std::printf("| %s | %s | %.1f %% |", fc.name().c_str(), pigment ? "blond" : "lossless", 100 * whole);
            for (int l = 0; l < 5; ++l)
                if (split) std::printf(" %.1f %%, %.1f %% |", 100 * energy_part[l], 100 * shape_part[l]);
                else std::printf(" %.3f / %.3f, %.1f %% |", energy[l][0], energy[l][1], 100 * share[l]);
            std::printf("\n");
            if (regions) {
                static const char* kRegName[6] = {"R", "TT", "TRT", "higher", "S", "f"};
                for (int l = 0; l < 6; ++l) {
                    std::printf("    %s %s regions (sin θi band from −1: back side front side):", pigment ? "blond" : "lossless",
                                kRegName[l]);
                    for (int g = 0; g < 16; ++g) std::printf("%s%.1f", g % 4 ? " " : " | ", 100 * region[l][g]);
                    std::printf("\n");
                }
            }
            std::fflush(stdout);
        }
    }
    return 0;
}
