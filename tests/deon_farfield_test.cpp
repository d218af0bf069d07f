// DeonFarFieldFiber (d'Eon et al. 2011's far-field fiber, h integrated by Gauss–Legendre
// in γ = asin h): the wrapped Gaussian, white furnace, agreement of eval with an
// independent adaptive integration of the far-field definition (and its convergence in the
// number of h nodes), the albedo, chi-square of sample against pdf with a negative control,
// sample/pdf/eval consistency, extremes and parameter validation.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <gtest/gtest.h>

#include <hairscatter/models/deon_farfield.hpp>

#include "support/chi2.hpp"
#include "support/reference_chiang.hpp"
#include "support/reference_farfield.hpp"
#include "support/model_specs.hpp"

namespace hs = hairscatter;
using ref::kPi;
using ref::FarFieldReference;
using ref::wrapped_gaussian_ref;

namespace {

struct Config {
    double beta_m, beta_n, alpha_deg;
    glm::dvec3 sigma_a{0.0};
};

template <typename T> hs::FiberParams<T> params(const Config& c) {
    return specs::fiber_params<T>(c.beta_m, c.beta_n, c.alpha_deg, c.sigma_a);
}

}  // namespace

// Both series (image sum for σ ≤ 0.75, Fourier above) against brute force: 1e-12 relative
// wherever D is above 1e-280 (double), 1e-4 relative above 1e-30 in float (the Fourier sum
// cancels to 1e-3 of its mean at its minimum for σ just above 0.75, so rounding of the
// terms is amplified 1000-fold there); unit mass; sampled circular moments
// E[cos nX] = e^(-n²σ²/2).
TEST(WrappedGaussian, MatchesImageSumIntegratesToOneAndSamples) {
    const std::vector<double> sigmas = {0.003, 0.05, 0.3, 0.6, 0.7499, 0.7501, 1.0, 1.5, 3.0, 7.8};
    double worst_d = 0, worst_f = 0;
    for (double sigma : sigmas) {
        const hs::WrappedGaussian<double> d(sigma);
        const hs::WrappedGaussian<float> df{float(sigma)};
        for (int i = 0; i <= 400; ++i) {
            const double x = -kPi + 2 * kPi * i / 400;
            const double r = wrapped_gaussian_ref(x, sigma);
            if (r > 1e-280) worst_d = std::max(worst_d, std::abs(d.pdf(x) / r - 1));
            if (r > 1e-30) worst_f = std::max(worst_f, std::abs(double(df.pdf(float(x))) / r - 1));
        }
        using GK = boost::math::quadrature::gauss_kronrod<double, 31>;
        const double mass = GK::integrate([&](double x) { return d.pdf(x); }, -kPi, kPi, 20, 1e-13);
        EXPECT_NEAR(mass, 1.0, 1e-10) << "σ = " << sigma;

        std::mt19937_64 rng(5);
        std::uniform_real_distribution<double> uni(0, 1);
        const int n = 200000;
        double c1 = 0, c2 = 0;
        for (int k = 0; k < n; ++k) {
            const double x = d.sample(uni(rng), uni(rng));
            ASSERT_TRUE(x >= -kPi && x <= kPi);
            c1 += std::cos(x);
            c2 += std::cos(2 * x);
        }
        // Standard error of a mean of cosines ≤ 1/√n ≈ 2.2e-3: 5 of them.
        EXPECT_NEAR(c1 / n, std::exp(-0.5 * sigma * sigma), 0.011) << "σ = " << sigma;
        EXPECT_NEAR(c2 / n, std::exp(-2.0 * sigma * sigma), 0.011) << "σ = " << sigma;
    }
    std::printf("[ wrapped  ] pdf vs image sum: worst relative %.3g (double), %.3g (float)\n", worst_d, worst_f);
    EXPECT_LT(worst_d, 1e-12);
    EXPECT_LT(worst_f, 1e-4);
}

namespace {

// ∫ f dωi = ∫∫ f cosθi dθi dφ. θi: composite 20-point Gauss–Legendre with breakpoints at
// every lobe's peak (θi = -θo'_p) and at ±1, 4, 16 of its widths √v_p. φ: the trapezoidal
// rule on M equispaced points, which for a periodic analytic integrand (here a constant
// plus wrapped Gaussians) has error ≈ 2 e^(-M²σ²/2): M = 14/σ puts it below 1e-40. The φ
// rule thus knows nothing of where the h nodes put the lobes.
template <typename T> double furnace(const hs::DeonFarFieldMaterial<T>& mat, double theta_o_deg) {
    const hs::DeonFarFieldFiber<T> fiber(mat);
    const double to = theta_o_deg * kPi / 180, phi_o = 0.3;
    const glm::vec<3, T> wo(ref::dir(to, phi_o));
    std::vector<double> cuts = {-kPi / 2, kPi / 2};
    for (int p = 0; p < 4; ++p) {
        const double t = to + mat.tilt().angle(p);
        const double peak = -std::atan2(std::sin(t), std::abs(std::cos(t)));
        const double w = std::sqrt(double(mat.lobe_variance(p)));
        for (double k : {-16.0, -4.0, -1.0, 0.0, 1.0, 4.0, 16.0}) cuts.push_back(std::clamp(peak + k * w, -kPi / 2, kPi / 2));
    }
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());

    const int m = std::max(64, int(std::ceil(14 / double(mat.azimuthal().sigma()))));
    using GL = boost::math::quadrature::gauss<double, 20>;
    auto inner = [&](double ti) {
        double s = 0;
        for (int k = 0; k < m; ++k) {
            const glm::vec<3, T> wi(ref::dir(ti, phi_o - kPi + 2 * kPi * k / m));
            s += double(fiber.eval(wo, wi).g);
        }
        return s * (2 * kPi / m) * std::cos(ti);
    };
    double total = 0;
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) total += GL::integrate(inner, cuts[k], cuts[k + 1]);
    return total;
}

template <typename T> void run_furnace(bool full) {
    const std::vector<double> bm = full ? std::vector<double>{0.05, 0.3, 1.0} : std::vector<double>{0.1, 0.7};
    const std::vector<double> bn = full ? std::vector<double>{0.1, 0.3, 1.0} : std::vector<double>{0.2, 0.9};
    const std::vector<double> al = {0.0, 5.0};
    const std::vector<double> th = {0.0, 60.0, 89.9};
    double worst = 1;
    int count = 0;
    for (double a : bm)
        for (double b : bn)
            for (double c : al) {
                const hs::DeonFarFieldMaterial<T> mat(params<T>({a, b, c}), 8);
                for (double t : th) {
                    const double e = furnace(mat, t);
                    ++count;
                    EXPECT_NEAR(e, 1.0, 0.005) << "βm " << a << " βn " << b << " α " << c << "° θo " << t << "°";
                    if (std::abs(e - 1) > std::abs(worst - 1)) worst = e;
                }
            }
    // The node count changes where the lobes sit, never the energy.
    for (int n : {1, 2, 5, 32, 64}) {
        const hs::DeonFarFieldMaterial<T> mat(params<T>({0.3, 0.3, 2.0}), n);
        const double e = furnace(mat, 70.0);
        ++count;
        EXPECT_NEAR(e, 1.0, 0.005) << n << " nodes";
        if (std::abs(e - 1) > std::abs(worst - 1)) worst = e;
    }
    std::printf("[ furnace  ] %d configurations (%s), worst ∫f dω = %.8f\n", count, sizeof(T) == 4 ? "float" : "double",
                worst);
}

}  // namespace

// σa = 0: ∫ f dωi = 1 within 0.5 % over βm, βn, α, θo up to 89.9° and node counts 1–64.
TEST(DeonFarFieldFurnace, LosslessFiberConservesEnergyDouble) { run_furnace<double>(true); }
TEST(DeonFarFieldFurnace, LosslessFiberConservesEnergyFloat) { run_furnace<float>(false); }


// eval (double) against the reference at random (wo, wi) for several parameter sets, for
// N_h = 8, 16, 32, 64 nodes; the worst relative error (over values above 1e-3 of each
// case's largest) is printed per N_h. The rule converges once the nodes' exit azimuths
// Φ(p, h_k) are closer than about σ: for βn ≥ 0.3 (σ ≥ 0.21 rad) 32 nodes are within 3e-4
// and 64 within 1e-7 (asserted); fewer nodes leave a comb of separate spikes (8 nodes:
// errors of order 1). Narrower detectors need proportionally more nodes: at βn = 0.1
// (σ = 0.044) 64 nodes are 20–30 % off between spikes (printed), and the automatic node
// count (auto_nodes: 156 there) must be within 3e-4 for βn from 0.1 to 1 (asserted).
TEST(DeonFarField, MatchesAdaptiveIntegrationOfTheDefinition) {
    struct Case {
        Config c;
        double theta_o_deg;
    };
    const std::vector<Case> cases = {
        {{0.3, 0.3, 2.0, {0.0, 0.0, 0.0}}, 30},    {{0.1, 0.5, 0.0, {0.5, 1.0, 2.0}}, -60},
        {{0.6, 0.3, -5.0, {0.2, 0.0, 4.0}}, 75},   {{0.2, 1.0, 2.0, {1.0, 0.3, 0.0}}, 5},
        {{0.4, 0.4, 10.0, {0.0, 0.7, 0.1}}, -20},
    };
    const std::vector<int> node_counts = {8, 16, 32, 64};
    // The reference values are computed once per case; each node count is compared to them.
    struct Point {
        glm::dvec3 wo, wi, f;
    };
    auto reference_points = [](const Case& k, std::mt19937_64& rng) {
        std::uniform_real_distribution<double> uni(0, 1);
        FarFieldReference r{{1.55, k.c.beta_m, k.c.beta_n, k.c.alpha_deg * kPi / 180, k.c.sigma_a}};
        const glm::dvec3 wo = ref::dir(k.theta_o_deg * kPi / 180, 2 * kPi * uni(rng));
        std::vector<Point> pts;
        for (int j = 0; j < 12; ++j) {
            // θi near the lobes' band (|θi + θo| small) half the time.
            const double ti = j % 2 ? std::asin(-0.99 + 1.98 * uni(rng)) : -k.theta_o_deg * kPi / 180 + 0.4 * (uni(rng) - 0.5);
            const glm::dvec3 wi = ref::dir(ti, 2 * kPi * uni(rng));
            pts.push_back({wo, wi, r.f(wo, wi)});
        }
        return pts;
    };
    auto measure = [&](const std::vector<Case>& cs, const std::vector<std::vector<Point>>& pts, int n) {
        double worst = 0;
        for (std::size_t i = 0; i < cs.size(); ++i) {
            const hs::DeonFarFieldMaterial<double> mat(params<double>(cs[i].c), n);
            const hs::DeonFarFieldFiber<double> fiber(mat);
            double peak = 0;
            for (const Point& q : pts[i]) peak = std::max({peak, q.f.r, q.f.g, q.f.b});
            for (const Point& q : pts[i]) {
                const glm::dvec3 f = fiber.eval(q.wo, q.wi);
                for (int c = 0; c < 3; ++c)
                    if (q.f[c] > 1e-3 * peak) worst = std::max(worst, std::abs(f[c] / q.f[c] - 1));
            }
        }
        return worst;
    };
    std::mt19937_64 rng(41);
    std::vector<std::vector<Point>> pts;
    for (const Case& k : cases) pts.push_back(reference_points(k, rng));
    std::vector<double> worst;
    for (int n : node_counts) worst.push_back(measure(cases, pts, n));
    std::printf("[ far-field] eval vs adaptive ½∫A_p D dh (βn ≥ 0.3): worst relative");
    for (std::size_t i = 0; i < node_counts.size(); ++i) std::printf("  N_h=%d: %.2g", node_counts[i], worst[i]);
    std::printf("\n");
    EXPECT_LT(worst[2], 3e-4);
    EXPECT_LT(worst[3], 1e-7);

    const std::vector<Case> narrow = {{{0.3, 0.1, 2.0, {0.0, 0.0, 0.0}}, 30}};
    const std::vector<std::vector<Point>> narrow_pts = {reference_points(narrow[0], rng)};
    std::printf("[ far-field] narrow detector (βn = 0.1, σ = %.3f rad):",
                FarFieldReference{{1.55, 0.3, 0.1, 0.0, glm::dvec3(0.0)}}.sigma());
    for (int n : node_counts) std::printf("  N_h=%d: %.2g", n, measure(narrow, narrow_pts, n));
    std::printf("\n");

    // The automatic node count over the detector widths, each case against its reference.
    std::printf("[ far-field] automatic node count:");
    for (double bn : {0.1, 0.15, 0.2, 0.3, 0.5, 1.0}) {
        const std::vector<Case> one = {{{0.3, bn, 2.0, {0.2, 0.4, 0.8}}, 25}};
        const std::vector<std::vector<Point>> one_pts = {reference_points(one[0], rng)};
        const int n = hs::DeonFarFieldMaterial<double>::auto_nodes(bn);
        const double e = measure(one, one_pts, hs::DeonFarFieldMaterial<double>::kAutoNodes);
        std::printf("  βn=%g: N_h=%d %.2g", bn, n, e);
        EXPECT_LT(e, 3e-4) << "βn = " << bn << ", " << n << " nodes";
    }
    std::printf("\n");
}

// albedo = ½ ∫ Σ_p A_p(h) dh: 1 for σa = 0 (to rounding, at any N_h), and the reference's
// adaptive h integral with absorption (32 nodes: 1e-8).
TEST(DeonFarField, AlbedoIsTheHAverageOfTheAttenuations) {
    const glm::dvec3 wo = ref::dir(0.7, 0.2);
    for (int n : {1, 4, 33}) {
        const hs::DeonFarFieldMaterial<double> mat(params<double>({0.3, 0.3, 2.0}), n);
        EXPECT_NEAR(hs::DeonFarFieldFiber<double>(mat).albedo(wo).g, 1.0, 1e-13) << n;
    }
    const Config c{0.3, 0.3, 2.0, {0.3, 1.0, 3.0}};
    const hs::DeonFarFieldMaterial<double> mat(params<double>(c), 32);
    const glm::dvec3 a = hs::DeonFarFieldFiber<double>(mat).albedo(wo);
    FarFieldReference r{{1.55, c.beta_m, c.beta_n, c.alpha_deg * kPi / 180, c.sigma_a}};
    for (int ch = 0; ch < 3; ++ch) {
        using GK = boost::math::quadrature::gauss_kronrod<double, 31>;
        const double ref_albedo = 0.5 * GK::integrate(
                                            [&](double h) {
                                                const auto ap = ref::Model{r.p, h}.Ap(0.7);
                                                return ap[0][ch] + ap[1][ch] + ap[2][ch] + ap[3][ch];
                                            },
                                            -1.0, 1.0, 18, 1e-12);
        EXPECT_NEAR(a[ch], ref_albedo, 1e-8) << "channel " << ch;
    }
}

namespace {

using Spec = specs::FarFieldSpec<double>;

}  // namespace

// A large rule: the automatic node count of a narrow detector (βn = 0.15: 90 nodes, 45
// stored with mirrors), on a coarser 12 × 24 histogram (its pdf is 10× dearer than the
// grid's).
TEST(DeonFarFieldChi2, SampleMatchesPdfAtAutoNodesNarrowDetector) {
    const Spec::Case c{0.3, 0.15, 2, 40, 0.5, hs::DeonFarFieldMaterial<double>::kAutoNodes};
    const hs::DeonFarFieldMaterial<double> mat(c.params<double>(), c.setting);
    const hs::DeonFarFieldFiber<double> fiber(mat);
    const glm::dvec3 wo = ref::dir(c.theta_o_deg * kPi / 180, 0.7);
    chi2::Options o = Spec::chi2_options();
    o.theta_bins = 12;
    o.phi_bins = 24;
    const auto r = chi2::test([&](const glm::dvec4& u) { return fiber.sample(wo, u).wi; },
                              [&](const glm::dvec3& wi) { return fiber.pdf(wo, wi); }, o);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.expected_total, 1.0, 1e-3);
    std::printf("[ chi2     ] %d nodes: p = %.3g\n", mat.nodes(), r.p_value);
}

// Negative control at the grid's significance (the contract suite passes the unmodified
// sampler of this case and rejects its pdf × 1.05): the pdf of a 4-node rule against the
// samples of the 8-node fiber must be rejected (the node placement shows in the sampled
// distribution, so a sampler that ignored it would fail).
TEST(DeonFarFieldChi2, NegativeControlsAreRejected) {
    const Spec::Case c{0.3, 0.3, 2, 30, 0.5, 8};
    const hs::DeonFarFieldMaterial<double> mat(c.params<double>(), c.setting);
    const hs::DeonFarFieldFiber<double> fiber(mat);
    const glm::dvec3 wo = ref::dir(c.theta_o_deg * kPi / 180, 0.7);
    auto sample = [&](const glm::dvec4& u) { return fiber.sample(wo, u).wi; };
    const hs::DeonFarFieldMaterial<double> coarse(c.params<double>(), 4);
    const hs::DeonFarFieldFiber<double> coarse_fiber(coarse);
    const auto other = chi2::test(sample, [&](const glm::dvec3& wi) { return coarse_fiber.pdf(wo, wi); },
                                  Spec::chi2_options());
    EXPECT_FALSE(other.passed) << "the 4-node pdf was accepted for the 8-node sampler (p = " << other.p_value << ")";
    std::printf("[ chi2     ] negative control: p = %.3g (4-node pdf, 8-node sampler)\n", other.p_value);
}


// Node counts 1 … 256 and 0 (automatic) are accepted (the rejections are the contract
// suite's); the automatic count follows β_n and stays in [24, 256].
TEST(DeonFarFieldMaterial, AcceptsNodeCountsAndChoosesAutomatically) {
    hs::FiberParams<double> p;
    EXPECT_NO_THROW(hs::DeonFarFieldMaterial<double>(p, 1));
    EXPECT_NO_THROW(hs::DeonFarFieldMaterial<double>(p, 256));
    EXPECT_EQ(hs::DeonFarFieldMaterial<double>(p).nodes(), hs::DeonFarFieldMaterial<double>::auto_nodes(p.beta_n));
    EXPECT_GE(hs::DeonFarFieldMaterial<double>::auto_nodes(0.3), 32);
    EXPECT_GT(hs::DeonFarFieldMaterial<double>::auto_nodes(0.1), 128);
    EXPECT_EQ(hs::DeonFarFieldMaterial<double>::auto_nodes(1.0), 24);
    EXPECT_EQ(hs::DeonFarFieldMaterial<double>::auto_nodes(0.01), 256);
}

// The quadrature's layout: ⌈n/2⌉ stored nodes with h ≥ 0, weights summing to 1 with the
// mirrors, nodes placed at h = sin(π x_k / 2) for the Gauss–Legendre x_k.
TEST(DeonFarFieldMaterial, NodesAreGaussLegendreInGamma) {
    for (int n : {1, 2, 7, 32, 64}) {
        const hs::DeonFarFieldMaterial<double> m(hs::FiberParams<double>{}, n);
        EXPECT_EQ(m.nodes(), n);
        EXPECT_EQ(m.half_nodes(), (n + 1) / 2);
        const hs::GaussLegendre<double> gl(n);
        double total = 0;
        for (int j = 0; j < m.half_nodes(); ++j) {
            EXPECT_GE(m.node_h(j), 0.0);
            EXPECT_NEAR(m.node_h(j), std::sin(kPi / 2 * gl.nodes[std::size_t(n - m.half_nodes() + j)]), 1e-15);
            total += m.node_weight(j) * (m.node_mirrored(j) ? 2 : 1);
        }
        EXPECT_NEAR(total, 1.0, 1e-14) << n;
    }
}
