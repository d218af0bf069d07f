// MarschnerFiber (Marschner et al. 2003 with d'Eon's 2θh correction): the cubic's roots and
// pushforward, the root sum N_p against a histogram of the definition, the Gauss–Hermite
// rule, the lobe peaks of Marschner's tilt convention, chi-square of sample against pdf
// with negative controls, sample/pdf/eval consistency, extremes, the furnace figure (not
// energy conserving: reported, bounded) and parameter validation.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <boost/math/quadrature/gauss.hpp>
#include <gtest/gtest.h>

#include <hairscatter/models/marschner.hpp>

#include "support/chi2.hpp"
#include "support/reference_chiang.hpp"
#include "support/model_specs.hpp"

namespace hs = hairscatter;
using ref::kPi;

namespace {

double deg(double d) { return d * kPi / 180; }

// The cubic transcribed from Marschner et al. 2003 eq. 10, independently of the library:
// Φ̂(p, γ) = (6pc/π - 2)γ - (8pc/π³)γ³ + pπ, c = asin(1/η').
double cubic_ref(int p, double eta_prime, double gamma) {
    const double c = std::asin(1 / eta_prime);
    return (6 * p * c / kPi - 2) * gamma - 8 * p * c / (kPi * kPi * kPi) * gamma * gamma * gamma + p * kPi;
}

// Marschner's A_p (eq. 9 with the chord 2cosγt/cosθt) transcribed independently: Bravais
// indices at θd, Fresnel per polarisation with its own Snell law (total internal
// reflection → 1), internal reflection F(1/η', 1/η'', γt).
struct AttenuationRef {
    double eta, theta_d, sigma_a;
    double eta_p() const { return std::sqrt(eta * eta - std::sin(theta_d) * std::sin(theta_d)) / std::cos(theta_d); }
    double eta_pp() const { return eta * eta * std::cos(theta_d) / std::sqrt(eta * eta - std::sin(theta_d) * std::sin(theta_d)); }
    static double fresnel(double n1, double n2, double gamma) {
        auto one = [&](double n, bool perp) {
            const double st = std::sin(gamma) / n;
            if (st >= 1) return 1.0;
            const double ct = std::sqrt(1 - st * st), ci = std::cos(gamma);
            const double r = perp ? (ci - n * ct) / (ci + n * ct) : (n * ci - ct) / (n * ci + ct);
            return r * r;
        };
        return 0.5 * (one(n1, true) + one(n2, false));
    }
    double operator()(int p, double h) const {
        const double gi = std::asin(h), gt = std::asin(h / eta_p());
        const double f = fresnel(eta_p(), eta_pp(), gi);
        if (p == 0) return f;
        const double cos_tt = std::sqrt(1 - std::pow(std::sin(theta_d) / eta, 2));
        const double t = std::exp(-sigma_a * 2 * std::cos(gt) / cos_tt);
        if (p == 1) return (1 - f) * (1 - f) * t;
        return (1 - f) * (1 - f) * fresnel(1 / eta_p(), 1 / eta_pp(), gt) * t * t;
    }
};

}  // namespace

// Every root solves Φ̂ = φ to 1e-10 in double, and the solver finds as many roots as a
// dense scan of Φ̂ - φ has sign changes, for η' from 1 + 1e-4 to 1e4 (both sides of the
// TT fold at 2/√3 and the TRT fold at 2) and targets across and beyond the range.
TEST(MarschnerCubic, RootsSolveTheCubic) {
    double worst = 0;
    int checked = 0, mismatched = 0;
    for (double ep : {1.0001, 1.05, 1.1547, 1.2, 1.55, 1.9, 1.999, 2.0, 2.001, 2.5, 10.0, 1e4}) {
        for (int p = 0; p < 3; ++p) {
            const hs::MarschnerCubic<double> cubic(p, 1 / ep);
            const double r = cubic.half_range();
            const int ngrid = 4000;
            std::vector<double> grid(ngrid + 1);
            for (int i = 0; i <= ngrid; ++i) grid[std::size_t(i)] = cubic.f(-kPi / 2 + kPi * i / ngrid);
            for (int j = 0; j <= 400; ++j) {
                const double x = -1.05 * r + 2.1 * r * j / 400;
                double g[3];
                const int n = cubic.roots(x, g);
                for (int i = 0; i < n; ++i) {
                    EXPECT_GE(g[i], -kPi / 2);
                    EXPECT_LE(g[i], kPi / 2);
                    worst = std::max(worst, std::abs(cubic_ref(p, ep, g[i]) - p * kPi - x));
                    ++checked;
                }
                for (int i = 1; i < n; ++i) EXPECT_LE(g[i - 1], g[i]);
                int changes = 0;
                for (int i = 0; i < ngrid; ++i)
                    if ((grid[std::size_t(i)] - x < 0) != (grid[std::size_t(i + 1)] - x < 0)) ++changes;
                // Roots closer than the scan's step (a double root at a fold, the triple root
                // at η' = 2) change sign by the parity of their multiplicity.
                int parity = 0;
                for (int i = 0, j = 0; i < n; i = j) {
                    for (j = i + 1; j < n && g[j] - g[j - 1] < 2 * kPi / ngrid; ++j) {
                    }
                    parity += (j - i) % 2;
                }
                // Otherwise only a target within 1e-3 of the fold's value may be resolved
                // differently (rounding decides whether the pair of roots exists).
                if (changes != n) ++mismatched;
                if (changes != n && changes != parity) {
                    EXPECT_LT(std::abs(std::abs(x) - r), 1e-3 * r + 1e-9)
                        << "p " << p << " η' " << ep << " x " << x << ": " << n << " roots, " << changes << " sign changes";
                }
            }
        }
    }
    std::printf("[ roots    ] %d roots, worst |Φ̂(γr) - φ| = %.3g (double); %d targets with roots closer than "
                "the scan resolves\n",
                checked, worst, mismatched);
    EXPECT_LT(worst, 1e-10);
}

// The pushforward CDF C(x) = ½|{h : Φ̂(asin h) - pπ ≤ x}| against the empirical CDF of 10⁶
// midpoints h: within 1/10⁶ plus rounding (each midpoint carries mass 10⁻⁶).
TEST(MarschnerCubic, PushforwardCdfMatchesDenseH) {
    const int nh = 1000000;
    double worst = 0;
    for (double ep : {1.2, 1.55, 1.9, 2.3}) {
        for (int p = 0; p < 3; ++p) {
            const hs::MarschnerCubic<double> cubic(p, 1 / ep);
            std::vector<double> v(nh);
            for (int i = 0; i < nh; ++i) v[std::size_t(i)] = cubic.f(std::asin(-1 + (2 * i + 1.0) / nh));
            std::sort(v.begin(), v.end());
            const double r = cubic.half_range();
            for (int j = 0; j <= 200; ++j) {
                const double x = -1.02 * r + 2.04 * r * j / 200;
                const double emp = double(std::upper_bound(v.begin(), v.end(), x) - v.begin()) / nh;
                worst = std::max(worst, std::abs(cubic.cdf(x) - emp));
            }
        }
    }
    std::printf("[ cdf      ] pushforward C(x) vs empirical CDF of 1e6 h: worst %.3g\n", worst);
    EXPECT_LT(worst, 1.5e-6);
}

// Marschner's N_p(φ) = Σ_r A_p(h_r)/|2 dΦ/dh| (fiber.smooth_azimuthal) against its
// definition, the density of Φ̂(p, h) for uniform h weighted by A_p(h)/2: 4·10⁶ midpoints h
// histogrammed into 180 bins of φ (Φ̂ from the cubic, the model's own Φ; A_p from the
// independent transcription above), against ∫_bin N_p dφ by 16-point Gauss–Legendre.
// Bins within 0.1 rad of a TRT fold (N is infinite there) are skipped. Tolerance 2e-3
// relative for bins above 1 % of the largest: a bin's edge cuts at most one h cell per
// root (mass ≤ A/4·10⁶ each, ≤ 5e-4 of the smallest compared bin), and the GL rule is
// accurate to ~1e-6 on bins that stay 0.1 rad from a fold.
TEST(MarschnerAzimuthal, RootSumMatchesHistogramOfTheDefinition) {
    hs::MarschnerParams<double> prm;
    prm.sigma_a = glm::dvec3(0.4);
    const hs::MarschnerMaterial<double> mat(prm);
    const hs::MarschnerFiber<double> fiber(mat);
    const double theta_o = 0.5, theta_i = -0.3, phi_o = 0.2;
    const AttenuationRef aref{prm.eta, 0.5 * (theta_o - theta_i), 0.4};
    const double ep = aref.eta_p();
    const glm::dvec3 wo = ref::dir(theta_o, phi_o);
    const int bins = 180, nh = 4000000;
    const double width = 2 * kPi / bins;
    double worst = 0;
    int compared = 0;
    for (int p = 0; p < 3; ++p) {
        std::vector<double> hist(bins, 0.0);
        for (int i = 0; i < nh; ++i) {
            const double h = -1 + (2 * i + 1.0) / nh;
            double phi = std::remainder(cubic_ref(p, ep, std::asin(h)), 2 * kPi);  // [-π, π]
            const int b = std::min(bins - 1, std::max(0, int((phi + kPi) / width)));
            hist[std::size_t(b)] += aref(p, h) / nh;  // ½ A_p dh with dh = 2/nh
        }
        const hs::MarschnerCubic<double> cubic(p, 1 / ep);
        const double fold_phi = cubic.fold() > 0 ? cubic.f(cubic.fold()) : -10;  // TRT: ±φc about 2π ≡ 0
        std::vector<double> mass(bins);
        double peak = 0;
        for (int b = 0; b < bins; ++b) {
            const double lo = -kPi + b * width;
            mass[std::size_t(b)] = boost::math::quadrature::gauss<double, 16>::integrate(
                [&](double phi) { return fiber.smooth_azimuthal(p, wo, ref::dir(theta_i, phi_o + phi)).g; }, lo, lo + width);
            peak = std::max(peak, mass[std::size_t(b)]);
        }
        for (int b = 0; b < bins; ++b) {
            const double lo = -kPi + b * width, hi = lo + width;
            const double d = std::min(std::abs(std::abs(lo) - fold_phi), std::abs(std::abs(hi) - fold_phi));
            if (p == 2 && d < 0.1) continue;
            if (mass[std::size_t(b)] < 0.01 * peak && hist[std::size_t(b)] < 0.01 * peak) continue;
            const double e = std::abs(hist[std::size_t(b)] / mass[std::size_t(b)] - 1);
            worst = std::max(worst, e);
            ++compared;
            EXPECT_LT(e, 2e-3) << "p " << p << " bin [" << lo << ", " << hi << "]: histogram " << hist[std::size_t(b)]
                               << ", root sum " << mass[std::size_t(b)];
        }
    }
    std::printf("[ N_p      ] root sum vs histogram of ½A_p over 4e6 h (η' = %.4f): %d bins, worst relative %.3g "
                "(tolerance 2e-3)\n",
                ep, compared, worst);
}

// The Gauss–Hermite rule integrates the standard normal's moments: 1, E z² = 1, E z⁴ = 3,
// E z⁶ = 15 (exact up to degree 2n - 1), symmetric nodes.
TEST(MarschnerMaterial, GaussHermiteRuleIntegratesNormalMoments) {
    for (int n : {1, 2, 3, 4, 7, 16, 40}) {
        const hs::GaussHermite<double> gh(n);
        double m[4] = {0, 0, 0, 0};
        for (int k = 0; k < n; ++k) {
            const double z = gh.nodes[std::size_t(k)], w = gh.weights[std::size_t(k)];
            m[0] += w, m[1] += w * z * z, m[2] += w * std::pow(z, 4), m[3] += w * std::pow(z, 6);
            EXPECT_NEAR(z, -gh.nodes[std::size_t(n - 1 - k)], 1e-14);
        }
        const double exact[4] = {1, 1, 3, 15};
        for (int j = 0; j < 4 && 2 * j <= 2 * n - 1; ++j)
            EXPECT_NEAR(m[j], exact[j], 1e-11 * exact[j]) << n << " nodes, moment " << 2 * j;
    }
}

// Marschner's tilt convention, pinned where the paper puts the lobes: M_p(θh) =
// g(β_p; 2θh - α_p) peaks at θi + θo = α_p with α_TT = -α_R/2, α_TRT = -3α_R/2 (Table 1),
// and the full eval's R highlight (TT, TRT absorbed away) sits there too, to the small
// pull of the cosθi/cos²θd factor (< 0.1° for β_R = 2°).
TEST(MarschnerLongitudinal, LobesPeakWhereThePaperPutsThem) {
    hs::MarschnerParams<double> prm;
    prm.alpha_r = deg(-8);
    prm.beta_r = deg(2);
    prm.sigma_a = glm::dvec3(1e3);
    const hs::MarschnerMaterial<double> mat(prm);
    const double expected[3] = {deg(-8), deg(4), deg(12)};
    for (double theta_o : {deg(-40), 0.0, deg(30)}) {
        for (int p = 0; p < 3; ++p) {
            double best = -1, arg = 0;
            for (int i = 0; i <= 200000; ++i) {
                const double ti = -kPi / 2 + kPi * i / 200000;
                const double v = mat.longitudinal(p).eval(ti, theta_o);
                if (v > best) best = v, arg = ti;
            }
            EXPECT_NEAR(arg + theta_o, expected[p], 2e-5) << "lobe " << p << " θo " << theta_o;
            EXPECT_NEAR(mat.lobe_shift(p), expected[p], 1e-15);
        }
        const hs::MarschnerFiber<double> fiber(mat);
        const glm::dvec3 wo = ref::dir(theta_o, 0.0);
        double best = -1, arg = 0;
        for (int i = 0; i <= 20000; ++i) {
            const double ti = -theta_o + deg(-20) + deg(40) * i / 20000;
            const double v = fiber.eval(wo, ref::dir(ti, 0.3)).g;
            if (v > best) best = v, arg = ti;
        }
        std::printf("[ peak     ] θo = %5.1f°: R highlight of eval at θi + θo = %.3f° (α_R = -8°)\n", theta_o * 180 / kPi,
                    (arg + theta_o) * 180 / kPi);
        EXPECT_NEAR(arg + theta_o, deg(-8), deg(0.1));
    }
}

// Marschner 2003 §4.3, the TRT caustic replacement, with one roughness node (no
// roughness) so that eval shows N_TRT itself: (i) at the cubic's fold φc (found here by a
// scan of the independent cubic) the smooth root sum is huge but eval stays finite; (ii)
// the caustic term is linear in k_G and shaped as two Gaussians of width w_c at ±φc; (iii) it fades out: present for
// η' ∈ (2, 2 + Δη'), exactly absent for η' ≥ 2 + Δη'.
TEST(MarschnerAzimuthal, TrtCausticIsReplacedAndFades) {
    const double theta_o = 0.2, theta_i = -0.2, phi_o = 0.1;  // θd = 0.2
    auto fiber_eval = [&](double eta, double gain, double phi) {
        hs::MarschnerParams<double> prm;
        prm.eta = eta;
        prm.caustic_gain = gain;
        prm.alpha_r = 0;
        const hs::MarschnerMaterial<double> mat(prm, 1);
        const hs::MarschnerFiber<double> fiber(mat);
        const glm::dvec3 wo = ref::dir(theta_o, phi_o), wi = ref::dir(theta_i, phi_o + phi);
        return std::make_pair(fiber.eval(wo, wi).g, fiber.smooth_azimuthal(2, wo, wi).g);
    };
    const AttenuationRef aref{1.55, 0.2, 0.0};
    const double ep = aref.eta_p();
    double phi_c = 0;
    for (int i = 0; i <= 200000; ++i) phi_c = std::max(phi_c, cubic_ref(2, ep, kPi / 2 * i / 200000) - 2 * kPi);
    const auto at_fold = fiber_eval(1.55, 0.5, phi_c);
    EXPECT_TRUE(std::isfinite(at_fold.first));
    EXPECT_GT(at_fold.second, 1e3 * at_fold.first) << "the root sum is not singular at the fold";

    // The added term is t Δh kG A_TRT(hc) (g(wc; φ - φc) + g(wc; φ + φc)) times factors
    // that do not depend on φ: its ratio to the two Gaussians is constant in φ.
    const double wc = hs::MarschnerParams<double>{}.caustic_width;
    auto gauss = [&](double x) { return std::exp(-0.5 * x * x / (wc * wc)); };
    double lo = 1e300, hi = 0;
    for (int i = 0; i <= 400; ++i) {
        const double phi = -1.5 + 3.0 * i / 400;
        const double d1 = fiber_eval(1.55, 1.0, phi).first - fiber_eval(1.55, 0.0, phi).first;
        const double d2 = fiber_eval(1.55, 2.0, phi).first - fiber_eval(1.55, 0.0, phi).first;
        EXPECT_GT(d1, 0.0);
        EXPECT_NEAR(d2, 2 * d1, 1e-12 * std::abs(d2) + 1e-14);  // + rounding of f itself (≲ 10)
        const double ratio = d1 / (gauss(phi - phi_c) + gauss(phi + phi_c));
        lo = std::min(lo, ratio), hi = std::max(hi, ratio);
    }
    std::printf("[ caustic  ] η' = %.4f: fold at φc = ±%.4f rad; caustic term / (g(φ - φc) + g(φ + φc)) constant to %.2g\n",
                ep, phi_c, hi / lo - 1);
    EXPECT_LT(hi / lo - 1, 1e-7);

    // η' = √(η² - sin²θd)/cosθd: η = 2.1 gives η' ≈ 2.14 (fading), η = 2.4 gives 2.45 > 2.3.
    for (double eta : {2.1, 2.4}) {
        const double ep2 = AttenuationRef{eta, 0.2, 0.0}.eta_p();
        const double d = fiber_eval(eta, 1.0, 0.0).first - fiber_eval(eta, 0.0, 0.0).first;
        if (ep2 < 2.3) {
            EXPECT_GT(d, 0.0) << "η' = " << ep2;
        } else {
            EXPECT_EQ(d, 0.0) << "η' = " << ep2;
        }
    }
}

// Eccentricity through η*(φh) at Marschner's half azimuth φh = (φi + φo)/2 (theory §3.4):
// η*1, η*2 by hand at a = 0.9; an eccentric fiber's eval equals the round fiber's with
// η = η*(φh) for the same directions; the round fiber does not depend on φo, the
// eccentric one does.
TEST(MarschnerMaterial, EccentricityEntersThroughTheHalfAzimuth) {
    const hs::EccentricIndex<double> e(1.55, 0.9);
    EXPECT_NEAR(e.eta1, 2 * 0.55 * 0.81 - 1.55 + 2, 1e-15);
    EXPECT_NEAR(e.eta2, 2 * 0.55 / 0.81 - 1.55 + 2, 1e-15);
    EXPECT_NEAR(e(1.0), e.eta1, 1e-15);
    EXPECT_NEAR(e(-1.0), e.eta2, 1e-15);
    hs::MarschnerParams<double> prm;
    prm.eccentricity = 0.9;
    prm.sigma_a = glm::dvec3(0.3, 0.5, 1.0);
    const hs::MarschnerMaterial<double> mat(prm);
    const hs::MarschnerFiber<double> fiber(mat);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> uni(0, 1);
    double spread = 0;
    for (int k = 0; k < 50; ++k) {
        const double to = std::asin(-0.9 + 1.8 * uni(rng)), ti = std::asin(-0.9 + 1.8 * uni(rng));
        const double phi_o = 2 * kPi * uni(rng), phi = -kPi + 2 * kPi * uni(rng);
        const glm::dvec3 wo = ref::dir(to, phi_o), wi = ref::dir(ti, phi_o + phi);
        hs::MarschnerParams<double> round = prm;
        round.eccentricity = 1;
        round.eta = e(std::cos(2 * phi_o + phi));
        const hs::MarschnerMaterial<double> round_mat(round);
        const glm::dvec3 f = fiber.eval(wo, wi), fr = hs::MarschnerFiber<double>(round_mat).eval(wo, wi);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], fr[c], 1e-10 * fr[c] + 1e-300) << k;
        // Rotating both directions about the axis: only the eccentric fiber changes.
        const glm::dvec3 wo2 = ref::dir(to, phi_o + 0.8), wi2 = ref::dir(ti, phi_o + 0.8 + phi);
        EXPECT_NEAR(hs::MarschnerFiber<double>(round_mat).eval(wo2, wi2).g, fr.g, 1e-10 * fr.g);
        spread = std::max(spread, std::abs(fiber.eval(wo2, wi2).g / f.g - 1));
    }
    EXPECT_GT(spread, 1e-2);
}

namespace {

using Spec = specs::MarschnerSpec<double>;

}  // namespace

// Negative control at the grid's significance (the contract suite rejects this case's pdf
// × 1.05): the pdf of the fiber whose R lobe is shifted by 3° more (α_R = -10.5° against
// samples of -7.5°) must be rejected.
TEST(MarschnerChi2, NegativeControlsAreRejected) {
    const Spec::Case c{7.5, 0.3, -7.5, 30, 0.0, 1.0, 7};
    const hs::MarschnerMaterial<double> mat(Spec::chi2_params(c), c.nodes);
    const hs::MarschnerFiber<double> fiber(mat);
    const glm::dvec3 wo = ref::dir(deg(c.theta_o_deg), 0.7);
    auto sample = [&](const glm::dvec4& u) { return fiber.sample(wo, u).wi; };
    Spec::Case shifted = c;
    shifted.alpha_r_deg -= 3;
    const hs::MarschnerMaterial<double> other_mat(Spec::chi2_params(shifted), c.nodes);
    const hs::MarschnerFiber<double> other(other_mat);
    const auto moved = chi2::test(sample, [&](const glm::dvec3& wi) { return other.pdf(wo, wi); },
                                  Spec::chi2_options());
    EXPECT_FALSE(moved.passed) << "the pdf with α_R 3° further was accepted (p = " << moved.p_value << ")";
    std::printf("[ chi2     ] negative control: p = %.3g (R lobe shifted by 3°)\n", moved.p_value);
}

namespace {

// ∫ f dωi = ∫∫ f cosθi dθi dφ: θi by 20-point Gauss–Legendre on pieces broken at each
// lobe's peak α_p - θo ± 1, 3, 6 widths and near the poles; φ by the trapezoidal rule on
// 512 points (periodic, so spectrally accurate once the points resolve σ and w_c).
double furnace(const hs::MarschnerMaterial<double>& mat, double theta_o) {
    const hs::MarschnerFiber<double> fiber(mat);
    const glm::dvec3 wo = ref::dir(theta_o, 0.3);
    std::vector<double> cuts = {-kPi / 2, -kPi / 2 + 0.02, kPi / 2 - 0.02, kPi / 2};
    for (int p = 0; p < 3; ++p) {
        const double peak = mat.lobe_shift(p) - theta_o, w = mat.lobe_width(p);
        for (double k : {-6.0, -3.0, -1.0, 0.0, 1.0, 3.0, 6.0}) cuts.push_back(std::clamp(peak + k * w, -kPi / 2, kPi / 2));
    }
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    const int m = 512;
    auto inner = [&](double ti) {
        double s = 0;
        for (int k = 0; k < m; ++k) s += fiber.eval(wo, ref::dir(ti, 0.3 + 2 * kPi * k / m)).g;
        return s * (2 * kPi / m) * std::cos(ti);
    };
    double total = 0;
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
        total += boost::math::quadrature::gauss<double, 20>::integrate(inner, cuts[k], cuts[k + 1]);
    return total;
}

}  // namespace

// Marschner 2003 is not energy conserving (docs/theory.md §3.5): ∫ f dωi for a lossless fiber
// at the default parameters is reported per θo, and only bounded: finite, positive and
// below 2 (the Gaussians integrate to 1 over the real line; A_R + A_TT + A_TRT ≤ 1; the
// 1/cos²θd factor stays near 1 except in a thin band at grazing θo).
TEST(MarschnerFurnace, ReportedPerAngleAndBounded) {
    const hs::MarschnerMaterial<double> mat{hs::MarschnerParams<double>{}};
    std::string figure;
    for (double t : {0.0, 30.0, 60.0, 80.0, 89.0}) {
        const double e = furnace(mat, deg(t));
        char buf[64];
        std::snprintf(buf, sizeof buf, "%s%g°: %.4f", figure.empty() ? "" : ", ", t, e);
        figure += buf;
        EXPECT_TRUE(std::isfinite(e));
        EXPECT_GT(e, 0.0);
        EXPECT_LT(e, 2.0) << "θo = " << t << "°";
        // A regression pin of the figures measured when the model was written (not a claim
        // about energy): a change of the model's definition moves them by more than 2e-3.
        const double pinned = t == 0 ? 0.9595 : t == 30 ? 0.9828 : t == 60 ? 1.0538 : t == 80 ? 0.6966 : 0.5634;
        EXPECT_NEAR(e, pinned, 2e-3) << "θo = " << t << "°: the furnace figure moved";
    }
    std::printf("[ furnace  ] ∫ f dωi, σa = 0, default parameters, per θo: %s\n", figure.c_str());
    ::testing::Test::RecordProperty("furnace", figure);
}

// The two sample/pdf mismatches the float stress run found (bench/stress.cpp, material 1:
// β_R = 1e-4 rad, β_n = 1e-3): u.x = 1 - ulp draws TRT at h → 1, whose exit azimuth is the
// end of the cubic's range (η' > 2 at this θd: no fold), and u.w = 1 - ulp puts φ at the
// far edge of the last roughness cell. There the azimuthal mass of the cell is ~1e-7 of h,
// once taken as the difference of two pushforward CDFs near 1 it was float rounding (the
// d'Eon lobe, 4e6 at its peak, magnifies it). Both pdfs must agree to the stress run's
// tolerance: 1e-2 relative + 1e-3 absolute (the float rounding of wi moves them by ~1e-4).
namespace {
// The stress run's material 1: both widths at their lower limits.
template <typename T> hs::MarschnerParams<T> narrowest_params() {
    hs::MarschnerParams<T> p;
    p.sigma_a = glm::vec<3, T>(T(0.5), T(0.3), T(0.2));
    p.beta_r = hs::kMinMarschnerWidth<T>;
    p.beta_n = hs::kMinRoughness<T>;
    return p;
}
}  // namespace

TEST(MarschnerFiber, FloatPdfOfTrtSampleAtTheEndOfTheRangeMatchesSample) {
    const hs::MarschnerMaterial<float> mat(narrowest_params<float>());
    const hs::MarschnerFiber<float> fiber(mat);
    // The same material in double: the float pdf must also be its value, not only agree
    // with itself (before the fix both float pdfs were 3-5 % off the double one).
    const hs::MarschnerMaterial<double> mat_d(narrowest_params<double>());
    const hs::MarschnerFiber<double> fiber_d(mat_d);
    struct Case {
        glm::vec3 wo;
        glm::vec4 u;
    };
    const Case cases[] = {
        {{0x1.98ef8cp-1f, -0x1.a9410ep-2f, -0x1.bde4cap-2f}, {0x1.fffffep-1f, 0x1.fffffep-1f, 0x1.1177cap-1f, 0x1.fffffep-1f}},
        {{0x1.5d6a1ap-1f, 0x1.6ad1f4p-2f, 0x1.475416p-1f}, {1.0f, 0x1.fffffep-1f, 0x1.b3f5cap-2f, 0x1.8c0fd2p-1f}},
    };
    for (const Case& c : cases) {
        const hs::HairSample<float> s = fiber.sample(c.wo, c.u);
        EXPECT_EQ(s.lobe, hs::SampledLobe::kTRT);
        ASSERT_GT(s.pdf, 0.0f);
        const double back = fiber.pdf(c.wo, s.wi);
        EXPECT_NEAR(back, s.pdf, 1e-2 * std::max(back, double(s.pdf)) + 1e-3) << "wi " << s.wi.x << " " << s.wi.y << " " << s.wi.z;
        // 1e-3 relative: the float rounding of θi and φ (~1e-7 rad) moves a mass that is
        // quadratic in a ~1e-3 rad window by ~2e-4 relative.
        const double ref = fiber_d.pdf(glm::dvec3(c.wo), glm::dvec3(s.wi));
        EXPECT_NEAR(s.pdf, ref, 1e-3 * ref);
        EXPECT_NEAR(back, ref, 1e-3 * ref);
    }
}
