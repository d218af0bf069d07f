// The glow volume's smoothing (render::LocalPlane, local linear regression): a plane through
// a lattice neighbourhood read at its centre reproduces linear light exactly, also where the
// neighbourhood is one-sided (a lit face, whose outer cells hold no hair), where the
// neighbourhood's mean is off by half the slope; it stays defined and in range otherwise.
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "local_plane.hpp"

namespace {

using glm::dvec3;

dvec3 linear(const dvec3& d) { return dvec3(2.0, 1.0, 0.5) + d.x * dvec3(0.5, -0.2, 0.1) - d.z * dvec3(0.3, 0.4, 0.2); }

// The 3 × 3 × 3 offsets, those with z ≤ z_max only.
template <class F> void each_offset(int z_max, F&& f) {
    for (int z = -1; z <= z_max; ++z)
        for (int y = -1; y <= 1; ++y)
            for (int x = -1; x <= 1; ++x) f(dvec3(x, y, z));
}

TEST(LocalPlane, ReproducesLinearLightAtAOneSidedFace) {
    std::mt19937 rng(3);
    std::uniform_int_distribution<std::uint32_t> weight(1, 12);
    for (int z_max : {1, 0}) {  // full neighbourhood; the outer layer empty (a face)
        render::LocalPlane plane;
        dvec3 total(0);
        double points = 0;
        each_offset(z_max, [&](const dvec3& d) {
            const std::uint32_t w = weight(rng);
            plane.add(d, linear(d), w);
            total += double(w) * linear(d), points += w;
        });
        const dvec3 c = plane.at_centre(), truth = linear(dvec3(0));
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], truth[k], 2e-3 * truth[k]) << z_max << " " << k;
        if (z_max == 0) {  // the negative control: the mean reads the face as deeper light
            const dvec3 mean = total / points;
            bool misses = false;
            for (int k = 0; k < 3; ++k) misses = misses || std::abs(mean[k] - truth[k]) > 2e-3 * truth[k];
            EXPECT_TRUE(misses) << "the mean would have passed too: the test shows nothing";
        }
    }
}

TEST(LocalPlane, ConstantLightIsExactAsInAFurnace) {
    render::LocalPlane plane;
    each_offset(0, [&](const dvec3& d) { plane.add(d, dvec3(0.15), 3); });
    EXPECT_EQ(plane.points(), 54u);
    const dvec3 c = plane.at_centre();
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], 0.15, 1e-12);
}

TEST(LocalPlane, DefinedInALayerAndWithinTheValuesRange) {
    // One cell thick (no z offsets) and one-sided in x: the ridge keeps the fit defined, the
    // in-plane slope is still followed (the mean would be off by half the x slope).
    render::LocalPlane layer;
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 0; ++x) layer.add(dvec3(x, y, 0), linear(dvec3(x, y, 0)), 2);
    const dvec3 c = layer.at_centre();
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], linear(dvec3(0))[k], 2e-3 * linear(dvec3(0))[k]) << k;
    // Noisy, one-sided neighbourhoods: never outside the values' range, never NaN.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u;
    for (int trial = 0; trial < 200; ++trial) {
        render::LocalPlane plane;
        double lo = 1e9, hi = -1e9;
        each_offset(trial % 2 == 0 ? 0 : 1, [&](const dvec3& d) {
            if (u(rng) < 0.5) return;
            const double v = u(rng) * (1 + d.x);
            plane.add(d, dvec3(v), 1 + std::uint32_t(u(rng) * 5));
            lo = std::min(lo, v), hi = std::max(hi, v);
        });
        const dvec3 v = plane.at_centre();
        if (plane.points() == 0) {
            EXPECT_EQ(v.x, 0.0);
            continue;
        }
        EXPECT_TRUE(v.x >= lo - 1e-12 && v.x <= hi + 1e-12) << trial << ": " << v.x << " outside [" << lo << ", " << hi << "]";
    }
}

// The 4 × 4 determinant by cofactor expansion along the first row.
double det4(const double m[4][4]) {
    double det = 0;
    for (int c = 0; c < 4; ++c) {
        double minor[3][3];
        for (int r = 1; r < 4; ++r)
            for (int k = 0, mc = 0; k < 4; ++k)
                if (k != c) minor[r - 1][mc++] = m[r][k];
        const double d3 = minor[0][0] * (minor[1][1] * minor[2][2] - minor[1][2] * minor[2][1]) -
                          minor[0][1] * (minor[1][0] * minor[2][2] - minor[1][2] * minor[2][0]) +
                          minor[0][2] * (minor[1][0] * minor[2][1] - minor[1][1] * minor[2][0]);
        det += (c % 2 == 0 ? 1.0 : -1.0) * m[0][c] * d3;
    }
    return det;
}

// Sparse random neighbourhoods (always holding the centre, as the glow's cells do) with
// random weights and values: the plane's centre is the ridge-regularised least-squares
// solution, here by Cramer's rule on the same normal equations (an independent solve),
// whatever rows the elimination swaps; and where the values are linear it is within the
// ridge's shrinkage of the truth when the weights are alike.
TEST(LocalPlane, SparseNeighbourhoodsSolveTheirNormalEquations) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u;
    for (int trial = 0; trial < 20000; ++trial) {
        const dvec3 g(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
        const bool alike = trial % 2 == 0;
        render::LocalPlane plane;
        double a[4][4] = {}, b[4] = {}, lo = 1e9, hi = -1e9;
        each_offset(1, [&](const dvec3& d) {
            if (!(d == dvec3(0)) && u(rng) < 0.7) return;
            const std::uint32_t w = alike ? 10 : 1 + std::uint32_t(u(rng) * 20);
            const double v = 1.0 + glm::dot(g, d) + (alike ? 0.0 : 0.3 * (u(rng) - 0.5));
            plane.add(d, dvec3(v), w);
            const double e[4] = {1, d.x, d.y, d.z};
            for (int r = 0; r < 4; ++r) {
                for (int c = 0; c < 4; ++c) a[r][c] += w * e[r] * e[c];
                b[r] += w * e[r] * v;
            }
            lo = std::min(lo, v), hi = std::max(hi, v);
        });
        const double total = a[0][0];
        for (int r = 1; r < 4; ++r) a[r][r] += 1e-3 * total;  // the plane's ridge
        double a0[4][4];
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) a0[r][c] = c == 0 ? b[r] : a[r][c];
        const double cramer = std::clamp(det4(a0) / det4(a), lo, hi);
        const double c = plane.at_centre().x;
        ASSERT_NEAR(c, cramer, 1e-9 * (1 + std::abs(cramer))) << trial;
        if (alike) {
            ASSERT_NEAR(c, 1.0, 0.05 * glm::length(g) + 1e-12) << trial;  // near-flat sparse sets shrink more
        }
    }
}

}  // namespace
