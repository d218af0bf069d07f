// Dual scattering (both formulations) against path tracing on slabs of explicit parallel
// fibers (tests/support/fiber_slab.hpp), swept over hair colour, slab depth and view: the
// table behind docs/theory.md §5.6. Prints Markdown. Usage: dual_slab_sweep [paths]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>

#include <hairscatter/dual.hpp>

#include "support/fiber_slab.hpp"

namespace hs = hairscatter;
using glm::dvec3;
using glm::dvec4;

namespace {

struct Sums {
    double path = 0, improved = 0, zinke = 0, path_sq = 0;
    int hits = 0;
};

double mean(const dvec3& v) { return (v.x + v.y + v.z) / 3; }

Sums run(const hs::FiberParams<double>& params, double tau, const dvec3& wl, const dvec3& wo, int paths) {
    using Dual = hs::DualScatteringBcsdf<hs::ChiangFiber<double>>;
    const hs::ChiangMaterial<double> mat(params);
    hs::DualTableOptions<double> oz;
    oz.settings = hs::DualScatteringSettings<double>::zinke2008();
    const auto improved = hs::DualScatteringTables<double>::build<hs::ChiangFiber<double>>(mat);
    const auto zinke = hs::DualScatteringTables<double>::build<hs::ChiangFiber<double>>(mat, oz);
    const slab::FiberSlab s(400, 8 * tau, tau, 7);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> U;
    const dvec3 axis(1, 0, 0);
    const double per_length = s.crossings_per_length(), proj = std::sqrt(wl.y * wl.y + wl.z * wl.z);
    Sums r;
    for (int k = 0; k < paths; ++k) {
        const slab::Hit hit = s.intersect(dvec3(0, U(rng) * s.width(), wo.z > 0 ? s.depth() : 0.0), -wo);
        if (hit.fiber < 0) continue;
        ++r.hits;
        const hs::FiberFrame<double> f0(axis, wo);
        const hs::ChiangFiber<double> fiber0(mat, glm::dot(hit.p - hit.axis, f0.y));
        const bool blocked = s.intersect(hit.p, wl, hit.fiber).fiber >= 0;
        const double up = wl.z > 0 ? (s.depth() - hit.p.z) / wl.z : hit.p.z / -wl.z;
        const double down = wl.z > 0 ? hit.p.z / wl.z : (s.depth() - hit.p.z) / -wl.z;
        hs::DualScatteringLight<double> l;
        l.direct_fraction = blocked ? 0 : 1;
        l.n = blocked ? per_length * proj * up : 0;
        l.beyond = per_length * proj * down;
        r.improved += mean(Dual(fiber0, improved).eval(f0.to_local(wo), f0.to_local(wl), l));
        l.beyond = hs::kUnbounded<double>;
        r.zinke += mean(Dual(fiber0, zinke).eval(f0.to_local(wo), f0.to_local(wl), l));

        double L = 0;
        dvec3 beta(1), w = wo;
        slab::Hit cur = hit;
        for (int depth = 0;; ++depth) {
            const hs::FiberFrame<double> fr(axis, w);
            const hs::ChiangFiber<double> fiber(mat, glm::dot(cur.p - cur.axis, fr.y));
            const dvec3 wo_l = fr.to_local(w);
            if (s.intersect(cur.p, wl, cur.fiber).fiber < 0) L += mean(beta * fiber.eval(wo_l, fr.to_local(wl)));
            const auto smp = fiber.sample(wo_l, dvec4(U(rng), U(rng), U(rng), U(rng)));
            if (!(smp.pdf > 0)) break;
            beta *= smp.weight;
            const dvec3 d = glm::normalize(fr.to_world(smp.wi));
            const slab::Hit next = s.intersect(cur.p, d, cur.fiber);
            if (next.fiber < 0) break;
            w = -d;
            cur = next;
            if (depth >= 3) {  // Russian roulette only: no depth cut
                const double q = std::min(0.95, std::max({beta.x, beta.y, beta.z}));
                if (U(rng) >= q) break;
                beta /= q;
            }
        }
        r.path += L;
        r.path_sq += L * L;
    }
    return r;
}

}  // namespace

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
    std::printf("| hair | fibers deep | view | path (mean ± 2σ) | improved / path | Zinke 2008 / path |\n");
    std::printf("|---|---|---|---|---|---|\n");
    for (const auto& h : hairs)
        for (double tau : {3.0, 10.0, 40.0})
            for (const auto& v : views) {
                hs::FiberParams<double> p;
                p.sigma_a = h.eumelanin < 0 ? dvec3(0) : hs::sigma_a_from_melanin(h.eumelanin, 0.0);
                const Sums s = run(p, tau, wl, v.wo, paths);
                const double m = s.path / s.hits, sd = std::sqrt(std::max(0.0, s.path_sq / s.hits - m * m) / s.hits);
                if (m < 1e-4 || 2 * sd > 0.2 * m) {
                    std::printf("| %s | %.0f | %s | %.5f ± %.5f | (too little light) | |\n", h.name, tau, v.name, m, 2 * sd);
                    continue;
                }
                std::printf("| %s | %.0f | %s | %.4f ± %.4f | %.3f | %.3f |\n", h.name, tau, v.name, m, 2 * sd,
                            s.improved / s.path, s.zinke / s.path);
                std::fflush(stdout);
            }
    return 0;
}
