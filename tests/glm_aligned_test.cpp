// The library under GLM_FORCE_DEFAULT_ALIGNED_GENTYPES (vec3 padded to 16 bytes), as some
// renderers build GLM: the dual-scattering tables must still build, look up and save/load.
#define GLM_FORCE_DEFAULT_ALIGNED_GENTYPES
#include <gtest/gtest.h>

#include <hairscatter/dual.hpp>

namespace hs = hairscatter;

TEST(AlignedGlm, DualTablesBuildLookUpAndRoundTrip) {
    const hs::ChiangMaterial<float> material{hs::FiberParams<float>{}};
    const auto t = hs::DualScatteringTables<float>::build<hs::ChiangFiber<float>>(material);
    for (int i = 0; i < t.size(); ++i) EXPECT_NEAR(t.entry(i).a_f.x + t.entry(i).a_b.x, 1.0f, 2e-3f);
    const auto e = t.lookup(0.3f);
    EXPECT_NEAR(e.a_f.y + e.a_b.y, 1.0f, 2e-3f);
    const std::string path = ::testing::TempDir() + "hairscatter_aligned.hsdt";
    t.save(path);
    const auto u = hs::DualScatteringTables<float>::load(path);
    EXPECT_EQ(u.entry(7).sigma2_b, t.entry(7).sigma2_b);
    const hs::ChiangFiber<float> fiber(material, 0.2f);
    hs::DualScatteringLight<float> light;
    light.direct_fraction = 0;
    light.n = 2;
    const glm::vec3 f = hs::DualScatteringBcsdf<hs::ChiangFiber<float>>(fiber, u).eval(
        glm::normalize(glm::vec3(0.2f, 0.9f, 0.1f)), glm::normalize(glm::vec3(-0.1f, -0.3f, 0.9f)), light);
    EXPECT_TRUE(f.x > 0 && std::isfinite(f.x));
}
