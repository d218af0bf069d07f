// Tests of Scene::count_hair, the exact count of the strands a ray crosses: against
// hand-placed strands, against a brute-force count (ray segment to fibre axis distance
// below the radius), and in the mean against the density of a random slab. Also prints
// what counting costs next to hair_occluded and intersect.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "rng.hpp"
#include "scene.hpp"

namespace {

using namespace render;

// A grid of straight strands along x from x = -2 to 2 (8 segments each, joints every 0.5),
// at y = 0.5 j (j < 5) and z = 0.5 k (k < 4), radius 0.05; strand j * 4 + k.
constexpr float kGridRadius = 0.05f;
SceneDescription grid() {
    SceneDescription d;
    d.name = "grid";
    d.hair.radius = kGridRadius;
    for (int j = 0; j < 5; ++j)
        for (int k = 0; k < 4; ++k) {
            std::vector<glm::vec3> strand;
            for (int m = 0; m <= 8; ++m) strand.emplace_back(-2.0f + 0.5f * float(m), 0.5f * float(j), 0.5f * float(k));
            d.hair.strands.push_back(strand);
        }
    return d;
}
std::uint32_t grid_strand(int j, int k) { return std::uint32_t(j * 4 + k); }

// The smallest distance between the segments p0 p1 and q0 q1 (Ericson, Real-Time
// Collision Detection, 5.1.9), in double so that the reference is not float-limited.
double segment_distance(glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 q0, glm::dvec3 q1) {
    const glm::dvec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    const double a = glm::dot(d1, d1), e = glm::dot(d2, d2), f = glm::dot(d2, r);
    double s = 0, t = 0;
    if (a <= 1e-30 && e <= 1e-30) return glm::length(r);
    if (a <= 1e-30) {
        t = std::clamp(f / e, 0.0, 1.0);
    } else {
        const double c = glm::dot(d1, r);
        if (e <= 1e-30) {
            s = std::clamp(-c / a, 0.0, 1.0);
        } else {
            const double b = glm::dot(d1, d2), denom = a * e - b * b;
            s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
            t = (b * s + f) / e;
            if (t < 0) {
                t = 0;
                s = std::clamp(-c / a, 0.0, 1.0);
            } else if (t > 1) {
                t = 1;
                s = std::clamp((b - c) / a, 0.0, 1.0);
            }
        }
    }
    return glm::length((p0 + s * d1) - (q0 + t * d2));
}

// The strands whose fibre (capsules of radius scale × radius around the segments) the
// segment o + t d, t in [tmin, tmax], enters or leaves; -1 if one lies wholly inside the
// strand but not inside one capsule (it may leave and re-enter at a bend).
long brute_count(const Hair& hair, glm::vec3 o, glm::vec3 d, float tmin, float tmax, double scale) {
    const glm::dvec3 a = glm::dvec3(o) + double(tmin) * glm::dvec3(d), b = glm::dvec3(o) + double(tmax) * glm::dvec3(d);
    const double r = scale * double(hair.radius);
    long n = 0;
    for (const auto& strand : hair.strands) {
        bool near = false, a_in = false, b_in = false, within_one = false;
        for (std::size_t k = 1; k < strand.size(); ++k) {
            near = near || segment_distance(a, b, strand[k - 1], strand[k]) < r;
            const bool ak = segment_distance(a, a, strand[k - 1], strand[k]) < r;
            const bool bk = segment_distance(b, b, strand[k - 1], strand[k]) < r;
            a_in = a_in || ak;
            b_in = b_in || bk;
            within_one = within_one || (ak && bk);  // a capsule is convex: no surface crossed
        }
        if (within_one) continue;
        if (a_in && b_in) return -1;
        if (near) ++n;
    }
    return n;
}

// The brute-force count when it is unambiguous (the same with the radius 0.01 % smaller
// and larger), else -1: Embree's float intersection may go either way on a grazing ray.
long reference_count(const Hair& hair, glm::vec3 o, glm::vec3 d, float tmax) {
    constexpr float kTmin = 1e-4f;  // the scene's ray epsilon for kNoStrand
    const long lo = brute_count(hair, o, d, kTmin, tmax, 0.9999), hi = brute_count(hair, o, d, kTmin, tmax, 1.0001);
    return lo == hi ? lo : -1;
}

glm::vec3 random_direction(Pcg32& rng) {
    const float z = 1.0f - 2.0f * rng.uniform(), phi = 6.2831853f * rng.uniform();
    const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
    return {s * std::cos(phi), s * std::sin(phi), z};
}

// n straight strands along x (x in [-1, 1], 8 segments) at uniform random y in
// [-half_width, half_width] and z in [0, depth].
Hair random_slab(int n, float radius, float half_width, float depth, std::uint64_t seed) {
    Pcg32 rng(seed, 1);
    Hair hair;
    hair.radius = radius;
    for (int s = 0; s < n; ++s) {
        const float y = half_width * (2.0f * rng.uniform() - 1.0f), z = depth * rng.uniform();
        std::vector<glm::vec3> strand;
        for (int m = 0; m <= 8; ++m) strand.emplace_back(-1.0f + 0.25f * float(m), y, z);
        hair.strands.push_back(strand);
    }
    return hair;
}

TEST(CountHair, GridCountsAreExact) {
    const SceneDescription d = grid();
    const Scene scene(d);
    const float r = kGridRadius;
    // Down a column (toward -z): all four depths, wherever the ray meets the fibres.
    for (float offset : {-0.9f, -0.5f, 0.0f, 0.3f, 0.8f})
        for (float x : {-1.8f, -0.3f, 0.2f, 1.7f}) {
            const glm::vec3 o{x, 0.5f + offset * r, 5.0f};
            EXPECT_EQ(scene.count_hair(o, {0, 0, -1}, 100.0f), 4u) << x << " " << offset;
            EXPECT_EQ(long(scene.count_hair(o, {0, 0, -1}, 100.0f)), reference_count(d.hair, o, {0, 0, -1}, 100.0f));
        }
    // Between the rows, just outside the fibres, and beyond the strands' ends: none.
    EXPECT_EQ(scene.count_hair({0.2f, 0.25f, 5.0f}, {0, 0, -1}, 100.0f), 0u);
    EXPECT_EQ(scene.count_hair({0.2f, 1.0f + 1.02f * r, 5.0f}, {0, 0, -1}, 100.0f), 0u);
    EXPECT_EQ(scene.count_hair({2.0f + 1.02f * r, 1.0f, 5.0f}, {0, 0, -1}, 100.0f), 0u);
    // Across the rows (along +y): five strands.
    EXPECT_EQ(scene.count_hair({0.3f, -1.0f, 1.0f}, {0, 1, 0}, 100.0f), 5u);
    // Along the diagonal y = z: the four strands with j = k.
    const glm::vec3 diag = glm::normalize(glm::vec3(0, 1, 1));
    EXPECT_EQ(scene.count_hair({0.6f, -1.0f, -1.0f}, diag, 100.0f), 4u);
    EXPECT_EQ(long(scene.count_hair({0.6f, -1.0f, -1.0f}, diag, 100.0f)),
              reference_count(d.hair, {0.6f, -1.0f, -1.0f}, diag, 100.0f));
    // A ray from the side of the grid with no hair in its way.
    EXPECT_EQ(scene.count_hair({0.3f, 5.0f, 0.25f}, {0, 1, 0}, 100.0f), 0u);
}

TEST(CountHair, ALimitStopsTheCountThere) {
    // Across the rows, five strands: a limit returns the minimum, stopping early or not.
    const Scene scene(grid());
    const glm::vec3 o{0.3f, -1.0f, 1.0f}, d{0, 1, 0};
    for (std::uint32_t limit : {0u, 1u, 3u, 5u, 6u, 64u, 65u, 1000u})
        EXPECT_EQ(scene.count_hair(o, d, 100.0f, kNoStrand, limit), std::min(limit, 5u)) << limit;
    // Past the inline set (a column of 150 strands) a limit above 64 counts in full first.
    SceneDescription c;
    c.hair.radius = 0.01f;
    for (int k = 0; k < 150; ++k)
        c.hair.strands.push_back({{-1, 0, 0.05f * float(k)}, {0, 0, 0.05f * float(k)}, {1, 0, 0.05f * float(k)}});
    const Scene column(c);
    const glm::vec3 top{0.2f, 0.003f, 10.0f}, down{0, 0, -1};
    EXPECT_EQ(column.count_hair(top, down, 100.0f, kNoStrand, 40), 40u);
    EXPECT_EQ(column.count_hair(top, down, 100.0f, kNoStrand, 100), 100u);
    EXPECT_EQ(column.count_hair(top, down, 100.0f, kNoStrand, 200), 150u);
}

TEST(CountHair, JointsAndRunsAlongAStrandCountOnce) {
    const Scene scene(grid());
    const float r = kGridRadius;
    // Through the joints at x = 0 and x = -1.5, where two segments (and the joint's cap)
    // report the crossing: each strand still counts once.
    for (float x : {0.0f, -1.5f, 1e-4f, -1e-4f})
        for (float offset : {0.0f, 0.5f, 0.99f}) {
            EXPECT_EQ(scene.count_hair({x, 1.5f + offset * r, 5.0f}, {0, 0, -1}, 100.0f), 4u) << x << " " << offset;
            // Tilted, through the joint of the strand at z = 1 and mid-segment elsewhere.
            EXPECT_EQ(scene.count_hair({x - 4.0f, 1.5f, 5.0f}, glm::normalize(glm::vec3(1, 0, -1)), 100.0f), 4u) << x;
        }
    // Into a strand's root and along it: all eight segments report, one strand.
    EXPECT_EQ(scene.count_hair({-3.0f, 1.0f, 0.5f}, glm::normalize(glm::vec3(1, 0.001f, 0)), 100.0f), 1u);
    EXPECT_EQ(scene.count_hair({-3.0f, 1.0f, 0.5f}, glm::normalize(glm::vec3(1, 0, 0.01f)), 100.0f), 1u);
    // Embree's round curves miss a ray (within about 1e-4) parallel to their axis; the
    // count sees what hair_occluded sees.
    const glm::vec3 along{-3.0f, 1.0f + 0.3f * r, 0.5f};
    EXPECT_EQ(scene.count_hair(along, {1, 0, 0}, 100.0f) > 0, scene.hair_occluded(along, {1, 0, 0}, 100.0f));

    // A strand bent at its joint: rays through the bend meet both segments and the cap.
    SceneDescription bent;
    bent.hair.radius = 0.05f;
    bent.hair.strands = {{{-1, 0, 0}, {0, 0, 0}, {1, 0.5f, 0}, {2, 0.5f, 0}}};
    const Scene bent_scene(bent);
    for (float x : {-0.01f, 0.0f, 0.01f, 0.03f})
        for (float y : {-0.04f, 0.0f, 0.04f}) {
            const glm::vec3 o{x, y, 3.0f};
            EXPECT_EQ(bent_scene.count_hair(o, {0, 0, -1}, 10.0f), 1u) << x << " " << y;
        }
    EXPECT_EQ(bent_scene.count_hair({-2.0f, 0.0f, 0.0f}, glm::normalize(glm::vec3(1, 0.01f, 0)), 10.0f), 1u);
}

TEST(CountHair, IgnoreSkipsItsStrandNearTheOrigin) {
    const Scene scene(grid());
    // A path leaving the top fibre of a column (z = 1.5): the rest of the column remains.
    const Hit hit = scene.intersect({0.25f, 0.0f, 5.0f}, {0, 0, -1}, 100.0f);
    ASSERT_EQ(hit.kind, Hit::kHair);
    ASSERT_EQ(hit.strand, grid_strand(0, 3));
    EXPECT_EQ(scene.count_hair(hit.p, {0, 0, -1}, 100.0f, hit.strand), 3u);
    // Without `ignore` the ray goes through the fibre it starts on.
    EXPECT_EQ(scene.count_hair(hit.p, {0, 0, -1}, 100.0f), 4u);
    // Leaving upward: nothing, with or without the own strand's exit at the surface.
    EXPECT_EQ(scene.count_hair(hit.p, {0, 0, 1}, 100.0f, hit.strand), 0u);
    // Like intersect's, the rule is close range: a strand met far from the origin counts
    // (a strand that loops back is another crossing), other strands always count.
    EXPECT_EQ(scene.count_hair({0.25f, 0.0f, 5.0f}, {0, 0, -1}, 100.0f, grid_strand(0, 0)), 4u);
    EXPECT_EQ(scene.count_hair(hit.p, {0, 0, -1}, 100.0f, grid_strand(0, 2)), 4u);
    // A count of zero exactly when hair_occluded says the way is clear.
    EXPECT_TRUE(scene.hair_occluded(hit.p, {0, 0, -1}, 100.0f, hit.strand));
    EXPECT_FALSE(scene.hair_occluded(hit.p, {0, 0, 1}, 100.0f, hit.strand));
}

TEST(CountHair, TmaxStopsCounting) {
    const Scene scene(grid());
    // Down the column from z = 5: fibres entered at t = 3.45, 3.95, 4.45 and 4.95.
    const glm::vec3 o{0.3f, 1.0f, 5.0f}, d{0, 0, -1};
    EXPECT_EQ(scene.count_hair(o, d, 3.0f), 0u);
    EXPECT_EQ(scene.count_hair(o, d, 3.7f), 1u);
    EXPECT_EQ(scene.count_hair(o, d, 4.2f), 2u);
    EXPECT_EQ(scene.count_hair(o, d, 4.7f), 3u);
    EXPECT_EQ(scene.count_hair(o, d, 5.2f), 4u);
    // Ending inside a fibre counts it: the ray has entered it. Lying wholly inside one does
    // not: no surface is crossed (as for hair_occluded).
    EXPECT_EQ(scene.count_hair(o, d, 3.5f), 1u);
    EXPECT_EQ(scene.count_hair({0.3f, 1.0f, 1.52f}, d, 0.04f), 0u);
    EXPECT_EQ(scene.count_hair({0.3f, 1.0f, 1.52f}, d, 0.1f), 1u);
}

TEST(CountHair, SurfacesAndTheLightAreNotSeen) {
    SceneDescription d = grid();
    Mesh wall;
    wall.name = "wall";
    wall.positions = {{-5, -5, 0.75f}, {5, -5, 0.75f}, {5, 5, 0.75f}, {-5, 5, 0.75f}};
    wall.triangles = {{0, 1, 2}, {0, 2, 3}};
    d.meshes.push_back(wall);
    d.light = AreaLight{{-5, -5, 3}, {10, 0, 0}, {0, 10, 0}, glm::vec3(1.0f)};
    const Scene scene(d);
    const glm::vec3 o{0.3f, 1.0f, 5.0f}, dir{0, 0, -1};
    EXPECT_EQ(scene.intersect(o, dir, 100.0f).kind, Hit::kLight);
    EXPECT_EQ(scene.intersect_opaque({0.3f, 0.25f, 1.2f}, dir, 100.0f).kind, Hit::kSurface);
    EXPECT_EQ(scene.count_hair(o, dir, 100.0f), 4u);
    EXPECT_EQ(scene.count_hair({0.3f, 0.25f, 5.0f}, dir, 100.0f), 0u);

    // No hair at all.
    d.hair.strands.clear();
    const Scene bald(d);
    EXPECT_EQ(bald.count_hair(o, dir, 100.0f), 0u);
}

TEST(CountHair, MoreStrandsThanTheInlineSet) {
    // A column of 150 strands, past the context's 64 inline entries.
    SceneDescription d;
    d.hair.radius = 0.01f;
    for (int k = 0; k < 150; ++k)
        d.hair.strands.push_back({{-1, 0, 0.05f * float(k)}, {0, 0, 0.05f * float(k)}, {1, 0, 0.05f * float(k)}});
    const Scene scene(d);
    for (float x : {-0.5f, 0.0f, 0.7f}) {
        EXPECT_EQ(scene.count_hair({x, 0.003f, 10.0f}, {0, 0, -1}, 100.0f), 150u) << x;
        EXPECT_EQ(scene.count_hair({x, 0.003f, -1.0f}, {0, 0, 1}, 100.0f), 150u) << x;
    }
    EXPECT_EQ(scene.count_hair({0.5f, 0.003f, 10.0f}, {0, 0, -1}, 10.0f - 0.05f * 99.5f), 50u);
}

TEST(CountHair, RandomRaysMatchBruteForce) {
    // Wavy strands through a unit block (bent joints everywhere), rays from random points
    // in and around it in random directions with random lengths.
    BlockOptions b;
    b.count = 600;
    b.size = 1.0f;
    b.radius = 0.01f;
    b.segments = 12;
    b.wave_amplitude = 0.05f;
    b.wavelength = 0.4f;
    SceneDescription d;
    d.hair = make_block(b);
    const Scene scene(d);
    Pcg32 rng(3, 5);
    int compared = 0, skipped = 0, crossings = 0;
    for (int i = 0; i < 2000; ++i) {
        const glm::vec3 o{1.4f * rng.uniform() - 0.7f, 1.4f * rng.uniform() - 0.2f, 1.4f * rng.uniform() - 0.7f};
        const glm::vec3 dir = random_direction(rng);
        const float tmax = 2.0f * rng.uniform();
        const long ref = reference_count(d.hair, o, dir, tmax);
        const std::uint32_t n = scene.count_hair(o, dir, tmax);
        EXPECT_EQ(n > 0, scene.hair_occluded(o, dir, tmax)) << i;
        if (ref < 0) {
            ++skipped;
            continue;
        }
        ++compared;
        crossings += int(ref);
        EXPECT_EQ(long(n), ref) << "ray " << i;
    }
    EXPECT_GT(crossings, 4000);  // the rays do cross hair: two or three strands each on average
    EXPECT_LT(skipped, 20);
    std::printf("[ count ] %d random rays match the brute force (%d crossings); %d ambiguous ones skipped\n", compared,
                crossings, skipped);
}

TEST(CountHair, RandomSlabMeanMatchesDensity) {
    // 1000 strands of radius 0.01 at random (y, z) in [-1, 1] × [0, 1]: density
    // ρ = 500 per unit area, so a ray across the slab crosses ρ · 2r · depth = 10 on average.
    const float r = 0.01f, half_width = 1.0f, depth = 1.0f;
    const int strands = 1000;
    SceneDescription d;
    d.hair = random_slab(strands, r, half_width, depth, 9);
    const Scene scene(d);
    const double density = strands / (2.0 * half_width * depth);
    Pcg32 rng(4, 2);
    const int rays = 20000;
    double sum = 0, sum_tilted = 0;
    for (int i = 0; i < rays; ++i) {
        const float x = rng.uniform() - 0.5f, y = half_width * (2.0f * rng.uniform() - 1.0f);
        const std::uint32_t n = scene.count_hair({x, y, -0.5f}, {0, 0, 1}, depth + 1.0f);
        sum += n;
        // Tilted in the x-z plane: the ray keeps its y, so it meets the same strands.
        const float a = 1.2f * (rng.uniform() - 0.5f);
        const glm::vec3 tilted{std::sin(a), 0.0f, std::cos(a)};
        const glm::vec3 o = glm::vec3(x, y, 0.5f * depth) - 0.6f * depth / tilted.z * tilted;
        sum_tilted += scene.count_hair(o, tilted, 1.2f * depth / tilted.z);
        if (i < 300) {
            const long ref = reference_count(d.hair, {x, y, -0.5f}, {0, 0, 1}, depth + 1.0f);
            if (ref >= 0) {
                EXPECT_EQ(long(n), ref) << i;
            }
        }
    }
    const double expected = density * 2.0 * r * depth, mean = sum / rays, mean_tilted = sum_tilted / rays;
    std::printf("[ count ] slab: mean %.4f (tilted %.4f), density x 2r x depth = %.4f\n", mean, mean_tilted, expected);
    // The count per ray has variance about 10, so the mean of 20,000 has 0.2 % noise.
    EXPECT_NEAR(mean, expected, 0.02 * expected);
    EXPECT_NEAR(mean_tilted, expected, 0.02 * expected);
}

TEST(CountHair, Cost) {
    // Not an assertion: what exact counting costs beside hair_occluded (which stops at the
    // first hit) and intersect (closest hit) on a slab ten fibres deep, one thread.
    SceneDescription d;
    d.hair = random_slab(1000, 0.01f, 1.0f, 1.0f, 9);
    const Scene scene(d);
    Pcg32 rng(8, 8);
    struct Ray {
        glm::vec3 o, d;
    };
    std::vector<Ray> rays;
    for (int i = 0; i < 100000; ++i) {
        const float a = 1.0f * (rng.uniform() - 0.5f), b = 1.0f * (rng.uniform() - 0.5f);
        const glm::vec3 dir = glm::normalize(glm::vec3(std::tan(a), std::tan(b), 1.0f));
        rays.push_back({{rng.uniform() - 0.5f, 1.6f * rng.uniform() - 0.8f, -0.5f}, dir});
    }
    using Clock = std::chrono::steady_clock;
    auto time = [&](auto&& call) {
        double best = 1e30;
        long long total = 0;
        for (int rep = 0; rep < 3; ++rep) {
            const auto t0 = Clock::now();
            for (const Ray& ray : rays) total += call(ray);
            best = std::min(best, std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / double(rays.size()));
        }
        return std::pair<double, long long>(best, total / 3);
    };
    const auto count = time([&](const Ray& ray) { return (long long)scene.count_hair(ray.o, ray.d, 3.0f); });
    const auto occluded = time([&](const Ray& ray) { return (long long)scene.hair_occluded(ray.o, ray.d, 3.0f); });
    const auto closest = time([&](const Ray& ray) { return (long long)(scene.intersect(ray.o, ray.d, 3.0f).kind); });
    std::printf("[ count ] ns per call, slab 10 fibres deep (mean count %.2f, %.1f %% occluded):\n"
                "[ count ]   count_hair %.0f, hair_occluded %.0f, intersect %.0f\n",
                double(count.second) / double(rays.size()), 100.0 * double(occluded.second) / double(rays.size()),
                count.first, occluded.first, closest.first);
    EXPECT_GT(count.second, 0);
}

}  // namespace
