// The physical fur reference (tests/support/physical_fur.hpp) against what is known
// independently of it: the hair reference when the medulla is absent or inert, energy,
// the medulla's chord and Fresnel optics by quadrature over the offset h, the phase
// function's sampling, reciprocity, and finite output at the parameters' extremes.
#include <array>
#include <cmath>
#include <cstdio>
#include <thread>
#include <vector>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <gtest/gtest.h>

#include "support/physical_fur.hpp"

namespace pf = phys_fiber;
namespace fur = phys_fur;

namespace {

constexpr int kThreads = 2;

glm::dvec3 direction(double theta_deg, double phi = 0) {
    const double t = theta_deg * pf::kPi / 180;
    return {std::sin(t), std::cos(t) * std::sin(phi), std::cos(t) * std::cos(phi)};  // φ = 0: wo in the x–z plane
}

// A smooth round fibre seen at θ, by the offset h of the entering ray: Fresnel at entry,
// Bravais' index for the refracted ray's distance |h|/η' from the axis, and the 3D lengths
// of its straight path through cortex and medulla (the in-plane chords over cos θt).
struct SmoothPath {
    double fresnel = 0;   // F at entry (= F at the exit of the unscattered TT path)
    double cortex = 0;    // 3D length in the cortex, both sides of the medulla
    double medulla = 0;   // 3D length in the medulla
};
SmoothPath smooth_path(double h, double theta, double eta, double kappa) {
    const double ct = std::cos(theta), st = std::sin(theta);
    const double eta_p = std::sqrt(eta * eta - st * st) / ct;  // Bravais' index η'
    const double cos_t = std::sqrt(1 - (st / eta) * (st / eta));
    const double hp = h / eta_p;
    SmoothPath p;
    p.fresnel = pf::fresnel(ct * std::sqrt(1 - h * h), eta);
    const double total = 2 * std::sqrt(std::max(0.0, 1 - hp * hp)) / cos_t;
    p.medulla = 2 * std::sqrt(std::max(0.0, kappa * kappa - hp * hp)) / cos_t;
    p.cortex = total - p.medulla;
    return p;
}

// ½ ∫ g(h) dh over the fibre's width, written over γ = asin h (h = sin γ, dh = cos γ dγ)
// and split where the refracted ray grazes the medulla (|h| = κη'), where g has a kink.
template <typename G>
double over_width(const G& g, double theta, double eta, double kappa) {
    using GK = boost::math::quadrature::gauss_kronrod<double, 31>;
    const double eta_p = std::sqrt(eta * eta - std::sin(theta) * std::sin(theta)) / std::cos(theta);
    const double gm = std::asin(std::min(1.0, kappa * eta_p));
    const auto f = [&](double gamma) { return 0.5 * g(std::sin(gamma)) * std::cos(gamma); };
    double sum = 0;
    const double cuts[5] = {-0.5 * pf::kPi, -gm, 0.0, gm, 0.5 * pf::kPi};
    for (int k = 0; k < 4; ++k)
        if (cuts[k + 1] > cuts[k]) sum += GK::integrate(f, cuts[k], cuts[k + 1], 15, 1e-12);
    return sum;
}

fur::Fur smooth_fur(double kappa) {
    fur::Fur f;
    f.cortex.roughness = 1e-4;  // smooth within the walk's numerics (as physical_fiber_test)
    f.cortex.tilt = 0;
    f.kappa = kappa;
    return f;
}

// Traces the smooth fibre f at θ (400,000 rays) and expects a per-channel tally of the
// histogram, per ray, to be ½ ∫ g(c, path(h)) dh within 4σ (weights in [0, 1]: the
// variance of a ray's tally is at most p(1 − p)).
template <typename Tally, typename G>
void expect_quadrature(const fur::Fur& f, double theta_deg, std::uint64_t seed, const char* what, const Tally& tally,
                       const G& g) {
    fur::Histogram h(4, 4);
    const long long n = 400000;
    fur::trace_parallel(fur::Tracer(f), direction(theta_deg), n, seed, kThreads, h);
    const double theta = theta_deg * pf::kPi / 180;
    for (int c = 0; c < 4; ++c) {
        const double quad = over_width([&](double hh) { return g(c, smooth_path(hh, theta, f.cortex.eta, f.kappa)); }, theta,
                                       f.cortex.eta, f.kappa);
        const double mc = tally(h, c) / n;
        const double sigma = std::sqrt(quad * (1 - quad) / n);
        std::printf("θ %2.0f° channel %d: %s trace %.5f quadrature %.5f (σ %.5f)\n", theta_deg, c, what, mc, quad, sigma);
        EXPECT_NEAR(mc, quad, 4 * sigma);
    }
}

}  // namespace

TEST(PhysicalFur, WithoutAMedullaIsThePhysicalFiber) {
    // κ = 0, and an inert medulla (σs^m = 0, σa^m = σa^c): both are physical_fiber.hpp's
    // round fibre. Different seeds: agreement within the noise, not by replay.
    pf::Fiber fiber;
    fiber.tilt = 2 * pf::kPi / 180;
    fiber.sigma_a = glm::dvec3(0.5447, 0.9061, 1.781);
    const glm::dvec3 wo = direction(30);
    const long long n = 1000000;
    pf::Histogram ref(8, 16);
    fur::trace_parallel(pf::Tracer(fiber), wo, n, 1, kThreads, ref);
    for (const double kappa : {0.0, 0.5}) {
        fur::Fur f;
        f.cortex = fiber;
        f.kappa = kappa;
        f.sigma_s = kappa > 0 ? 0.0 : 5.0;  // with κ = 0 σs^m has nothing to act on
        f.sigma_a_medulla = fiber.sigma_a;
        fur::Histogram h(8, 16);
        fur::trace_parallel(fur::Tracer(f), wo, n, kappa > 0 ? 3 : 2, kThreads, h);
        for (int c = 0; c < 4; ++c) {
            for (int l = 0; l < pf::kLobes; ++l) {
                const double a = h.lobe_energy[l][c] / n, b = ref.lobe_energy[l][c] / n;
                // Weights in [0, 1]: their variance is at most p(1 − p); two estimates.
                const double sigma = std::sqrt(2 * b * (1 - b) / n);
                EXPECT_NEAR(a, b, 4 * sigma) << "κ " << kappa << " class " << l << " channel " << c;
            }
            EXPECT_EQ(h.lobe_energy[fur::kScattered][c], 0.0);
        }
        // The lossless channel's bins hold counts: a two-sample chi-square over the
        // sphere, bins with fewer than 10 rays between both pooled.
        double chi2 = 0, pool_a = 0, pool_b = 0;
        int dof = 0;
        for (int bin = 0; bin < 8 * 16; ++bin) {
            double a = 0;
            for (int l = 0; l < fur::kClasses; ++l) a += h.energy[std::size_t((bin * fur::kClasses + l) * 4)];
            const double b = ref.f(bin, 0) * n * ref.bin_solid_angle();
            if (a + b < 10) {
                pool_a += a;
                pool_b += b;
                continue;
            }
            chi2 += (a - b) * (a - b) / (a + b);
            ++dof;
        }
        if (pool_a + pool_b > 0) {
            chi2 += (pool_a - pool_b) * (pool_a - pool_b) / (pool_a + pool_b);
            ++dof;
        }
        const double p = boost::math::cdf(boost::math::complement(boost::math::chi_squared(dof), chi2));
        std::printf("κ %.1f: histogram chi-square %.1f, %d bins, p %.3f\n", kappa, chi2, dof, p);
        EXPECT_GT(p, 1e-3);
    }
}

TEST(PhysicalFur, LosslessKeepsEnergy) {
    struct Medulla {
        double kappa, sigma_s, g;
    };
    for (const Medulla& m : {Medulla{0.3, 1, 0}, Medulla{0.6, 10, 0.5}, Medulla{0.9, 10, -0.6}, Medulla{0.9, 50, 0.9}}) {
        for (const double roughness : {1e-4, 0.3}) {
            fur::Fur f;
            f.cortex.roughness = roughness;
            f.cortex.sigma_a = glm::dvec3(0.2, 0.5, 1.0);
            f.sigma_a_medulla = glm::dvec3(1.0, 0.0, 0.3);
            f.kappa = m.kappa;
            f.sigma_s = m.sigma_s;
            f.g = m.g;
            fur::Histogram h(8, 8);
            fur::trace_parallel(fur::Tracer(f), direction(40, 0.3), 100000, 3, kThreads, h);
            double out = 0, binned = 0;
            for (int l = 0; l < fur::kClasses; ++l) out += h.lobe_energy[l][0] / h.rays;
            for (int bin = 0; bin < 64; ++bin) binned += h.f(bin, 0) * h.bin_solid_angle();
            std::printf("κ %.1f σs %4.0f g %+.1f β %.0e: out %.6f lost %.1e scattered %.4f scatterings/ray %.1f\n", m.kappa,
                        m.sigma_s, m.g, roughness, out, h.lost[0] / h.rays, h.lobe_energy[fur::kScattered][0] / h.rays,
                        h.scatterings / h.rays);
            // Rays trapped past the caps: none expected at these optical sizes.
            EXPECT_LT(h.lost[0] / h.rays, 1e-4);
            EXPECT_NEAR(out, 1.0, 1e-4);
            EXPECT_NEAR(binned, out, 1e-9);  // every exit is binned once
            EXPECT_EQ(h.absorbed[0], 0.0);
            EXPECT_GT(h.lobe_energy[fur::kScattered][0], 0.0);
            // Absorbing channels: out + absorbed + lost is what went in.
            for (int c = 1; c < 4; ++c) {
                double sum = h.absorbed[c] + h.lost[c];
                for (int l = 0; l < fur::kClasses; ++l) sum += h.lobe_energy[l][c];
                EXPECT_NEAR(sum / h.rays, 1.0, 1e-9);
            }
        }
    }
}

TEST(PhysicalFur, FirstScatterIsTheMedullaChord) {
    // The light that scatters in the medulla before it first meets the boundary again:
    // ½ ∫ (1 − F) e^{−σa^c ℓc/2} σs/σt (1 − e^{−σt ℓm}) dh, σt = σs^m + σa^m, the cortex
    // crossed once (ℓc/2) before the medulla. Channels: lossless; cortex absorbing;
    // medulla absorbing; both.
    const double kappa = 0.5, sigma_s = 1.5;
    const double sa_c[4] = {0, 0.4, 0, 0.4}, sa_m[4] = {0, 0, 1.0, 1.0};
    fur::Fur f = smooth_fur(kappa);
    f.sigma_s = sigma_s;
    f.cortex.sigma_a = glm::dvec3(sa_c[1], sa_c[2], sa_c[3]);
    f.sigma_a_medulla = glm::dvec3(sa_m[1], sa_m[2], sa_m[3]);
    for (const double theta_deg : {0.0, 30.0})
        expect_quadrature(
            f, theta_deg, 5, "first-passage scattering",
            [](const fur::Histogram& h, int c) { return h.first_passage_scattered[c]; },
            [&](int c, const SmoothPath& p) {
                const double st = sigma_s + sa_m[c];
                return (1 - p.fresnel) * std::exp(-sa_c[c] * 0.5 * p.cortex) * sigma_s / st * (1 - std::exp(-st * p.medulla));
            });
}

TEST(PhysicalFur, HenyeyGreensteinSamplingMatchesItsDensity) {
    using GK = boost::math::quadrature::gauss_kronrod<double, 15>;
    for (const double g : {-0.7, 0.0, 0.3, 0.9}) {
        // The density integrates to 1 (2π ∫ p dcos): the expected counts below are right.
        const double total = 2 * pf::kPi * GK::integrate([&](double c) { return fur::hg_phase(c, g); }, -1.0, 1.0, 10, 1e-12);
        EXPECT_NEAR(total, 1.0, 1e-9);
        // Chi-square of sampled cosines in 40 bins against the density integrated per bin
        // (bins equal in the cosine, finer than the forward peak at g 0.9 needs: 20 % of
        // the mass in the last bin).
        const int bins = 40, n = 400000;
        std::vector<double> observed(bins, 0.0);
        pf::Rng rng(7);
        double mean_cos = 0, mean_dot = 0;
        const glm::dvec3 d = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
        for (int k = 0; k < n; ++k) {
            const double c = fur::sample_hg_cos(g, rng.uniform());
            observed[std::size_t(std::min(bins - 1, int((c + 1) * 0.5 * bins)))] += 1;
            mean_cos += c / n;
            const double u1 = rng.uniform(), u2 = rng.uniform();
            const glm::dvec3 w = fur::scatter_direction(d, g, u1, u2);
            ASSERT_NEAR(glm::length(w), 1.0, 1e-12);
            mean_dot += glm::dot(w, d) / n;
        }
        double chi2 = 0;
        for (int b = 0; b < bins; ++b) {
            const double lo = -1 + 2.0 * b / bins, hi = -1 + 2.0 * (b + 1) / bins;
            const double e = n * 2 * pf::kPi * GK::integrate([&](double c) { return fur::hg_phase(c, g); }, lo, hi, 10, 1e-12);
            chi2 += (observed[std::size_t(b)] - e) * (observed[std::size_t(b)] - e) / e;
        }
        const double p = boost::math::cdf(boost::math::complement(boost::math::chi_squared(bins - 1), chi2));
        // The mean cosine of Henyey–Greenstein is g; σ of the sample mean ≤ 1/√n.
        std::printf("g %+.1f: chi-square %.1f (p %.3f), mean cosine %.4f, 3D mean cosine %.4f\n", g, chi2, p, mean_cos, mean_dot);
        EXPECT_GT(p, 1e-3);
        EXPECT_NEAR(mean_cos, g, 4 / std::sqrt(double(n)));
        EXPECT_NEAR(mean_dot, g, 4 / std::sqrt(double(n)));
    }
}

TEST(PhysicalFur, MedullaAbsorptionIsTheChordQuadrature) {
    // σs^m = 0: TT of the smooth fibre is ½ ∫ (1 − F)² e^{−σa^c ℓc − σa^m ℓm} dh (the exit
    // sees the entry's angle). Channels: lossless; medulla only; both; cortex only.
    const double sa_c[4] = {0, 0, 0.5, 0.5}, sa_m[4] = {0, 1.0, 1.0, 0};
    fur::Fur f = smooth_fur(0.6);
    f.cortex.sigma_a = glm::dvec3(sa_c[1], sa_c[2], sa_c[3]);
    f.sigma_a_medulla = glm::dvec3(sa_m[1], sa_m[2], sa_m[3]);
    for (const double theta_deg : {0.0, 30.0})
        expect_quadrature(
            f, theta_deg, 9, "TT", [](const fur::Histogram& h, int c) { return h.lobe_energy[fur::kTT][c]; },
            [&](int c, const SmoothPath& p) {
                return (1 - p.fresnel) * (1 - p.fresnel) * std::exp(-sa_c[c] * p.cortex - sa_m[c] * p.medulla);
            });
}

TEST(PhysicalFur, ThinMedullaScattersWithItsPhaseFunction) {
    // η = 1: no boundary (Fresnel 0, no refraction), the medulla a scattering cylinder in
    // air. Optically thin (σs^m κ = 0.018), light scatters once and leaves along the
    // scattered direction: seen from θ = 0, the scattered light's forward share (exits
    // with z < 0, the first half of the azimuth bins) is Henyey–Greenstein's P(cos > 0).
    // Tolerance 0.01 beyond the noise: the ~2 % of scattered light that scatters again.
    using GK = boost::math::quadrature::gauss_kronrod<double, 15>;
    for (const double g : {-0.5, 0.5}) {
        fur::Fur f = smooth_fur(0.9);
        f.cortex.eta = 1;
        f.sigma_s = 0.02;
        f.g = g;
        fur::Histogram h(4, 8);
        fur::trace_parallel(fur::Tracer(f), direction(0), 1000000, 13, kThreads, h);
        double forward = 0, all = 0;
        for (int bin = 0; bin < 32; ++bin) {
            const double e = h.f(bin, 0, fur::kScattered);
            all += e;
            if (bin % 8 < 4) forward += e;
        }
        const double share = forward / all;
        const double expected = 2 * pf::kPi * GK::integrate([&](double c) { return fur::hg_phase(c, g); }, 0.0, 1.0, 10, 1e-12);
        const double scattered = h.lobe_energy[fur::kScattered][0];
        const double sigma = std::sqrt(expected * (1 - expected) / scattered);
        std::printf("g %+.1f: forward share %.4f, Henyey–Greenstein %.4f (σ %.4f), %.0f rays scattered\n", g, share, expected,
                    sigma, scattered);
        EXPECT_NEAR(share, expected, 4 * sigma + 0.01);
    }
}

TEST(PhysicalFur, ScatteredLightIsReciprocal) {
    // f(wo, wi) = S(wo, wi) cos θi with S symmetric (docs/theory.md §2). Light from a bin A
    // drawn with density ∝ cos θo (the power a far-field beam puts on the fibre) and
    // collected in a bin B carries (1/C_A) ∫_A ∫_B S cos θo cos θi, C_A = ∫_A cos θ dω:
    // C_A E(A→B) = C_B E(B→A) exactly, bins of any size.
    fur::Fur f;
    f.cortex.tilt = 0;  // a plain microsurface, whose walk Heitz et al. 2016 show reciprocal
    f.cortex.sigma_a = glm::dvec3(0.5447, 0.9061, 1.781);
    f.sigma_a_medulla = glm::dvec3(0.3);
    f.kappa = 0.6;
    f.sigma_s = 4;
    f.g = 0.5;
    const fur::Tracer tracer(f);
    const int n_u = 6, n_phi = 8, batches = 16;
    const long long per_batch = 40000;
    struct Bin {
        int iu, ip;
    };
    const auto u_lo = [&](const Bin& b) { return -1 + 2.0 * b.iu / n_u; };
    const auto cos_weight = [&](const Bin& b) {  // C = ∫ √(1 − u²) du dφ over the bin
        const auto prim = [](double u) { return 0.5 * (u * std::sqrt(1 - u * u) + std::asin(u)); };
        return (prim(u_lo(b) + 2.0 / n_u) - prim(u_lo(b))) * 2 * pf::kPi / n_phi;
    };
    // Energy per ray from bin `from` into bin `to`, per batch: [batch][channel][scattered only?].
    const auto transfer = [&](const Bin& from, const Bin& to, std::uint64_t seed) {
        std::vector<std::array<std::array<double, 2>, 4>> out(batches);
        const double lo = u_lo(from), hi = lo + 2.0 / n_u;
        const double u_min = lo < 0 && hi > 0 ? 0.0 : std::min(std::fabs(lo), std::fabs(hi));
        const double cos_max = std::sqrt(1 - u_min * u_min);
        std::vector<std::thread> pool;
        for (int t = 0; t < kThreads; ++t)
            pool.emplace_back([&, t] {
                pf::Rng rng(seed * 7919 + std::uint64_t(t));
                for (int b = t; b < batches; b += kThreads) {
                    fur::Histogram h(n_u, n_phi);
                    for (long long k = 0; k < per_batch;) {
                        const double u = lo + (hi - lo) * rng.uniform();
                        const double phi = -pf::kPi + 2 * pf::kPi / n_phi * (from.ip + rng.uniform());
                        const double c = std::sqrt(1 - u * u);
                        if (rng.uniform() * cos_max > c) continue;  // rejection: density ∝ cos θ
                        tracer.trace(glm::dvec3(u, c * std::cos(phi), c * std::sin(phi)), 1, seed * 1000003u + std::uint64_t(b * per_batch + k), h);
                        ++k;
                    }
                    const int bin = to.iu * n_phi + to.ip;
                    for (int ch = 0; ch < 4; ++ch)
                        for (int only = 0; only < 2; ++only)
                            out[std::size_t(b)][std::size_t(ch)][std::size_t(only)] =
                                h.f(bin, ch, only ? fur::kScattered : -1) * h.bin_solid_angle();
                }
            });
        for (auto& th : pool) th.join();
        return out;
    };
    const Bin pairs[2][2] = {{{3, 1}, {4, 5}}, {{2, 0}, {5, 3}}};
    for (const auto& pr : pairs) {
        const auto ab = transfer(pr[0], pr[1], 21), ba = transfer(pr[1], pr[0], 22);
        const double ca = cos_weight(pr[0]), cb = cos_weight(pr[1]);
        for (int ch : {0, 2})
            for (int only = 0; only < 2; ++only) {
                double m[2] = {0, 0}, v[2] = {0, 0};
                for (int side = 0; side < 2; ++side) {
                    const auto& e = side ? ba : ab;
                    const double scale = side ? cb : ca;
                    for (int b = 0; b < batches; ++b) m[side] += scale * e[std::size_t(b)][std::size_t(ch)][std::size_t(only)] / batches;
                    for (int b = 0; b < batches; ++b) {
                        const double x = scale * e[std::size_t(b)][std::size_t(ch)][std::size_t(only)] - m[side];
                        v[side] += x * x / (batches - 1) / batches;  // variance of the batch mean
                    }
                }
                const double sigma = std::sqrt(v[0] + v[1]);
                std::printf("bins (%d,%d)↔(%d,%d) channel %d %s: C·E %.5f / %.5f (σ %.5f)\n", pr[0].iu, pr[0].ip, pr[1].iu,
                            pr[1].ip, ch, only ? "scattered" : "all", m[0], m[1], sigma);
                EXPECT_GT(m[0], 10 * sigma);  // the pair sees light
                EXPECT_NEAR(m[0], m[1], 4 * sigma);
                // Power: without the cosines C the two sides differ beyond the noise.
                EXPECT_GT(std::fabs(m[0] / ca - m[1] / cb), 4 * std::sqrt(v[0] / (ca * ca) + v[1] / (cb * cb)));
            }
    }
}

TEST(PhysicalFur, ExtremeParametersStayFinite) {
    for (const double g : {-0.99, 0.99})
        for (const double theta_deg : {0.0, 89.0})
            for (const double roughness : {1e-4, 0.3}) {
                fur::Fur f;
                f.cortex.roughness = roughness;
                f.cortex.sigma_a = glm::dvec3(0.5447, 0.9061, 1.781);
                f.sigma_a_medulla = glm::dvec3(0.5, 0, 0);
                f.kappa = 0.99;
                f.sigma_s = 1e3;
                f.g = g;
                f.max_scatterings = 20000;  // σs^m 1e3 over 0.99: deep rays diffuse for ~10⁶ events
                fur::Histogram h(8, 8);
                fur::trace_parallel(fur::Tracer(f), direction(theta_deg, 0.2), 400, 11, kThreads, h);
                for (const double e : h.energy) ASSERT_TRUE(std::isfinite(e) && e >= 0);
                for (int c = 0; c < 4; ++c) {
                    ASSERT_TRUE(std::isfinite(h.lost[c]) && std::isfinite(h.absorbed[c]));
                    double sum = h.absorbed[c] + h.lost[c];
                    for (int l = 0; l < fur::kClasses; ++l) sum += h.lobe_energy[l][c];
                    EXPECT_NEAR(sum, h.rays, 1e-9 * h.rays);
                }
                std::printf("g %+.2f θ %2.0f° β %.0e: scattered %.3f lost %.3f scatterings/ray %.0f\n", g, theta_deg, roughness,
                            h.lobe_energy[fur::kScattered][0] / h.rays, h.lost[0] / h.rays, h.scatterings / h.rays);
                EXPECT_GT(h.lobe_energy[fur::kScattered][0], 0.0);
            }
}
