// Tests of the fur, slab and head scenes: the fur's strands grow from the body sphere and stay
// outside it, as long and as tilted as asked; a ray along the slab's normal crosses
// --slab-depth fibers on average; the back light hides behind the slab; bad options are
// refused naming their flag.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "render.hpp"
#include "scenes.hpp"
#include "shading.hpp"

namespace {

using namespace render;

constexpr float kDeg = 3.14159265358979f / 180.0f;

float polyline_length(const std::vector<glm::vec3>& s) {
    float l = 0;
    for (std::size_t i = 1; i < s.size(); ++i) l += glm::length(s[i] - s[i - 1]);
    return l;
}

// The message of the std::invalid_argument that f throws ("" when it throws none).
template <class F>
std::string refusal(F f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

FurOptions small_fur() {
    FurOptions o;
    o.count = 4000;
    o.center = {0.5f, 3.0f, -1.0f};
    return o;
}

TEST(Fur, SameSeedSameStrandsOtherSeedOthers) {
    const FurOptions o = small_fur();
    EXPECT_EQ(make_fur(o).strands, make_fur(o).strands);
    FurOptions other = o;
    other.seed = o.seed + 1;
    EXPECT_NE(make_fur(other).strands, make_fur(o).strands);
}

TEST(Fur, CountsAndLengthsAsAsked) {
    const FurOptions o = small_fur();
    const Hair h = make_fur(o);
    ASSERT_EQ(h.strands.size(), std::size_t(o.count));
    EXPECT_EQ(h.radius, o.radius);
    double sum = 0;
    float lo = 1e9f, hi = 0;
    for (const auto& s : h.strands) {
        ASSERT_EQ(s.size(), std::size_t(o.segments) + 1);
        const float l = polyline_length(s);
        sum += l;
        lo = std::min(lo, l), hi = std::max(hi, l);
    }
    // ±30 % uniform: the mean is the length, the extremes near 0.7 and 1.3 of it (pushing a
    // point out of the body lengthens a strand only slightly).
    EXPECT_NEAR(sum / double(h.strands.size()), o.length, 0.02 * o.length);
    EXPECT_GE(lo, 0.7f * o.length * 0.999f);
    EXPECT_LT(lo, 0.72f * o.length);
    EXPECT_LE(hi, 1.3f * o.length * 1.02f);
    EXPECT_GT(hi, 1.28f * o.length);
}

TEST(Fur, RootsLieOnTheSphereAreaUniformly) {
    const FurOptions o = small_fur();
    const Hair h = make_fur(o);
    // Area-uniform: the height above the centre is uniform in [-R, R] (Archimedes), and so
    // is each other axis; four bins of each hold a quarter of the roots.
    int bins[3][4] = {};
    for (const auto& s : h.strands) {
        const glm::vec3 rel = s.front() - o.center;
        ASSERT_NEAR(glm::length(rel), o.body_radius, 1e-5f * o.body_radius);
        for (int a = 0; a < 3; ++a) ++bins[a][std::min(3, int(2 * (rel[a] / o.body_radius + 1)))];
    }
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 4; ++b)
            EXPECT_NEAR(bins[a][b] / double(o.count), 0.25, 0.025) << "axis " << a << " bin " << b;
}

TEST(Fur, StrandsStayOutsideTheBody) {
    for (float tilt : {0.0f, 30.0f, 85.0f}) {
        FurOptions o = small_fur();
        o.tilt_deg = tilt;
        o.gravity = 3.0f;  // bends the strands into the body, were they not kept out
        const Hair h = make_fur(o);
        for (const auto& s : h.strands)
            for (std::size_t k = 1; k < s.size(); ++k)
                ASSERT_GE(glm::length(s[k] - o.center), (o.body_radius + o.radius) * (1 - 1e-6f)) << tilt;
    }
}

TEST(Fur, StrandsLeaveTiltedTowardTheComb) {
    FurOptions o = small_fur();
    o.gravity = 0;  // the first segment's direction is the growth direction
    const Hair h = make_fur(o);
    double tilt_sum = 0, toward = 0;
    int n = 0;
    for (const auto& s : h.strands) {
        const glm::vec3 normal = glm::normalize(s[0] - o.center), d = glm::normalize(s[1] - s[0]);
        const float tilt = std::acos(std::clamp(glm::dot(normal, d), -1.0f, 1.0f));
        EXPECT_LE(tilt, (o.tilt_deg + o.tilt_jitter_deg) * kDeg + 1e-3f);
        EXPECT_GE(tilt, (o.tilt_deg - o.tilt_jitter_deg) * kDeg - 1e-3f);
        tilt_sum += tilt;
        // Away from the poles the comb (-y) has a tangent part: the strand leans along it.
        if (std::abs(normal.y) < 0.9f) {
            const glm::vec3 down(0, -1, 0), comb = glm::normalize(down - glm::dot(down, normal) * normal);
            toward += glm::dot(d - glm::dot(d, normal) * normal, comb) > 0 ? 1 : 0;
            ++n;
        }
    }
    EXPECT_NEAR(tilt_sum / double(h.strands.size()) / kDeg, o.tilt_deg, 1.0);
    EXPECT_EQ(toward, double(n));
}

// The points' projection into a w × h image of the camera lies inside it.
bool in_view(const Camera& c, const glm::vec3& p, float aspect) {
    const glm::vec3 f = glm::normalize(c.target - c.eye), r = glm::normalize(glm::cross(f, c.up)),
                    u = glm::cross(r, f);
    const glm::vec3 q = p - c.eye;
    const float depth = glm::dot(q, f), t = std::tan(0.5f * c.fov_y_deg * kDeg);
    return depth > 0 && std::abs(glm::dot(q, r) / depth) < t * aspect && std::abs(glm::dot(q, u) / depth) < t;
}

TEST(FurScene, BallIsAboveTheGroundAndInView) {
    FurOptions o;
    o.count = 3000;
    LightingOptions l;
    const SceneDescription with_body = make_fur_scene(o, l);
    EXPECT_EQ(with_body.name, "fur");
    ASSERT_EQ(with_body.meshes.size(), 2u);
    EXPECT_EQ(with_body.meshes[0].name, "ground");
    EXPECT_EQ(with_body.meshes[1].name, "body");
    EXPECT_EQ(with_body.meshes[1].albedo, glm::vec3(0.4f));
    for (const auto& s : with_body.hair.strands)
        for (const glm::vec3& p : s) {
            ASSERT_GT(p.y, 0.1f);                            // clear of the ground
            ASSERT_TRUE(in_view(with_body.camera, p, 4.0f / 3.0f));  // the default 480 × 360
        }
    o.body = false;
    const SceneDescription shell = make_fur_scene(o, l);
    ASSERT_EQ(shell.meshes.size(), 1u);
    EXPECT_EQ(shell.meshes[0].name, "ground");
    EXPECT_EQ(shell.hair.strands, with_body.hair.strands);  // the body does not change the fur
}

TEST(Scenes, RemoveGroundKeepsTheOtherMeshes) {
    FurOptions o;
    o.count = 10;
    SceneDescription d = make_fur_scene(o, LightingOptions{});
    remove_ground(d);
    ASSERT_EQ(d.meshes.size(), 1u);
    EXPECT_EQ(d.meshes[0].name, "body");
    SceneDescription cornell = make_cornell_scene(BlockOptions{}, LightingOptions{});
    const std::size_t walls = cornell.meshes.size();
    remove_ground(cornell);
    EXPECT_EQ(cornell.meshes.size(), walls);  // its floor is a wall of the box
}

// The number of strands each of `rays` rays along z, at heights spread evenly over
// [r, H - r], crosses: those whose axis lies within r of the ray's y (the distance between
// a line along x and one along z is their offset along y, whatever z).
std::vector<int> crossings(const SlabOptions& o, const Hair& h, int rays) {
    std::vector<float> ys;
    for (const auto& s : h.strands) ys.push_back(s.front().y);
    std::sort(ys.begin(), ys.end());
    std::vector<int> counts;
    for (int i = 0; i < rays; ++i) {
        const float y = o.radius + (o.height - 2 * o.radius) * (float(i) + 0.5f) / float(rays);
        counts.push_back(int(std::upper_bound(ys.begin(), ys.end(), y + o.radius) -
                             std::lower_bound(ys.begin(), ys.end(), y - o.radius)));
    }
    return counts;
}

TEST(Slab, StraightStrandsAlongXFillTheBox) {
    SlabOptions o;
    const Hair h = make_slab(o);
    EXPECT_EQ(h.radius, o.radius);
    ASSERT_EQ(h.strands.size(), std::size_t(std::lround(o.depth * o.height / (2 * o.radius))));
    EXPECT_EQ(int(h.strands.size()), o.strand_count());
    for (const auto& s : h.strands) {
        ASSERT_EQ(s.size(), std::size_t(o.segments) + 1);
        EXPECT_FLOAT_EQ(s.front().x, -0.5f * o.width);
        EXPECT_FLOAT_EQ(s.back().x, 0.5f * o.width);
        for (const glm::vec3& p : s) {
            ASSERT_EQ(p.y, s.front().y);
            ASSERT_EQ(p.z, s.front().z);
        }
        EXPECT_GE(s.front().y, 0.0f);
        EXPECT_LE(s.front().y, o.height);
        EXPECT_GE(s.front().z, -0.5f * o.thickness);
        EXPECT_LE(s.front().z, 0.5f * o.thickness);
    }
    EXPECT_EQ(make_slab(o).strands, h.strands);
    SlabOptions other = o;
    other.seed = o.seed + 1;
    EXPECT_NE(make_slab(other).strands, h.strands);
}

// --slab-vertical: the same box, the fibers along y (sides unequal, so that a swap shows).
TEST(Slab, VerticalStrandsAlongYFillTheSameBox) {
    SlabOptions o;
    o.width = 3;
    o.height = 6;
    o.vertical = true;
    const Hair h = make_slab(o);
    ASSERT_EQ(h.strands.size(), std::size_t(std::lround(o.depth * o.width / (2 * o.radius))));
    EXPECT_EQ(int(h.strands.size()), o.strand_count());
    for (const auto& s : h.strands) {
        ASSERT_EQ(s.size(), std::size_t(o.segments) + 1);
        EXPECT_FLOAT_EQ(s.front().y, 0.0f);
        EXPECT_FLOAT_EQ(s.back().y, o.height);
        for (const glm::vec3& p : s) {
            ASSERT_EQ(p.x, s.front().x);
            ASSERT_EQ(p.z, s.front().z);
        }
        EXPECT_GE(s.front().x, -0.5f * o.width);
        EXPECT_LE(s.front().x, 0.5f * o.width);
        EXPECT_GE(s.front().z, -0.5f * o.thickness);
        EXPECT_LE(s.front().z, 0.5f * o.thickness);
    }
}

TEST(Slab, RaysAlongTheNormalCrossDepthFibersOnAverage) {
    for (float depth : {5.0f, 10.0f}) {
        SlabOptions o;
        o.depth = depth;
        const std::vector<int> c = crossings(o, make_slab(o), 20000);
        double sum = 0, empty = 0;
        for (int k : c) sum += k, empty += k == 0;
        const double mean = sum / double(c.size());
        std::printf("[ figures ] slab depth %g: %.3f fibers per ray, %.4f of the rays cross none (Poisson: %.4f)\n",
                    double(depth), mean, empty / double(c.size()), std::exp(-double(depth)));
        EXPECT_NEAR(mean, depth, 0.03 * depth);
    }
}

// Independent uniform positions (overlap) make the count per ray binomial, nearly Poisson
// (variance = mean), unlike a grid's even one; fibers that may not overlap vary a little
// less (a fiber keeps the others out of its disc) but still vary. Rays closer than 2r see
// overlapping strands, so a 5-unit slab has only ~250 independent heights: a 100-unit one
// pins the variance to ~3 %.
TEST(Slab, FiberCountsPerRayVaryLikePoissonOrALittleLess) {
    for (bool overlap : {true, false}) {
        SlabOptions o;
        o.height = 100;
        o.overlap = overlap;
        const std::vector<int> c = crossings(o, make_slab(o), 100000);
        double sum = 0, sum2 = 0;
        for (int k : c) sum += k, sum2 += double(k) * k;
        const double mean = sum / double(c.size()), var = sum2 / double(c.size()) - mean * mean;
        std::printf("[ figures ] slab depth %g, 100 units tall, %s: mean %.3f, variance %.3f\n", double(o.depth),
                    overlap ? "overlap" : "no overlap", mean, var);
        EXPECT_NEAR(mean, o.depth, 0.02 * o.depth);
        if (overlap) {
            EXPECT_NEAR(var / mean, 1.0, 0.1);
        } else {
            EXPECT_LT(var / mean, 0.95);
            EXPECT_GT(var / mean, 0.5);
        }
    }
}

// By default no two fibers overlap: every pair of axes lies at least a diameter apart (as
// real fibers), up to the packing a random sequential addition reaches; denser slabs are
// refused unless overlap is asked for.
TEST(Slab, FibersDoNotOverlapUnlessAskedTo) {
    for (float depth : {5.0f, 10.0f, 14.0f}) {
        SlabOptions o;
        o.depth = depth;
        const Hair h = make_slab(o);
        std::vector<glm::vec2> axes;
        for (const auto& s : h.strands) axes.push_back({s.front().y, s.front().z});
        std::sort(axes.begin(), axes.end(), [](const glm::vec2& a, const glm::vec2& b) { return a.x < b.x; });
        float closest = 1e9f;
        for (std::size_t i = 0; i < axes.size(); ++i)
            for (std::size_t j = i + 1; j < axes.size() && axes[j].x - axes[i].x < 2 * o.radius; ++j)
                closest = std::min(closest, glm::length(axes[j] - axes[i]));
        std::printf("[ figures ] slab depth %g: packing %.3f, closest axes %.5f apart (diameter %.5f)\n",
                    double(depth), o.packing(), double(closest), double(2 * o.radius));
        EXPECT_GE(closest, 2 * o.radius * (1 - 1e-5f)) << depth;
    }
    SlabOptions dense;
    dense.depth = 20;  // 63 % of the section
    EXPECT_THROW(make_slab(dense), std::invalid_argument);
    dense.overlap = true;
    EXPECT_EQ(int(make_slab(dense).strands.size()), dense.strand_count());
}

// Where the segment from the eye to p crosses the plane z = z0.
glm::vec3 at_z(const glm::vec3& eye, const glm::vec3& p, float z0) {
    return eye + (p - eye) * ((z0 - eye.z) / (p.z - eye.z));
}

TEST(SlabScene, TheBackLightHidesBehindTheSlab) {
    SlabOptions o;
    o.back_lit = true;
    LightingOptions l;
    const SceneDescription d = make_slab_scene(o, l);
    EXPECT_EQ(d.name, "slab");
    EXPECT_TRUE(d.meshes.empty());  // no ground
    ASSERT_TRUE(d.light.has_value());
    const AreaLight& a = *d.light;
    EXPECT_NEAR(a.normal().z, 1.0f, 1e-6f);  // toward the slab and the camera
    EXPECT_NEAR(a.corner.z, -kSlabBackLightDistance, 1e-6f);
    EXPECT_NEAR(std::sqrt(a.area()), l.light_size, 1e-5f);
    EXPECT_NEAR(a.corner.y + 0.5f * (a.edge_u + a.edge_v).y, 0.5f * o.height, 1e-5f);  // centred
    // Each sightline to the light enters the slab's box through its back face inside it,
    // so the camera sees the light only through the gaps between fibers.
    for (const glm::vec3& corner : {a.corner, a.corner + a.edge_u, a.corner + a.edge_v, a.corner + a.edge_u + a.edge_v}) {
        const glm::vec3 q = at_z(d.camera.eye, corner, -0.5f * o.thickness);
        EXPECT_LT(std::abs(q.x), 0.5f * o.width);
        EXPECT_GT(q.y, 0.0f);
        EXPECT_LT(q.y, o.height);
    }
    // The slab in view.
    for (const auto& s : d.hair.strands)
        for (const glm::vec3& p : s) ASSERT_TRUE(in_view(d.camera, p, 4.0f / 3.0f));
    // Front-lit: the usual light above and in front, emitting downward.
    o.back_lit = false;
    const SceneDescription front = make_slab_scene(o, l);
    ASSERT_TRUE(front.light.has_value());
    EXPECT_NEAR(front.light->normal().y, -1.0f, 1e-6f);
    EXPECT_GT(front.light->corner.z, 0.0f);
}

TEST(Scenes, FurAndSlabRenderHair) {
    const FurOptions fur;  // the default 20,000 strands: fewer leave the body mostly bare
    SlabOptions slab;
    slab.back_lit = true;
    RenderOptions ro;
    ro.width = 32;
    ro.height = 24;
    ro.spp = 1;
    for (const SceneDescription& d : {make_fur_scene(fur, LightingOptions{}), make_slab_scene(slab, LightingOptions{})})
        for (Integrator i : {Integrator::kSingle, Integrator::kDual, Integrator::kPath}) {
            SceneDescription copy = d;
            const Scene scene(std::move(copy));
            ShadingOptions so;
            so.dual_scattering = i == Integrator::kDual;
            const ShadingSetup shading(scene, so);
            ro.integrator = i;
            const RenderResult r = render::render(scene, shading, ro);
            EXPECT_GT(r.hair_pixels, std::size_t(ro.width * ro.height) / 10) << d.name;
            EXPECT_EQ(r.dropped, 0u) << d.name;
        }
}

// The showcase bust: the strands root on the scalp and never enter the head, neck or
// shoulders; they fall from above the head to below the neck (onto the shoulders); the
// parting shows: on either side of it the strands leave in opposite directions; and it
// renders with hair filling a good part of the image.
HeadOptions small_head() {
    HeadOptions o;
    o.count = 3000;
    o.clumps = 60;
    return o;
}

TEST(Head, StrandsStayOutsideTheBodyAndFallToTheShoulders) {
    const HeadOptions o = small_head();
    const Hair hair = make_head(o);
    ASSERT_EQ(hair.strands.size(), std::size_t(o.count));
    const std::vector<Ellipsoid> body = o.body();
    std::size_t inside = 0, reach_shoulders = 0;
    for (const auto& s : hair.strands) {
        // The root on the head ellipsoid.
        const glm::vec3 q = (s[0] - body[0].center) / body[0].radii;
        EXPECT_NEAR(glm::length(q), 1.0f, 1e-4f);
        for (std::size_t k = 1; k < s.size(); ++k)
            for (const Ellipsoid& e : body) inside += e.push_out(s[k], o.radius) != s[k];
        reach_shoulders += s.back().y < body[2].center.y + body[2].radii.y;
    }
    EXPECT_EQ(inside, 0u);
    EXPECT_GT(reach_shoulders, hair.strands.size() / 2);
    EXPECT_EQ(make_head(o).strands, hair.strands);  // deterministic
}

TEST(Head, StrandsLeaveThePartingOnBothSides) {
    HeadOptions o = small_head();
    o.clump = 0;
    o.frizz = 0;
    const Hair hair = make_head(o);
    int left = 0, right = 0, wrong = 0;
    for (const auto& s : hair.strands) {
        const glm::vec3 root = s[0] - o.center;
        if (root.y < 0.7f || root.z < 0 || std::abs(root.x - o.parting) > 0.25f) continue;  // near the parting, on top
        const float dx = s[1].x - s[0].x;
        const bool right_of_part = root.x > o.parting;
        (right_of_part ? right : left) += 1;
        wrong += right_of_part ? dx < 0 : dx > 0;
    }
    EXPECT_GT(left, 20);
    EXPECT_GT(right, 20);
    EXPECT_EQ(wrong, 0);
}

TEST(Head, TheShowcaseRendersHair) {
    LightingOptions l;
    l.env = "studio";
    l.light_power = 0;
    SceneDescription d = make_head_scene(small_head(), l);
    d.environment_map = load_environment(l);
    const Scene scene(std::move(d));
    const ShadingSetup shading(scene, ShadingOptions{});
    RenderOptions ro;
    ro.width = 48;
    ro.height = 27;
    ro.spp = 1;
    ro.integrator = Integrator::kPath;
    const RenderResult r = render::render(scene, shading, ro);
    EXPECT_GT(r.hair_pixels, std::size_t(ro.width * ro.height) / 16);
    EXPECT_EQ(r.dropped, 0u);
    HeadOptions bad = small_head();
    bad.clump = 2;
    EXPECT_NE(refusal([&] { validate(bad); }).find("--clump"), std::string::npos);
    bad = small_head();
    bad.length = 0;
    EXPECT_NE(refusal([&] { validate(bad); }).find("--hair-length"), std::string::npos);
    bad = small_head();
    bad.frizz = NAN;
    EXPECT_NE(refusal([&] { validate(bad); }).find("--frizz"), std::string::npos);
    EXPECT_EQ(refusal([&] { validate(small_head()); }), "");
}

TEST(Scenes, BadFurAndSlabOptionsNameTheirFlag) {
    const auto fur = [](auto change) {
        FurOptions o;
        change(o);
        return refusal([&] { validate(o); });
    };
    EXPECT_EQ(fur([](FurOptions&) {}), "");
    EXPECT_NE(fur([](FurOptions& o) { o.count = 0; }).find("--fur-hairs"), std::string::npos);
    EXPECT_NE(fur([](FurOptions& o) { o.length = 0; }).find("--fur-length"), std::string::npos);
    EXPECT_NE(fur([](FurOptions& o) { o.length = NAN; }).find("--fur-length"), std::string::npos);
    EXPECT_NE(fur([](FurOptions& o) { o.tilt_deg = 90; }).find("--fur-tilt"), std::string::npos);
    EXPECT_NE(fur([](FurOptions& o) { o.tilt_deg = -1; }).find("--fur-tilt"), std::string::npos);
    EXPECT_NE(fur([](FurOptions& o) { o.radius = 0; }).find("--fiber-radius"), std::string::npos);

    struct Case {
        float depth, radius;
        bool back_lit;
        float light_size, light_power;
        const char* flag;  // nullptr: accepted
    };
    const Case cases[] = {
        {5, 0.01f, true, 2, 1, nullptr},
        {0, 0.01f, false, 2, 1, "--slab-depth"},
        {INFINITY, 0.01f, false, 2, 1, "--slab-depth"},
        {1e6f, 0.01f, false, 2, 1, "--slab-depth"},  // 2.5·10^8 strands
        {5, -0.01f, false, 2, 1, "--fiber-radius"},
        {5, 1, false, 2, 1, "--fiber-radius"},
        {5, 0.01f, true, 7, 1, "--light-size"},  // would show beside the slab
        {5, 0.01f, false, 7, 1, nullptr},        // a front light of any size is fine
        {5, 0.01f, true, 7, 0, nullptr},         // and so is no light
    };
    for (const Case& c : cases) {
        SlabOptions o;
        o.depth = c.depth, o.radius = c.radius, o.back_lit = c.back_lit;
        LightingOptions l;
        l.light_size = c.light_size, l.light_power = c.light_power;
        const std::string m = refusal([&] { validate(o, l); });
        if (c.flag) EXPECT_NE(m.find(c.flag), std::string::npos) << c.flag << ": " << m;
        else EXPECT_EQ(m, "");
    }
}

}  // namespace
