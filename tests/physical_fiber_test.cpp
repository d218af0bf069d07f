// The physical fiber reference (tests/support/physical_fiber.hpp) against what is known
// independently of it: the microsurface walk's single scattering against the microfacet
// BSDF integrated by quadrature, a smooth round fiber against Fresnel optics in closed
// form, energy, symmetry, and the cached figures (tests/data/physical_fiber.txt) against a
// fresh trace, so that the cache cannot drift from the code.
#include <cmath>
#include <cstdio>

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <gtest/gtest.h>

#include "support/physical_fiber_cases.hpp"

namespace pf = phys_fiber;

namespace {

// GGX's distribution of normals (Walter et al. 2007 eq. 33), for the quadrature.
double ggx_d(double cos_m, double alpha) {
    if (cos_m <= 0) return 0;
    const double c2 = cos_m * cos_m, t2 = (1 - c2) / c2;
    const double a2 = alpha * alpha;
    return a2 / (pf::kPi * c2 * c2 * (a2 + t2) * (a2 + t2));
}

// ∫ F(i·h) D(h) G2(i, o) / (4 cos θi) dωo over the upper hemisphere, with the
// height-correlated G2 = 1 / (1 + Λ(i) + Λ(o)): the single-scattering reflection of the
// Smith microsurface (Heitz 2014 §5; Heitz et al. 2016 §4 show the walk's first order is it).
double single_reflection(const glm::dvec3& wi, double alpha, double eta) {
    using GK = boost::math::quadrature::gauss_kronrod<double, 31>;
    const auto inner = [&](double theta) {
        return GK::integrate(
            [&](double phi) {
                const glm::dvec3 o(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
                const glm::dvec3 h = glm::normalize(wi + o);
                const double g2 = 1 / (1 + pf::lambda(wi, alpha) + pf::lambda(o, alpha));
                return pf::fresnel(glm::dot(wi, h), eta) * ggx_d(h.z, alpha) * g2 / (4 * wi.z) * std::sin(theta);
            },
            -pf::kPi, pf::kPi, 15, 1e-10);
    };
    return GK::integrate(inner, 0.0, 0.5 * pf::kPi, 15, 1e-9);
}

}  // namespace

TEST(PhysicalFiber, WalkSingleScatteringIsTheMicrofacetBsdf) {
    for (double alpha : {0.2, 0.5}) {
        for (double theta_deg : {0.0, 45.0, 75.0}) {
            const double t = theta_deg * pf::kPi / 180;
            const glm::dvec3 wi(std::sin(t), 0, std::cos(t));
            pf::Rng rng(11);
            const int n = 400000;
            int single_reflections = 0, reflected = 0;
            for (int k = 0; k < n; ++k) {
                const pf::Scatter s = pf::interact(wi, alpha, 1.55, pf::Interface::kRandomWalk, rng);
                ASSERT_TRUE(std::isfinite(s.dir.x) && std::isfinite(s.dir.z));
                ASSERT_GE(s.events, 1);
                // Directions leave on the side the walk says.
                ASSERT_EQ(s.transmitted, s.dir.z < 0);
                if (!s.transmitted) ++reflected;
                if (!s.transmitted && s.events == 1) ++single_reflections;
            }
            const double mc = double(single_reflections) / n;
            const double quad = single_reflection(wi, alpha, 1.55);
            const double sigma = std::sqrt(quad * (1 - quad) / n);
            std::printf("α %.1f θ %2.0f°: single reflection walk %.5f quadrature %.5f (σ %.5f); all orders %.5f\n", alpha,
                        theta_deg, mc, quad, sigma, double(reflected) / n);
            EXPECT_NEAR(mc, quad, 4 * sigma + 2e-4);
        }
    }
}

TEST(PhysicalFiber, SmoothRoundFiberIsFresnelOptics) {
    // A nearly smooth round fiber seen at θo: R = ½∫ F(cos θ cos γ) dh; at θo = 0,
    // TT = ½∫ (1 − F)² exp(−2 σa cos γt) dh (the exit sees the entry's angle).
    for (double theta_deg : {0.0, 40.0}) {
        pf::Fiber f;
        f.roughness = 1e-4;
        f.tilt = 0;
        f.sigma_a = glm::dvec3(0.5);
        const pf::Tracer tracer(f);
        pf::Histogram h(8, 8);
        const double t = theta_deg * pf::kPi / 180;
        tracer.trace(glm::dvec3(std::sin(t), 0, std::cos(t)), 1000000, 3, h);
        boost::math::quadrature::gauss<double, 30> g;
        const auto r_int = [&](double gamma) { return 0.5 * pf::fresnel(std::cos(t) * std::cos(gamma), 1.55) * std::cos(gamma); };
        const double r = g.integrate(r_int, -0.5 * pf::kPi, 0.0) + g.integrate(r_int, 0.0, 0.5 * pf::kPi);
        const double r_mc = h.lobe_energy[pf::kR][0] / h.rays;
        std::printf("θ %2.0f°: R trace %.5f closed form %.5f\n", theta_deg, r_mc, r);
        EXPECT_NEAR(r_mc, r, 4 * std::sqrt(r * (1 - r) / h.rays));
        if (theta_deg == 0) {
            const auto tt_int = [&](double gamma) {
                const double fr = pf::fresnel(std::cos(gamma), 1.55);
                const double st = std::sin(gamma) / 1.55;
                return 0.5 * (1 - fr) * (1 - fr) * std::exp(-2 * 0.5 * std::sqrt(1 - st * st)) * std::cos(gamma);
            };
            const double tt = g.integrate(tt_int, -0.5 * pf::kPi, 0.0) + g.integrate(tt_int, 0.0, 0.5 * pf::kPi);
            const double tt_mc = h.lobe_energy[pf::kTT][1] / h.rays;
            std::printf("θ  0°: TT trace %.5f closed form %.5f\n", tt_mc, tt);
            EXPECT_NEAR(tt_mc, tt, 4 * std::sqrt(tt * (1 - tt) / h.rays));
        }
    }
}

TEST(PhysicalFiber, LosslessKeepsEnergyAndSmithLosesIt) {
    for (const double aspect : {1.0, 0.5}) {
        pf::Fiber f;
        f.aspect = aspect;
        f.orientation = 0.7;
        f.roughness = 0.4;
        const pf::Tracer tracer(f);
        pf::Histogram h(8, 8);
        tracer.trace(glm::dvec3(0.5, 0.3, std::sqrt(1 - 0.34)), 200000, 5, h);
        double out = 0;
        for (int l = 0; l < pf::kLobes; ++l) out += h.lobe_energy[l][0];
        // Rays stopped after max_events bounces (trapped by total internal reflection).
        EXPECT_LT(h.lost[0] / h.rays, 2e-4);
        EXPECT_NEAR(out / h.rays, 1.0, 2e-4);
        EXPECT_EQ(h.absorbed[0], 0.0);
        // Blond: out + absorbed + lost is what went in.
        double blond = 0;
        for (int l = 0; l < pf::kLobes; ++l) blond += h.lobe_energy[l][1];
        EXPECT_NEAR((blond + h.absorbed[1] + h.lost[1]) / h.rays, 1.0, 1e-9);
        // Negative control: the single-event Smith boundary loses the masked light.
        f.interface = pf::Interface::kSmith;
        pf::Histogram s(8, 8);
        pf::Tracer(f).trace(glm::dvec3(0.5, 0.3, std::sqrt(1 - 0.34)), 100000, 5, s);
        EXPECT_GT(s.lost[0] / s.rays, 0.02);
    }
}

TEST(PhysicalFiber, RoundFiberIgnoresOrientation) {
    const glm::dvec3 wo(0.3, 0.0, std::sqrt(1 - 0.09));
    pf::Histogram a(6, 12), b(6, 12);
    pf::Fiber f;
    f.sigma_a = glm::dvec3(0.3);
    pf::Tracer(f).trace(wo, 400000, 1, a);
    f.orientation = 1.2;
    pf::Tracer(f).trace(wo, 400000, 2, b);
    double diff = 0, sum = 0;
    for (int k = 0; k < 72; ++k) {
        diff += std::fabs(a.f(k, 1) - b.f(k, 1));
        sum += a.f(k, 1);
    }
    EXPECT_LT(diff / sum, 0.02);  // the noise of 400,000 rays in 72 bins is about 0.6 %
}

TEST(PhysicalFiber, CacheIsWhatTheTracerComputes) {
    const std::vector<pf::CachedCase> cache = pf::read_cache(HAIRSCATTER_TEST_DATA_DIR "/physical_fiber.txt");
    EXPECT_EQ(cache.size(), pf::physical_cases().size());
    for (const std::size_t k : {std::size_t(1), std::size_t(16)}) {
        const pf::CachedCase& c = cache[k];
        const pf::CachedCase fresh = pf::trace_case(c.c, 1600000, c.n_u, c.n_phi, 2, 99 + k);
        for (int ch : {0, 2}) {
            double diff = 0, sum = 0;
            for (int b = 0; b < c.n_u * c.n_phi; ++b) {
                diff += std::fabs(fresh.at(b, ch) - c.at(b, ch));
                sum += c.at(b, ch);
            }
            // The fresh trace's noise dominates; a cache from other physics is far off.
            std::printf("%s channel %d: L1 %.4f, fresh noise %.4f\n", c.c.name().c_str(), ch, diff / sum, fresh.noise_l1[ch]);
            EXPECT_LT(diff / sum, 1.6 * fresh.noise_l1[ch] + 0.005);
        }
    }
}
