// The fur fibre's lobe controls (FurControls, models/fur.hpp): the defaults change nothing;
// a gain scales its lobe's energy and nothing else (R, TT, TRT through lobe_split, S through
// eval_scattered, the residual through what is left), a tint per channel; sample's weight
// stays eval / pdf under controls; bad controls are named.
#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include <hairscatter/models/fur.hpp>

namespace hs = hairscatter;

namespace {

using V3 = glm::dvec3;

hs::FurParams<double> medulla_params() {
    hs::FurParams<double> p;
    p.cortex.sigma_a = V3(0.5447, 0.9061, 1.781);
    p.kappa = 0.6;
    p.sigma_s = 10;
    p.g = 0.3;
    return p;
}

const V3 kWo = glm::normalize(V3(0.3, 0.8, 0.2));
const V3 kWi = glm::normalize(V3(-0.2, -0.5, 0.7));
constexpr double kH = 0.37;

void expect_near(const V3& a, const V3& b, double tol, const std::string& what) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], tol * std::fmax(1.0, std::fabs(b[c]))) << what << " channel " << c;
}

}  // namespace

TEST(FurControls, DefaultsChangeNothing) {
    const hs::FurMaterial<double> plain(medulla_params()), controlled(medulla_params(), hs::FurControls<double>());
    const hs::FurFiber<double> a(plain, kH), b(controlled, kH);
    EXPECT_EQ(a.eval(kWo, kWi), b.eval(kWo, kWi));
    EXPECT_EQ(a.pdf(kWo, kWi), b.pdf(kWo, kWi));
    EXPECT_FALSE(controlled.has_lobe_weights());
}

// Gain 2 on R, TT or TRT doubles that lobe's A_p and adds A_p to the albedo, nothing else.
TEST(FurControls, AGainScalesItsLobe) {
    const hs::FurMaterial<double> plain(medulla_params());
    const hs::FurFiber<double> base(plain, kH);
    const auto split = base.lobe_split(kWo);
    const V3 albedo = base.albedo(kWo);
    for (int p = 0; p < 3; ++p) {
        hs::FurControls<double> c;
        c.lobes.gain[p] = 2;
        const hs::FurMaterial<double> m(medulla_params(), c);
        const hs::FurFiber<double> f(m, kH);
        const auto s = f.lobe_split(kWo);
        expect_near(s.a[p], 2.0 * split.a[p], 1e-12, "A_p of lobe " + std::to_string(p));
        expect_near(f.albedo(kWo), albedo + split.a[p], 1e-12, "albedo, lobe " + std::to_string(p));
        for (int q = 0; q < 4; ++q)
            if (q != p) expect_near(s.a[q], split.a[q], 1e-12, "another lobe's A, lobe " + std::to_string(p));
    }
}

// S's gain scales eval_scattered and adds its energy to the residual's entry of lobe_split;
// the residual's gain leaves S alone.
TEST(FurControls, TheMedullaLobesGainAndTint) {
    const hs::FurMaterial<double> plain(medulla_params());
    const hs::FurFiber<double> base(plain, kH);
    const V3 s0 = base.eval_scattered(kWo, kWi);
    ASSERT_GT(s0.x, 0.0);
    hs::FurControls<double> c;
    c.gain_s = 2;
    c.tint_s = V3(1, 0.5, 0);
    const hs::FurMaterial<double> m(medulla_params(), c);
    const hs::FurFiber<double> f(m, kH);
    expect_near(f.eval_scattered(kWo, kWi), V3(2, 1, 0) * s0, 1e-12, "f_S");
    expect_near(f.eval(kWo, kWi) - f.eval_scattered(kWo, kWi), base.eval(kWo, kWi) - s0, 1e-12, "the other lobes");
    const V3 gained = f.albedo(kWo) - base.albedo(kWo);
    expect_near(f.lobe_split(kWo).a[3] - base.lobe_split(kWo).a[3], gained, 1e-12, "the residual's entry");
    EXPECT_GT(gained.x, 0.0);
    EXPECT_LT(gained.z, 0.0);  // tint 0: S's blue is gone

    // (A thin medulla: through the dense one the residual's T³ leaves nothing to scale.)
    hs::FurParams<double> thin = medulla_params();
    thin.kappa = 0.3;
    thin.sigma_s = 1;
    hs::FurControls<double> r;
    r.lobes.gain[3] = 2;
    const hs::FurMaterial<double> thin_plain(thin), mr(thin, r);
    const hs::FurFiber<double> fb(thin_plain, kH), fr(mr, kH);
    expect_near(fr.eval_scattered(kWo, kWi), fb.eval_scattered(kWo, kWi), 1e-12, "f_S under the residual's gain");
    const V3 residual = fr.albedo(kWo) - fb.albedo(kWo);  // the residual's own energy
    for (int ch = 0; ch < 3; ++ch) EXPECT_GT(residual[ch], 0.0);
    expect_near(fr.lobe_split(kWo).a[3] - fb.lobe_split(kWo).a[3], residual, 1e-12, "the residual's entry");
}

// Sampling follows the controls: every sample's weight is eval / pdf and its pdf is pdf().
TEST(FurControls, SampleWeightIsEvalOverPdfUnderControls) {
    hs::FurControls<double> c;
    c.lobes.gain[0] = 3;
    c.lobes.tint[1] = V3(1, 0.2, 0.2);
    c.lobes.override_alpha(2, 0.1);
    c.gain_s = 0.5;
    const hs::FurMaterial<double> m(medulla_params(), c);
    const hs::FurFiber<double> f(m, kH);
    int checked = 0;
    for (int i = 0; i < 400; ++i) {
        const glm::dvec4 u((i % 20 + 0.5) / 20, std::fmod(i * 0.618034, 1.0), std::fmod(i * 0.414214, 1.0),
                           std::fmod(i * 0.732051, 1.0));
        const auto s = f.sample(kWo, u);
        if (!(s.pdf > 0)) continue;
        ++checked;
        EXPECT_NEAR(s.pdf, f.pdf(kWo, s.wi), 1e-9 * s.pdf);
        expect_near(s.weight, f.eval(kWo, s.wi) / s.pdf, 1e-9, "weight");
    }
    EXPECT_GT(checked, 350);
}

TEST(FurControls, BadControlsAreNamed) {
    hs::FurControls<double> c;
    c.gain_s = -1;
    c.tint_s.g = 2e6;
    c.lobes.gain[1] = -2;
    const std::string m = hs::validate(c);
    for (const char* name : {"gain_s", "tint_s.g", "gain_tt"}) EXPECT_NE(m.find(name), std::string::npos) << m;
    EXPECT_THROW(hs::FurMaterial<double>(medulla_params(), c), std::invalid_argument);
    EXPECT_TRUE(hs::validate(hs::FurControls<double>()).empty());
}
