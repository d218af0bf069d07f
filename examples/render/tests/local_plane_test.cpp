// The glow volume's smoothing (render::LocalPlane, local linear regression): a plane through
// a lattice neighbourhood read at its centre reproduces linear light exactly, also where the
// neighbourhood is one-sided (a lit face, whose outer cells hold no hair), where the
// neighbourhood's mean is off by half the slope; it stays defined and in range otherwise.
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
            EXPECT_GT(std::abs(mean.x - truth.x), 0.1) << "the mean would have been right: the test shows nothing";
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
    // One cell thick (no z offsets): the ridge keeps the fit defined, the in-plane slope is
    // still followed.
    render::LocalPlane layer;
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x) layer.add(dvec3(x, y, 0), linear(dvec3(x, y, 0)), 2);
    const dvec3 c = layer.at_centre();
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], linear(dvec3(0))[k], 1e-9);
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

}  // namespace
