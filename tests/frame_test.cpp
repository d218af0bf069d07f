// The fiber frame (docs/theory.md §1) and the geometric meaning of h.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

namespace hs = hairscatter;

TEST(FiberFrame, OrthonormalRightHandedAndInvertible) {
    std::mt19937_64 rng(5);
    std::normal_distribution<double> g;
    for (int k = 0; k < 1000; ++k) {
        const glm::dvec3 t(g(rng), g(rng), g(rng)), r(g(rng), g(rng), g(rng));
        const hs::FiberFrame<double> f(t, r);
        EXPECT_NEAR(glm::length(f.x), 1, 1e-12);
        EXPECT_NEAR(glm::length(f.y), 1, 1e-12);
        EXPECT_NEAR(glm::dot(f.x, f.y), 0, 1e-12);
        EXPECT_NEAR(glm::length(glm::cross(f.x, f.y) - f.z), 0, 1e-12);  // z = x × y
        EXPECT_NEAR(glm::dot(f.x, glm::normalize(t)), 1, 1e-12);
        // The reference lies in the x–z plane with a positive z component.
        const glm::dvec3 rl = f.to_local(r);
        EXPECT_NEAR(rl.y, 0, 1e-9 * glm::length(r));
        EXPECT_GE(rl.z, 0);
        const glm::dvec3 w(g(rng), g(rng), g(rng));
        EXPECT_NEAR(glm::length(f.to_world(f.to_local(w)) - w), 0, 1e-12);
    }
}

TEST(FiberFrame, ReferenceAlongTangentStillGivesAFrame) {
    const hs::FiberFrame<float> f(glm::vec3(0, 0, 2), glm::vec3(0, 0, 1));
    EXPECT_NEAR(glm::length(f.y), 1, 1e-6);
    EXPECT_NEAR(glm::dot(f.x, f.y), 0, 1e-6);
    EXPECT_NEAR(glm::dot(f.x, f.z), 0, 1e-6);
}

// With the frame built from wo, a hit at offset h = dot(hit - axis, y)/r has the surface
// normal n = (0, h, sqrt(1 - h²)); the R lobe must peak at the mirror reflection of wo
// about n — which pins the sign convention of h and Φ(0, h) = -2γo.
TEST(FiberFrame, RLobePeaksAtGeometricMirrorDirection) {
    hs::FiberParams<double> p;
    p.alpha = 0;
    p.beta_m = 0.1;
    p.beta_n = 0.1;
    p.sigma_a = glm::dvec3(50.0);  // absorb everything but R
    const glm::dvec3 tangent(0.3, -0.2, 0.9), wo_world = glm::normalize(glm::dvec3(0.2, 0.9, -0.1));
    const hs::FiberFrame<double> frame(tangent, wo_world);
    const glm::dvec3 wo = frame.to_local(wo_world);
    for (double h : {-0.8, -0.3, 0.4, 0.7}) {
        const hs::ChiangMaterial<double> fiber_material(p);
        const hs::ChiangFiber<double> fiber(fiber_material, h);
        const glm::dvec3 n(0, h, std::sqrt(1 - h * h));
        // Mirror of wo in the plane perpendicular to the fiber: flip the azimuthal part about
        // n, and the longitudinal part: θi = -θo.
        const glm::dvec3 wo_perp(0, wo.y, wo.z);
        const glm::dvec3 refl_perp = 2 * glm::dot(wo_perp, n) * n - wo_perp;
        const double phi_expected = std::atan2(refl_perp.z, refl_perp.y);
        double best = -1, best_phi = 0;
        for (double phi = -M_PI; phi < M_PI; phi += 1e-3) {
            const double ct = std::sqrt(1 - wo.x * wo.x);
            const glm::dvec3 wi(-wo.x, ct * std::cos(phi), ct * std::sin(phi));
            const double f = fiber.eval(wo, wi).g;
            if (f > best) best = f, best_phi = phi;
        }
        EXPECT_NEAR(std::remainder(best_phi - phi_expected, 2 * M_PI), 0.0, 2e-3) << "h = " << h;
    }
}
