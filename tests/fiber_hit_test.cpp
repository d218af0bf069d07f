// FiberHit / fiber_offset: h of a ray's hit on a round fiber is the ray's impact parameter
// (its signed distance from the axis along the frame's y, over the radius), whatever the
// fiber's orientation, the ray's inclination and the axis point used; edge cases.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include <hairscatter/fiber/hit.hpp>

namespace {

namespace hs = hairscatter;
using glm::dvec3;

// The first intersection of o + t d (unit d) with the infinite cylinder of radius r around
// the line c + s a (unit a); false when the ray misses.
bool hit_cylinder(const dvec3& o, const dvec3& d, const dvec3& c, const dvec3& a, double r, dvec3& p) {
    const dvec3 oc = o - c;
    const dvec3 dp = d - glm::dot(d, a) * a, op = oc - glm::dot(oc, a) * a;
    const double A = glm::dot(dp, dp), B = 2 * glm::dot(dp, op), C = glm::dot(op, op) - r * r;
    const double disc = B * B - 4 * A * C;
    if (A < 1e-12 || disc < 0) return false;
    const double t = (-B - std::sqrt(disc)) / (2 * A);
    p = o + t * d;
    return t > 0;
}

dvec3 random_unit(std::mt19937_64& rng) {
    std::normal_distribution<double> n;
    return glm::normalize(dvec3(n(rng), n(rng), n(rng)));
}

// Across random fibers and rays: h from the hit point (with the axis point at the hit's own
// curve parameter, or slid along the axis) equals the impact parameter computed from the
// ray's origin, which lies at the same y as every point of the ray (d = -wo has no y part).
TEST(FiberHit, OffsetIsTheImpactParameter) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    int checked = 0;
    for (int k = 0; k < 2000; ++k) {
        const dvec3 a = random_unit(rng), c(u(rng), u(rng), u(rng));
        const double r = 0.05 + 0.5 * std::abs(u(rng));
        const dvec3 d = random_unit(rng);
        if (std::abs(glm::dot(d, a)) > 0.98) continue;  // nearly along the fiber
        // A ray aimed at a random offset b across the fiber.
        const double b = 0.999 * u(rng);
        const dvec3 side = glm::normalize(glm::cross(a, d));
        const dvec3 o = c + b * r * side - 10.0 * d + 0.3 * u(rng) * a;
        dvec3 p;
        ASSERT_TRUE(hit_cylinder(o, d, c, a, r, p)) << k;
        const dvec3 axis = c + glm::dot(p - c, a) * a;
        const hs::FiberHit<double> hit(p, axis, a, -d, r);
        const double impact = glm::dot(o - axis, hit.frame.y) / r;
        EXPECT_NEAR(hit.h, impact, 1e-9) << k;
        EXPECT_NEAR(std::abs(hit.h), std::abs(b), 1e-9) << k;
        // Any axis point will do: the tangent component is dropped.
        EXPECT_NEAR(hs::fiber_offset(hit.frame, p, axis + 0.7 * a, r), hit.h, 1e-9) << k;
        // wo in the frame lies in the x–z plane, unit, with x = sinθo along the tangent.
        EXPECT_NEAR(hit.wo.y, 0.0, 1e-12);
        EXPECT_NEAR(glm::length(hit.wo), 1.0, 1e-12);
        EXPECT_NEAR(hit.wo.x, glm::dot(-d, a), 1e-12);
        EXPECT_GT(hit.wo.z, 0.0);
        ++checked;
    }
    EXPECT_GT(checked, 1800);
}

// The library's sign: with wo = +z and the tangent +x, y = +y, so a hit above the axis has
// h > 0; seen from behind (wo = -z) the frame's y flips and with it h.
TEST(FiberHit, SignFollowsTheFrame) {
    const glm::vec3 axis(0), tangent(2, 0, 0), above(0.25f, 0.05f, 0.0866f);
    const hs::FiberHit<float> front(above, axis, tangent, glm::vec3(0, 0, 1), 0.1f);
    EXPECT_NEAR(front.h, 0.5f, 1e-6f);
    EXPECT_NEAR(front.frame.y.y, 1.0f, 1e-6f);
    const hs::FiberHit<float> back(above * glm::vec3(1, 1, -1), axis, tangent, glm::vec3(0, 0, -1), 0.1f);
    EXPECT_NEAR(back.h, -0.5f, 1e-6f);
}

TEST(FiberHit, EdgeCases) {
    const hs::FiberFrame<float> frame(glm::vec3(1, 0, 0), glm::vec3(0, 0, 1));
    const glm::vec3 axis(0);
    // A point a rounding error outside the tube is clamped to the rim.
    EXPECT_EQ(hs::fiber_offset(frame, glm::vec3(0, 0.1001f, 0), axis, 0.1f), 1.0f);
    EXPECT_EQ(hs::fiber_offset(frame, glm::vec3(0, -0.2f, 0), axis, 0.1f), -1.0f);
    // Degenerate radii and non-finite points give the centre, never NaN.
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    EXPECT_EQ(hs::fiber_offset(frame, glm::vec3(0, 0.05f, 0), axis, 0.0f), 0.0f);
    EXPECT_EQ(hs::fiber_offset(frame, glm::vec3(0, 0.05f, 0), axis, -0.1f), 0.0f);
    EXPECT_EQ(hs::fiber_offset(frame, glm::vec3(0, 0.05f, 0), axis, nan), 0.0f);
    EXPECT_EQ(hs::fiber_offset(frame, glm::vec3(0, nan, 0), axis, 0.1f), 0.0f);
    EXPECT_EQ(hs::fiber_offset(frame, glm::vec3(0, 0.05f, 0), axis, inf), 0.0f);
    // A wo along the fiber still gives a frame and a finite h.
    const hs::FiberHit<float> along(glm::vec3(0, 0.05f, 0), axis, glm::vec3(1, 0, 0), glm::vec3(1, 0, 0), 0.1f);
    EXPECT_TRUE(std::isfinite(along.h));
    EXPECT_NEAR(along.wo.x, 1.0f, 1e-6f);
}

}  // namespace
