// Tests of the environment maps: the sampler's directions follow its pdf (chi-square) and
// the pdf follows the map's luminance, a constant map renders the constant environment's
// image within noise with every integrator, and a bad file is refused naming --env and
// the file.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

#include <common/image_io.hpp>
#include <support/chi2.hpp>

#include "environment.hpp"
#include "render.hpp"
#include "scenes.hpp"
#include "shading.hpp"

namespace {

using namespace render;

// A small map with a bright "sun" pixel, a gradient and a black band: a pdf far from uniform.
LatLongMap test_map() {
    LatLongMap m;
    m.name = "test";
    m.width = 32;
    m.height = 16;
    m.rgb.assign(std::size_t(m.width * m.height * 3), 0.0f);
    for (int y = 0; y < m.height; ++y)
        for (int x = 0; x < m.width; ++x) {
            float* p = &m.rgb[std::size_t(3 * (y * m.width + x))];
            const float v = y >= 10 && y < 12 ? 0.0f : 0.1f + 0.05f * float(x % 7) + 0.02f * float(y);
            p[0] = v, p[1] = 0.5f * v, p[2] = 2.0f * v;
        }
    float* sun = &m.rgb[std::size_t(3 * (3 * m.width + 20))];
    sun[0] = sun[1] = sun[2] = 40.0f;
    return m;
}

chi2::Result chi_square(const Environment& env, const std::function<double(const glm::dvec3&)>& pdf, int tests) {
    chi2::Options opt;
    opt.samples = 200000;
    // The map's pixel edges cross the cells: a shallower cubature keeps the test fast, and
    // the pdf still integrates to 1 within 2e-3 (checked below).
    opt.max_depth = 4;
    opt.num_tests = tests;
    return chi2::test(
        [&](const glm::dvec4& u) {
            const Environment::Sample s = env.sample(float(u.x), float(u.y));
            return s.pdf > 0 ? glm::dvec3(s.wi) : glm::dvec3(0);
        },
        pdf, opt);
}

TEST(EnvironmentMap, SampledDirectionsFollowThePdf) {
    const Environment maps[] = {Environment(test_map(), 0.0f, 1.0f), Environment(test_map(), 73.0f, 2.0f),
                                Environment(make_studio_map(128), -30.0f, 1.0f)};
    for (const Environment& env : maps) {
        const chi2::Result r = chi_square(env, [&](const glm::dvec3& w) { return double(env.pdf(glm::vec3(w))); }, 3);
        std::printf("environment chi2: p = %.4f, statistic %.1f, dof %d, integral of the pdf %.5f\n", r.p_value,
                    r.statistic, r.dof, r.expected_total);
        EXPECT_TRUE(r.passed) << r.report;
        EXPECT_NEAR(r.expected_total, 1.0, 2e-3);
    }
}

TEST(EnvironmentMap, AUniformPdfFailsTheTest) {  // the negative control: the test can fail
    const Environment env(test_map(), 0.0f, 1.0f);
    const chi2::Result r = chi_square(env, [](const glm::dvec3&) { return 1.0 / (4 * chi2::kPi); }, 1);
    EXPECT_FALSE(r.passed);
}

TEST(EnvironmentMap, PdfIsProportionalToLuminance) {
    // Away from the poles, pdf / luminance is the same for every lit pixel: sampling is by
    // luminance, the sin θ of the marginal cancels the lat-long map's area element.
    const LatLongMap m = test_map();
    const Environment env(m, 0.0f, 1.0f);
    double ratio0 = 0;
    for (int y = 4; y < 12; ++y)
        for (int x = 0; x < m.width; ++x) {
            const glm::vec2 uv((float(x) + 0.5f) / float(m.width), (float(y) + 0.5f) / float(m.height));
            const glm::vec3 d = env.from_map(uv);
            const glm::vec3 L = env.radiance(d);
            const float lum = 0.2126f * L.x + 0.7152f * L.y + 0.0722f * L.z;
            if (lum <= 0) {
                EXPECT_EQ(env.pdf(d), 0.0f);
                continue;
            }
            const double ratio = double(env.pdf(d)) / double(lum);
            if (ratio0 == 0) ratio0 = ratio;
            EXPECT_NEAR(ratio / ratio0, 1.0, 1e-4) << x << ", " << y;
        }
    // A sample's pdf is the pdf of its direction, and its radiance the map's there.
    for (float u : {0.1f, 0.37f, 0.5f, 0.93f}) {
        const Environment::Sample s = env.sample(u, 1 - u * u);
        ASSERT_GT(s.pdf, 0);
        EXPECT_NEAR(s.pdf / env.pdf(s.wi), 1.0f, 1e-3f);
        EXPECT_EQ(s.Le, env.radiance(s.wi));
    }
}

TEST(EnvironmentMap, RotationTurnsTheMapAboutUp) {
    const Environment a(test_map(), 0.0f, 1.0f), b(test_map(), 90.0f, 1.0f);
    const glm::vec3 d = glm::normalize(glm::vec3(0.3f, 0.4f, -0.8f));
    const glm::vec3 turned(d.z, d.y, -d.x);  // d turned 90° about +y, from +z toward +x
    EXPECT_EQ(a.radiance(d), b.radiance(turned));
    EXPECT_NEAR(a.pdf(d), b.pdf(turned), 1e-6f * a.pdf(d));
}

// A constant map and the constant environment light a block alike: the map's sampler
// draws other directions (rows weighted by sin θ at their centres, not exactly uniform),
// so the images agree within noise, not bit for bit.
TEST(EnvironmentMap, AConstantMapRendersTheConstantEnvironment) {
    BlockOptions block;
    block.count = 400;
    LightingOptions lighting;
    lighting.light_power = 0;  // the environment alone
    lighting.environment = 0.5f;
    LatLongMap flat;
    flat.width = 64;
    flat.height = 32;
    flat.rgb.assign(std::size_t(flat.width * flat.height * 3), 0.5f);
    for (Integrator integrator : {Integrator::kSingle, Integrator::kDual, Integrator::kPath}) {
        RenderOptions o;
        o.integrator = integrator;
        o.width = 40;
        o.height = 30;
        o.spp = 32;
        double mean[2] = {0, 0};
        for (int with_map = 0; with_map < 2; ++with_map) {
            SceneDescription d = make_block_scene(block, lighting);
            if (with_map) d.environment_map = std::make_shared<const Environment>(flat, 40.0f, 1.0f);
            const Scene scene(std::move(d));
            ShadingOptions so;
            so.dual_scattering = integrator == Integrator::kDual;
            const ShadingSetup shading(scene, so);
            const RenderResult r = render::render(scene, shading, o);
            for (float v : r.rgb) mean[with_map] += double(v);
            mean[with_map] /= double(r.rgb.size());
        }
        std::printf("environment: %s, constant %.5f, constant map %.5f (%+.2f %%)\n", to_string(integrator), mean[0],
                    mean[1], 100 * (mean[1] / mean[0] - 1));
        EXPECT_NEAR(mean[1] / mean[0], 1.0, 0.02) << to_string(integrator);
    }
}

std::string temp_path(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("hairscatter_env_" + name)).string();
}

// Expects read_lat_long_exr (or the Environment it makes) to refuse the file with a
// message naming --env, the file and `reason`.
void expect_refused(const std::string& path, const std::string& reason) {
    try {
        const Environment env(read_lat_long_exr(path), 0.0f, 1.0f);
        ADD_FAILURE() << path << " was accepted";
    } catch (const std::invalid_argument& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("--env " + path), std::string::npos) << m;
        EXPECT_NE(m.find(reason), std::string::npos) << m;
    }
}

TEST(EnvironmentMap, BadFilesAreRefusedNamingTheFile) {
    expect_refused(temp_path("missing.exr"), "cannot open");
    {
        const std::string p = temp_path("text.exr");
        std::FILE* f = std::fopen(p.c_str(), "w");
        std::fputs("not an image", f);
        std::fclose(f);
        expect_refused(p, "cannot read it as OpenEXR");
    }
    {  // a luminance-only file
        const std::string p = temp_path("y_only.exr");
        std::vector<float> y(8 * 4, 1.0f);
        Imf::Header h(8, 4);
        h.channels().insert("Y", Imf::Channel(Imf::FLOAT));
        Imf::FrameBuffer fb;
        fb.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(y.data()), sizeof(float), 8 * sizeof(float)));
        Imf::OutputFile out(p.c_str(), h);
        out.setFrameBuffer(fb);
        out.writePixels(4);
    }
    expect_refused(temp_path("y_only.exr"), "no R channel");
    auto write = [](const std::string& name, int w, int h, float value) {
        const std::string p = temp_path(name);
        hairscatter_examples::write_exr_rgb(p, w, h, std::vector<float>(std::size_t(w * h * 3), value), {});
        return p;
    };
    expect_refused(write("black.exr", 8, 4, 0.0f), "the map is black");
    expect_refused(write("nan.exr", 8, 4, std::numeric_limits<float>::quiet_NaN()), "not finite");
    expect_refused(write("negative.exr", 8, 4, -1.0f), "negative");
    expect_refused(write("square.exr", 8, 8, 1.0f), "not a lat-long map");
    // and a good one is read back as written
    const LatLongMap m = read_lat_long_exr(write("good.exr", 8, 4, 0.25f));
    EXPECT_EQ(m.width, 8);
    EXPECT_EQ(m.height, 4);
    EXPECT_EQ(m.rgb[5], 0.25f);
}

}  // namespace
