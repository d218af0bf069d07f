// FurFiber (models/fur.hpp): with no medulla it is ChiangFiber; the lossless fibre keeps
// every bit of energy; sample draws the pdf (chi-square, with a negative control) and its
// weight is eval / pdf; finite output at the parameters' extremes; bad parameters named;
// the tables built valid; and the model against the physical fur reference's cache
// (tests/data/physical_fur.txt, written by `physical_fur_tool cache`).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include <hairscatter/models/chiang.hpp>
#include <hairscatter/models/fur.hpp>

#include "support/chi2.hpp"
#include "support/physical_fur_cases.hpp"

namespace hs = hairscatter;

namespace {

constexpr double kPi = 3.14159265358979323846;
using Tab = hs::detail::RoughCortexTables<double>;  // (the values' indices: the same for float)

template <typename T>
hs::FurParams<T> fur_params(double kappa, double sigma_s, double g, glm::dvec3 sigma_a, bool rough_cortex = false) {
    hs::FurParams<T> p;
    p.rough_cortex = rough_cortex;
    p.kappa = T(kappa);
    p.sigma_s = T(sigma_s);
    p.g = T(g);
    p.cortex.sigma_a = glm::vec<3, T>(sigma_a);
    return p;
}

glm::dvec3 random_direction(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> uni(0, 1);
    const double z = 1 - 2 * uni(rng), r = std::sqrt(std::max(0.0, 1 - z * z)), phi = 2 * kPi * uni(rng);
    return {z, r * std::cos(phi), r * std::sin(phi)};
}

glm::dvec3 direction(double theta_deg, double phi = 0) {
    const double t = theta_deg * kPi / 180;
    return {std::sin(t), std::cos(t) * std::cos(phi), std::cos(t) * std::sin(phi)};
}

// ∫ eval(wo, ·) over the sphere: midpoint in sinθ and φ (every lobe at β 0.3 is many cells wide).
template <typename Fiber> glm::dvec3 integrate(const Fiber& fiber, const glm::dvec3& wo, int n = 600) {
    using T = typename Fiber::Real;
    glm::dvec3 sum(0.0);
    const auto at = fiber.at(glm::vec<3, T>(wo));
    for (int i = 0; i < n; ++i) {
        const double x = -1 + (i + 0.5) * 2.0 / n, c = std::sqrt(1 - x * x);
        for (int j = 0; j < 2 * n; ++j) {
            const double phi = -kPi + (j + 0.5) * kPi / n;
            sum += glm::dvec3(at.eval(glm::vec<3, T>(T(x), T(c * std::cos(phi)), T(c * std::sin(phi)))));
        }
    }
    return sum * (2.0 / n) * (kPi / n);
}

}  // namespace

// κ = 0: the medulla is absent and FurFiber is ChiangFiber: f, pdf, albedo and the sampled
// directions agree within 1e-4 relative (float and double) over random parameters and
// directions, σs^m and g ignored.
template <typename T> void kappa_zero_is_chiang(double tol) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> uni(0, 1);
    using V3 = glm::vec<3, T>;
    double worst = 0;
    for (int m = 0; m < 6; ++m) {
        hs::FurParams<T> p = fur_params<T>(0, 10 * uni(rng), 0.5, glm::dvec3(2 * uni(rng), uni(rng), 0.3 * uni(rng)));
        p.cortex.beta_m = T(0.1 + 0.8 * uni(rng));
        p.cortex.beta_n = T(0.1 + 0.8 * uni(rng));
        p.cortex.alpha = T((uni(rng) - 0.5) * 0.15);
        const hs::FurMaterial<T> fur_mat(p);
        const hs::ChiangMaterial<T> chiang_mat(p.cortex);
        for (double h : {-0.9, -0.2, 0.0, 0.5, 0.99}) {
            const hs::FurFiber<T> fur(fur_mat, T(h));
            const hs::ChiangFiber<T> chiang(chiang_mat, T(h));
            for (int k = 0; k < 200; ++k) {
                const V3 wo(random_direction(rng)), wi(random_direction(rng));
                const glm::dvec3 a(fur.eval(wo, wi)), b(chiang.eval(wo, wi));
                for (int c = 0; c < 3; ++c) {
                    const double e = std::fabs(a[c] - b[c]) / std::max(b[c], 1e-3);
                    worst = std::max(worst, e);
                    EXPECT_LE(e, tol) << "f channel " << c << " h " << h;
                }
                const double pa = fur.pdf(wo, wi), pb = chiang.pdf(wo, wi);
                EXPECT_LE(std::fabs(pa - pb), tol * std::max(pb, 1e-3)) << "pdf h " << h;
                const glm::dvec3 aa(fur.albedo(wo)), ab(chiang.albedo(wo));
                for (int c = 0; c < 3; ++c) EXPECT_NEAR(aa[c], ab[c], tol * ab[c] + 1e-12);
                const glm::vec<4, T> u(T(uni(rng)), T(uni(rng)), T(uni(rng)), T(uni(rng)));
                const hs::HairSample<T> sa = fur.sample(wo, u), sb = chiang.sample(wo, u);
                EXPECT_LE(glm::length(glm::dvec3(sa.wi - sb.wi)), 100 * tol) << "sample h " << h;
            }
        }
    }
    std::printf("[ fur ] κ = 0 against Chiang: worst relative difference of f %.2e\n", worst);
}
TEST(FurFiber, KappaZeroIsChiangDouble) { kappa_zero_is_chiang<double>(1e-4); }
TEST(FurFiber, KappaZeroIsChiangFloat) { kappa_zero_is_chiang<float>(1e-4); }

// σa^c = σa^m = 0: albedo 1 within 1e-3 at every offset and inclination (by construction:
// the extinction's loss from the unscattered lobes is the scattered lobe's energy), and the
// integral of eval over the sphere equals the albedo (every lobe's shape normalised); with
// the smooth and the rough cortex.
TEST(FurFiber, LosslessFurnace) {
    double worst_albedo = 0, worst_integral = 0;
    for (bool rough : {false, true})
    for (double kappa : {0.3, 0.6, 0.9})
        for (double sigma_s : {1.0, 10.0})
            for (double g : {0.0, 0.5}) {
                const hs::FurMaterial<double> mat(fur_params<double>(kappa, sigma_s, g, glm::dvec3(0), rough));
                for (double h : {-0.95, -0.3, 0.0, 0.4, 0.8})
                    for (double theta : {-80.0, -30.0, 0.0, 45.0, 75.0}) {
                        const hs::FurFiber<double> fiber(mat, h);
                        const glm::dvec3 a = fiber.albedo(direction(theta));
                        for (int c = 0; c < 3; ++c) worst_albedo = std::max(worst_albedo, std::fabs(a[c] - 1));
                        EXPECT_NEAR(a.x, 1, 1e-3) << kappa << " " << sigma_s << " " << h << " " << theta;
                    }
                if (g == 0) {
                    const hs::FurFiber<double> fiber(mat, 0.4);
                    const glm::dvec3 wo = direction(30);
                    const glm::dvec3 i = integrate(fiber, wo);
                    worst_integral = std::max(worst_integral, std::fabs(i.x - fiber.albedo(wo).x));
                    EXPECT_NEAR(i.x, fiber.albedo(wo).x, 1e-3) << "κ " << kappa << " σs " << sigma_s;
                }
            }
    std::printf("[ fur ] lossless: worst |albedo − 1| %.2e, worst |∫ eval − albedo| %.2e\n", worst_albedo, worst_integral);
}

// The rough cortex (FurParams::rough_cortex) moves light from TT into the orders past TRT,
// and its facets reflect less than the smooth boundary: lossless, no medulla, averaged over
// h, at θo 0°, 30° and 75°, the residual's share grows several times (light trapped by total
// internal reflection at tilted facets) and TT falls, the more the nearer grazing; R falls
// below the smooth F (the facets seen from wo and Smith's masking of their reflections),
// by more than a quarter at 75°, where the smooth cylinder reflects 0.36; its walk's shares
// of the entered light add up to 1 at every node, its tail ratio lies in [0, 1), and its
// entry reflectance over the smooth F in (0, 1.2]. Both with the facets from β (GGX 0.182 at
// β_m 0.3) and with GGX 0.17 facets (FurParams::facet_alpha).
TEST(FurFiber, RoughCortexTrapsLightPastTRT) {
    const hs::FurMaterial<double> smooth(fur_params<double>(0, 0, 0, glm::dvec3(0)));
    for (double facet_alpha : {0.0, 0.17}) {  // the facets from β, and GGX 0.17
        hs::FurParams<double> rough_params = fur_params<double>(0, 0, 0, glm::dvec3(0), true);
        rough_params.facet_alpha = facet_alpha;
        const hs::FurMaterial<double> rough(rough_params);
        double previous_drop = 0;
        for (double theta : {0.0, 30.0, 75.0}) {
            double a[2][4] = {};
            constexpr int kH = 400;
            for (int k = 0; k < kH; ++k)
                for (int r = 0; r < 2; ++r) {
                    const auto s = hs::FurFiber<double>(r ? rough : smooth, -1 + (k + 0.5) * 2.0 / kH).lobe_split(direction(theta));
                    for (int p = 0; p < 4; ++p) a[r][p] += s.a[p].x / kH;
                }
            std::printf("[ fur ] rough cortex (facet α %.2f), θo %2.0f°: R %.3f / %.3f, TT %.3f / %.3f, TRT %.3f / %.3f,"
                        " later %.3f / %.3f (smooth / rough)\n", facet_alpha, theta, a[0][0], a[1][0], a[0][1], a[1][1], a[0][2],
                        a[1][2], a[0][3], a[1][3]);
            EXPECT_LT(a[1][0], a[0][0]);
            if (theta > 60) {
                EXPECT_LT(a[1][0], 0.75 * a[0][0]);
            }
            EXPECT_GT(a[1][3], 4 * a[0][3]);
            EXPECT_GT(a[1][3], 0.05);
            const double drop = a[0][1] - a[1][1];
            EXPECT_GT(drop, previous_drop);
            previous_drop = drop;
        }
        const auto& t = rough.rough_cortex();
        const double v = hs::longitudinal_variance(rough_params.cortex.beta_m);
        for (int i = 0; i < Tab::kTheta; ++i)
            std::printf("[ fur ] θo node %2d: TRT v %.3f (4v %.3f) δ %+.1f°, residual v %.3f δ %+.1f°\n", i,
                        t.share[i][0][Tab::kVTRT], 4 * v, std::asin(t.share[i][0][Tab::kSinDeltaTRT]) * 180 / kPi,
                        t.share[i][0][Tab::kVRes], std::asin(t.share[i][0][Tab::kSinDeltaRes]) * 180 / kPi);
        for (const auto& row : t.share)
            for (const auto& node : row) {
                EXPECT_NEAR(node[Tab::kTT] + node[Tab::kTRT] + node[Tab::kLater], 1.0, 1e-9);
                EXPECT_GE(node[Tab::kTailRatio], 0.0);
                EXPECT_LT(node[Tab::kTailRatio], 1.0);
                EXPECT_GT(node[Tab::kFr], 0.0);
                EXPECT_LE(node[Tab::kFr], 1.2);
                // R's tail (fit_deon_tail): a weight, and a lobe no narrower than the core; the
                // core within the fit's range about the quartiles' lobe
                EXPECT_GE(node[Tab::kTailWeightR], 0.0);
                EXPECT_LE(node[Tab::kTailWeightR], 1.0);
                if (node[Tab::kTailWeightR] > 0) {
                    EXPECT_GE(node[Tab::kTailR], node[Tab::kVR] * (1 - 1e-12));
                }
                EXPECT_GE(node[Tab::kVR], node[Tab::kQuartileVR] / 4 * (1 - 1e-12));
                EXPECT_LE(node[Tab::kVR], node[Tab::kQuartileVR] * 4 * (1 + 1e-12));
                // TRT's and the residual's lobes from the walk (fit_deon_lobe_l1): a variance
                // and a turn of less than a right angle
                EXPECT_GT(node[Tab::kVTRT], 0.0);
                EXPECT_GT(node[Tab::kVRes], 0.0);
                EXPECT_LT(std::fabs(node[Tab::kSinDeltaTRT]), 1.0);
                EXPECT_LT(std::fabs(node[Tab::kSinDeltaRes]), 1.0);
                for (int c = 0; c < 3; ++c) {  // lossless, no medulla: the later orders leave, unscattered
                    EXPECT_NEAR(node[Tab::kLaterOut + c], node[Tab::kLater], 1e-12);
                    EXPECT_EQ(node[Tab::kLaterScatter + c], 0.0);
                }
            }
    }
}

// R's shape on the rough cortex: the d'Eon lobe fitted to its reflections' quartiles of
// sin θi (deon_lobe_from_quartiles) recovers a lobe from its own quartiles, the pole's
// included, and the table's R narrows toward the rim, where a facet's longitudinal slope
// turns the reflection by 2a cos γ only (v_R ≈ v cos²γ at θo 0°; a single v per lobe, as
// Chiang's, fails this).
TEST(FurFiber, RoughCortexRLobeFromItsFacets) {
    for (double v : {1e-3, 0.02, 0.0846, 0.3})
        for (double theta_c : {-1.3, -0.5, 0.0}) {
            const hs::DeonLongitudinal<double> lobe(v);
            constexpr int kN = 200000;
            std::vector<double> cdf(kN + 1, 0.0);
            for (int k = 0; k < kN; ++k) {  // midpoint rule over θi, weight M cos θi
                const double t = -0.5 * kPi + kPi * (k + 0.5) / kN, c = std::cos(t);
                cdf[std::size_t(k) + 1] = cdf[std::size_t(k)] + lobe.eval(std::sin(t), c, -std::sin(theta_c), std::cos(theta_c)) * c;
            }
            double q[3];
            for (int j = 0; j < 3; ++j) {
                const auto at = std::lower_bound(cdf.begin(), cdf.end(), 0.25 * (j + 1) * cdf[kN]);
                q[j] = std::sin(-0.5 * kPi + kPi * double(at - cdf.begin()) / kN);
            }
            const hs::detail::DeonLobeFit fit = hs::detail::deon_lobe_from_quartiles(q[0], q[1], q[2]);
            // (the fit's own rule, 32 midpoints over the lobe's cdf, is good to ~0.3° near the
            // pole; the quartiles of a node's 2,000 reflections are noisier than that)
            EXPECT_NEAR(fit.v, v, 0.02 * v) << "v " << v << " θc " << theta_c;
            EXPECT_NEAR(fit.theta_c, theta_c, 1e-2) << "v " << v << " θc " << theta_c;
        }
    const hs::FurMaterial<double> rough(fur_params<double>(0, 0, 0, glm::dvec3(0), true));
    const auto& t = rough.rough_cortex();
    const double v = hs::longitudinal_variance(0.3);
    constexpr int kMid = hs::detail::RoughCortexTables<double>::kTheta / 2, kH = hs::detail::RoughCortexTables<double>::kH;
    static_assert(hs::detail::RoughCortexTables<double>::kTheta % 2 == 1, "a node at θo = 0");
    std::printf("[ fur ] rough cortex, θo 0°: v_R / v over |h| =");
    for (int j = 0; j < kH; ++j) std::printf(" %.3f", t.share[kMid][j][Tab::kQuartileVR] / v);
    std::printf("\n");
    EXPECT_NEAR(t.share[kMid][0][Tab::kQuartileVR] / v, 1.0, 0.1);  // the axis: Chiang's v (2,000 walks: ~3 % noise)
    for (int j = 1; j < kH; ++j) EXPECT_LT(t.share[kMid][j][Tab::kQuartileVR], 1.05 * t.share[kMid][j - 1][Tab::kQuartileVR]) << "node " << j;
    EXPECT_LT(t.share[kMid][kH - 1][Tab::kQuartileVR] / v, 0.1);  // the rim
}

// R's azimuth on the rough cortex (RoughCortexTables' ψ_R): the facets' reflections turn
// toward wo where the mean surface meets the light at grazing incidence, so the median turn
// is about 0 on the axis (by symmetry; within the walk's noise, 2°), rises toward the rim,
// and at a given |h| rises toward grazing θo; and the fibre's R lobe is centred on
// −2γ + sign(h) ψ_R: its azimuthal mean over φ moves toward 0 by ψ_R on both sides.
TEST(FurFiber, RoughCortexTurnsRTowardTheLight) {
    const hs::FurMaterial<double> rough(fur_params<double>(0, 0, 0, glm::dvec3(0), true));
    const auto& t = rough.rough_cortex();
    constexpr int kTheta = hs::detail::RoughCortexTables<double>::kTheta, kH = hs::detail::RoughCortexTables<double>::kH;
    constexpr int kMid = kTheta / 2;
    const double deg = 180 / kPi;
    for (int i = kMid; i < kTheta - 1; ++i) {
        std::printf("[ fur ] rough cortex, node θo %4.1f°: ψ_R over γ =", (2.0 * i / (kTheta - 1) - 1) * 1.5 * deg);
        for (int j = 0; j < kH; ++j) std::printf(" %.1f°", t.share[i][j][Tab::kPsiR] * deg);
        std::printf("\n");
        EXPECT_LT(std::fabs(t.share[i][0][Tab::kPsiR]) * deg, 2.0) << "node " << i;
        EXPECT_GT(t.share[i][kH - 1][Tab::kPsiR], t.share[i][kH / 2][Tab::kPsiR] + 5 / deg) << "node " << i;
        if (i > kMid) {
            EXPECT_GT(t.share[i][kH - 2][Tab::kPsiR], t.share[i - 1][kH - 2][Tab::kPsiR] - 1 / deg) << "node " << i;
        }
    }
    EXPECT_GT(t.share[kTheta - 2][kH / 2][Tab::kPsiR] * deg, 10.0);  // θo 71.6°, γ 45°
    // The fibre's R: its N_R about the turned centre, seen in eval with the other lobes off.
    hs::FurControls<double> only_r;
    for (int l = 1; l < 4; ++l) only_r.lobes.gain[l] = 0;
    only_r.gain_s = 0;
    const hs::FurMaterial<double> r_only(fur_params<double>(0, 0, 0, glm::dvec3(0), true), only_r);
    for (double h : {-0.9, 0.9}) {
        const hs::FurFiber<double> fiber(r_only, h);
        const glm::dvec3 wo = direction(75);
        double best = -1, best_phi = 0;
        for (int k = 0; k < 3600; ++k) {  // the peak of f over φ in the plane of R's centre
            const double phi = -kPi + (k + 0.5) * 2 * kPi / 3600;
            const double f = fiber.eval(wo, direction(-75, phi)).x;
            if (f > best) best = f, best_phi = phi;
        }
        const double gamma = std::asin(h), smooth = -2 * gamma;
        std::printf("[ fur ] θo 75°, h %+.1f: R peaks at φ %.1f°, the smooth mirror's %.1f°\n", h, best_phi * deg, smooth * deg);
        EXPECT_LT(std::fabs(best_phi), std::fabs(smooth) - 10 / deg) << h;
        EXPECT_GT(best_phi * smooth, 0.0) << h;
    }
}

// TT's azimuth on the rough cortex (RoughCortexTables' ψ_TT): the walk follows each chord
// round the section (a chord at γ' to the normal turns the position by π − 2γ') and takes the
// exit's turn from the smooth cylinder's Φ(1, h). Nearly smooth, untilted facets (GGX 0.002)
// give back the smooth cylinder, ψ_TT within 0.5° at every node up to θo 60° and γ 67.5° (a
// check of that geometry, not only of symmetry); with the default facets ψ_TT is about 0 on the axis (by
// symmetry, within the walk's noise) and grows toward the rim, where the facets wo sees lean
// toward it and refract the light less far round; and the fibre's TT lobe is centred on
// Φ(1, h) + sign(h) ψ_TT.
// The rough cortex on nearly smooth, untilted facets (GGX 0.002, no cuticle tilt): its walk
// should give back the smooth cylinder's geometry.
namespace {
hs::FurParams<double> nearly_smooth_facets(double kappa, double sigma_s) {
    hs::FurParams<double> p = fur_params<double>(kappa, sigma_s, 0, glm::dvec3(0), true);
    p.cortex.alpha = 0;
    p.facet_alpha = 0.002;
    return p;
}
}  // namespace

TEST(FurFiber, RoughCortexTurnsTTByItsFacets) {
    constexpr int kTheta = hs::detail::RoughCortexTables<double>::kTheta, kH = hs::detail::RoughCortexTables<double>::kH;
    constexpr int kMid = kTheta / 2;
    const double deg = 180 / kPi;
    const hs::FurMaterial<double> smooth(nearly_smooth_facets(0, 0)), rough(fur_params<double>(0, 0, 0, glm::dvec3(0), true));
    for (int i = 0; i < kTheta; ++i) {
        const double theta = (2.0 * i / (kTheta - 1) - 1) * 1.5;
        std::printf("[ fur ] node θo %5.1f°: ψ_TT over γ, smooth facets / default =", theta * deg);
        for (int j = 0; j < kH; ++j)
            std::printf(" %.1f°/%.1f°", smooth.rough_cortex().share[i][j][Tab::kPsiTT] * deg, rough.rough_cortex().share[i][j][Tab::kPsiTT] * deg);
        std::printf("\n");
        if (std::fabs(theta) > 60 / deg) continue;
        // (up to γ 67.5°: nearer the rim a refraction out of the fibre turns by η cos γt / cos γ
        // times its facet's tilt, and even GGX 0.002 turns TT by degrees there)
        for (int j = 0; j < kH - 2; ++j) EXPECT_LT(std::fabs(smooth.rough_cortex().share[i][j][Tab::kPsiTT]) * deg, 0.5) << i << " " << j;
        EXPECT_LT(std::fabs(rough.rough_cortex().share[i][0][Tab::kPsiTT]) * deg, 2.0) << "node " << i;
    }
    const auto& t = rough.rough_cortex();
    EXPECT_GT(std::fabs(t.share[kMid][kH - 2][Tab::kPsiTT]), std::fabs(t.share[kMid][kH / 2][Tab::kPsiTT]) + 2 / deg);
    // The fibre's TT at a node (θo 0.5 rad, γ 78.75°), the other lobes off: its peak over φ.
    hs::FurControls<double> only_tt;
    for (int l = 0; l < 4; ++l) only_tt.lobes.gain[l] = l == 1 ? 1.0 : 0.0;
    only_tt.gain_s = 0;
    const hs::FurMaterial<double> tt_only(fur_params<double>(0, 0, 0, glm::dvec3(0), true), only_tt);
    const int i = kMid + 2, j = kH - 2;
    const double theta = 0.5, gamma = kPi / 2 * j / (kH - 1);
    const double eta_p = std::sqrt(1.55 * 1.55 - std::sin(theta) * std::sin(theta)) / std::cos(theta);
    for (double sign : {-1.0, 1.0}) {
        const double h = sign * std::sin(gamma), gamma_t = std::asin(h / eta_p);
        const double smooth_phi = std::remainder(2 * gamma_t - 2 * std::asin(h) + kPi, 2 * kPi);
        const double expected = std::remainder(smooth_phi + sign * t.share[i][j][Tab::kPsiTT], 2 * kPi);
        const hs::FurFiber<double> fiber(tt_only, h);
        double best = -1, best_phi = 0;
        for (int k = 0; k < 7200; ++k) {
            const double phi = -kPi + (k + 0.5) * 2 * kPi / 7200;
            const double f = fiber.eval(direction(theta * deg), direction(-theta * deg, phi)).x;
            if (f > best) best = f, best_phi = phi;
        }
        std::printf("[ fur ] θo %.1f°, h %+.3f: TT peaks at φ %.2f°, Φ(1, h) %.2f°, turned %.2f°\n", theta * deg, h, best_phi * deg,
                    smooth_phi * deg, expected * deg);
        EXPECT_NEAR(std::remainder(best_phi - expected, 2 * kPi) * deg, 0.0, 0.2) << h;
    }
}

// TRT's azimuth and TT's and TRT's azimuthal widths from the same walk (RoughCortexTables:
// ψ_TRT, the median turn of TRT's exits from the smooth cylinder's Φ(2, h), and s_TT, s_TRT,
// the logistic scales of their turns' mean absolute deviations about the median). Nearly smooth, untilted facets
// give back the smooth cylinder: ψ_TRT within 0.5° of 0 and both widths under 0.02 rad up to
// θo 60° and γ 56.25° (GGX 0.002 turns the chords by thousandths of a radian), which checks
// TRT's geometry (two chords carry the light by 2π − 2γ'_1 − 2γ'_2). With the facets β
// implies, TRT is wider than TT wherever |θo| ≤ 45° and γ ≤ 67.5°, by more than half again: a
// facet tilted by δ across the fibre turns a reflected chord by 2δ and a refracted one by
// about δ (1 − 1/η). And the fibre's N_TRT is that logistic about the turned centre: with only
// TRT on, its eval over φ peaks at Φ(2, h) ± ψ_TRT and falls to 3/4 of the peak at s_TRT ln 3
// from it (a logistic's quartiles lie at ±s ln 3), at a node.
TEST(FurFiber, RoughCortexSpreadsTTAndTRTByItsFacets) {
    constexpr int kTheta = hs::detail::RoughCortexTables<double>::kTheta, kH = hs::detail::RoughCortexTables<double>::kH;
    constexpr int kMid = kTheta / 2;
    const double deg = 180 / kPi;
    const hs::FurMaterial<double> smooth(nearly_smooth_facets(0, 0)), rough(fur_params<double>(0, 0, 0, glm::dvec3(0), true));
    const auto& s = smooth.rough_cortex();
    const auto& t = rough.rough_cortex();
    for (int i = 0; i < kTheta; ++i) {
        const double theta = (2.0 * i / (kTheta - 1) - 1) * 1.5;
        std::printf("[ fur ] node θo %5.1f°: over γ, ψ_TRT smooth / default, s_TT, s_TRT default =", theta * deg);
        for (int j = 0; j < kH; ++j)
            std::printf(" %.1f°/%.1f° %.3f %.3f", s.share[i][j][Tab::kPsiTRT] * deg, t.share[i][j][Tab::kPsiTRT] * deg, t.share[i][j][Tab::kScaleTT], t.share[i][j][Tab::kScaleTRT]);
        std::printf("\n");
        if (std::fabs(theta) > 60 / deg) continue;
        for (int j = 0; j < kH - 3; ++j) {
            EXPECT_LT(std::fabs(s.share[i][j][Tab::kPsiTRT]) * deg, 0.5) << i << " " << j;
            EXPECT_LT(s.share[i][j][Tab::kScaleTT], 0.02) << i << " " << j;
            EXPECT_LT(s.share[i][j][Tab::kScaleTRT], 0.02) << i << " " << j;
        }
        if (std::fabs(theta) > 45 / deg) continue;
        for (int j = 0; j < kH - 2; ++j) EXPECT_GT(t.share[i][j][Tab::kScaleTRT], 1.5 * t.share[i][j][Tab::kScaleTT]) << i << " " << j;
    }
    hs::FurControls<double> only_trt;
    for (int l = 0; l < 4; ++l) only_trt.lobes.gain[l] = l == 2 ? 1.0 : 0.0;
    only_trt.gain_s = 0;
    const hs::FurMaterial<double> trt_only(fur_params<double>(0, 0, 0, glm::dvec3(0), true), only_trt);
    const int i = kMid + 2, j = kH / 2;
    const double theta = 0.5, gamma = kPi / 2 * j / (kH - 1), width = t.share[i][j][Tab::kScaleTRT] * std::log(3.0);
    const double eta_p = std::sqrt(1.55 * 1.55 - std::sin(theta) * std::sin(theta)) / std::cos(theta);
    for (double sign : {-1.0, 1.0}) {
        const double h = sign * std::sin(gamma), gamma_t = std::asin(h / eta_p);
        const double smooth_phi = std::remainder(4 * gamma_t - 2 * std::asin(h) + 2 * kPi, 2 * kPi);
        const double expected = std::remainder(smooth_phi + sign * t.share[i][j][Tab::kPsiTRT], 2 * kPi);
        const hs::FurFiber<double> fiber(trt_only, h);
        const auto f = [&](double phi) { return fiber.eval(direction(theta * deg), direction(-theta * deg, phi)).x; };
        double best = -1, best_phi = 0;
        for (int k = 0; k < 7200; ++k) {
            const double phi = -kPi + (k + 0.5) * 2 * kPi / 7200;
            if (f(phi) > best) best = f(phi), best_phi = phi;
        }
        std::printf("[ fur ] θo %.1f°, h %+.3f: TRT peaks at φ %.2f°, Φ(2, h) %.2f°, turned %.2f°; at ±s_TRT ln 3 %.3f, %.3f of it\n",
                    theta * deg, h, best_phi * deg, smooth_phi * deg, expected * deg, f(expected - width) / best,
                    f(expected + width) / best);
        EXPECT_NEAR(std::remainder(best_phi - expected, 2 * kPi) * deg, 0.0, 0.2) << h;
        EXPECT_NEAR(f(expected - width) / best, 0.75, 0.01) << h;
        EXPECT_NEAR(f(expected + width) / best, 0.75, 0.01) << h;
    }
}

// The rough entry's path to the medulla (RoughCortexTables' k: the walk's first chords that
// meet the medulla, their mean 3D path through the cortex to it over the smooth chord's at h).
// Nearly smooth, untilted facets give back the smooth cylinder (k within 0.02 of 1 wherever
// the smooth chord meets the medulla, up to θo 60° and γ 67.5°); the facets β implies leave
// it within 0.05 of 1 on the axis at θo 0° and lengthen it toward grazing light, where the
// visible facets lean toward wo and refract the light across the section: by over 15 % on the
// axis at θo ±71.6° (κ 0.6; docs/fur_breakdown.md, fur_breakdown_tool --first-chord).
TEST(FurFiber, RoughEntryLengthensThePathToTheMedulla) {
    constexpr int kTheta = hs::detail::RoughCortexTables<double>::kTheta, kH = hs::detail::RoughCortexTables<double>::kH;
    constexpr int kMid = kTheta / 2;
    const hs::FurMaterial<double> smooth(nearly_smooth_facets(0.6, 1)), rough(fur_params<double>(0.6, 1, 0, glm::dvec3(0), true));
    for (int i = 0; i < kTheta; ++i) {
        const double theta = (2.0 * i / (kTheta - 1) - 1) * 1.5;
        std::printf("[ fur ] node θo %5.1f°: k over γ, smooth facets / default =", theta * 180 / kPi);
        for (int j = 0; j < kH; ++j) std::printf(" %.3f/%.3f", smooth.rough_cortex().share[i][j][Tab::kEntryPath], rough.rough_cortex().share[i][j][Tab::kEntryPath]);
        std::printf("\n");
        if (std::fabs(theta) > kPi / 3) continue;
        for (int j = 0; j < kH - 2; ++j) EXPECT_NEAR(smooth.rough_cortex().share[i][j][Tab::kEntryPath], 1.0, 0.02) << i << " " << j;
    }
    EXPECT_NEAR(rough.rough_cortex().share[kMid][0][Tab::kEntryPath], 1.0, 0.05);
    EXPECT_GT(rough.rough_cortex().share[kMid + 5][0][Tab::kEntryPath], 1.15);
    EXPECT_GT(rough.rough_cortex().share[kMid - 5][0][Tab::kEntryPath], 1.15);
}

// The default facets (FurParams::facet_alpha 0) are the GGX whose reflections give R the
// longitudinal spread β_m gives it (facet_alpha_from_beta): for narrow lobes √3/2 Φ⁻¹(¾) √v
// (R's upper quartile of θi, Φ⁻¹(¾) √v, is twice the facets' slope quartile along the fibre,
// α/√3), rising with β_m until R's lobe is wider than GGX 1's reflections (β_m ≳ 0.62),
// where it stays 1; and the walk over those facets, with Smith's masking, Fresnel and the
// quartile fit, gives R at the axis (θo 0°, h 0) the variance v(β_m) of Chiang's R within
// the walk's noise, from smooth to rough.
TEST(FurMaterial, DefaultFacetsSpreadRAsBetaDoes) {
    double previous = 0;
    for (double beta : {0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.6, 0.7, 1.0}) {
        const double alpha = hs::detail::facet_alpha_from_beta(beta, 1.55), v = hs::longitudinal_variance(beta);
        std::printf("[ fur ] β_m %.2f: facet α %.4f (narrow-lobe limit %.4f)\n", beta, alpha,
                    0.5 * std::sqrt(3.0) * 0.67448975019608171 * std::sqrt(v));
        if (beta <= 0.05) {
            EXPECT_NEAR(alpha, 0.5 * std::sqrt(3.0) * 0.67448975019608171 * std::sqrt(v), 0.01 * alpha) << beta;
        }
        if (beta < 0.65) {
            EXPECT_GT(alpha, previous) << beta;
            EXPECT_LT(alpha, 1.0) << beta;
        } else {
            EXPECT_EQ(alpha, 1.0) << beta;
        }
        previous = alpha;
    }
    constexpr int kMid = hs::detail::RoughCortexTables<double>::kTheta / 2;
    for (double beta : {0.15, 0.3, 0.5}) {
        hs::FurParams<double> p = fur_params<double>(0, 0, 0, glm::dvec3(0), true);
        p.cortex.beta_m = beta;
        const hs::FurMaterial<double> rough(p);
        const double ratio = rough.rough_cortex().share[kMid][0][Tab::kQuartileVR] / hs::longitudinal_variance(beta);
        std::printf("[ fur ] β_m %.2f: v_R / v on the axis %.3f\n", beta, ratio);
        // (the quartile fit over 8,000 reflections: ~3–5 % noise in v_R at β_m ≤ 0.3, more at
        // 0.5, whose GGX 0.46 spreads the reflections' tails over the sphere)
        EXPECT_NEAR(ratio, 1.0, beta < 0.4 ? 0.1 : 0.15) << beta;
    }
}

// The rough cortex's microsurfaces (RoughFacets: GGX 0.5 and, from β_m 0.3, the roughness
// it implies, 0.182, both about the 2° tilt) are Smith's: over slopes drawn from their own
// distribution, the facets' mean projected area toward v, E[⟨v·m̃⟩] (m̃ the unnormalised
// normal), is the mean surface's times 1 + Λ(v) (Heitz 2014) for v above it, within four
// standard errors of the draws' mean; and the visible normals drawn for d, above the mean
// surface or below it (a ray the walk sends upward into the microsurface), have the mean of
// the slopes' normals weighted by ⟨d·m̃⟩, which the unweighted mean misses by more than three
// times the bound away from the normal.
TEST(FurFiber, RoughFacetsAreSmithMicrosurfaces) {
    const double tilt = 2 * kPi / 180;
    for (double given : {0.5, 0.0}) {
        const hs::detail::RoughFacets facets = hs::detail::RoughFacets::of(1.55, tilt, 0.3, given);
        const double ggx = facets.ggx;
        std::mt19937_64 rng(8);
        std::uniform_real_distribution<double> uni;
        // A facet's unnormalised normal in the fibre's frame, from GGX's slopes (p, q) about the
        // tilted normal: |slope| = α √(u / (1 − u)) (Walter et al. 2007 eq. 35's tan θm).
        const double k = 1 / std::sqrt(1 + facets.mean_a * facets.mean_a);
        const auto slopes = [&] {
            const double u = uni(rng), r = ggx * std::sqrt(u / (1 - u)), phi = 2 * kPi * uni(rng);
            const double p = r * std::cos(phi), q = r * std::sin(phi);
            return glm::dvec3(k * (p + facets.mean_a), k * (1 - facets.mean_a * p), q);
        };
        constexpr int kN = 2000000;
        std::vector<glm::dvec3> m(kN);
        for (auto& x : m) x = slopes();
        for (double theta : {0.2, 0.9, 1.3})
            for (double phi : {0.0, 1.0}) {
                const glm::dvec3 v(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
                double area = 0, square = 0;
                for (const auto& x : m) {
                    const double a = std::max(0.0, glm::dot(v, x));
                    area += a / kN, square += a * a / kN;
                }
                // (GGX's slopes have no variance, but the draws' own spread bounds their mean's
                // error: the second moment grows only as the log of the largest draw)
                // (c: the projection on the tilted mean surface's unit normal, as the slopes')
                const double c = k * facets.mean_projection(v), se = std::sqrt((square - area * area) / kN);
                std::printf("[ fur ] GGX %.3f θ %.1f φ %.0f: area %.5f, c (1 + Λ) %.5f (σ %.1e)\n", ggx, theta, phi, area,
                            c * (1 + facets.lambda(v)), se);
                EXPECT_NEAR(area, c * (1 + facets.lambda(v)), 4 * se) << "GGX " << ggx << " θ " << theta << " φ " << phi;
                for (double side : {1.0, -1.0}) {
                    // (below: a ray rising at a grazing angle, one the microsurface can still meet)
                    const glm::dvec3 d = side > 0 ? v : glm::normalize(glm::dvec3(v.x, -0.05, v.z));
                    glm::dvec3 want(0.0), got(0.0), plain(0.0);
                    double weight = 0;
                    for (const auto& x : m) {
                        const double w = std::max(0.0, glm::dot(d, x));
                        want += w * glm::normalize(x), weight += w;
                        plain += glm::normalize(x) / double(kN);
                    }
                    want /= weight;
                    hs::detail::FurRng frng(11);
                    constexpr int kDraws = 400000;
                    for (int i = 0; i < kDraws; ++i) got += facets.sample(d, frng) / double(kDraws);
                    // (below the mean surface the visible facets are the tail's, whose heavy
                    // weights the plain draws' mean follows slowly)
                    const double bound = side < 0 ? 8e-3 : 4e-3;
                    for (int c = 0; c < 3; ++c)
                        EXPECT_NEAR(got[c], want[c], bound) << "GGX " << ggx << " θ " << theta << " φ " << phi << " side " << side;
                    if (theta > 0.5 || side < 0) {  // (near the normal every facet is about equally visible)
                        EXPECT_GT(glm::length(plain - want), 3 * bound) << "GGX " << ggx << " θ " << theta << " φ " << phi;
                    }
                }
            }
    }
}

// The coloured fibre: ∫ eval = albedo per channel, and the albedo lies in [0, 1].
TEST(FurFiber, AlbedoMatchesIntegralWithAbsorption) {
    for (bool rough : {false, true}) {
    const hs::FurMaterial<double> mat(fur_params<double>(0.6, 10, 0.3, glm::dvec3(0.5447, 0.9061, 1.781), rough));
    const hs::FurFiber<double> fiber(mat, -0.35);
    const glm::dvec3 wo = direction(20, 0.3);
    const glm::dvec3 i = integrate(fiber, wo), a = fiber.albedo(wo);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(i[c], a[c], 1e-3);
        EXPECT_GT(a[c], 0);
        EXPECT_LT(a[c], 1);
    }
    }
}

// Samples against the pdf (chi-square, Bonferroni over the tables) in float and double, and a
// negative control: the same samples against the pdf of a medulla half as scattering fail.
// The scattered lobe's azimuthal table steps at |φ| = kπ/32: the cubature cuts the cells there
// (chi2::Options::phi_breaks), so every piece is smooth and converges to 1e-6 well before
// depth 4; the pdf is the bound fibre's (at(wo), equal to the stateless pdf bit for bit: the
// contract suite's BoundToWoMatchesUnbound). Same samples, cells and expected counts as
// with whole cells, at a fraction of the pdf evaluations.
template <typename T> void chi_square(bool negative) {
    struct Case {
        double kappa, sigma_s, g, h, theta;
        glm::dvec3 sigma_a;
        bool rough;
    };
    const Case cases[] = {{0.6, 10, 0, 0.3, 30, glm::dvec3(0), false},
                          {0.9, 1, 0.5, -0.7, 60, glm::dvec3(0.5, 0.9, 1.8), false},
                          {0.3, 10, 0, 0.1, -10, glm::dvec3(0.2), false},
                          {0.8, 30, -0.3, 0.0, 80, glm::dvec3(2, 1, 0.5), false},
                          {0.5, 2, 0, 0.25, 40, glm::dvec3(0), true},
                          {0.6, 3, 0.5, -0.5, -70, glm::dvec3(0.3, 0.6, 1.2), true}};
    constexpr double kPhiO = 0.4;  // wo's azimuth: the table's steps sit at φi = φo ± kπ/32
    chi2::Options opt;
    opt.samples = 200000;
    opt.num_tests = 6;
    opt.max_depth = 4;
    constexpr int kBins = hs::MedullaTables<T>::kPhiBins;
    for (int k = -kBins; k <= kBins; ++k) opt.phi_breaks.push_back(std::remainder(kPhiO + k * kPi / kBins, 2 * kPi));
    for (const Case& c : cases) {
        const hs::FurMaterial<T> mat(fur_params<T>(c.kappa, c.sigma_s, c.g, c.sigma_a, c.rough));
        const hs::FurFiber<T> fiber(mat, T(c.h));
        const glm::vec<3, T> wo(direction(c.theta, kPhiO));
        const auto at = fiber.at(wo);
        const chi2::Histogram hist = chi2::histogram([&](const glm::dvec4& u) { return glm::dvec3(at.sample(glm::vec<4, T>(u)).wi); }, opt);
        const std::string what = "κ " + std::to_string(c.kappa) + " σs " + std::to_string(c.sigma_s);
        if (negative) {
            const hs::FurMaterial<T> other(fur_params<T>(c.kappa, 0.5 * c.sigma_s, c.g, c.sigma_a, c.rough));
            const auto wrong = hs::FurFiber<T>(other, T(c.h)).at(wo);
            const chi2::Result r = chi2::compare(
                hist, chi2::expected_counts([&](const glm::dvec3& wi) { return double(wrong.pdf(glm::vec<3, T>(wi))); }, opt), opt);
            EXPECT_FALSE(r.passed) << "negative control passed: " << what;
        } else {
            const chi2::Result r = chi2::compare(
                hist, chi2::expected_counts([&](const glm::dvec3& wi) { return double(at.pdf(glm::vec<3, T>(wi))); }, opt), opt);
            EXPECT_TRUE(r.passed) << what << " p " << r.p_value << "\n" << r.report;
            EXPECT_NEAR(r.expected_total, 1, 2e-3) << what;
            EXPECT_EQ(r.invalid, 0) << what;
        }
    }
}
TEST(FurFiber, ChiSquareDouble) { chi_square<double>(false); }
TEST(FurFiber, ChiSquareFloat) { chi_square<float>(false); }
TEST(FurFiber, ChiSquareNegativeControl) { chi_square<double>(true); }

// Every sample's weight is eval / pdf at its wi and its pdf is pdf(wo, wi), to 1e-4, through
// the stateless and the bound calls.
template <typename T> void weight_is_eval_over_pdf() {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> uni(0, 1);
    const hs::FurMaterial<T> smooth(fur_params<T>(0.7, 5, 0.4, glm::dvec3(0.3, 0.6, 1.2)));
    const hs::FurMaterial<T> rough(fur_params<T>(0.7, 5, 0.4, glm::dvec3(0.3, 0.6, 1.2), true));
    int scattered = 0;
    for (int k = 0; k < 20000; ++k) {
        const hs::FurFiber<T> fiber(k % 2 ? rough : smooth, T(2 * uni(rng) - 1));
        const glm::vec<3, T> wo(random_direction(rng));
        const glm::vec<4, T> u(T(uni(rng)), T(uni(rng)), T(uni(rng)), T(uni(rng)));
        const hs::HairSample<T> s = fiber.sample(wo, u), b = fiber.at(wo).sample(u);
        ASSERT_GT(s.pdf, T(0));
        EXPECT_EQ(glm::dvec3(s.wi), glm::dvec3(b.wi));
        const hs::HairEvalPdf<T> e = fiber.eval_pdf(wo, s.wi);
        EXPECT_NEAR(double(s.pdf), double(e.pdf), 1e-4 * double(e.pdf));
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(double(s.weight[c]), double(e.f[c] / e.pdf), 1e-4 * double(e.f[c] / e.pdf) + 1e-7);
        scattered += s.lobe == hs::SampledLobe::kResidual;
    }
    EXPECT_GT(scattered, 1000);  // the scattered lobe (reported as the residual) is drawn
}
TEST(FurFiber, WeightIsEvalOverPdfDouble) { weight_is_eval_over_pdf<double>(); }
TEST(FurFiber, WeightIsEvalOverPdfFloat) { weight_is_eval_over_pdf<float>(); }

// No NaN, Inf or negative value at the parameters' extremes, offsets ±1 and the poles.
template <typename T> void finite_at_extremes() {
    using V3 = glm::vec<3, T>;
    const V3 dirs[] = {V3(1, 0, 0), V3(-1, 0, 0), V3(0, 1, 0), V3(0, 0, -1), V3(T(0.999999), T(1e-3), 0),
                       V3(T(-0.5), T(0.5), T(0.7)), V3(T(1e-30), 1, 0)};
    const T hs_[] = {T(-1), T(-0.999), T(0), T(0.5), T(1)};
    const T us[] = {T(0), T(1e-7), T(0.5), T(0.9999999), T(1)};
    struct Medulla {
        double kappa, sigma_s, g, sigma_a;
    };
    // No medulla, a vanishing one, one filling the fibre, barely and densely scattering, both
    // extremes of g, transparent and opaque (σa 50 in cortex and medulla).
    const Medulla medullas[] = {{0, 0, 0, 0},         {0, 0, 0, 50},          {0.5, 1e-6, 0.99, 0},
                                {0.999999, 200, -0.99, 0}, {0.999999, 200, 0.99, 50}, {0.5, 5, 0, 50},
                                {1e-6, 10, 0, 0}};
    // The rough cortex's facets in turn: from β, and GGX at both ends of its range.
    const double facet_alphas[] = {0, 1, 1e-3};
    for (std::size_t k = 0; k < std::size(medullas); ++k)
    for (bool rough : {false, true}) {
        const Medulla& m = medullas[k];
        // (The rough cortex on every medulla but the two dense ones, whose simulation is most
        // of this test's time; it covers the opaque cortex and the vanishing medulla.)
        if (rough && m.sigma_s > 100) continue;
        hs::FurParams<T> p = fur_params<T>(m.kappa, m.sigma_s, m.g, glm::dvec3(m.sigma_a), rough);
        p.sigma_a_medulla = V3(T(m.sigma_a));
        p.facet_alpha = T(facet_alphas[k % 3]);
        const hs::FurMaterial<T> mat(p);
        for (T h : hs_) {
            const hs::FurFiber<T> fiber(mat, h);
            for (const V3& wo : dirs) {
                const V3 a = fiber.albedo(wo);
                for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(a[c]) && a[c] >= 0 && a[c] <= T(1.0001));
                for (const V3& wi : dirs) {
                    const hs::HairEvalPdf<T> e = fiber.eval_pdf(wo, wi);
                    ASSERT_TRUE(std::isfinite(e.pdf) && e.pdf >= 0);
                    for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(e.f[c]) && e.f[c] >= 0);
                }
                for (T u0 : us)
                    for (T u1 : us) {
                        const hs::HairSample<T> s = fiber.sample(wo, glm::vec<4, T>(u0, u1, T(1) - u1, u0));
                        ASSERT_TRUE(std::isfinite(s.pdf) && s.pdf >= 0);
                        for (int c = 0; c < 3; ++c)
                            ASSERT_TRUE(std::isfinite(s.weight[c]) && s.weight[c] >= 0 && std::isfinite(s.wi[c]));
                    }
            }
        }
    }
}
TEST(FurFiber, FiniteAtExtremesDouble) { finite_at_extremes<double>(); }
TEST(FurFiber, FiniteAtExtremesFloat) { finite_at_extremes<float>(); }

// Each bad parameter is rejected with a message that names it.
TEST(FurMaterial, RejectsBadParametersByName) {
    const double nan = std::nan("");
    struct Bad {
        const char* name;
        void (*change)(hs::FurParams<double>&);
    };
    const Bad bad[] = {
        {"kappa", [](hs::FurParams<double>& p) { p.kappa = 1; }},
        {"kappa", [](hs::FurParams<double>& p) { p.kappa = -0.1; }},
        {"sigma_s", [](hs::FurParams<double>& p) { p.sigma_s = -1; }},
        {"sigma_s", [](hs::FurParams<double>& p) { p.sigma_s = HUGE_VAL; }},
        {"sigma_a_medulla.g", [](hs::FurParams<double>& p) { p.sigma_a_medulla.y = -2; }},
        {"g", [](hs::FurParams<double>& p) { p.g = 1; }},
        {"g", [](hs::FurParams<double>& p) { p.g = -1.5; }},
        {"eta", [](hs::FurParams<double>& p) { p.cortex.eta = 0.9; }},
        {"sigma_a.b", [](hs::FurParams<double>& p) { p.cortex.sigma_a.z = -1; }},
        {"facet_alpha", [](hs::FurParams<double>& p) { p.facet_alpha = 1.5; }},
        {"facet_alpha", [](hs::FurParams<double>& p) { p.facet_alpha = -0.1; }},
    };
    for (const Bad& b : bad) {
        hs::FurParams<double> p;
        b.change(p);
        EXPECT_NE(hs::validate(p).find(b.name), std::string::npos) << b.name << ": " << hs::validate(p);
        try {
            const hs::FurMaterial<double> m(p);
            ADD_FAILURE() << "accepted a bad " << b.name;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(b.name), std::string::npos) << e.what();
        }
    }
    hs::FurParams<double> p;
    p.g = nan;
    EXPECT_NE(hs::validate(p).find("g = "), std::string::npos);
    EXPECT_TRUE(hs::validate(hs::FurParams<double>()).empty());
    EXPECT_THROW(hs::FurFiber<double>::checked(hs::FurMaterial<double>(hs::FurParams<double>()), 1.5), std::invalid_argument);
}

// The tables built for thin to dense medullas (κ 0.3 and 0.9, σs^m 1 and 10, blond cortex),
// with the smooth and the rough cortex, are valid: per |θo| bin the azimuthal density is
// non-negative, integrates to 1 over |φ| ∈ [0, π] and its cdf is its running integral from
// 0 to 1; the escape fractions of the absorbing fibre lie in (0, 1) and fall from red to
// blue, as the cortex's σa^c rises (the same paths, each absorbing more); q's mix w ∈ [0, 1] and
// skew b ∈ [−1, 1]; the rough cortex's shares of the entered light add up to 1, its tail
// ratio in [0, 1). (How long the build takes is a benchmark: BM_FurTablesGrid in
// bench/chiang_bench.cpp, results under bench/results/.)
TEST(FurMaterial, TablesBuiltForTheGridAreValid) {
    using Tables = hs::MedullaTables<float>;
    constexpr double kWidth = kPi / Tables::kPhiBins;
    for (bool rough : {false, true})
        for (double kappa : {0.3, 0.9})
            for (double sigma_s : {1.0, 10.0}) {
                const hs::FurMaterial<float> mat(fur_params<float>(kappa, sigma_s, 0, glm::dvec3(0.5447, 0.9061, 1.781), rough));
                const Tables& t = mat.medulla();
                const std::string what = "κ " + std::to_string(kappa) + " σs " + std::to_string(sigma_s) + (rough ? " rough" : "");
                for (int b = 0; b < Tables::kThetaBins; ++b) {
                    double mass = 0;
                    EXPECT_EQ(t.cdf[b][0], 0.0f) << what;
                    EXPECT_EQ(t.cdf[b][Tables::kPhiBins], 1.0f) << what;
                    for (int k = 0; k < Tables::kPhiBins; ++k) {
                        EXPECT_GE(t.density[b][k], 0.0f) << what;
                        mass += double(t.density[b][k]) * kWidth;
                        EXPECT_NEAR(double(t.cdf[b][k + 1]), mass, 1e-5) << what << " bin " << b << " φ bin " << k;
                    }
                    EXPECT_NEAR(mass, 1, 1e-5) << what;
                    for (int c = 0; c < 3; ++c) {
                        const double e = double(t.escape[b][c]);
                        EXPECT_GT(e, 0) << what;
                        EXPECT_LT(e, 1) << what;
                        if (c > 0) {
                            EXPECT_LT(e, double(t.escape[b][c - 1])) << what << " bin " << b << " channel " << c;
                        }
                    }
                    EXPECT_GE(t.longitudinal[b][0], 0.0f) << what;
                    EXPECT_LE(t.longitudinal[b][0], 1.0f) << what;
                    EXPECT_GE(t.longitudinal[b][1], -1.0f) << what;
                    EXPECT_LE(t.longitudinal[b][1], 1.0f) << what;
                }
                for (const auto& row : mat.rough_cortex().share)
                    for (const auto& node : row) {
                        if (!rough) {
                            for (float v : node) EXPECT_EQ(v, 0.0f) << what;
                            continue;
                        }
                        EXPECT_NEAR(double(node[Tab::kTT]) + double(node[Tab::kTRT]) + double(node[Tab::kLater]), 1.0, 1e-6) << what;
                        EXPECT_GE(node[Tab::kTailRatio], 0.0f) << what;
                        EXPECT_LT(node[Tab::kTailRatio], 1.0f) << what;
                        for (int c = 0; c < 3; ++c) {  // the later orders' light: leaves, scatters or is absorbed
                            EXPECT_GE(node[Tab::kLaterOut + c], 0.0f) << what;
                            EXPECT_GE(node[Tab::kLaterScatter + c], 0.0f) << what;
                            EXPECT_LE(double(node[Tab::kLaterOut + c]) + double(node[Tab::kLaterScatter + c]),
                                      double(node[Tab::kLater]) + 1e-6) << what;
                        }
                    }
            }
}

// The model, averaged over the offset h (a far-field beam, as the reference traces), against
// the physical fur reference's bins: relative L1 over the sphere per case, lossless and blond
// (the RGB mean), of the whole f and of the light scattered in the medulla alone (the
// reference's scattered class against eval_scattered). The rough cortex is GGX 0.17, matched
// to the model's β_m = β_n = 0.3 by the width of R (fur_roughness_tool), with the 2° cuticle
// tilt on both sides, and the model's cortex rough too (FurParams::rough_cortex: the entry's
// reflectance and the orders of exit from a walk over the facets, the GGX its own β_m implies,
// 0.182, FurParams::facet_alpha left 0: the model is given nothing of the reference's
// microsurface, and nothing is fitted to this reference); the whole f then
// carries what a rough fibre does that the model still does not (the lobes' shapes past R,
// the tilt feeding the medulla; docs/models.md),
// and so does the scattered light's energy, which the cortex's paths feed. The nearly smooth, untilted cortex (GGX 0.02, tilt 0 in both) measures
// the medulla's lobe where the model's smooth-cylinder paths hold. The figures of
// docs/models.md, printed; the bounds guard what is reached (the goal, 5 %, is not reached
// everywhere: see docs/models.md).
TEST(FurPhysical, AgainstThePhysicalFur) {
    const std::vector<phys_fur::FurCached> cases = phys_fur::read_fur_cache(HAIRSCATTER_TEST_DATA_DIR "/physical_fur.txt");
    constexpr int kH = 48;  // midpoint offsets over [-1, 1]
    struct Row {
        double all[2] = {0, 0}, scattered[2] = {0, 0}, energy[2][2] = {{0, 0}, {0, 0}};  // [lossless, blond]
    };
    std::vector<Row> rows(cases.size());
    std::vector<std::thread> pool;
    for (int t = 0; t < 2; ++t)
        pool.emplace_back([&, t] {
            for (std::size_t k = std::size_t(t); k < cases.size(); k += 2) {
                const phys_fur::FurCase& fc = cases[k].fur;
                for (int b = 0; b < 2; ++b) {
                    const glm::dvec3 sa = b ? glm::dvec3(phys_fiber::kBlond[0], phys_fiber::kBlond[1], phys_fiber::kBlond[2]) : glm::dvec3(0);
                    hs::FurParams<double> prm = fur_params<double>(fc.kappa, fc.sigma_s, fc.g, sa);
                    prm.cortex.alpha = fc.tilt_deg * kPi / 180;  // the reference's cuticle tilt
                    prm.rough_cortex = fc.roughness >= 0.1;  // the walk over its facets, from β
                    const hs::FurMaterial<double> mat(prm);
                    std::vector<hs::FurFiber<double>> fibers;
                    for (int i = 0; i < kH; ++i) fibers.emplace_back(mat, -1 + (i + 0.5) * 2.0 / kH);
                    const bool smooth = fc.roughness < 0.1;
                    for (int part = smooth ? 1 : 0; part < (fc.kappa > 0 ? 2 : 1); ++part) {
                        const auto eval = [&](const glm::dvec3& wo, const glm::dvec3& wi) {
                            glm::dvec3 f(0.0);
                            for (const auto& fiber : fibers) f += part ? fiber.eval_scattered(wo, wi) : fiber.eval(wo, wi);
                            return f / double(kH);
                        };
                        const phys_fiber::CachedCase& ref = part ? cases[k].scattered : cases[k].bins;
                        const std::vector<glm::dvec3> bins = phys_fiber::model_bins(ref, eval);
                        double e = 0;
                        for (int ch = 0; ch < (b ? 3 : 1); ++ch) {
                            const phys_fiber::ModelError m = phys_fiber::compare(ref, bins, ch, b ? ch + 1 : 0);
                            e += m.l1 / (b ? 3 : 1);
                            if (part && ch == (b ? 1 : 0)) rows[k].energy[b][0] = m.energy_model, rows[k].energy[b][1] = m.energy_ref;
                        }
                        (part ? rows[k].scattered : rows[k].all)[b] = e;
                    }
                }
            }
        });
    for (auto& th : pool) th.join();
    double worst_all = 0, worst[2] = {0, 0}, mean[2] = {0, 0};  // scattered: [rough, smooth]
    double mean_all[2] = {0, 0};                                // f on the rough cortex: [lossless, blond]
    int n[2] = {0, 0}, n_all = 0;
    for (std::size_t k = 0; k < cases.size(); ++k) {
        const Row& r = rows[k];
        const int smooth = cases[k].fur.roughness < 0.1;
        std::printf("[ physical ] %-34s f: lossless %5.1f %% blond %5.1f %% | scattered: lossless %5.1f %% blond %5.1f %%"
                    " (energy lossless %.3f/%.3f, blond G %.3f/%.3f)\n",
                    cases[k].fur.name().c_str(), 100 * r.all[0], 100 * r.all[1], 100 * r.scattered[0], 100 * r.scattered[1],
                    r.energy[0][0], r.energy[0][1], r.energy[1][0], r.energy[1][1]);
        worst_all = std::max({worst_all, r.all[0], r.all[1]});
        if (!smooth) mean_all[0] += r.all[0], mean_all[1] += r.all[1], ++n_all;
        if (cases[k].fur.kappa > 0) {
            worst[smooth] = std::max({worst[smooth], r.scattered[0], r.scattered[1]});
            mean[smooth] += r.scattered[0] + r.scattered[1];
            n[smooth] += 2;
        }
    }
    for (int sm = 0; sm < 2; ++sm) mean[sm] /= std::max(1, n[sm]);
    for (double& m : mean_all) m /= std::max(1, n_all);
    std::printf("[ physical ] rough cortex: f worst %.2f %%, mean %.2f %% lossless, %.2f %% blond; scattered worst %.2f %%,"
                " mean %.2f %%\n", 100 * worst_all, 100 * mean_all[0], 100 * mean_all[1], 100 * worst[0], 100 * mean[0]);
    std::printf("[ physical ] smooth cortex: scattered worst %.1f %%, mean %.1f %% (goal: 5 %%)\n", 100 * worst[1], 100 * mean[1]);
    // Measured: 10.21 %, mean 6.20 % lossless and 6.47 % blond; scattered 10.56 %, 5.28 %; smooth
    // cortex's scattered 6.0 %, 4.1 % (10.24 %, 6.33 %, 6.54 %; 10.6 %, 5.5 %; 6.3 %, 4.8 % before
    // q's two shapes passed the exit's transmission, MedullaTables' U and C; 11.35 %,
    // 6.83 %, 6.60 % before TRT's and the later orders' longitudinal lobes from the walk; 12.07 %,
    // 6.88 %, 7.76 % before R's heavy tail from the walk; 11.9 %,
    // 6.9 %, 7.8 %; 15.4 %, 7.1 % before the later orders' chords through the medulla from the
    // walk; 12.1 %, 7.0 %,
    // 7.9 % with those widths matched by the turns' quartiles; 13.8 %, 7.7 %, 8.25 % before TT's
    // and TRT's azimuthal widths and TRT's turn from the facets; 8.5 % blond,
    // scattered 22.2 % and 8.1 % before the rough entry's longer path to the medulla, k; 15.3 %,
    // 8.6 %, 9.3 % before TT's azimuth turned by its facets, ψ_TT; 17.7 %,
    // 8.6 %, 9.9 %; 22.5 %, 8.2 % before R's azimuth turned toward wo, ψ_R; 16.4 %, 8.4 %,
    // 9.7 %; 22.0 %, 8.2 % given the reference's GGX 0.17; 23.2 %, 10.2 %, 12.9 %; 22.8 %
    // and 9.1 % with the walk on the microsurface over Gaussian facets from β; 20.7 %,
    // 9.9 %, 12.5 %; 23.9 %, 9.1 % with the facets' Gaussian slopes from β, one facet event
    // per meeting and R's shape from its moments; 26.1 %, 9.5 % and 15.7 % with Chiang's one R
    // lobe width at every h; 58.6 %, 12.8 % and 21.6 % with the smooth F at the rough cortex's
    // entry and a smooth boundary in the medulla tables; 19.0 % and 25.2 % mean with the smooth
    // cortex's orders); 6.3 %, 4.8 % (the reference's noise: 1–3 %).
    EXPECT_LT(worst_all, 0.105);
    EXPECT_LT(mean_all[0], 0.064);
    EXPECT_LT(mean_all[1], 0.067);
    EXPECT_LT(worst[0], 0.11);
    EXPECT_LT(mean[0], 0.056);
    EXPECT_LT(worst[1], 0.065);
    EXPECT_LT(mean[1], 0.045);
}
