// Tests of the renderer library: the fiber offset h of a hit follows the library's
// convention, a lossless hair block vanishes in a white furnace under the path tracer,
// rendering is deterministic, and the hair mask marks exactly the hair pixels.
#include <gtest/gtest.h>

#include <cmath>

#include <tbb/global_control.h>

#include "render.hpp"
#include "scenes.hpp"

namespace {

using namespace render;

// The mean of channel c (or of all three, c = -1) over the hair pixels; sets n to their count.
double mean_over_hair(const RenderResult& r, int c, std::size_t& n) {
    double sum = 0;
    n = 0;
    for (std::size_t i = 0; i < r.hair_mask.size(); ++i)
        if (r.hair_mask[i]) {
            sum += c >= 0 ? r.rgb[3 * i + std::size_t(c)] : (r.rgb[3 * i] + r.rgb[3 * i + 1] + r.rgb[3 * i + 2]) / 3.0;
            ++n;
        }
    return n ? sum / double(n) : 0.0;
}

// One straight strand along +x through the origin, radius 0.1.
SceneDescription one_strand() {
    SceneDescription d;
    d.name = "strand";
    d.hair.radius = 0.1f;
    d.hair.strands = {{{-1, 0, 0}, {0, 0, 0}, {1, 0, 0}}};
    return d;
}

TEST(RenderHit, OffsetFollowsTheLibraryFrame) {
    const Scene scene(one_strand());
    // A ray toward -z: wo = +z, so the frame is x = tangent, z = wo, y = z × x = +y and
    // h = dot(hit - axis, y) / radius.
    for (float offset : {-0.9f, -0.5f, 0.0f, 0.3f, 0.8f}) {
        const Hit hit = scene.intersect({0.25f, offset * 0.1f, 5.0f}, {0, 0, -1}, 100.0f);
        ASSERT_EQ(hit.kind, Hit::kHair) << offset;
        EXPECT_NEAR(hit.h, offset, 1e-3f) << offset;
        EXPECT_NEAR(hit.tangent.x, 1.0f, 1e-6f);
        const hairscatter::FiberFrame<float> frame(hit.tangent, glm::vec3(0, 0, 1));
        EXPECT_NEAR(frame.y.y, 1.0f, 1e-6f);
    }
    // Seen from the other side (wo = -z) the frame's y flips, and with it h.
    const Hit back = scene.intersect({0.25f, 0.05f, -5.0f}, {0, 0, 1}, 100.0f);
    ASSERT_EQ(back.kind, Hit::kHair);
    EXPECT_NEAR(back.h, -0.5f, 1e-3f);
}

TEST(RenderHit, RaysLeavingAFiberSkipItsStrand) {
    const Scene scene(one_strand());
    const Hit hit = scene.intersect({0.25f, 0.0f, 5.0f}, {0, 0, -1}, 100.0f);
    ASSERT_EQ(hit.kind, Hit::kHair);
    EXPECT_EQ(scene.intersect(hit.p, {0, 0, -1}, 100.0f, hit.strand).kind, Hit::kMiss);
    EXPECT_EQ(scene.intersect(hit.p - glm::vec3(0, 0, 1e-3f), {0, 0, -1}, 100.0f).kind, Hit::kHair);  // negative control
}

// A lossless fiber (σa = 0) conserves energy, so in a constant environment of radiance 1
// every hair pixel converges to 1 under the path tracer. (Uniform sampling converges too,
// but its weights 4π f multiply over dozens of bounces into a distribution far too
// heavy-tailed for a test of this size.)
TEST(RenderPath, LosslessHairVanishesInAWhiteFurnace) {
    BlockOptions b;
    b.count = 300;
    b.size = 1.0f;
    b.radius = 0.01f;
    SceneDescription d;
    d.name = "furnace";
    d.hair = make_block(b);
    d.environment = glm::vec3(1.0f);
    d.camera.eye = {0, 0.5f, 4};
    d.camera.target = {0, 0.5f, 0};
    d.camera.fov_y_deg = 10;
    const Scene scene(std::move(d));
    for (Sampling s : {Sampling::kImportance, Sampling::kMis}) {
        RenderOptions o;
        o.integrator = Integrator::kPath;
        o.sampling = s;
        o.width = o.height = 24;
        o.spp = 64;
        o.max_depth = 1000;
        std::size_t n;
        const double mean = mean_over_hair(render::render(scene, o), -1, n);
        ASSERT_GT(n, 100u);
        EXPECT_NEAR(mean, 1.0, 0.03) << to_string(s);
    }
}

TEST(RenderPath, AbsorbingHairDoesNotVanishInTheFurnace) {  // the negative control
    BlockOptions b;
    b.count = 300;
    b.size = 1.0f;
    SceneDescription d;
    d.hair = make_block(b);
    d.hair_params.sigma_a = hairscatter::sigma_a_from_melanin(1.3f, 0.0f);
    d.environment = glm::vec3(1.0f);
    d.camera.eye = {0, 0.5f, 4};
    d.camera.target = {0, 0.5f, 0};
    d.camera.fov_y_deg = 10;
    const Scene scene(std::move(d));
    RenderOptions o;
    o.integrator = Integrator::kPath;
    o.width = o.height = 24;
    o.spp = 16;
    std::size_t n;
    const double blue = mean_over_hair(render::render(scene, o), 2, n);
    ASSERT_GT(n, 100u);
    EXPECT_LT(blue, 0.5);
}

TEST(Render, SameSeedSameImageWhateverTheThreads) {
    BlockOptions b;
    b.count = 200;
    const Scene scene(make_block_scene(b, LightingOptions{}));
    RenderOptions o;
    o.width = 40;
    o.height = 30;
    o.spp = 2;
    for (Integrator i : {Integrator::kSingle, Integrator::kDual, Integrator::kPath}) {
        o.integrator = i;
        const RenderResult a = render::render(scene, o);
        RenderResult c;
        {
            tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
            c = render::render(scene, o);
        }
        EXPECT_EQ(a.rgb, c.rgb) << to_string(i);
        o.seed = 2;
        EXPECT_NE(render::render(scene, o).rgb, a.rgb) << to_string(i);
        o.seed = 1;
    }
}

TEST(Render, HairOnlyRendersExactlyTheMaskedPixels) {
    BlockOptions b;
    b.count = 200;
    const Scene scene(make_block_scene(b, LightingOptions{}));
    RenderOptions o;
    o.width = 40;
    o.height = 30;
    o.spp = 1;
    o.hair_only = true;
    const RenderResult r = render::render(scene, o);
    ASSERT_GT(r.hair_pixels, 0u);
    ASSERT_LT(r.hair_pixels, r.hair_mask.size());
    std::size_t lit_outside = 0;
    for (std::size_t i = 0; i < r.hair_mask.size(); ++i)
        if (!r.hair_mask[i]) lit_outside += r.rgb[3 * i] != 0 || r.rgb[3 * i + 1] != 0 || r.rgb[3 * i + 2] != 0;
    EXPECT_EQ(lit_outside, 0u);
    o.hair_only = false;
    EXPECT_EQ(render::render(scene, o).hair_mask, r.hair_mask);
}

}  // namespace
