// Parameter validation, and absorption from pigments or colour.
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

namespace hs = hairscatter;

namespace {
hs::FiberParams<double> good() {
    hs::FiberParams<double> p;
    p.sigma_a = hs::sigma_a_from_concentrations(1.3, 0.2);
    return p;
}
// The message must name the field so a user knows what to fix.
void expect_error(const hs::FiberParams<double>& p, const std::string& field) {
    const std::string m = hs::validate(p);
    EXPECT_NE(m.find(field), std::string::npos) << "message: '" << m << "'";
    EXPECT_THROW(hs::ChiangMaterial<double>{p}, std::invalid_argument);
}
const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();
}  // namespace

TEST(FiberParams, DefaultsAreValid) {
    EXPECT_EQ(hs::validate(good()), "");
    EXPECT_EQ(hs::validate(hs::FiberParams<float>{}), "");
    EXPECT_NO_THROW(hs::ChiangMaterial<double>{good()});
}

TEST(FiberParams, RejectsEachBadKind) {
    for (double eta : {1.0, 0.9, -1.5, kNaN, kInf}) {
        auto p = good();
        p.eta = eta;
        expect_error(p, "eta");
    }
    for (double b : {0.0, -0.1, 1.01, kNaN}) {
        auto p = good();
        p.beta_m = b;
        expect_error(p, "beta_m");
        p = good();
        p.beta_n = b;
        expect_error(p, "beta_n");
    }
    for (double a : {0.5, -0.5, kNaN, kInf}) {
        auto p = good();
        p.alpha = a;
        expect_error(p, "alpha");
    }
    for (int c = 0; c < 3; ++c)
        for (double s : {-1e-3, kNaN, kInf}) {
            auto p = good();
            p.sigma_a[c] = s;
            expect_error(p, std::string("sigma_a.") + "rgb"[c]);
        }
}

TEST(FiberParams, ReportsEveryBadFieldAtOnce) {
    hs::FiberParams<double> p;
    p.eta = 1.0;
    p.beta_m = 2.0;
    const std::string m = hs::validate(p);
    EXPECT_NE(m.find("eta"), std::string::npos);
    EXPECT_NE(m.find("beta_m"), std::string::npos);
}

TEST(FiberParams, BoundaryValuesAreValid) {
    auto p = good();
    p.beta_m = 1.0;
    p.beta_n = 1.0;
    p.alpha = -hs::kMaxCuticleTilt<double>;
    p.eta = 1.0000001;
    p.sigma_a = glm::dvec3(0.0);
    EXPECT_EQ(hs::validate(p), "");
}

TEST(ChiangFiber, RejectsOffsetOutsideFiber) {
    const hs::ChiangMaterial<double> m(good());
    EXPECT_THROW(hs::ChiangFiber<double>::checked(m, 1.01), std::invalid_argument);
    EXPECT_THROW(hs::ChiangFiber<double>::checked(m, kNaN), std::invalid_argument);
    EXPECT_EQ(hs::ChiangFiber<double>::checked(m, -1.0).h(), -1.0);
    // The device-side constructor clamps instead: hit offsets round slightly outside.
    EXPECT_EQ(hs::ChiangFiber<double>(m, 1.0000001).h(), 1.0);
    EXPECT_EQ(hs::ChiangFiber<double>(m, -3.0).h(), -1.0);
}

TEST(SigmaA, FromMelaninIsLinearInConcentrations) {
    const glm::dvec3 e = hs::sigma_a_from_concentrations(1.0, 0.0), ph = hs::sigma_a_from_concentrations(0.0, 1.0);
    EXPECT_DOUBLE_EQ(e.r, 0.419);
    EXPECT_DOUBLE_EQ(e.b, 1.37);
    EXPECT_DOUBLE_EQ(ph.g, 0.4);
    const glm::dvec3 mix = hs::sigma_a_from_concentrations(2.0, 0.5);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(mix[c], 2 * e[c] + 0.5 * ph[c], 1e-15);
}

// Chiang et al. 2016 eq. 9 inverted by hand: c = exp(-sqrt(σa) · poly(βn)).
TEST(SigmaA, FromColorInvertsChiangFit) {
    for (double bn : {0.1, 0.3, 0.8, 1.0}) {
        const glm::dvec3 c(0.8, 0.4, 0.1);
        const glm::dvec3 s = hs::sigma_a_from_color(c, bn);
        const double poly = 5.969 - 0.215 * bn + 2.532 * bn * bn - 10.73 * std::pow(bn, 3) +
                            5.574 * std::pow(bn, 4) + 0.245 * std::pow(bn, 5);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(std::exp(-std::sqrt(s[k]) * poly), c[k], 1e-12);
    }
    EXPECT_EQ(hs::sigma_a_from_color(glm::dvec3(1.0), 0.3), glm::dvec3(0.0));
}

TEST(SigmaA, FromColorRejectsOutOfRange) {
    EXPECT_THROW(hs::sigma_a_from_color(glm::dvec3(0.0, 0.5, 0.5), 0.3), std::invalid_argument);
    EXPECT_THROW(hs::sigma_a_from_color(glm::dvec3(0.5, 1.5, 0.5), 0.3), std::invalid_argument);
    EXPECT_THROW(hs::sigma_a_from_color(glm::dvec3(0.5, 0.5, kNaN), 0.3), std::invalid_argument);
    EXPECT_THROW(hs::sigma_a_from_color(glm::dvec3(0.5), 0.0), std::invalid_argument);
}
