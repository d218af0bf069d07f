// Dual scattering (the two-stream estimator with exact and Poisson counts, and the BCSDF in
// both formulations) against path tracing on slabs of explicit parallel fibers
// (tests/support/fiber_slab.hpp), swept over hair colour, slab depth and view: the table
// behind docs/theory.md §5.6. Prints Markdown. Usage: dual_slab_sweep [paths]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>

#include <hairscatter/dual.hpp>

#include "support/fiber_slab.hpp"

namespace hs = hairscatter;
using glm::dvec3;

int main(int argc, char** argv) {
    const int paths = argc > 1 ? std::atoi(argv[1]) : 20000;
    const struct {
        const char* name;
        double eumelanin;
    } hairs[] = {{"white", -1}, {"blond", 0.3}, {"brown", 1.3}, {"dark", 8}};
    const dvec3 wl = glm::normalize(dvec3(0.3, 0.35, 0.9));
    const struct {
        const char* name;
        dvec3 wo;
    } views[] = {{"from the light's side", glm::normalize(dvec3(-0.1, -0.2, 0.95))},
                 {"grazing", glm::normalize(dvec3(0.2, 0.5, 0.7))},
                 {"through the slab", glm::normalize(dvec3(-0.2, -0.3, -0.9))}};
    std::printf("| hair | fibers deep | view | path (mean ± 2σ) | two-stream / path | two-stream, Poisson counts / path "
                "| improved / path | Zinke 2008 / path |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    for (const auto& h : hairs)
        for (double tau : {3.0, 10.0, 40.0})
            for (const auto& v : views) {
                hs::FiberParams<double> p;
                p.sigma_a = h.eumelanin < 0 ? dvec3(0) : hs::sigma_a_from_concentrations(h.eumelanin, 0.0);
                const slab::Sums s = slab::compare_dual(p, tau, wl, v.wo, paths);
                slab::Lighting light;
                light.wl = wl;
                const slab::TwoStreamSums t = slab::compare_two_stream(p, tau, light, v.wo, paths);
                const double m = t.path_mean(), sd = t.path_noise() / 2;
                if (m < 1e-4 || 2 * sd > 0.2 * m) {
                    std::printf("| %s | %.0f | %s | %.5f ± %.5f | (too little light) | | | |\n", h.name, tau, v.name, m, 2 * sd);
                    continue;
                }
                // Each comparison against its own path-traced estimate (same slab and rays).
                std::printf("| %s | %.0f | %s | %.4f ± %.4f | %.3f | %.3f | %.3f | %.3f |\n", h.name, tau, v.name, m, 2 * sd,
                            t.exact / t.path, t.expected / t.path, s.improved / s.path, s.zinke / s.path);
                std::fflush(stdout);
            }
    return 0;
}
