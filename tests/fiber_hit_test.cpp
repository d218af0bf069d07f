// FiberHit / fiber_offset: h of a ray's hit on a round fiber is the ray's impact parameter
// (its signed distance from the axis along the frame's y, over the radius), whatever the
// fiber's orientation, the ray's inclination and the axis point used; edge cases.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include <hairscatter/fiber/hit.hpp>
#include <hairscatter/models/chiang.hpp>

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

// The convention end to end, against the geometry: a smooth fiber's R lobe must send the
// viewing ray where a mirror at the hit's surface normal sends it. A mirrored h (a frame
// built from a reference facing away, or a curve's v read the wrong way) puts the lobe at
// the mirror image of that direction, which this test sees; a furnace test cannot.
TEST(FiberHit, RLobePeaksWhereTheSurfaceMirrors) {
    hs::FiberParams<double> params;
    params.beta_m = params.beta_n = 0.05;
    params.alpha = 0;
    params.sigma_a = dvec3(0);
    const hs::ChiangMaterial<double> material(params);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    int checked = 0;
    for (int k = 0; k < 500; ++k) {
        const dvec3 a = random_unit(rng), c(u(rng), u(rng), u(rng)), d = random_unit(rng);
        if (std::abs(glm::dot(d, a)) > 0.8) continue;
        const double r = 0.1, b = 0.2 + 0.7 * std::abs(u(rng));  // |h| away from 0, where R is symmetric
        const dvec3 side = glm::normalize(glm::cross(a, d));
        const dvec3 o = c + (u(rng) < 0 ? -b : b) * r * side - 10.0 * d;
        dvec3 p;
        ASSERT_TRUE(hit_cylinder(o, d, c, a, r, p)) << k;
        const dvec3 axis = c + glm::dot(p - c, a) * a;
        const dvec3 n = glm::normalize(p - axis);
        const dvec3 mirror = d - 2 * glm::dot(d, n) * n;  // where the light must come from (reciprocity)
        const hs::FiberHit<double> hit(p, axis, a, -d, r);
        const auto right = hs::BasicChiangFiber<double, hs::LobeSet::kR>(material, hit.h).at(hit.wo);
        const auto mirrored = hs::BasicChiangFiber<double, hs::LobeSet::kR>(material, -hit.h).at(hit.wo);
        const dvec3 wi = hit.frame.to_local(mirror);
        const double f_right = right.eval(wi).x, f_mirrored = mirrored.eval(wi).x;
        EXPECT_GT(f_right, 20 * f_mirrored) << k << " h " << hit.h;
        // The lobe's own sample lands next to the mirror direction.
        const auto s = right.sample(glm::dvec4(0.5, 0.5, 0.5, 0.5));
        EXPECT_GT(glm::dot(hit.frame.to_world(s.wi), mirror), 0.95) << k;
        ++checked;
    }
    EXPECT_GT(checked, 300);
}

// A ribbon's normal facing away from the viewer mirrors h; FiberFrame::facing flips it.
TEST(FiberFrame, FacingFlipsABackFacingReference) {
    const dvec3 tangent(1, 0, 0), wo = glm::normalize(dvec3(0.2, 0.1, 1)), hit(0, 0.05, 0.0866), axis(0);
    const dvec3 normal(0, 0, 1);
    const hs::FiberFrame<double> front(tangent, normal), back(tangent, -normal);
    EXPECT_NEAR(hs::fiber_offset(front, hit, axis, 0.1), 0.5, 1e-12);
    EXPECT_NEAR(hs::fiber_offset(back, hit, axis, 0.1), -0.5, 1e-12);  // the trap
    const auto fixed = hs::FiberFrame<double>::facing(tangent, -normal, wo);
    EXPECT_NEAR(hs::fiber_offset(fixed, hit, axis, 0.1), 0.5, 1e-12);
    EXPECT_GT(fixed.to_local(wo).z, 0.0);
    EXPECT_EQ(hs::FiberFrame<double>::facing(tangent, normal, wo).y, front.y);
}

// h from a curve's v equals h from the hit point, whichever way v runs, as long as
// `across` says which way that is; a wrong `across` is exactly the mirror.
TEST(FiberHit, FromVMatchesTheHitPoint) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int k = 0; k < 1000; ++k) {
        const dvec3 a = random_unit(rng), c(u(rng), u(rng), u(rng)), d = random_unit(rng);
        if (std::abs(glm::dot(d, a)) > 0.98) continue;
        const double r = 0.3, b = 0.999 * u(rng);
        const dvec3 side = glm::normalize(glm::cross(a, d));
        const dvec3 o = c + b * r * side - 10.0 * d;
        dvec3 p;
        ASSERT_TRUE(hit_cylinder(o, d, c, a, r, p));
        const dvec3 axis = c + glm::dot(p - c, a) * a;
        const hs::FiberHit<double> geometric(p, axis, a, -d, r);
        // An intersector whose v grows along `side`, and one whose v grows the other way.
        const double v_side = 0.5 + 0.5 * glm::dot(p - axis, side) / r;
        const auto h1 = hs::FiberHit<double>::from_v(a, -d, v_side, side);
        const auto h2 = hs::FiberHit<double>::from_v(a, -d, 1 - v_side, -side);
        EXPECT_NEAR(h1.h, geometric.h, 1e-9) << k;
        EXPECT_NEAR(h2.h, geometric.h, 1e-9) << k;
        EXPECT_NEAR(hs::FiberHit<double>::from_v(a, -d, v_side, -side).h, -geometric.h, 1e-9) << k;
        EXPECT_EQ(h1.wo, geometric.wo);
    }
    const hs::FiberFrame<float> f(glm::vec3(1, 0, 0), glm::vec3(0, 0, 1));
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(hs::fiber_offset_from_v(f, nan, glm::vec3(0, 1, 0)), 0.0f);
    EXPECT_EQ(hs::fiber_offset_from_v(f, 2.0f, glm::vec3(0, 1, 0)), 1.0f);
    EXPECT_EQ(hs::fiber_offset_from_v(f, -1.0f, glm::vec3(0, 1, 0)), -1.0f);
    EXPECT_EQ(hs::fiber_offset_from_v(f, 0.75f, glm::vec3(0, 0, 1)), 0.0f);  // no component along y
    EXPECT_EQ(hs::fiber_offset_from_v(f, 0.75f, glm::vec3(nan)), 0.0f);
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
