// HuangFiber against physics: the physical fiber reference (tests/support/physical_fiber.hpp,
// ray tracing of a rough dielectric cylinder of elliptical section, every order, its
// boundary a random walk on the Smith microsurface) and its cache, and the model's
// interface totals against the microsurface walk itself. The figures are
// docs/huang_physical.md's (scripts/physical-reference.sh).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>

#include <gtest/gtest.h>

#include <hairscatter/models/huang.hpp>

#include "support/physical_fiber_huang.hpp"

namespace hs = hairscatter;
namespace pf = phys_fiber;

namespace {

const std::vector<pf::CachedCase>& cache() {
    static const std::vector<pf::CachedCase> c = pf::read_cache(HAIRSCATTER_TEST_DATA_DIR "/physical_fiber.txt");
    return c;
}

}  // namespace

// The interface's total reflectance (the closed-form single scattering plus the model's own
// walk of the multiple scattering, docs/theory.md §3.6) against this file's microsurface
// random walk, which scatters until the light leaves: within 3 % (plus the walk's noise) at
// roughness 0.1 and 0.3 from both sides, where one event without shadowing (the model
// before) is off by up to 42 %. Measured: worst 1.3 % at β 0.1 and 2.3 % at β 0.3 (outside,
// c 0.4: the model's 8192 walks per cosine); the two-event rule before it, 4.6 % outside
// (β 0.3 near grazing) and 2.4 % inside.
TEST(HuangPhysical, InterfaceTotalsMatchTheMicrosurface) {
    for (double beta : {0.1, 0.3}) {
        hs::HuangParams<double> p;
        p.roughness = beta;
        const hs::HuangMaterial<double> mat(p, hs::HuangQuadrature{4, 1, 1});
        double worst_total = 0, worst_single = 0;
        for (const bool outside : {true, false}) {
            for (double c : {1.0, 0.8, 0.6, 0.4, 0.2, 0.1}) {
                const glm::dvec3 wi(std::sqrt(1 - c * c), 0, c);
                pf::Rng rng(7);
                const int n = 200000;
                int reflected = 0;
                for (int k = 0; k < n; ++k)
                    if (!pf::interact(wi, beta, outside ? 1.55 : 1 / 1.55, pf::Interface::kRandomWalk, rng).transmitted)
                        ++reflected;
                const double walk = double(reflected) / n, sigma = std::sqrt(walk * (1 - walk) / n);
                const double model = outside ? mat.total_reflectance_outside(c) : mat.total_reflectance_inside(c);
                const double one_event = outside ? mat.reflectance_outside(c) : mat.reflectance_inside(c);
                worst_total = std::max(worst_total, std::fabs(model - walk) / walk);
                worst_single = std::max(worst_single, std::fabs(one_event - walk) / walk);
                EXPECT_NEAR(model, walk, 0.03 * walk + 3 * sigma) << "β " << beta << (outside ? " outside" : " inside") << " c " << c;
            }
        }
        std::printf("[ physical ] β %.1f: interface total vs walk worst %.3f (one event unshadowed: %.3f)\n", beta,
                    worst_total, worst_single);
        EXPECT_GT(worst_single, 2 * worst_total);  // the negative control: shadowing matters
    }
    // Reported, not asserted: the two-event rule's limit at a rougher surface (docs/theory.md
    // §3.6 quotes it), outside at c = 0.1, 0.2 and 1.
    hs::HuangParams<double> p;
    p.roughness = 0.6;
    const hs::HuangMaterial<double> mat(p, hs::HuangQuadrature{4, 1, 1});
    for (double c : {0.1, 0.2, 1.0}) {
        const glm::dvec3 wi(std::sqrt(1 - c * c), 0, c);
        pf::Rng rng(9);
        const int n = 200000;
        int reflected = 0;
        for (int k = 0; k < n; ++k)
            if (!pf::interact(wi, 0.6, 1.55, pf::Interface::kRandomWalk, rng).transmitted) ++reflected;
        std::printf("[ physical ] β 0.6 outside c %.1f: interface total %.4f, walk %.4f (%+.0f %%)\n", c,
                    mat.total_reflectance_outside(c), double(reflected) / n,
                    100 * (mat.total_reflectance_outside(c) / (double(reflected) / n) - 1));
    }
}

// R alone: the light reflected without entering carries the energy the physical fiber's
// does, within 2 % (measured 0.0–1.0 %, with the interfaces' totals from the microsurface's
// walk; 0.1–3.2 % up to θo = 30° and 0.5–5.2 % at 75° with the two-event rule, whose totals
// ran a few per cent high near grazing at β 0.3; 0.1–5.5 % and 1.4–8.7 % with the beam
// weighted by v·m, which put more of it on the rims at grazing incidence); the unshadowed
// surface of the model before was 3–36 % too bright.
TEST(HuangPhysical, ReflectionEnergyMatchesTheFiber) {
    for (const pf::CachedCase& c : cache()) {
        hs::LobeControls<double> only_r;
        only_r.gain[1] = only_r.gain[2] = only_r.gain[3] = 0;
        const hs::HuangMaterial<double> mat(pf::huang_params(c.c, false), hs::HuangQuadrature(), only_r);
        const double model = hs::HuangFiber<double>(mat).albedo(c.c.wo()).x;
        const double ref = c.lobe_energy[pf::kR][0];
        EXPECT_NEAR(model, ref, 0.02 * ref) << c.c.name();
    }
}

// f against the physical fiber over the sphere (relative L1 of bin averages, 24 cases,
// lossless and blond, default quadrature): the figures of docs/huang_physical.md, printed.
// The goal is 5 %; the model is not there (measured worst 15.3 %, mean 7.73 %: the lattices'
// shape at the default and TRT's shape at b/a 0.5; docs/models.md has the per-lobe
// breakdown). The bounds guard what is reached: worst 15.5 %, mean 8 % (the
// model before this reference: 38 % and 19 %; before the unbiased internal reflection:
// 21.1 % and 13.2 %; with TT's paths uniform in γ rather than in h: 20.4 % and 12.8 %;
// without the exit kernel of the paths' entry cells: 19.4 % and 12.0 %; with the
// residual's θ profile d'Eon's M of variance 4β rather than the interior chain's: 19.2 %
// and 11.0 %; with the offsets weighted by the beam at the mesonormal, max(0, v·m),
// rather than uniform in h: 15.8 % and 9.03 %; with the interfaces' totals by the two-event
// rule rather than the microsurface's walk: 15.5 % and 8.21 %). Each case binds its wo once (at(wo), the
// same values as eval).
TEST(HuangPhysical, AgainstThePhysicalFiber) {
    const std::vector<pf::CachedCase>& cases = cache();
    std::vector<double> lossless(cases.size()), blond(cases.size());
    std::vector<std::thread> pool;
    for (int t = 0; t < 2; ++t)
        pool.emplace_back([&, t] {
            for (std::size_t k = std::size_t(t); k < cases.size(); k += 2) {
                for (int b = 0; b < 2; ++b) {
                    const hs::HuangMaterial<double> mat(pf::huang_params(cases[k].c, b == 1));
                    const hs::HuangFiber<double> fiber(mat);
                    const auto bound = fiber.at(cases[k].c.wo());
                    const std::vector<glm::dvec3> bins =
                        pf::model_bins(cases[k], [&](const glm::dvec3&, const glm::dvec3& wi) { return bound.eval(wi); });
                    double e = 0;
                    for (int ch = 0; ch < (b ? 3 : 1); ++ch) e += pf::compare(cases[k], bins, ch, b ? ch + 1 : 0).l1;
                    (b ? blond : lossless)[k] = b ? e / 3 : e;
                }
            }
        });
    for (auto& th : pool) th.join();
    double worst = 0, mean = 0;
    for (std::size_t k = 0; k < cases.size(); ++k) {
        std::printf("[ physical ] %-28s lossless %5.1f %%  blond %5.1f %%  (reference noise %.1f %%)\n",
                    cases[k].c.name().c_str(), 100 * lossless[k], 100 * blond[k], 100 * cases[k].noise_l1[0]);
        worst = std::max({worst, lossless[k], blond[k]});
        mean += (lossless[k] + blond[k]) / (2.0 * double(cases.size()));
    }
    std::printf("[ physical ] worst %.1f %%, mean %.1f %% (goal: 5 %%)\n", 100 * worst, 100 * mean);
    EXPECT_LT(worst, 0.155);
    EXPECT_LT(mean, 0.08);
}

// The shadowing terms over extreme inputs (NaN, infinities, cosines outside [0, 1], every
// roughness of the range): finite, in [0, 1] for G1 and the reflection's escape, ≥ 0 for Λ;
// and against the reference's own Λ where the cosine is valid.
TEST(HuangPhysical, ShadowingTermsAreFiniteEverywhere) {
    const double nan = std::nan(""), inf = HUGE_VAL;
    const double cosines[] = {nan, -inf, -1, -1e-30, 0, 1e-38, 1e-30, 1e-8, 0.3, 0.999999, 1, 1 + 1e-7, 2, inf};
    for (double alpha : {0.02, 0.3, 1.0}) {
        const hs::Ggx<double> g(alpha);
        const hs::Ggx<float> gf{float(alpha)};
        for (double c : cosines) {
            for (double g1v : {0.0, 0.5, 1.0}) {
                const double e = g.unshadowed_reflection(g1v, c);
                const float ef = gf.unshadowed_reflection(float(g1v), float(c));
                EXPECT_TRUE(std::isfinite(e) && e >= 0 && e <= 1) << alpha << " " << c;
                EXPECT_TRUE(std::isfinite(ef) && ef >= 0 && ef <= 1) << alpha << " " << c;
            }
            const double l = g.lambda(c), g1 = g.g1(c);
            const float lf = gf.lambda(float(c)), g1f = gf.g1(float(c));
            EXPECT_TRUE(std::isfinite(l) && l >= 0) << alpha << " " << c;
            EXPECT_TRUE(std::isfinite(lf) && lf >= 0) << alpha << " " << c;
            EXPECT_TRUE(std::isfinite(g1) && g1 >= 0 && g1 <= 1 + 1e-12) << alpha << " " << c;
            EXPECT_TRUE(std::isfinite(g1f) && g1f >= 0 && g1f <= 1 + 1e-6f) << alpha << " " << c;
            if (c > 1e-6 && c <= 1) {
                const glm::dvec3 w(std::sqrt(1 - c * c), 0, c);
                EXPECT_NEAR(l, pf::lambda(w, alpha), 1e-9 * (1 + l));
                EXPECT_NEAR(g1, 1 / (1 + l), 1e-12);
            }
        }
    }
}
