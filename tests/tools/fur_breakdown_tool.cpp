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
// With --split, each lobe's share is split into its energy's part, |E_p − E_ref,p| over the
// reference's whole energy, and its shape's, Σ_bins |f_p E_ref,p / E_p − f_ref,p| dω over the
// same (the lobe scaled to the reference's energy first).
// The model's facets are those its β implies (FurParams::facet_alpha 0), as in the test, or
// with --facet-alpha A GGX of roughness A (the reference's own: 0.17).
//
//   fur_breakdown_tool [--rays N] [--threads T] [--only SUBSTRING] [--marginals] [--split] [--facet-alpha A]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <hairscatter/models/fur.hpp>

#include "support/fur_model_bins.hpp"
#include "support/physical_fur_cases.hpp"

namespace hs = hairscatter;

namespace {

constexpr int kNu = 16, kNphi = 32;

// The model's f of lobe `only` (0–3 Chiang's lobes, 4 the scattered one) per bin.
double g_facet_alpha = 0;  // --facet-alpha

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
    }
    std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
    long long rays = 1000000;
    int threads = 2;
    std::string only;
    bool marginals = false, split = false;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--rays") && i + 1 < argc) rays = std::atoll(argv[++i]);
        else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threads = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
        else if (!std::strcmp(argv[i], "--marginals")) marginals = true;
        else if (!std::strcmp(argv[i], "--split")) split = true;
        else if (!std::strcmp(argv[i], "--facet-alpha") && i + 1 < argc) g_facet_alpha = std::atof(argv[++i]);
        else {
            std::fprintf(stderr, "usage: fur_breakdown_tool [--rays N] [--threads T] [--only SUBSTRING] [--marginals]"
                                 " [--split] [--facet-alpha A]\n");
            return 2;
        }
    }
    if (rays < 2 || threads < 1) {
        std::fprintf(stderr, "fur_breakdown_tool: bad arguments\n");
        return 2;
    }
    const glm::dvec3 blond(phys_fiber::kBlond[0], phys_fiber::kBlond[1], phys_fiber::kBlond[2]);
    const double dw = (2.0 / kNu) * (2 * phys_fiber::kPi / kNphi);
    std::printf("# fur_breakdown_tool --rays %lld%s%s%s --facet-alpha %g\n\n", rays, only.empty() ? "" : " --only ", only.c_str(),
                split ? " --split" : "", g_facet_alpha);
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
            const int channels = pigment ? 3 : 1;
            for (int c = 0; c < channels; ++c) {
                const int mch = pigment ? c : 0, ch = pigment ? c + 1 : 0;
                double ref_total = 0, part[5] = {}, diff_whole = 0, e[5][2] = {};
                for (int b = 0; b < kNu * kNphi; ++b) {
                    double m_sum = 0, r_sum = 0;
                    for (int l = 0; l < 5; ++l) {
                        const double m = lobe[l][std::size_t(b)][mch], r = h.f(b, ch, l);
                        part[l] += std::fabs(m - r) * dw;
                        e[l][0] += m * dw;
                        e[l][1] += r * dw;
                        m_sum += m;
                        r_sum += r;
                    }
                    ref_total += r_sum * dw;
                    diff_whole += std::fabs(m_sum - r_sum) * dw;
                }
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
            std::fflush(stdout);
        }
    }
    return 0;
}
