// Which rough cortex the fur model's unscattered lobes stand for: matches the physical
// reference's GGX roughness α to the model's β by lobe width, not by name, and measures the
// model against the cortex so matched (docs/models.md, "Fur with a medulla").
//
// For each α it traces the physical fibre without a medulla (tests/support/physical_fur.hpp,
// κ = 0: physical_fiber.hpp's round GGX fibre) at θo, bins the exit directions 64 × 32 (equal
// solid angle) and reports per path class the energy and the longitudinal width: the
// standard deviation of θi about its mean, over the class's marginal in sin θi. The model's
// lobes (FurFiber at κ = 0, which is ChiangFiber, one lobe at a time by its gains) are
// binned the same way (averaged over 48 offsets h). The matched α is the one whose R lobe
// has the model's R width. Then the whole f, relative L1 over 16 × 32 bins, lossless and
// blond, at every α.
//
//   fur_roughness_tool [--rays N] [--threads T] [--theta DEG] [--beta B] [--tilt DEG] [--alphas A,B,..] [--dat FILE]
//
// --dat writes the marginals in sin θi and φ of the model and of the reference at every α
// (for docs/fur_roughness.gp).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include <hairscatter/models/fur.hpp>

#include "support/fur_model_bins.hpp"
#include "support/physical_fur_cases.hpp"

namespace hs = hairscatter;

namespace {

constexpr int kNu = 64, kNphi = 32;
constexpr const char* kClassName[4] = {"R", "TT", "TRT", "higher"};

struct Widths {
    double energy[4] = {}, width[4] = {}, mean[4] = {};
};

// Energy, mean θi and its standard deviation per class from f per bin (1/sr), cls-major.
Widths widths_of(const std::vector<std::vector<double>>& f) {
    Widths w;
    const double dw = (2.0 / kNu) * (2 * phys_fiber::kPi / kNphi);
    for (int cls = 0; cls < 4; ++cls) {
        double e = 0, m1 = 0, m2 = 0;
        for (int iu = 0; iu < kNu; ++iu) {
            const double theta = std::asin(-1 + (iu + 0.5) * 2.0 / kNu);
            double row = 0;
            for (int ip = 0; ip < kNphi; ++ip) row += f[std::size_t(cls)][std::size_t(iu * kNphi + ip)] * dw;
            e += row;
            m1 += row * theta;
            m2 += row * theta * theta;
        }
        w.energy[cls] = e;
        w.mean[cls] = e > 0 ? m1 / e : 0;
        w.width[cls] = e > 0 ? std::sqrt(std::max(0.0, m2 / e - w.mean[cls] * w.mean[cls])) : 0;
    }
    return w;
}

hs::FurMaterial<double> model(double beta, double tilt, const glm::dvec3& sigma_a, int only_lobe) {
    hs::FurParams<double> p;
    p.cortex.beta_m = beta;
    p.cortex.beta_n = beta;
    p.cortex.alpha = tilt;
    p.cortex.sigma_a = sigma_a;
    hs::FurControls<double> c;
    if (only_lobe >= 0)
        for (int l = 0; l < 4; ++l) c.lobes.gain[l] = l == only_lobe ? 1.0 : 0.0;
    return hs::FurMaterial<double>(p, c);
}

}  // namespace

int main(int argc, char** argv) {
    long long rays = 1000000;
    int threads = 2;
    double theta = 30, beta = 0.3, tilt_deg = 2;
    std::string dat;
    std::vector<double> alphas = {0.02, 0.05, 0.1, 0.125, 0.15, 0.17, 0.2, 0.25, 0.3};
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--rays")) rays = std::atoll(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--threads")) threads = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--theta")) theta = std::atof(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--beta")) beta = std::atof(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--tilt")) tilt_deg = std::atof(argv[i + 1]);  // both fibres' α, degrees
        else if (!std::strcmp(argv[i], "--dat")) dat = argv[i + 1];
        else if (!std::strcmp(argv[i], "--alphas")) {  // comma-separated
            alphas.clear();
            for (const char* s = argv[i + 1]; *s;) {
                char* end = nullptr;
                alphas.push_back(std::strtod(s, &end));
                if (end == s) break;
                s = *end == ',' ? end + 1 : end;
            }
        }
        else {
            std::fprintf(stderr, "usage: fur_roughness_tool [--rays N] [--threads T] [--theta DEG] [--beta B] [--tilt DEG] [--alphas A,B,..] [--dat FILE]\n");
            return 2;
        }
    }
    if (rays < 2 || threads < 1 || argc % 2 == 0) {
        std::fprintf(stderr, "fur_roughness_tool: bad arguments\n");
        return 2;
    }
    const glm::dvec3 blond(phys_fiber::kBlond[0], phys_fiber::kBlond[1], phys_fiber::kBlond[2]);
    phys_fiber::CachedCase fine, coarse;
    fine.c.theta_deg = coarse.c.theta_deg = theta;
    fine.n_u = kNu, fine.n_phi = kNphi;
    coarse.n_u = 16, coarse.n_phi = kNphi;

    // The model, lobe by lobe (lossless), and whole (lossless and blond).
    std::vector<std::vector<double>> mf(4, std::vector<double>(std::size_t(kNu * kNphi)));
    for (int l = 0; l < 4; ++l) {
        const std::vector<glm::dvec3> b = phys_fur::fur_model_bins(model(beta, tilt_deg * phys_fiber::kPi / 180, glm::dvec3(0.0), l), fine);
        for (std::size_t k = 0; k < b.size(); ++k) mf[std::size_t(l)][k] = b[k].x;
    }
    const Widths mw = widths_of(mf);
    const std::vector<glm::dvec3> whole[2] = {phys_fur::fur_model_bins(model(beta, tilt_deg * phys_fiber::kPi / 180, glm::dvec3(0.0), -1), coarse),
                                              phys_fur::fur_model_bins(model(beta, tilt_deg * phys_fiber::kPi / 180, blond, -1), coarse)};
    std::printf("# fur_roughness_tool --rays %lld --theta %g --beta %g\n", rays, theta, beta);
    std::printf("model beta_m = beta_n = %.3g:", beta);
    for (int l = 0; l < 4; ++l)
        std::printf("  %s energy %.4f width %.2f deg", kClassName[l], mw.energy[l], mw.width[l] * 180 / phys_fiber::kPi);
    std::printf("\n\n| GGX α | R energy | R width | TT energy | TT width | TRT energy | TRT width | higher energy | higher width | f lossless | f blond |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
    std::FILE* out = dat.empty() ? nullptr : std::fopen(dat.c_str(), "w");
    if (out) {
        std::fprintf(out, "# marginals at theta_o %g: block 0 the model (beta %g), then one per GGX alpha\n", theta, beta);
        std::fprintf(out, "# columns: sin(theta_i) or phi, then f integrated over the other angle for R, TT, TRT, higher\n");
    }
    const auto write_marginals = [&](const char* label, const std::vector<std::vector<double>>& f) {
        if (!out) return;
        const double dphi = 2 * phys_fiber::kPi / kNphi, du = 2.0 / kNu;
        std::fprintf(out, "# %s: over sin(theta_i)\n", label);
        for (int iu = 0; iu < kNu; ++iu) {
            std::fprintf(out, "%.5f", -1 + (iu + 0.5) * du);
            for (int l = 0; l < 4; ++l) {
                double s = 0;
                for (int ip = 0; ip < kNphi; ++ip) s += f[std::size_t(l)][std::size_t(iu * kNphi + ip)] * dphi;
                std::fprintf(out, " %.6g", s);
            }
            std::fprintf(out, "\n");
        }
        std::fprintf(out, "\n\n# %s: over phi\n", label);
        for (int ip = 0; ip < kNphi; ++ip) {
            std::fprintf(out, "%.5f", -phys_fiber::kPi + (ip + 0.5) * dphi);
            for (int l = 0; l < 4; ++l) {
                double s = 0;
                for (int iu = 0; iu < kNu; ++iu) s += f[std::size_t(l)][std::size_t(iu * kNphi + ip)] * du;
                std::fprintf(out, " %.6g", s);
            }
            std::fprintf(out, "\n");
        }
        std::fprintf(out, "\n\n");
    };
    write_marginals("model", mf);

    for (const double alpha : alphas) {
        phys_fur::FurCase fc{0, 0, 0, theta, alpha};
        phys_fur::Fur fur = fc.fur();
        fur.cortex.tilt = tilt_deg * phys_fiber::kPi / 180;
        const phys_fur::Tracer tracer(fur);
        phys_fur::Histogram h(kNu, kNphi);
        phys_fur::trace_parallel(tracer, fine.c.wo(), rays, 7, threads, h);
        std::vector<std::vector<double>> pf(4, std::vector<double>(std::size_t(kNu * kNphi)));
        for (int l = 0; l < 4; ++l)
            for (int b = 0; b < kNu * kNphi; ++b) pf[std::size_t(l)][std::size_t(b)] = h.f(b, 0, l);
        const Widths pw = widths_of(pf);
        // Rebinned to 16 × 32 (4 rows of sin θ each: equal solid angle), every class.
        coarse.f.assign(std::size_t(16 * kNphi * 4), 0.0);
        for (int b = 0; b < kNu * kNphi; ++b) {
            const int cb = (b / kNphi) / 4 * kNphi + b % kNphi;
            for (int ch = 0; ch < 4; ++ch) coarse.f[std::size_t(cb * 4 + ch)] += 0.25 * h.f(b, ch);
        }
        double l1[2] = {0, 0};
        l1[0] = phys_fiber::compare(coarse, whole[0], 0, 0).l1;
        for (int ch = 0; ch < 3; ++ch) l1[1] += phys_fiber::compare(coarse, whole[1], ch, ch + 1).l1 / 3;
        std::printf("| %.3g |", alpha);
        for (int l = 0; l < 4; ++l) std::printf(" %.4f | %.2f° |", pw.energy[l], pw.width[l] * 180 / phys_fiber::kPi);
        std::printf(" %.1f %% | %.1f %% |\n", 100 * l1[0], 100 * l1[1]);
        std::fflush(stdout);
        char label[32];
        std::snprintf(label, sizeof(label), "GGX %.2f", alpha);
        write_marginals(label, pf);
    }
    if (out) std::fclose(out);
    return 0;
}
