// Spectral rendering: the melanin spectra against their published formula and the RGB
// coefficients, the checks on bad input, and the N-channel Chiang fiber: the RGB model bit
// for bit at N = 3, lossless at N = 1 and 4, sampled as its pdf says, finite everywhere.
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include <hairscatter/fiber/spectral.hpp>
#include <hairscatter/models/chiang_spectral.hpp>

#include "support/chi2.hpp"

namespace hs = hairscatter;

namespace {

constexpr double kPi = 3.14159265358979323846;

template <typename T> glm::vec<3, T> dir(double theta, double phi) {
    return glm::vec<3, T>(T(std::sin(theta)), T(std::cos(theta) * std::cos(phi)), T(std::cos(theta) * std::sin(phi)));
}

template <typename T> bool same_bits(T a, T b) { return std::memcmp(&a, &b, sizeof a) == 0; }

template <typename T> hs::FiberParams<T> params(double beta_m, double beta_n, double alpha_deg, glm::dvec3 sigma_a) {
    hs::FiberParams<T> p;
    p.beta_m = T(beta_m);
    p.beta_n = T(beta_n);
    p.alpha = hs::radians(T(alpha_deg));
    p.sigma_a = glm::vec<3, T>(sigma_a);
    return p;
}

// The RGB model and the 3-channel one over random materials (with and without lobe
// controls), offsets and directions: every output the same bits.
template <typename T, hs::LobeSet K> void expect_rgb_bit_for_bit() {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u01(0, 1);
    int compared = 0, differ = 0;
    auto check = [&](T a, T b) {
        ++compared;
        differ += same_bits(a, b) ? 0 : 1;
    };
    for (int m = 0; m < 24; ++m) {
        const auto p = params<T>(0.02 + 0.95 * u01(rng), 0.02 + 0.95 * u01(rng), 4 * u01(rng) - 2,
                                 glm::dvec3(4 * u01(rng), 4 * u01(rng), 4 * u01(rng)));
        hs::LobeControls<T> c;
        if (m % 3 == 1) {
            c.gain[1] = T(0.5);
            c.tint[2] = glm::vec<3, T>(T(1), T(0.5), T(0.2));
        }
        const hs::ChiangMaterial<T> mat(p, c);
        const hs::SpectralValues<T, 3> sigma{{p.sigma_a.x, p.sigma_a.y, p.sigma_a.z}};
        for (int i = 0; i < 100; ++i) {
            const T h = T(2 * u01(rng) - 1);
            const hs::BasicChiangFiber<T, K> rgb(mat, h);
            const hs::BasicChiangSpectralFiber<T, 3, K> spectral(mat, h, sigma);
            const auto wo = dir<T>(std::asin(2 * u01(rng) - 1), 2 * kPi * u01(rng));
            const auto wi = dir<T>(std::asin(2 * u01(rng) - 1), 2 * kPi * u01(rng));
            const glm::vec<4, T> u(T(u01(rng)), T(u01(rng)), T(u01(rng)), T(u01(rng)));
            const auto e = rgb.eval_pdf(wo, wi);
            const auto es = spectral.eval_pdf(wo, wi);
            const auto f = rgb.eval(wo, wi);
            const auto fs = spectral.eval(wo, wi);
            check(e.pdf, es.pdf);
            check(rgb.pdf(wo, wi), spectral.pdf(wo, wi));
            const auto s = rgb.sample(wo, u);
            const auto ss = spectral.sample(wo, u);
            const auto b = rgb.at(wo).sample(u);
            const auto bs = spectral.at(wo).sample(u);
            const auto be = rgb.at(wo).eval_pdf(wi);
            const auto bes = spectral.at(wo).eval_pdf(wi);
            const auto a = rgb.albedo(wo);
            const auto as = spectral.albedo(wo);
            check(s.pdf, ss.pdf);
            check(b.pdf, bs.pdf);
            check(be.pdf, bes.pdf);
            EXPECT_EQ(s.lobe, ss.lobe);
            EXPECT_EQ(b.lobe, bs.lobe);
            for (int q = 0; q < 3; ++q) {
                check(e.f[q], es.f[q]);
                check(f[q], fs[q]);
                check(s.wi[q], ss.wi[q]);
                check(s.weight[q], ss.weight[q]);
                check(b.wi[q], bs.wi[q]);
                check(b.weight[q], bs.weight[q]);
                check(be.f[q], bes.f[q]);
                check(a[q], as[q]);
            }
        }
    }
    EXPECT_EQ(differ, 0) << differ << " of " << compared << " results differ";
}

// ∫ eval dω per channel over the sphere (cubature in (sinθi, φ)).
template <typename Fiber> std::vector<double> integral(const Fiber& fiber, const glm::vec<3, typename Fiber::Real>& wo, int c) {
    using T = typename Fiber::Real;
    const chi2::CellIntegrator integrate(
        [&](double x, double phi) {
            const double r = std::sqrt(std::max(0.0, 1 - x * x));
            return double(fiber.eval(wo, glm::vec<3, T>(T(x), T(r * std::cos(phi)), T(r * std::sin(phi))))[c]);
        },
        2, 5);
    double total = 0;
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 16; ++j)
            total += integrate.integrate(-1 + i * 0.25, -1 + (i + 1) * 0.25, -kPi + j * kPi / 8, -kPi + (j + 1) * kPi / 8);
    return {total};
}

}  // namespace

// The spectra are Donner & Jensen 2006's power laws: 6.6e10 λ^-3.33 and 2.9e14 λ^-4.75 mm⁻¹,
// here against the formula evaluated in long double and a few of its values written out.
TEST(MelaninSpectra, MatchThePublishedFormula) {
    for (long double lambda : {360.0L, 400.0L, 450.0L, 500.0L, 550.0L, 600.0L, 650.0L, 700.0L, 830.0L}) {
        const long double e = 6.6e10L * std::pow(lambda, -3.33L), p = 2.9e14L * std::pow(lambda, -4.75L);
        EXPECT_NEAR(hs::eumelanin_absorption_per_mm(double(lambda)) / double(e), 1.0, 1e-13) << double(lambda);
        EXPECT_NEAR(hs::pheomelanin_absorption_per_mm(double(lambda)) / double(p), 1.0, 1e-13) << double(lambda);
        EXPECT_NEAR(hs::eumelanin_absorption_per_mm(float(lambda)) / float(e), 1.0f, 3e-6f) << double(lambda);
        EXPECT_NEAR(hs::pheomelanin_absorption_per_mm(float(lambda)) / float(p), 1.0f, 3e-6f) << double(lambda);
    }
    EXPECT_NEAR(hs::eumelanin_absorption_per_mm(500.0), 67.91627, 1e-4);
    EXPECT_NEAR(hs::pheomelanin_absorption_per_mm(500.0), 43.88241, 1e-4);
    EXPECT_NEAR(hs::eumelanin_absorption_per_mm(650.0), 28.34931, 1e-4);
    EXPECT_NEAR(hs::pheomelanin_absorption_per_mm(650.0), 12.62001, 1e-4);
}

// "RGB agrees with spectral": at the reference wavelengths, σa of the spectra is the RGB
// coefficients of sigma_a_from_concentrations within 1.1 %, for each pigment alone and for
// mixes (both are linear in the concentrations with non-negative coefficients).
TEST(MelaninSpectra, AgreeWithRgbAtTheReferenceWavelengths) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> conc(0, 8);
    for (int k = 0; k < 200; ++k) {
        const double ce = k == 0 ? 1 : (k == 1 ? 0 : conc(rng)), cp = k == 0 ? 0 : (k == 1 ? 1 : conc(rng));
        const glm::dvec3 rgb = hs::sigma_a_from_concentrations(ce, cp);
        for (int c = 0; c < 3; ++c) {
            const double s = hs::sigma_a_from_concentrations_at(ce, cp, hs::rgb_reference_wavelength<double>(c));
            EXPECT_NEAR(s / rgb[c], 1.0, 0.011) << "ce " << ce << " cp " << cp << " channel " << c;
        }
    }
    // The fit is not loose: some coefficient is more than 1 % off (a looser bound would hide
    // a change of the constants).
    const double r = hs::sigma_a_from_concentrations_at(1.0, 0.0, hs::rgb_reference_wavelength<double>(0)) / 0.419;
    EXPECT_GT(std::abs(r - 1), 0.01);
}

TEST(MelaninSpectra, BadInputIsRefusedByName) {
    using V4 = hs::SpectralValues<double, 4>;
    const V4 good{{400, 500, 600, 700}};
    EXPECT_NO_THROW(hs::spectral_sigma_a(hs::MelaninConcentrations<double>{1.3, 0.2}, good));
    auto message = [&](hs::MelaninConcentrations<double> c, const V4& l) {
        try {
            hs::spectral_sigma_a(c, l);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(message({-0.1, 0.2}, good).find("eumelanin = -0.1 is outside its range"), std::string::npos)
        << message({-0.1, 0.2}, good);
    EXPECT_NE(message({1, std::nan("")}, good).find("pheomelanin"), std::string::npos);
    const std::string m = message({1, 0}, V4{{400, 300, 600, 900}});
    EXPECT_NE(m.find("wavelength[1] (nm) = 300 is outside its range [360, 830]"), std::string::npos) << m;
    EXPECT_NE(m.find("wavelength[3] (nm) = 900"), std::string::npos) << m;
    EXPECT_EQ(m.find("wavelength[0]"), std::string::npos) << m;
    EXPECT_NE(message({1, 0}, V4{{400, std::nan(""), 600, 700}}).find("wavelength[1]"), std::string::npos);
    // Per hit nothing throws: out-of-range input is clamped (NaN to the lower end).
    const auto clamped = hs::clamped_spectral_sigma_a(hs::MelaninConcentrations<double>{-1, std::nan("")},
                                                      V4{{300, 900, std::nan(""), 500}});
    for (int c = 0; c < 4; ++c) EXPECT_EQ(clamped[c], 0.0);
    const auto edge = hs::clamped_spectral_sigma_a(hs::MelaninConcentrations<double>{1, 0}, V4{{300, 900, std::nan(""), 500}});
    // Not bit for bit: with a constant wavelength the compiler may fold the log (Clang does),
    // where the clamped path calls libm's at run time, and the power law's exponent (3.33)
    // turns one ulp of log λ into about 7 ulps of σa. 1e-13 relative is far below any
    // clamping mistake (1 nm changes σa by about 1 %).
    const auto near = [](double a, double b) { return std::abs(a - b) <= 1e-13 * std::abs(b); };
    EXPECT_PRED2(near, edge[0], hs::sigma_a_from_concentrations_at(1.0, 0.0, 360.0));
    EXPECT_PRED2(near, edge[1], hs::sigma_a_from_concentrations_at(1.0, 0.0, 830.0));
    EXPECT_EQ(edge[2], edge[0]);
    EXPECT_PRED2(near, edge[3], hs::sigma_a_from_concentrations_at(1.0, 0.0, 500.0));
}

TEST(MelaninSpectra, UniformWavelengthsAreStratified) {
    for (double u : {0.0, 0.1, 0.5, 0.93, 1.0}) {
        const auto l = hs::sample_uniform_wavelengths<double, 4>(u);
        for (int c = 0; c < 4; ++c) {
            EXPECT_TRUE(hs::wavelength_in_range(l[c])) << l[c];
            // One per quarter of the range, from u's position in it.
            const double x = std::fmod((l[c] - 360) / 470 - u - c / 4.0 + 2, 1.0);
            EXPECT_TRUE(x < 1e-12 || x > 1 - 1e-12) << u << " " << c << " " << l[c];
        }
    }
    EXPECT_DOUBLE_EQ(hs::uniform_wavelength_pdf<double>(), 1.0 / 470);
}

TEST(SpectralChiang, ThreeChannelsAreTheRgbModelBitForBit) {
    expect_rgb_bit_for_bit<float, hs::LobeSet::kAll>();
    expect_rgb_bit_for_bit<double, hs::LobeSet::kAll>();
    expect_rgb_bit_for_bit<float, hs::LobeSet::kR | hs::LobeSet::kTRT>();
    expect_rgb_bit_for_bit<double, hs::LobeSet::kTT | hs::LobeSet::kResidual>();
    expect_rgb_bit_for_bit<float, hs::LobeSet::kR>();
}

// σa = 0: every channel integrates to 1 (N = 1 and N = 4), and with absorption each
// channel's integral is its albedo, which falls as σa grows.
TEST(SpectralChiang, FurnaceIsLosslessPerChannel) {
    const hs::ChiangMaterial<double> mat(params<double>(0.3, 0.3, 2, glm::dvec3(0)));
    for (double theta : {-70.0, 0.0, 35.0}) {
        const auto wo = dir<double>(theta * kPi / 180, 0.3);
        const hs::ChiangSpectralFiber<double, 1> one(mat, 0.3, hs::SpectralValues<double, 1>{{0.0}});
        EXPECT_NEAR(integral(one, wo, 0)[0], 1.0, 1e-5) << theta;
        EXPECT_NEAR(one.albedo(wo)[0], 1.0, 1e-12) << theta;
        const hs::ChiangSpectralFiber<double, 4> lossless(mat, -0.6, hs::SpectralValues<double, 4>::filled(0.0));
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(integral(lossless, wo, c)[0], 1.0, 1e-5) << theta << " " << c;
        const auto sigma = hs::spectral_sigma_a(hs::MelaninConcentrations<double>{0.8, 0.3},
                                                hs::sample_uniform_wavelengths<double, 4>(0.2));
        const hs::ChiangSpectralFiber<double, 4> absorbing(mat, -0.6, sigma);
        const auto a = absorbing.albedo(wo);
        for (int c = 0; c < 4; ++c) {
            EXPECT_NEAR(integral(absorbing, wo, c)[0], a[c], 1e-5) << theta << " " << c;
            EXPECT_LT(a[c], 1.0);
        }
        // The shortest wavelength absorbs most.
        int shortest = 0;
        for (int c = 1; c < 4; ++c) shortest = sigma[c] > sigma[shortest] ? c : shortest;
        for (int c = 0; c < 4; ++c) EXPECT_LE(a[shortest], a[c]);
    }
}

// The sampler against the pdf (chi-square, the contract's harness) for a 4-wavelength fiber
// with melanin, stateless and bound, and each sample's weight is eval / pdf per channel.
TEST(SpectralChiang, SamplesFollowThePdf) {
    const hs::ChiangMaterial<double> mat(params<double>(0.3, 0.4, 2, glm::dvec3(0)));
    const auto sigma =
        hs::spectral_sigma_a(hs::MelaninConcentrations<double>{1.3, 0.2}, hs::SpectralValues<double, 4>{{420, 520, 610, 700}});
    const hs::ChiangSpectralFiber<double, 4> fiber(mat, 0.35, sigma);
    chi2::Options options;
    options.num_tests = 4;
    for (double theta : {-30.0, 60.0}) {
        const auto wo = dir<double>(theta * kPi / 180, 0.7);
        const auto bound = fiber.at(wo);
        const chi2::Result stateless = chi2::test([&](const glm::dvec4& u) { return fiber.sample(wo, u).wi; },
                                                  [&](const glm::dvec3& wi) { return fiber.pdf(wo, wi); }, options);
        EXPECT_TRUE(stateless.passed) << stateless.report;
        const chi2::Result at = chi2::test([&](const glm::dvec4& u) { return bound.sample(u).wi; },
                                           [&](const glm::dvec3& wi) { return fiber.pdf(wo, wi); }, options);
        EXPECT_TRUE(at.passed) << at.report;
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> u01(0, 1);
        for (int k = 0; k < 1000; ++k) {
            const glm::dvec4 u(u01(rng), u01(rng), u01(rng), u01(rng));
            const auto s = fiber.sample(wo, u);
            ASSERT_GT(s.pdf, 0);
            const auto e = fiber.eval_pdf(wo, s.wi);
            EXPECT_NEAR(s.pdf, e.pdf, 1e-12 * e.pdf);
            for (int c = 0; c < 4; ++c) EXPECT_NEAR(s.weight[c], e.f[c] / e.pdf, 1e-12 * (1 + s.weight[c]));
        }
    }
}

// Extreme but valid materials, σa from 0 to 10⁶, grazing and polar directions and every
// offset: every output finite and non-negative, for N = 1, 4 and 8 in float and double.
template <typename T, int N> void expect_finite_sweep() {
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u01(0, 1);
    int bad = 0;
    auto ok = [&](T x) { bad += std::isfinite(double(x)) && x >= T(0) ? 0 : 1; };
    for (double beta : {1e-3, 0.05, 0.3, 1.0})
        for (double sigma_scale : {0.0, 1e-3, 1.0, 1e2, 1e6}) {
            const hs::ChiangMaterial<T> mat(params<T>(beta, 1.0 - 0.9 * beta, 8 * u01(rng) - 4, glm::dvec3(0)));
            hs::SpectralValues<T, N> sigma;
            for (int c = 0; c < N; ++c) sigma[c] = T(sigma_scale * (c + 1) / N);
            for (double h : {-1.0, -0.999, -0.3, 0.0, 0.7, 1.0}) {
                const hs::ChiangSpectralFiber<T, N> fiber(mat, T(h), sigma);
                for (double theta : {-90.0, -89.9, -45.0, 0.0, 30.0, 89.99, 90.0}) {
                    const auto wo = dir<T>(theta * kPi / 180, 2 * kPi * u01(rng));
                    for (int k = 0; k < 20; ++k) {
                        const auto wi = dir<T>(std::asin(2 * u01(rng) - 1), 2 * kPi * u01(rng));
                        const glm::vec<4, T> u(T(u01(rng)), T(u01(rng)), T(u01(rng)), T(u01(rng)));
                        const auto e = fiber.eval_pdf(wo, wi);
                        const auto s = fiber.sample(wo, u);
                        const auto a = fiber.albedo(wo);
                        ok(e.pdf);
                        ok(s.pdf);
                        for (int c = 0; c < N; ++c) {
                            ok(e.f[c]);
                            ok(s.weight[c]);
                            ok(a[c]);
                        }
                    }
                }
            }
        }
    EXPECT_EQ(bad, 0);
    // Non-finite input: nothing, as in every model.
    const hs::ChiangMaterial<T> mat(params<T>(0.3, 0.3, 2, glm::dvec3(0)));
    const hs::ChiangSpectralFiber<T, N> fiber(mat, T(0.2), hs::SpectralValues<T, N>::filled(T(0.5)));
    const T nan = std::numeric_limits<T>::quiet_NaN();
    const glm::vec<3, T> wo = dir<T>(0.3, 0.2), bad_w(nan, T(0), T(1));
    EXPECT_EQ(fiber.pdf(bad_w, wo), T(0));
    EXPECT_EQ(fiber.eval(wo, bad_w)[0], T(0));
    EXPECT_EQ(fiber.sample(wo, glm::vec<4, T>(nan)).lobe, hs::SampledLobe::kNone);
    EXPECT_FALSE(fiber.at(bad_w).valid());
    // σa below 0 or not finite is taken as 0 (the lower end, as FiberParamBounds::clamp).
    const T inf = std::numeric_limits<T>::infinity();
    hs::SpectralValues<T, N> odd = hs::SpectralValues<T, N>::filled(T(0));
    for (int c = 0; c < N; ++c) odd[c] = c % 4 == 0 ? nan : (c % 4 == 1 ? T(-1) : (c % 4 == 2 ? inf : -inf));
    const hs::ChiangSpectralFiber<T, N> clamped(mat, T(0.2), odd),
        zero(mat, T(0.2), hs::SpectralValues<T, N>::filled(T(0)));
    const auto wi = dir<T>(-0.4, 2.5);
    for (int c = 0; c < N; ++c) EXPECT_EQ(clamped.eval(wo, wi)[c], zero.eval(wo, wi)[c]) << c;
    EXPECT_EQ(fiber.at(bad_w).sample(glm::vec<4, T>(T(0.5))).pdf, T(0));
}

TEST(SpectralChiang, FiniteAndNonNegativeEverywhere) {
    expect_finite_sweep<float, 1>();
    expect_finite_sweep<float, 4>();
    expect_finite_sweep<float, 8>();
    expect_finite_sweep<double, 1>();
    expect_finite_sweep<double, 4>();
    expect_finite_sweep<double, 8>();
}

// One channel of an N-channel fiber is the same bits whatever the other channels hold: the
// channels share nothing but the geometry (and the lobe choice, which the pdf carries).
TEST(SpectralChiang, ChannelsAreIndependent) {
    const hs::ChiangMaterial<float> mat(params<float>(0.25, 0.35, 2, glm::dvec3(0)));
    const hs::SpectralValues<float, 4> a{{0.1f, 0.7f, 2.0f, 0.4f}}, b{{0.1f, 3.0f, 0.0f, 9.0f}};
    const hs::ChiangSpectralFiber<float, 4> fa(mat, 0.4f, a), fb(mat, 0.4f, b);
    const hs::ChiangSpectralFiber<float, 1> one(mat, 0.4f, hs::SpectralValues<float, 1>{{0.1f}});
    for (int k = 0; k < 50; ++k) {
        const auto wo = dir<float>(0.03 * k - 0.7, 0.1 * k), wi = dir<float>(0.5 - 0.02 * k, 2.0 - 0.09 * k);
        EXPECT_TRUE(same_bits(fa.eval(wo, wi)[0], fb.eval(wo, wi)[0]));
        EXPECT_TRUE(same_bits(fa.eval(wo, wi)[0], one.eval(wo, wi)[0]));
    }
}
