// Writes the physical fiber reference's cache (tests/data/physical_fiber.txt) and reports
// Huang et al. 2022's fiber against it (the table of docs/models.md). Run by
// scripts/physical-reference.sh; the tests read the cache.
//
//   physical_fiber_tool generate --rays N --threads T --out FILE
//   physical_fiber_tool report --cache FILE [--quadrature default|fine|fast|cycles|x8]
//   physical_fiber_tool residual --rays N --threads T   the residual's θ shape against the
//                                                       reference's orders ≥ TRRT
//   physical_fiber_tool breakdown --rays N --threads T  each lobe's share of each case's
//                                                       error, and the lattices' part in it
//   physical_fiber_tool lattice --threads T             TT's and TRT's lattice error alone,
//                                                       model against model (no trace)
//   physical_fiber_tool walk --cache FILE --variant V   the residual in the θ shape of an
//       [--walk-u N --walk-h N --walks N]               interior walk (variants a–f, below)
//   physical_fiber_tool walk-shape --case K --rays N --variant V   that shape and R per row
//                                                       against a fresh trace of case K
//   physical_fiber_tool decompose --case K --rays N     case K's error by lobe, quadrature,
//                                                       marginal and region of wi
//   physical_fiber_tool azimuth --rays N --walks W      the residual's azimuth traced with W
//       [--harmonics K]                                 rays (smoothed to K harmonics)
//                                                       against the orders ≥ TRRT
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include <hairscatter/models/huang.hpp>

#include "support/physical_fiber_huang.hpp"

namespace hs = hairscatter;
using phys_fiber::CachedCase;

namespace {

struct Row {
    double err[2] = {0, 0}, r_model = 0;
};

// A case with no cached data: the bins model_bins integrates the model over.
CachedCase grid_of(const phys_fiber::Case& c, int n_u, int n_phi) {
    CachedCase cc;
    cc.c = c;
    cc.n_u = n_u;
    cc.n_phi = n_phi;
    return cc;
}
// Lobe `lobe` alone (the others' gains 0) of the fiber p at quadrature q, averaged over
// cc's bins at cc's wo.
std::vector<glm::dvec3> lobe_bins(const CachedCase& cc, const hs::HuangParams<double>& p, const hs::HuangQuadrature& q, int lobe) {
    hs::LobeControls<double> only;
    for (int j = 0; j < 4; ++j) only.gain[j] = j == lobe ? 1 : 0;
    const hs::HuangMaterial<double> mat(p, q, only);
    const hs::HuangFiber<double, 4096> fiber(mat);
    const auto bound = fiber.at(cc.c.wo());
    return phys_fiber::model_bins(cc, [&](const glm::dvec3&, const glm::dvec3& wi) { return bound.eval(wi); });
}

Row report_row(const CachedCase& c, const std::string& quadrature) {
    Row row;
    for (int blond = 0; blond < 2; ++blond) {
        const hs::HuangParams<double> p = phys_fiber::huang_params(c.c, blond != 0);
        const hs::HuangQuadrature q = quadrature == "fine"     ? hs::huang_scaled_quadrature(p.roughness)
                                      : quadrature == "fast"   ? hs::huang_fast_quadrature(p.roughness)
                                      : quadrature == "cycles" ? hs::huang_cycles_class_quadrature(p.roughness)
                                      : quadrature == "x8"     ? hs::huang_scaled_quadrature(p.roughness, 8, 2)
                                                               : hs::HuangQuadrature();
        const hs::HuangMaterial<double> mat(p, q);
        const hs::HuangFiber<double> fiber(mat);
        // Each case binds its wo once (at(wo): the same values as eval, a fraction of the time).
        const auto bound = fiber.at(c.c.wo());
        const auto eval = [&](const glm::dvec3&, const glm::dvec3& wi) { return bound.eval(wi); };
        const std::vector<glm::dvec3> bins = phys_fiber::model_bins(c, eval);
        for (int ch = 0; ch < (blond ? 3 : 1); ++ch)
            row.err[blond] += phys_fiber::compare(c, bins, ch, blond ? ch + 1 : 0).l1 / (blond ? 3 : 1);
        if (!blond) {
            hs::LobeControls<double> only_r;
            only_r.gain[1] = only_r.gain[2] = only_r.gain[3] = 0;
            const hs::HuangMaterial<double> rmat(p, q, only_r);
            row.r_model = hs::HuangFiber<double>(rmat).albedo(c.c.wo()).x;
        }
    }
    return row;
}

int report(const std::string& cache, const std::string& quadrature, int threads) {
    const std::vector<CachedCase> cases = phys_fiber::read_cache(cache);
    std::vector<Row> rows(cases.size());
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            for (std::size_t k = std::size_t(t); k < cases.size(); k += std::size_t(threads)) rows[k] = report_row(cases[k], quadrature);
        });
    for (auto& th : pool) th.join();
    std::printf("| b/a | ψ | β | θo | lossless | blond (RGB mean) | noise | R energy model / ref | albedo ref |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|\n");
    double worst = 0, mean = 0;
    for (std::size_t k = 0; k < cases.size(); ++k) {
        const CachedCase& c = cases[k];
        double albedo = 0;
        for (int l = 0; l < phys_fiber::kLobes; ++l) albedo += c.lobe_energy[l][0];
        worst = std::max({worst, rows[k].err[0], rows[k].err[1]});
        mean += (rows[k].err[0] + rows[k].err[1]) / (2.0 * double(cases.size()));
        std::printf("| %.2g | %g° | %.2g | %g° | %.1f %% | %.1f %% | %.1f %% | %.4f / %.4f | %.4f |\n", c.c.aspect, c.c.psi_deg,
                    c.c.roughness, c.c.theta_deg, 100 * rows[k].err[0], 100 * rows[k].err[1], 100 * c.noise_l1[0],
                    rows[k].r_model, c.lobe_energy[phys_fiber::kR][0], albedo);
    }
    std::printf("\nworst %.1f %%, mean %.2f %%\n", 100 * worst, 100 * mean);
    return 0;
}

// Lossless lobe energies, model against reference, per case: where the energy goes.
int lobes(const std::string& cache) {
    const std::vector<CachedCase> cases = phys_fiber::read_cache(cache);
    std::printf("| case | R model/ref | TT model/ref | TRT model/ref | ≥ TRRT (residual) model/ref |\n|---|---|---|---|---|\n");
    for (const CachedCase& c : cases) {
        std::printf("| %s |", c.c.name().c_str());
        for (int p = 0; p < 4; ++p) {
            hs::LobeControls<double> only;
            for (int k = 0; k < 4; ++k) only.gain[k] = k == p ? 1 : 0;
            const hs::HuangMaterial<double> mat(phys_fiber::huang_params(c.c, false), hs::HuangQuadrature(), only);
            const double e = hs::HuangFiber<double>(mat).albedo(c.c.wo()).x;
            std::printf(" %.4f / %.4f |", e, c.lobe_energy[p][0]);
        }
        std::printf("\n");
    }
    return 0;
}

// Per-lobe contributions to the relative L1 (of the total energy) for a few cases, traced
// afresh with the lobes kept apart: where the error comes from.
int diagnose(long long rays, int threads, bool blond_only) {
    const std::vector<phys_fiber::Case> all = phys_fiber::physical_cases();
    std::printf("| case | ch | R | TT | TRT | residual vs ≥TRRT | total | R energy m/r | TT m/r | TRT m/r | res m/r |\n");
    for (const phys_fiber::Case& c : all) {
        const phys_fiber::Tracer tracer(c.fiber());
        phys_fiber::Histogram h(24, 48);
        std::vector<phys_fiber::Histogram> parts(std::size_t(threads), phys_fiber::Histogram(24, 48));
        std::vector<std::thread> pool;
        for (int t = 0; t < threads; ++t)
            pool.emplace_back([&, t] { tracer.trace(c.wo(), rays / threads, 77 + std::uint64_t(t), parts[std::size_t(t)]); });
        for (auto& th : pool) th.join();
        for (const auto& p : parts) h.add(p);
        const CachedCase cc = grid_of(c, 24, 48);
        for (int blond = blond_only ? 1 : 0; blond < 2; ++blond) {
            const int ch = blond ? 2 : 0;
            double l1[5] = {}, total_ref = 0, em[4] = {}, er[4] = {};
            std::vector<double> sum_model(std::size_t(24 * 48), 0.0);
            const double dw = h.bin_solid_angle();
            for (int p = 0; p < 4; ++p) {
                hs::LobeControls<double> only;
                for (int k = 0; k < 4; ++k) only.gain[k] = k == p ? 1 : 0;
                const hs::HuangMaterial<double> mat(phys_fiber::huang_params(c, blond != 0), hs::HuangQuadrature(), only);
                const hs::HuangFiber<double> fiber(mat);
                const auto eval = [&](const glm::dvec3& wo, const glm::dvec3& wi) { return fiber.eval(wo, wi); };
                const std::vector<glm::dvec3> m = phys_fiber::model_bins(cc, eval);
                for (int b = 0; b < 24 * 48; ++b) {
                    const double r = h.f(b, ch, p), x = m[std::size_t(b)][blond ? 1 : 0];
                    l1[p] += std::fabs(x - r) * dw;
                    em[p] += x * dw;
                    er[p] += r * dw;
                    sum_model[std::size_t(b)] += x;
                }
            }
            for (int b = 0; b < 24 * 48; ++b) {
                l1[4] += std::fabs(sum_model[std::size_t(b)] - h.f(b, ch)) * dw;
                total_ref += h.f(b, ch) * dw;
            }
            std::printf("| %s | %d |", c.name().c_str(), ch);
            for (double x : l1) std::printf(" %.1f %% |", 100 * x / total_ref);
            for (int p = 0; p < 4; ++p) std::printf(" %.4f/%.4f |", em[p], er[p]);
            std::printf("\n");
            std::fflush(stdout);
        }
    }
    return 0;
}

// Per case, lossless and blond (RGB mean): how much each lobe contributes to the relative
// L1 of f, traced afresh with the classes apart (R, TT, TRT, ≥ TRRT against the model's
// residual): Σ_bins |f_p,model − f_p,ref| dω over the reference's total energy, so that the
// lobes' shares add up to at least the total. TT and TRT once more at a fine quadrature
// (`fine`: 512 paths × 4 internal normals, 128 offset nodes): what is left there is the
// model's definition, the difference is its lattices' error.
int breakdown(long long rays, int threads) {
    const int nu = 24, nphi = 48;
    const std::vector<phys_fiber::Case> all = phys_fiber::physical_cases();
    struct Result {
        double total[2] = {}, lobe[2][4] = {}, fine[2][2] = {}, noise[2] = {};
    };
    std::vector<Result> results(all.size());
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            for (std::size_t k = std::size_t(t); k < all.size(); k += std::size_t(threads)) {
                const phys_fiber::Case& c = all[k];
                const phys_fiber::Tracer tracer(c.fiber());
                phys_fiber::Histogram half[2] = {phys_fiber::Histogram(nu, nphi), phys_fiber::Histogram(nu, nphi)};
                for (int s = 0; s < 2; ++s) tracer.trace(c.wo(), rays / 2, 4242 + 2 * k + std::uint64_t(s), half[s]);
                phys_fiber::Histogram h(nu, nphi);
                h.add(half[0]);
                h.add(half[1]);
                const CachedCase cc = grid_of(c, nu, nphi);
                const double dw = h.bin_solid_angle();
                Result& res = results[k];
                for (int blond = 0; blond < 2; ++blond) {
                    const hs::HuangParams<double> p = phys_fiber::huang_params(c, blond != 0);
                    const int channels = blond ? 3 : 1;
                    // model[q][lobe][bin]: q 0 default, 1 fine (TT, TRT only)
                    std::vector<glm::dvec3> model[2][4];
                    for (int q = 0; q < 2; ++q)
                        for (int l = 0; l < 4; ++l)
                            if (q == 0 || l == 1 || l == 2)
                                model[q][l] = lobe_bins(cc, p, q ? hs::HuangQuadrature{128, 512, 4} : hs::HuangQuadrature(), l);
                    for (int ch = 0; ch < channels; ++ch) {
                        const int rch = blond ? ch + 1 : 0, mch = blond ? ch : 0;
                        double ref_total = 0, l1 = 0, diff = 0;
                        double lobe[4] = {}, fine[2] = {};
                        for (int b = 0; b < nu * nphi; ++b) {
                            ref_total += h.f(b, rch) * dw;
                            diff += std::fabs(half[0].f(b, rch) - half[1].f(b, rch)) * dw;
                            double sum = 0;
                            for (int l = 0; l < 4; ++l) {
                                const double x = model[0][l][std::size_t(b)][mch];
                                sum += x;
                                lobe[l] += std::fabs(x - h.f(b, rch, l)) * dw;
                            }
                            for (int l = 1; l < 3; ++l)
                                fine[l - 1] += std::fabs(model[1][l][std::size_t(b)][mch] - h.f(b, rch, l)) * dw;
                            l1 += std::fabs(sum - h.f(b, rch)) * dw;
                        }
                        res.total[blond] += l1 / ref_total / channels;
                        res.noise[blond] += 0.5 * diff / ref_total / channels;
                        for (int l = 0; l < 4; ++l) res.lobe[blond][l] += lobe[l] / ref_total / channels;
                        for (int l = 0; l < 2; ++l) res.fine[blond][l] += fine[l] / ref_total / channels;
                    }
                }
                std::fprintf(stderr, "%s done\n", c.name().c_str());
            }
        });
    for (auto& th : pool) th.join();
    std::printf("| case | fiber | total | R | TT | TRT | residual vs ≥ TRRT | TT fine | TRT fine | noise |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
    double mean[10] = {};
    for (std::size_t k = 0; k < all.size(); ++k)
        for (int blond = 0; blond < 2; ++blond) {
            const Result& r = results[k];
            const double row[8] = {r.total[blond],   r.lobe[blond][0], r.lobe[blond][1], r.lobe[blond][2],
                                   r.lobe[blond][3], r.fine[blond][0], r.fine[blond][1], r.noise[blond]};
            std::printf("| %s | %s |", all[k].name().c_str(), blond ? "blond" : "lossless");
            for (int j = 0; j < 8; ++j) {
                std::printf(" %.1f %% |", 100 * row[j]);
                mean[j] += row[j] / double(2 * all.size());
            }
            std::printf("\n");
        }
    std::printf("| mean | |");
    for (int j = 0; j < 8; ++j) std::printf(" %.1f %% |", 100 * mean[j]);
    std::printf("\n");
    return 0;
}

// The reference's histogram of case c, traced afresh with the classes apart.
phys_fiber::Histogram traced(const phys_fiber::Case& c, long long rays, int threads, int nu, int nphi) {
    const phys_fiber::Tracer tracer(c.fiber());
    std::vector<phys_fiber::Histogram> parts(std::size_t(threads), phys_fiber::Histogram(nu, nphi));
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] { tracer.trace(c.wo(), rays / threads, 77 + std::uint64_t(t), parts[std::size_t(t)]); });
    for (auto& th : pool) th.join();
    phys_fiber::Histogram h(nu, nphi);
    for (const auto& q : parts) h.add(q);
    return h;
}

// The residual's longitudinal shape against the reference's orders ≥ TRRT, traced afresh
// with the classes apart: per case and channel (lossless, blond G), the model's residual
// energy times M(v; θi | θo)/2π for several variances v (4β, the model's before its chain profile, and a wider 8β; the sum over
// orders of a variance that grows per interface, β²(1/2 + 3/2 (2 + r̄/(1 − r̄))) with r̄ the
// mean internal reflectance, two refractions at β²/4 and each internal reflection at
// 3β²/2 as the TT and TRT lobes' β²/2 and 2β²; and k β²), the relative L1 of that lobe
// against the ≥ TRRT class and of the whole f, both over the reference's total energy, and
// "floor": the reference's own θ profile spread uniformly in φ (the best any
// azimuth-uniform residual with the right energy can do).
int residual_shapes(long long rays, int threads) {
    const int nu = 24, nphi = 48;
    const double kinds[] = {-4, 0, 2, 4, 6, -8};  // -k: k β; 0: the per-order sum; k: k β²
    constexpr int kKinds = 6;
    double total_sum[kKinds] = {}, total_worst[kKinds] = {}, lobe_sum[kKinds] = {}, floor_sum = 0;
    int rows = 0;
    std::printf("| case | ch | floor | 4β: residual / total | per-order | 2β² | 4β² | 6β² | 8β |\n|---|---|---|---|---|---|---|---|---|\n");
    for (const phys_fiber::Case& c : phys_fiber::physical_cases()) {
        const phys_fiber::Histogram h = traced(c, rays, threads, nu, nphi);
        const CachedCase cc = grid_of(c, nu, nphi);
        const double dw = h.bin_solid_angle();
        const glm::dvec3 wo = c.wo();
        const double so = wo.x, co = std::sqrt(1 - so * so);
        for (int blond = 0; blond < 2; ++blond) {
            const int ch = blond ? 2 : 0, mch = blond ? 1 : 0;
            const hs::HuangParams<double> p = phys_fiber::huang_params(c, blond != 0);
            hs::LobeControls<double> no_res, only_res;
            no_res.gain[3] = 0;
            only_res.gain[0] = only_res.gain[1] = only_res.gain[2] = 0;
            const hs::HuangMaterial<double> m0(p, no_res), m1(p, only_res);
            const hs::HuangFiber<double> f0(m0), f1(m1);
            const std::vector<glm::dvec3> others =
                phys_fiber::model_bins(cc, [&](const glm::dvec3& a, const glm::dvec3& b) { return f0.eval(a, b); });
            const double e_res = f1.albedo(wo)[mch];
            double r_bar = 0;
            for (int k = 0; k <= 64; ++k) r_bar += m0.total_reflectance_inside(k / 64.0) / 65;
            double total_ref = 0, floor = 0;
            for (int b = 0; b < nu * nphi; ++b) total_ref += h.f(b, ch) * dw;
            for (int iu = 0; iu < nu; ++iu) {
                double row = 0;
                for (int ip = 0; ip < nphi; ++ip) row += h.f(iu * nphi + ip, ch, phys_fiber::kHigher) / nphi;
                for (int ip = 0; ip < nphi; ++ip) floor += std::fabs(row - h.f(iu * nphi + ip, ch, phys_fiber::kHigher)) * dw;
            }
            floor_sum += floor / total_ref;
            std::printf("| %s | %s | %.1f %% |", c.name().c_str(), blond ? "blond G" : "lossless", 100 * floor / total_ref);
            for (int k = 0; k < kKinds; ++k) {
                const double beta = p.roughness;
                const double v = kinds[k] < 0 ? -kinds[k] * beta
                                 : kinds[k] == 0 ? beta * beta * (0.5 + 1.5 * (2 + r_bar / (1 - r_bar)))
                                                 : kinds[k] * beta * beta;
                const hs::DeonLongitudinal<double> lobe(v);
                double e_lobe = 0, e_total = 0;
                for (int iu = 0; iu < nu; ++iu) {
                    // M averaged over the bin's row: 64 midpoints in θ.
                    const double t0 = std::asin(std::max(-1.0, -1 + 2.0 * iu / nu));
                    const double t1 = std::asin(std::min(1.0, -1 + 2.0 * (iu + 1) / nu));
                    double m = 0;
                    for (int j = 0; j < 64; ++j) {
                        const double th = t0 + (t1 - t0) * (j + 0.5) / 64;
                        m += lobe.eval(std::sin(th), std::cos(th), so, co) * std::cos(th) * (t1 - t0) / 64;
                    }
                    const double f = e_res * m / (2.0 / nu) / (2 * phys_fiber::kPi);
                    for (int ip = 0; ip < nphi; ++ip) {
                        const int b = iu * nphi + ip;
                        e_lobe += std::fabs(f - h.f(b, ch, phys_fiber::kHigher)) * dw;
                        e_total += std::fabs(f + others[std::size_t(b)][mch] - h.f(b, ch)) * dw;
                    }
                }
                lobe_sum[k] += e_lobe / total_ref;
                total_sum[k] += e_total / total_ref;
                total_worst[k] = std::max(total_worst[k], e_total / total_ref);
                std::printf(" %.1f / %.1f %% |", 100 * e_lobe / total_ref, 100 * e_total / total_ref);
            }
            std::printf("\n");
            std::fflush(stdout);
            ++rows;
        }
    }
    std::printf("\nfloor mean %.1f %%\n", 100 * floor_sum / rows);
    const char* names[kKinds] = {"4β", "per-order", "2β²", "4β²", "6β²", "8β"};
    for (int k = 0; k < kKinds; ++k)
        std::printf("%s: residual lobe mean %.1f %%, total mean %.1f %%, worst %.1f %%\n", names[k], 100 * lobe_sum[k] / rows,
                    100 * total_sum[k] / rows, 100 * total_worst[k]);
    return 0;
}


// The residual's θ profile from a walk of the light that stays inside (measured against the
// physical fiber and not kept: docs/models.md, "Tried and not kept"). The interior light of
// a round fiber is a Markov chain over (u, h): u the axial component of its direction, h its
// chord's offset, which a smooth round section conserves. At each interface the model's own
// microfacet events (an 8 × 8 rule over D_v at the tilted mesonormal) reflect it into another
// state or let it out, at sin θi = the refracted direction's axial component. TRT's two
// internal events come first (their reflected part only), then the chain runs until 1e-6 of
// the light is left. The variants differ in the start and in what masked light does:
//   a  the light starts at u = −sin θo/η, offsets h/η' uniform (η' Bravais' index); a
//      reflection behind the mesonormal is mirrored about it; exits are not masked;
//   b  a, but a reflection behind the mesonormal meets a second visible normal, and an exit
//      is masked by its G1, the masked part going on as that facet's reflection;
//   c  b, the beam entering through the entry's visible normals at 32 offsets;
//   d  c, a masked exit staying in its state (as if reflected by the mesonormal);
//   e  c, a masked exit meeting the surface again from outside (the two-event rule): back
//      in through a second normal with 1 − F, out by its reflection with F;
//   f  c with the reference's own interface (Heitz et al. 2016's random walk on the
//      microsurface, 256 walks per state): what the chain gives with the physical boundary.
constexpr int kWalkBins = 72;  // exits in sin θi; a multiple of the reference's 24 rows
// The chain's states: u bins × h bins, and variant f's walks per state.
struct WalkGrid {
    int u = 72, h = 16, walks = 256;
};

// A visible normal of ggx seen from v about the mesonormal m (both unit, v·m > 0).
glm::dvec3 visible_normal(const hs::Ggx<double>& ggx, const glm::dvec3& v, const glm::dvec3& m, double u1, double u2) {
    const double c = glm::dot(v, m);
    const glm::dvec3 e1 = glm::normalize(v - c * m), e2 = glm::cross(m, e1);
    const glm::dvec3 h = ggx.sample_visible_local(glm::dvec3(glm::dot(v, e1), glm::dot(v, e2), c), u1, u2);
    return h.x * e1 + h.y * e2 + h.z * m;
}
// The direction refracted from v (pointing back where the light came from) through the
// facet h, n = η_t / η_i; only where the light is not totally reflected.
glm::dvec3 refracted(const glm::dvec3& v, const glm::dvec3& h, double n) {
    const double c = glm::dot(v, h), k = 1 - (1 - c * c) / (n * n);
    return glm::normalize(-v / n + (c / n - std::sqrt(std::max(0.0, k))) * h);
}

std::vector<double> walk_profile(const hs::HuangParams<double>& p, double sin_o, char variant, const WalkGrid& grid = WalkGrid()) {
    const int nu = grid.u, nh = grid.h, nq = 8, ns = nu * nh, nx = kWalkBins;
    const double eta = p.eta;
    const hs::Ggx<double> ggx(p.roughness);
    const glm::dvec3 m_out(std::sin(p.alpha), std::cos(p.alpha), 0.0), m_in = -m_out;  // the surface normal is +y
    const auto bin = [&](double x) { return std::min(nu - 1, std::max(0, int((x + 1) * 0.5 * nu))); };
    const auto xbin = [&](double x) { return std::min(nx - 1, std::max(0, int((x + 1) * 0.5 * nx))); };
    const auto state = [&](const glm::dvec3& x) {
        const double inplane = std::sqrt(x.y * x.y + x.z * x.z);
        return bin(x.x) * nh + std::min(nh - 1, int((inplane > 0 ? std::fabs(x.z) / inplane : 0.0) * nh));
    };
    const auto mirrored = [&](const glm::dvec3& x) { return x - std::min(0.0, 2 * glm::dot(x, m_in)) * m_in; };
    struct Step {
        int to;
        double w;
    };
    std::vector<std::vector<Step>> reflect{std::size_t(ns)};
    std::vector<double> leave(std::size_t(ns * nx), 0.0);
    phys_fiber::Fiber fiber;
    fiber.eta = eta;
    fiber.roughness = p.roughness;
    fiber.tilt = p.alpha;
    phys_fiber::Rng rng(12345);
    const int kWalks = grid.walks;
    for (int s = 0; s < ns; ++s) {
        const double u = -1 + (s / nh + 0.5) * 2.0 / nu, hh = (s % nh + 0.5) / nh, r_u = std::sqrt(1 - u * u);
        const glm::dvec3 d(u, r_u * std::sqrt(1 - hh * hh), r_u * hh), v = -d;  // d travels to the surface
        if (!(glm::dot(v, m_in) > 1e-6)) continue;
        if (variant == 'f') {
            for (int k = 0; k < kWalks; ++k) {
                const auto e = phys_fiber::boundary_event(d, glm::dvec3(0, 1, 0), true, fiber, rng);
                if (!e) continue;
                if (e->transmitted) leave[std::size_t(s * nx + xbin(e->dir.x))] += 1.0 / kWalks;
                else reflect[std::size_t(s)].push_back({state(e->dir), 1.0 / kWalks});
            }
            continue;
        }
        for (int a = 0; a < nq; ++a)
            for (int b = 0; b < nq; ++b) {
                const double u1 = (a + 0.5) / nq, u2 = (b + 0.5) / nq, w = 1.0 / (nq * nq);
                const double u1b = std::fmod(u1 + 0.5, 1.0), u2b = std::fmod(u2 + 0.5, 1.0);  // a second normal
                const glm::dvec3 h = visible_normal(ggx, v, m_in, u1, u2);
                const double vh = glm::dot(v, h), f = hs::fresnel_any(vh, 1 / eta);
                const glm::dvec3 r = 2 * vh * h - v;
                if (variant != 'a' && glm::dot(r, m_in) < 0) {
                    const glm::dvec3 v2 = -r, h2 = visible_normal(ggx, v2, m_in, u1b, u2b);
                    const double f2 = hs::fresnel_any(glm::dot(v2, h2), 1 / eta);
                    reflect[std::size_t(s)].push_back({state(mirrored(2 * glm::dot(v2, h2) * h2 - v2)), w * f * f2});
                    if (f2 < 1) leave[std::size_t(s * nx + xbin(refracted(v2, h2, 1 / eta).x))] += w * f * (1 - f2);
                } else {
                    reflect[std::size_t(s)].push_back({state(mirrored(r)), w * f});
                }
                if (!(f < 1)) continue;
                const glm::dvec3 t = refracted(v, h, 1 / eta);
                const double g = variant == 'a' ? 1.0 : ggx.g1(glm::dot(t, m_out)), masked = w * (1 - f) * (1 - g);
                leave[std::size_t(s * nx + xbin(t.x))] += w * (1 - f) * g;
                if (!(masked > 0)) continue;
                const glm::dvec3 v2 = -t;
                if (variant == 'e' && glm::dot(v2, m_out) > 1e-6) {
                    const glm::dvec3 h2 = visible_normal(ggx, v2, m_out, u1b, u2b);
                    const double f2 = hs::fresnel_any(glm::dot(v2, h2), eta);
                    reflect[std::size_t(s)].push_back({state(mirrored(refracted(v2, h2, eta))), masked * (1 - f2)});
                    leave[std::size_t(s * nx + xbin((2 * glm::dot(v2, h2) * h2 - v2).x))] += masked * f2;
                } else {
                    const glm::dvec3 back = variant == 'b' || variant == 'c' ? mirrored(r) : d - 2 * glm::dot(d, m_in) * m_in;
                    reflect[std::size_t(s)].push_back({state(back), masked});
                }
            }
    }
    // The light inside after the entry.
    std::vector<double> q(std::size_t(ns), 0.0), out(std::size_t(nx), 0.0);
    const double cos_o = std::sqrt(1 - sin_o * sin_o), eta_p = std::sqrt(eta * eta - sin_o * sin_o) / cos_o;
    for (int k = 0; k < 32; ++k) {
        const double hh = (k + 0.5) / 32;
        if (variant == 'a' || variant == 'b') {
            q[std::size_t(state(glm::dvec3(-sin_o / eta, std::sqrt(1 - hh * hh / (eta_p * eta_p)), hh / eta_p)))] += 1.0 / 32;
            continue;
        }
        const glm::dvec3 v(sin_o, cos_o * std::sqrt(1 - hh * hh), -cos_o * hh);
        if (!(glm::dot(v, m_out) > 1e-6)) continue;
        if (variant == 'f') {
            for (int k = 0; k < kWalks; ++k) {
                const auto e = phys_fiber::boundary_event(-v, glm::dvec3(0, 1, 0), false, fiber, rng);
                if (e && e->transmitted) q[std::size_t(state(e->dir))] += 1.0 / (32.0 * kWalks);
            }
            continue;
        }
        for (int a = 0; a < nq; ++a)
            for (int b = 0; b < nq; ++b) {
                const glm::dvec3 h = visible_normal(ggx, v, m_out, (a + 0.5) / nq, (b + 0.5) / nq);
                const glm::dvec3 t = refracted(v, h, eta);
                if (glm::dot(t, m_out) < 0) q[std::size_t(state(t))] += (1 - hs::fresnel_any(glm::dot(v, h), eta)) / (32.0 * nq * nq);
            }
    }
    const auto step = [&](bool leaving) {
        std::vector<double> next(std::size_t(ns), 0.0);
        for (int s = 0; s < ns; ++s) {
            const double x = q[std::size_t(s)];
            if (x == 0) continue;
            for (const Step& st : reflect[std::size_t(s)]) next[std::size_t(st.to)] += x * st.w;
            if (leaving)
                for (int j = 0; j < nx; ++j) out[std::size_t(j)] += x * leave[std::size_t(s * nx + j)];
        }
        q = next;
        double left = 0;
        for (double x : q) left += x;
        return left;
    };
    step(false);  // TT's exit and TRT's: what they reflect
    step(false);
    for (int it = 0; it < 20000 && step(true) > 1e-6; ++it) {
    }
    double sum = 0;
    for (double x : out) sum += x;
    for (double& x : out) x = sum > 0 ? x / sum / (2.0 / nx) : 0.0;
    return out;
}

// Per case (cached reference), lossless and blond: the default's relative L1 with its residual
// M(4β) and with the residual's energy in walk_profile's θ shape instead (uniform in φ).
int walk(const std::string& cache, int threads, char variant, const WalkGrid& grid) {
    const std::vector<CachedCase> cases = phys_fiber::read_cache(cache);
    std::vector<std::array<double, 4>> rows(cases.size());
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            for (std::size_t k = std::size_t(t); k < cases.size(); k += std::size_t(threads)) {
                const CachedCase& c = cases[k];
                for (int blond = 0; blond < 2; ++blond) {
                    const hs::HuangParams<double> p = phys_fiber::huang_params(c.c, blond != 0);
                    hs::LobeControls<double> no_res, only_res;
                    no_res.gain[3] = 0;
                    only_res.gain[0] = only_res.gain[1] = only_res.gain[2] = 0;
                    const hs::HuangMaterial<double> m0(p, hs::HuangQuadrature(), no_res), m1(p, hs::HuangQuadrature(), only_res);
                    const hs::HuangFiber<double> f0(m0), f1(m1);
                    const auto b0 = f0.at(c.c.wo()), b1 = f1.at(c.c.wo());
                    std::vector<glm::dvec3> with_walk =
                        phys_fiber::model_bins(c, [&](const glm::dvec3&, const glm::dvec3& wi) { return b0.eval(wi); });
                    std::vector<glm::dvec3> with_m = with_walk;
                    const std::vector<glm::dvec3> res =
                        phys_fiber::model_bins(c, [&](const glm::dvec3&, const glm::dvec3& wi) { return b1.eval(wi); });
                    for (std::size_t b = 0; b < res.size(); ++b) with_m[b] += res[b];
                    const glm::dvec3 e_res = f1.albedo(c.c.wo());
                    const std::vector<double> prof = walk_profile(p, c.c.wo().x, variant, grid);
                    const int per = kWalkBins / c.n_u;
                    for (int iu = 0; iu < c.n_u; ++iu) {
                        double d = 0;
                        for (int j = 0; j < per; ++j) d += prof[std::size_t(iu * per + j)] / per;
                        for (int ip = 0; ip < c.n_phi; ++ip) with_walk[std::size_t(iu * c.n_phi + ip)] += e_res * d / (2 * phys_fiber::kPi);
                    }
                    for (int ch = 0; ch < (blond ? 3 : 1); ++ch) {
                        rows[k][std::size_t(2 * blond)] += phys_fiber::compare(c, with_m, ch, blond ? ch + 1 : 0).l1 / (blond ? 3 : 1);
                        rows[k][std::size_t(2 * blond + 1)] += phys_fiber::compare(c, with_walk, ch, blond ? ch + 1 : 0).l1 / (blond ? 3 : 1);
                    }
                }
            }
        });
    for (auto& th : pool) th.join();
    std::printf("| case | lossless: M(4β) → walk | blond: M(4β) → walk |\n|---|---|---|\n");
    double worst[2] = {}, mean[2] = {};
    for (std::size_t k = 0; k < cases.size(); ++k) {
        std::printf("| %s | %.1f → %.1f %% | %.1f → %.1f %% |\n", cases[k].c.name().c_str(), 100 * rows[k][0], 100 * rows[k][1],
                    100 * rows[k][2], 100 * rows[k][3]);
        for (int q = 0; q < 2; ++q)
            for (int b = 0; b < 2; ++b) {
                worst[q] = std::max(worst[q], rows[k][std::size_t(2 * b + q)]);
                mean[q] += rows[k][std::size_t(2 * b + q)] / double(2 * cases.size());
            }
    }
    std::printf("\nvariant %c, %d × %d states, %d walks: M(4β) worst %.1f %%, mean %.1f %%; walk worst %.1f %%, mean %.1f %%\n", variant, grid.u, grid.h,
                grid.walks, 100 * worst[0], 100 * mean[0], 100 * worst[1], 100 * mean[1]);
    return 0;
}

// One case (index `which` into physical_cases), lossless, traced afresh: the reference's
// orders ≥ TRRT averaged over φ per row of sin θi (as a density per unit sin θi) beside
// walk_profile's, and R's energy and L1 per row, model against reference, with R's φ
// profile in the two rows nearest θi = −90° (every other bin).
int walk_shape(long long rays, int threads, int which, char variant) {
    const int nu = 24, nphi = 48;
    const phys_fiber::Case c = phys_fiber::physical_cases().at(std::size_t(which));
    const phys_fiber::Histogram h = traced(c, rays, threads, nu, nphi);
    const hs::HuangParams<double> p = phys_fiber::huang_params(c, false);
    const std::vector<double> prof = walk_profile(p, c.wo().x, variant);
    const double dw = h.bin_solid_angle();
    double e = 0;
    std::vector<double> row(std::size_t(nu), 0.0);
    for (int iu = 0; iu < nu; ++iu) {
        for (int ip = 0; ip < nphi; ++ip) row[std::size_t(iu)] += h.f(iu * nphi + ip, 0, phys_fiber::kHigher) * dw;
        e += row[std::size_t(iu)];
    }
    std::printf("%s, variant %c: orders >= TRRT, energy %.4f\n| sin θi | reference | walk |\n|---|---|---|\n", c.name().c_str(), variant, e);
    const int per = kWalkBins / nu;
    for (int iu = 0; iu < nu; ++iu) {
        double d = 0;
        for (int j = 0; j < per; ++j) d += prof[std::size_t(iu * per + j)] / per;
        std::printf("| %+.3f | %.4f | %.4f |\n", -1 + (iu + 0.5) * 2.0 / nu, row[std::size_t(iu)] / e / (2.0 / nu), d);
    }
    hs::LobeControls<double> only_r;
    only_r.gain[1] = only_r.gain[2] = only_r.gain[3] = 0;
    const hs::HuangMaterial<double> mat(p, hs::HuangQuadrature(), only_r);
    const hs::HuangFiber<double> fiber(mat);
    const auto bound = fiber.at(c.wo());
    const std::vector<glm::dvec3> m =
        phys_fiber::model_bins(grid_of(c, nu, nphi), [&](const glm::dvec3&, const glm::dvec3& wi) { return bound.eval(wi); });
    std::printf("\nR per row of sin θi: energy model / reference, L1\n");
    double l1 = 0, er = 0;
    for (int iu = 0; iu < nu; ++iu) {
        double a = 0, b = 0, d = 0;
        for (int ip = 0; ip < nphi; ++ip) {
            const int k = iu * nphi + ip;
            a += m[std::size_t(k)].x * dw;
            b += h.f(k, 0, phys_fiber::kR) * dw;
            d += std::fabs(m[std::size_t(k)].x - h.f(k, 0, phys_fiber::kR)) * dw;
        }
        l1 += d;
        er += b;
        if (a > 1e-3 || b > 1e-3) std::printf("row %d: %.4f / %.4f, L1 %.4f\n", iu, a, b, d);
    }
    std::printf("R: L1 %.4f, energy %.4f (reference)\n", l1, er);
    for (int iu = 0; iu < 2; ++iu) {
        std::printf("row %d, f model/reference by φ:", iu);
        for (int ip = 0; ip < nphi; ip += 2)
            std::printf(" %.2f/%.2f", m[std::size_t(iu * nphi + ip)].x, h.f(iu * nphi + ip, 0, phys_fiber::kR));
        std::printf("\n");
    }
    return 0;
}

// One case (index `which` into physical_cases), traced afresh with the classes apart: per
// lobe (R, TT, TRT, the residual against orders ≥ TRRT), lossless and blond (RGB mean), its
// energy model / reference, its L1 over the reference's total energy at the default
// quadrature and at eight times the paths (`x8`: the lattices' part), the L1 of its
// marginals in sin θi and in φ alone (θ shape or azimuth), and where it lies: each lobe's
// L1 over 4 bands of sin θi × 8 sectors of φ measured from wo's azimuth (0 backward, ±180°
// forward).
int decompose(long long rays, int threads, int which) {
    const int nu = 24, nphi = 48, nb = 4, ns = 8;
    const phys_fiber::Case c = phys_fiber::physical_cases().at(std::size_t(which));
    const phys_fiber::Histogram h = traced(c, rays, threads, nu, nphi);
    const CachedCase cc = grid_of(c, nu, nphi);
    const double dw = h.bin_solid_angle();
    const char* names[4] = {"R", "TT", "TRT", "res/≥TRRT"};
    std::printf("%s, %lld rays\n", c.name().c_str(), rays);
    // The reference's orders ≥ TRRT over φ − φo (lossless), as 2π × its density in φ (1 for
    // the model's uniform residual), from φ − φo = −180° in steps of 360°/48.
    {
        std::vector<double> col(std::size_t(nphi), 0.0);
        double e = 0;
        for (int b = 0; b < nu * nphi; ++b) {
            const int rel = (b % nphi - 3 * nphi / 4 + nphi + nphi / 2) % nphi;
            col[std::size_t(rel)] += h.f(b, 0, phys_fiber::kHigher) * dw;
            e += h.f(b, 0, phys_fiber::kHigher) * dw;
        }
        std::printf("orders >= TRRT, lossless, 2π × density over φ − φo from −180°:");
        for (double x : col) std::printf(" %.2f", x / e * nphi);
        std::printf("\n");
    }
    for (int blond = 0; blond < 2; ++blond) {
        const hs::HuangParams<double> p = phys_fiber::huang_params(c, blond != 0);
        const int channels = blond ? 3 : 1;
        std::vector<glm::dvec3> model[2][4];
        for (int q = 0; q < 2; ++q)
            for (int l = 0; l < 4; ++l)
                model[q][l] = lobe_bins(cc, p, q ? hs::huang_scaled_quadrature(p.roughness, 8, 2) : hs::HuangQuadrature(), l);
        double total = 0, total_x8 = 0, e_model[4] = {}, e_ref[4] = {}, l1[2][4] = {}, mu[4] = {}, mphi[4] = {};
        std::vector<double> where(std::size_t(5 * nb * ns), 0.0);  // [lobe or total][band][sector]
        for (int ch = 0; ch < channels; ++ch) {
            const int rch = blond ? ch + 1 : 0, mch = blond ? ch : 0;
            double ref_total = 0;
            for (int b = 0; b < nu * nphi; ++b) ref_total += h.f(b, rch) * dw;
            const double k = 1.0 / (ref_total * channels);
            for (int l = 0; l < 4; ++l) {
                std::vector<double> ru(std::size_t(nu), 0.0), rp(std::size_t(nphi), 0.0);
                for (int b = 0; b < nu * nphi; ++b) {
                    const double r = h.f(b, rch, l), x = model[0][l][std::size_t(b)][mch];
                    e_model[l] += x * dw / channels;
                    e_ref[l] += r * dw / channels;
                    l1[0][l] += std::fabs(x - r) * dw * k;
                    l1[1][l] += std::fabs(model[1][l][std::size_t(b)][mch] - r) * dw * k;
                    ru[std::size_t(b / nphi)] += (x - r) * dw;
                    rp[std::size_t(b % nphi)] += (x - r) * dw;
                    const int iu = b / nphi, ip = b % nphi;
                    // φ from wo's azimuth (+90° in the histogram's frame), in [−180°, 180°)
                    const int rel = (ip - 3 * nphi / 4 + nphi) % nphi;  // 0 at wo's azimuth
                    const int sector = ((rel + nphi / (2 * ns)) % nphi) * ns / nphi;
                    where[std::size_t((l * nb + iu * nb / nu) * ns + sector)] += std::fabs(x - r) * dw * k;
                }
                for (double v : ru) mu[l] += std::fabs(v) * k;
                for (double v : rp) mphi[l] += std::fabs(v) * k;
            }
            for (int b = 0; b < nu * nphi; ++b) {
                double sum = 0, sum8 = 0;
                for (int l = 0; l < 4; ++l) {
                    sum += model[0][l][std::size_t(b)][mch];
                    sum8 += model[1][l][std::size_t(b)][mch];
                }
                const int iu = b / nphi, ip = b % nphi;
                const int rel = (ip - 3 * nphi / 4 + nphi) % nphi;
                const int sector = ((rel + nphi / (2 * ns)) % nphi) * ns / nphi;
                total += std::fabs(sum - h.f(b, rch)) * dw * k;
                total_x8 += std::fabs(sum8 - h.f(b, rch)) * dw * k;
                where[std::size_t((4 * nb + iu * nb / nu) * ns + sector)] += std::fabs(sum - h.f(b, rch)) * dw * k;
            }
        }
        std::printf("\n%s: total %.1f %% (x8 %.1f %%)\n| lobe | energy model / ref | L1 | L1 x8 | L1 of θ marginal | L1 of φ marginal |\n|---|---|---|---|---|---|\n",
                    blond ? "blond" : "lossless", 100 * total, 100 * total_x8);
        for (int l = 0; l < 4; ++l)
            std::printf("| %s | %.4f / %.4f | %.1f %% | %.1f %% | %.1f %% | %.1f %% |\n", names[l], e_model[l], e_ref[l], 100 * l1[0][l],
                        100 * l1[1][l], 100 * mu[l], 100 * mphi[l]);
        for (int l = 0; l < 5; ++l) {
            std::printf("%s L1 (%%) by sin θi band (rows, −1 → 1) × φ − φo sector (0°, 45°, …, ±180°, …, −45°):\n", l < 4 ? names[l] : "total");
            for (int bnd = 0; bnd < nb; ++bnd) {
                std::printf("  ");
                for (int s = 0; s < ns; ++s) std::printf(" %5.2f", 100 * where[std::size_t((l * nb + bnd) * ns + s)]);
                std::printf("\n");
            }
        }
    }
    return 0;
}

// The residual's azimuth (huang_residual::AzimuthTrace) against the reference's orders
// ≥ TRRT over φ − φo (lossless; 48 bins), per case: the L1 of the shapes, uniform and
// traced with `walks` rays (its Fourier series up to `harmonics` if > 0, every sine kept:
// the material keeps only cosines where a mirror keeps wo), and the trace's time.
int azimuth(long long rays, int threads, int walks, int harmonics) {
    const int nu = 24, nphi = 48;
    double sum[2] = {}, worst[2] = {};
    int n = 0;
    for (const phys_fiber::Case& c : phys_fiber::physical_cases()) {
        const phys_fiber::Histogram h = traced(c, rays, threads, nu, nphi);
        std::vector<double> ref(std::size_t(nphi), 0.0);
        double e = 0;
        for (int b = 0; b < nu * nphi; ++b) {
            const int rel = (b % nphi - 3 * nphi / 4 + nphi + nphi / 2) % nphi;
            ref[std::size_t(rel)] += h.f(b, 0, phys_fiber::kHigher);
            e += h.f(b, 0, phys_fiber::kHigher);
        }
        const hs::HuangParams<double> p = phys_fiber::huang_params(c, false);
        const glm::dvec3 v = hs::EllipticalSection<double>(p.aspect_ratio, p.orientation).to_section(c.wo());
        const auto t0 = std::chrono::steady_clock::now();
        const hs::huang_residual::AzimuthTrace trace(p.eta, p.roughness, p.alpha, p.aspect_ratio);
        std::vector<double> prof = trace.profile(v.x, std::atan2(v.z, v.y), nphi, walks, 1234);
        if (harmonics > 0) {  // the density's Fourier series up to `harmonics`, as a probe
            std::vector<double> sm(std::size_t(nphi), 1.0 / nphi);
            for (int k = 1; k <= harmonics; ++k) {
                double ck = 0, sk = 0;
                for (int j = 0; j < nphi; ++j) {
                    const double phi = -phys_fiber::kPi + (j + 0.5) * 2 * phys_fiber::kPi / nphi;
                    ck += prof[std::size_t(j)] * std::cos(k * phi);
                    sk += prof[std::size_t(j)] * std::sin(k * phi);
                }
                for (int j = 0; j < nphi; ++j) {
                    const double phi = -phys_fiber::kPi + (j + 0.5) * 2 * phys_fiber::kPi / nphi;
                    sm[std::size_t(j)] += 2.0 / nphi * (ck * std::cos(k * phi) + sk * std::sin(k * phi));
                }
            }
            prof = sm;
        }
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        double l1[2] = {};
        for (int j = 0; j < nphi; ++j) {
            l1[0] += std::fabs(ref[std::size_t(j)] / e - 1.0 / nphi);
            l1[1] += std::fabs(ref[std::size_t(j)] / e - prof[std::size_t(j)]);
        }
        std::printf("%s: L1 uniform %.3f, traced %.3f (%.3f s)\n  ref:", c.name().c_str(), l1[0], l1[1], s);
        for (int j = 0; j < nphi; j += 2) std::printf(" %.2f", ref[std::size_t(j)] / e * nphi);
        std::printf("\n  tr: ");
        for (int j = 0; j < nphi; j += 2) std::printf(" %.2f", prof[std::size_t(j)] * nphi);
        std::printf("\n");
        std::fflush(stdout);
        for (int k = 0; k < 2; ++k) {
            sum[k] += l1[k];
            worst[k] = std::max(worst[k], l1[k]);
        }
        ++n;
    }
    std::printf("mean L1 uniform %.3f, traced %.3f; worst %.3f, %.3f\n", sum[0] / n, sum[1] / n, worst[0], worst[1]);
    return 0;
}

int generate(long long rays, int threads, const std::string& out, int n_u, int n_phi) {
    std::vector<CachedCase> cases;
    const auto t0 = std::chrono::steady_clock::now();
    std::uint64_t seed = 1;
    for (const phys_fiber::Case& c : phys_fiber::physical_cases()) {
        cases.push_back(phys_fiber::trace_case(c, rays, n_u, n_phi, threads, seed++));
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::fprintf(stderr, "%s: noise %.2f %% (lossless), %.0f s\n", c.name().c_str(), 100 * cases.back().noise_l1[0], s);
    }
    char comment[160];
    std::snprintf(comment, sizeof(comment), "%lld rays per case, %d x %d bins", rays, n_u, n_phi);
    phys_fiber::write_cache(out, cases, comment);
    return 0;
}

// The lattices' error alone, model against model (no trace): per case, lossless, TT and TRT
// at the default quadrature against 128 offset nodes and 1024 paths × 2 internal normals
// (the lattice's limit), Σ_bins |f_p − f_p,fine| dω (the lossless albedo is 1).
int lattice(int threads) {
    const std::vector<phys_fiber::Case> all = phys_fiber::physical_cases();
    std::vector<std::array<double, 2>> err(all.size());
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            for (std::size_t k = std::size_t(t); k < all.size(); k += std::size_t(threads)) {
                const CachedCase cc = grid_of(all[k], 24, 48);
                const hs::HuangParams<double> p = phys_fiber::huang_params(all[k], false);
                const double dw = (2.0 / cc.n_u) * (2 * phys_fiber::kPi / cc.n_phi);
                for (int l = 1; l < 3; ++l) {
                    hs::LobeControls<double> only;
                    for (int j = 0; j < 4; ++j) only.gain[j] = j == l ? 1 : 0;
                    std::vector<glm::dvec3> bins[2];
                    for (int q = 0; q < 2; ++q) {
                        const hs::HuangMaterial<double> mat(p, q ? hs::HuangQuadrature{128, 1024, 2} : hs::HuangQuadrature(), only);
                        const hs::HuangFiber<double, 4096> fiber(mat);
                        const auto bound = fiber.at(all[k].wo());
                        bins[q] = phys_fiber::model_bins(cc, [&](const glm::dvec3&, const glm::dvec3& wi) { return bound.eval(wi); });
                    }
                    double d = 0;
                    for (std::size_t b = 0; b < bins[0].size(); ++b) d += std::fabs(bins[0][b].x - bins[1][b].x) * dw;
                    err[k][std::size_t(l - 1)] = d;
                }
            }
        });
    for (auto& th : pool) th.join();
    std::printf("| case | TT | TRT |\n|---|---|---|\n");
    double mean[2] = {}, worst[2] = {};
    for (std::size_t k = 0; k < all.size(); ++k) {
        std::printf("| %s | %.1f %% | %.1f %% |\n", all[k].name().c_str(), 100 * err[k][0], 100 * err[k][1]);
        for (int l = 0; l < 2; ++l) {
            mean[l] += err[k][std::size_t(l)] / double(all.size());
            worst[l] = std::max(worst[l], err[k][std::size_t(l)]);
        }
    }
    std::printf("| mean | %.1f %% | %.1f %% |\n| worst | %.1f %% | %.1f %% |\n", 100 * mean[0], 100 * mean[1], 100 * worst[0],
                100 * worst[1]);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        if (argc < 2) throw std::invalid_argument("usage: physical_fiber_tool generate|report [options]");
        const std::string mode = argv[1];
        long long rays = 20000000;
        int threads = 2, n_u = 24, n_phi = 48, which = 0, harmonics = 0;
        char variant = 'c';
        WalkGrid grid;
        std::string out = "physical_fiber.txt", cache = out, quadrature = "default";
        for (int i = 2; i + 1 < argc; i += 2) {
            const std::string k = argv[i], v = argv[i + 1];
            if (k == "--rays") rays = std::atoll(v.c_str());
            else if (k == "--threads") threads = std::atoi(v.c_str());
            else if (k == "--out") out = v;
            else if (k == "--cache") cache = v;
            else if (k == "--quadrature") quadrature = v;
            else if (k == "--bins-u") n_u = std::atoi(v.c_str());
            else if (k == "--bins-phi") n_phi = std::atoi(v.c_str());
            else if (k == "--variant") variant = v.empty() ? 'a' : v[0];
            else if (k == "--case") which = std::atoi(v.c_str());
            else if (k == "--walk-u") grid.u = std::atoi(v.c_str());
            else if (k == "--walk-h") grid.h = std::atoi(v.c_str());
            else if (k == "--walks") grid.walks = std::atoi(v.c_str());
            else if (k == "--harmonics") harmonics = std::atoi(v.c_str());
            else throw std::invalid_argument("unknown option " + k);
        }
        if (mode == "generate") return generate(rays, threads, out, n_u, n_phi);
        if (mode == "report") return report(cache, quadrature, threads);
        if (mode == "lobes") return lobes(cache);
        if (mode == "diagnose") return diagnose(rays, threads, quadrature == "blond");
        if (mode == "residual") return residual_shapes(rays, threads);
        if (mode == "breakdown") return breakdown(rays, threads);
        if (mode == "lattice") return lattice(threads);
        if (mode == "walk") return walk(cache, threads, variant, grid);
        if (mode == "walk-shape") return walk_shape(rays, threads, which, variant);
        if (mode == "decompose") return decompose(rays, threads, which);
        if (mode == "azimuth") return azimuth(rays, threads, grid.walks, harmonics);
        throw std::invalid_argument("unknown mode " + mode);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "physical_fiber_tool: %s\n", e.what());
        return 1;
    }
}
