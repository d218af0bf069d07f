// Two-stream dual scattering at the arrival direction (dual/two_stream.hpp): the stacks'
// coefficients and their lossless identity, the kernel spreads from the stacks' events,
// the source kernel's sampler against its pdf (chi-square, negative controls, float and
// double), the Poisson counts, extremes, and the whole estimator on explicit fiber slabs:
// the white furnace at every depth, and back-lit slabs against path tracing.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include <hairscatter/dual.hpp>

#include "support/chi2.hpp"
#include "support/fiber_slab.hpp"

namespace hs = hairscatter;
using glm::dvec3;
using glm::dvec4;

namespace {

hs::FiberParams<double> params(double eumelanin) {
    hs::FiberParams<double> p;
    p.sigma_a = eumelanin < 0 ? dvec3(0) : hs::sigma_a_from_concentrations(eumelanin, 0.0);
    return p;
}

template <typename T> hs::DualScatteringTables<T> tables_of(double eumelanin) {
    hs::FiberParams<T> p;
    const dvec3 s = params(eumelanin).sigma_a;
    p.sigma_a = glm::vec<3, T>(T(s.x), T(s.y), T(s.z));
    const hs::ChiangMaterial<T> material(p);
    return hs::DualScatteringTables<T>::template build<hs::ChiangFiber<T>>(material);
}

dvec3 direction(double theta_deg, double phi) {
    const double t = theta_deg * hs::kPi<double> / 180;
    return dvec3(std::sin(t), std::cos(t) * std::cos(phi), std::cos(t) * std::sin(phi));
}

}  // namespace

// The depth dual_streams gives a stack of n fibers: the fibers the turning light crosses.
double turned(const hs::DualScatteringEntry<double>& e, double n) {
    const double mu_f = (e.mu_f.x + e.mu_f.y + e.mu_f.z) / 3;
    return std::min(hs::dual_turned_depth(std::min(n, hs::kDeepStack<double>), mu_f), hs::kDeepStack<double>);
}

TEST(DualTwoStream, LosslessStacksPassOrReturnEverything) {
    // c_f + c_b = (T_n + R_n T_m) / (1 - R_n R_m) = 1 when T_k + R_k = 1: what keeps the
    // furnace. Checked against layered_stack, at fractional, huge and unbounded depths
    // (deeper than kDeepStack is kDeepStack).
    const auto tables = tables_of<double>(-1);
    for (double theta : {-80.0, -30.0, 0.0, 45.0, 85.0}) {
        const double sin_t = std::sin(theta * hs::kPi<double> / 180);
        const auto e = tables.lookup(sin_t);
        for (double n : {0.0, 0.4, 1.0, 3.5, 40.0, 1e6, hs::kUnbounded<double>}) {
            for (double m : {0.0, 1.0, 7.0, 1e4, hs::kUnbounded<double>}) {
                const auto s = hs::dual_streams(e, n, m);
                for (int c = 0; c < 3; ++c) {
                    EXPECT_NEAR(s.forward[c] + s.back[c], 1.0, 2e-6) << theta << " " << n << " " << m;
                    const auto sn = hs::layered_stack(e.a_f[c], e.a_b[c], turned(e, n));
                    const auto sm = hs::layered_stack(e.a_f[c], e.a_b[c], turned(e, m));
                    const double den = 1 - sn.R * sm.R;
                    if (den > 1e-9) {
                        EXPECT_NEAR(s.forward[c], sn.T_ / den, 1e-9);
                        EXPECT_NEAR(s.back[c], sn.R * sm.T_ / den, 1e-9);
                    }
                }
            }
        }
    }
    // float keeps it too
    const auto tf = tables_of<float>(-1);
    for (float n : {1.0f, 12.0f, 300.0f, std::numeric_limits<float>::infinity()}) {
        for (float m : {0.0f, 5.0f, std::numeric_limits<float>::infinity()}) {
            const auto s = hs::dual_streams(tf.view(), 0.3f, n, m);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.forward[c] + s.back[c], 1.0f, 2e-3f) << n << " " << m;
        }
    }
}

// Stacks inclined to their fibers (hs::dual_stack_entry): the layers return a_b·rho_b and
// pass the rest on, a_f + a_b kept. A lossless stack then still passes or returns everything
// (the furnace), and the entry's own albedos and the 1D stack come back where rho_b is 1.
TEST(DualTwoStream, InclinedStacksKeepTheFurnace) {
    const auto lossless = tables_of<double>(-1);
    const auto blond = tables_of<double>(0.3);
    for (double theta : {0.0, 30.0, 45.0, 60.0, -70.0}) {
        const double sin_t = std::sin(theta * hs::kPi<double> / 180);
        const auto el = hs::dual_stack_entry(lossless.lookup(sin_t)), eb = hs::dual_stack_entry(blond.lookup(sin_t));
        const auto rb = blond.lookup(sin_t);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(eb.a_f[c] + eb.a_b[c], rb.a_f[c] + rb.a_b[c], 1e-15) << theta;
            EXPECT_NEAR(eb.a_b[c], rb.a_b[c] * rb.rho_b[c], 1e-15) << theta;
            EXPECT_EQ(eb.rho_b[c], 1.0);
        }
        if (std::abs(theta) >= 45) {
            EXPECT_LT(eb.a_b.g, 0.6 * rb.a_b.g) << theta;  // most passes on
        }
        for (double n : {1.0, 5.0, 40.0, hs::kUnbounded<double>}) {
            for (double m : {0.0, 3.0, hs::kUnbounded<double>}) {
                const auto s = hs::dual_streams(el, n, m);
                for (int c = 0; c < 3; ++c) {
                    EXPECT_NEAR(s.forward[c] + s.back[c], 1.0, 2e-6) << theta << " " << n << " " << m;
                }
            }
        }
    }
    // NaN rho_b is the 1D stack; out-of-range values are clamped
    auto e = blond.lookup(0.5);
    e.rho_b = glm::dvec3(std::numeric_limits<double>::quiet_NaN(), -2.0, 7.0);
    const auto s = hs::dual_stack_entry(e);
    EXPECT_EQ(s.a_b.x, e.a_b.x);
    EXPECT_EQ(s.a_b.y, 0.0);
    EXPECT_EQ(s.a_b.z, e.a_b.z);
}

TEST(DualTwoStream, UnobstructedAndOneSidedLimits) {
    const auto tables = tables_of<double>(0.3);
    const auto e = tables.lookup(0.2);
    // nothing along a: the source itself, whatever lies beyond
    for (double m : {0.0, 5.0, hs::kUnbounded<double>}) {
        const auto s = hs::dual_streams(e, 0.0, m);
        EXPECT_EQ(s.forward, dvec3(1));
        EXPECT_EQ(s.back, dvec3(0));
    }
    // nothing beyond: the n stack's own transmittance and reflectance
    const auto s = hs::dual_streams(e, 4.0, 0.0);
    for (int c = 0; c < 3; ++c) {
        const auto st = hs::layered_stack(e.a_f[c], e.a_b[c], turned(e, 4.0));
        EXPECT_NEAR(s.forward[c], st.T_, 1e-12);
        EXPECT_NEAR(s.back[c], st.R, 1e-12);
    }
    // absorbing hair loses light: less passes the deeper it is
    double prev = 2;
    for (double n : {1.0, 2.0, 5.0, 20.0}) {
        const auto t = hs::dual_streams(e, n, 3.0);
        const double sum = (t.forward + t.back).x;
        EXPECT_LT(sum, 1.0);
        EXPECT_LT(t.forward.x, prev);
        prev = t.forward.x;
    }
    // bad counts: NaN is none, negative is none, +Inf is a deep volume; never NaN out
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(hs::dual_streams(e, nan, nan).forward, dvec3(1));
    EXPECT_EQ(hs::dual_streams(e, -3.0, -1.0).forward, dvec3(1));
    const auto deep = hs::dual_streams(e, hs::kUnbounded<double>, 2.0);
    for (int c = 0; c < 3; ++c) {
        EXPECT_TRUE(std::isfinite(deep.forward[c]) && std::isfinite(deep.back[c]));
        EXPECT_NEAR(deep.forward[c], 0.0, 1e-12);
    }
}

TEST(DualTwoStream, CountLimitIsWhereMoreFibersStopMattering) {
    // Beyond the limit, T_N < tolerance and R_N within it of R_∞ (checked on the stacks);
    // a lossless fiber never gets there (kDeepStack); darker hair gets there sooner.
    double prev = 1e30;
    for (double eumelanin : {0.1, 0.3, 1.3, 8.0}) {
        const auto tables = tables_of<double>(eumelanin);
        for (double sin_t : {-0.9, 0.0, 0.4}) {
            const auto e = tables.lookup(sin_t);
            for (double tol : {1e-2, 1e-3, 1e-5}) {
                const double n = hs::dual_count_limit(e, tol);
                ASSERT_LT(n, hs::kDeepStack<double>) << eumelanin;
                for (int c = 0; c < 3; ++c) {
                    const auto s = hs::layered_stack(e.a_f[c], e.a_b[c], n);
                    const auto deep = hs::layered_stack(e.a_f[c], e.a_b[c], 1e6);
                    EXPECT_LT(s.T_, tol) << eumelanin << " " << sin_t << " " << tol;
                    EXPECT_LT(std::abs(s.R - deep.R), tol) << eumelanin << " " << sin_t << " " << tol;
                }
            }
        }
        const double n = hs::dual_count_limit(tables.lookup(0.0), 1e-3);
        EXPECT_LT(n, prev) << eumelanin;
        prev = n;
    }
    EXPECT_EQ(hs::dual_count_limit(tables_of<double>(-1).lookup(0.2), 1e-3), hs::kDeepStack<double>);
    const auto tf = tables_of<float>(0.3);
    EXPECT_NEAR(hs::dual_count_limit(tf.view().lookup(0.2f), 1e-3f), hs::dual_count_limit(tables_of<double>(0.3).lookup(0.2), 1e-3),
                0.5);
}

TEST(DualTwoStream, SpreadsCountTheStacksEvents) {
    // One fiber and nothing beyond: a transmitted path is exactly one forward event
    // (T_1 = a_f), so v_f = β̄²_f; a reflected one is one backward event (R_1 = a_b), v_b = β̄²_b.
    const auto tables = tables_of<double>(0.3);
    const auto e = tables.lookup(0.1);
    const auto one = hs::dual_streams(e, 1.0, 0.0);
    const double bf = (e.beta2_f.x + e.beta2_f.y + e.beta2_f.z) / 3, bb = (e.beta2_b.x + e.beta2_b.y + e.beta2_b.z) / 3;
    EXPECT_NEAR(one.spread_f, bf, 1e-4 * bf);
    EXPECT_NEAR(one.spread_b, bb, 1e-4 * bb);
    // n fibers in a row of non-returning layers would be n events; with returns, more
    double prev_f = 0, prev_b = 0;
    for (double n : {1.0, 2.0, 5.0, 10.0}) {
        const auto s = hs::dual_streams(e, n, 2.0);
        EXPECT_GE(s.spread_f, n * bf * (1 - 1e-6)) << n;
        EXPECT_GT(s.spread_f, prev_f);
        EXPECT_GT(s.spread_b, prev_b);
        prev_f = s.spread_f;
        prev_b = s.spread_b;
    }
    // float agrees with double where the finite differences are resolved
    const auto tf = tables_of<float>(0.3);
    const auto sf = hs::dual_streams(tf.view(), 0.1f, 5.0f, 2.0f);
    const auto sd = hs::dual_streams(tables.view(), 0.1, 5.0, 2.0);
    EXPECT_NEAR(sf.spread_f, sd.spread_f, 0.02 * sd.spread_f);
    EXPECT_NEAR(sf.spread_b, sd.spread_b, 0.02 * sd.spread_b);
}

TEST(DualTwoStream, KernelIntegratesToTheStreams) {
    // ∫ eval ds = c_f + c_b per channel: each kernel is a density. Midpoint rule over
    // (sinθ, φ), which is equal-area.
    const auto tables = tables_of<double>(0.3);
    for (double theta : {0.0, 40.0, -75.0}) {
        const dvec3 a = direction(theta, 0.7);
        const auto st = hs::dual_streams(tables.view(), a.x, 3.0, 2.0);
        const hs::DualSourceKernel<double> k(a, st);
        const int nt = 800, np = 800;
        dvec3 sum(0);
        double pdf_sum = 0;
        for (int i = 0; i < nt; ++i)
            for (int j = 0; j < np; ++j) {
                const double z = -1 + 2 * (i + 0.5) / nt, phi = -hs::kPi<double> + 2 * hs::kPi<double> * (j + 0.5) / np;
                const double r = std::sqrt(1 - z * z);
                const dvec3 s(z, r * std::cos(phi), r * std::sin(phi));
                sum += k.eval(s);
                pdf_sum += k.pdf(s);
            }
        const double cell = 4 * hs::kPi<double> / (double(nt) * np);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c] * cell, st.forward[c] + st.back[c], 2e-3) << theta;
        EXPECT_NEAR(pdf_sum * cell, 1.0, 2e-3) << theta;
    }
}

TEST(DualTwoStream, KernelSamplerMatchesPdfChi2) {
    const auto tables = tables_of<double>(0.3);
    struct Case {
        double theta, n, m;
    };
    const Case cases[] = {{10, 1, 0}, {-50, 4, 3}, {70, 0.5, 20}, {0, 30, 1}};
    const int n_tests = int(std::size(cases)) + 2;
    double min_p = 1;
    for (const Case& c : cases) {
        const dvec3 a = direction(c.theta, 0.3);
        const hs::DualSourceKernel<double> k(a, hs::dual_streams(tables.view(), a.x, c.n, c.m));
        chi2::Options opt;
        opt.num_tests = n_tests;
        opt.samples = 200000;
        opt.max_depth = 5;
        const auto r = chi2::test([&](const dvec4& u) { return k.sample(u).s; }, [&](const dvec3& s) { return k.pdf(s); }, opt);
        min_p = std::min(min_p, r.p_value);
        EXPECT_TRUE(r.passed) << "θa " << c.theta << " n " << c.n << "\n" << r.report;
        EXPECT_NEAR(r.expected_total, 1.0, 1e-3);
    }
    std::printf("[ chi2     ] %zu source-kernel cases, smallest p-value %.3g\n", std::size(cases), min_p);
    // Negative controls: the pdf 5 % too large; the samples' azimuth moved by 0.3 rad.
    const dvec3 a = direction(20, 0.3);
    const hs::DualSourceKernel<double> k(a, hs::dual_streams(tables.view(), a.x, 2.0, 2.0));
    chi2::Options opt;
    opt.num_tests = n_tests;
    opt.samples = 200000;
    opt.max_depth = 5;
    const chi2::Expected expected = chi2::expected_counts([&](const dvec3& s) { return k.pdf(s); }, opt);
    const auto scaled = chi2::compare(chi2::histogram([&](const dvec4& u) { return k.sample(u).s; }, opt), expected.scaled(1.05), opt);
    EXPECT_FALSE(scaled.passed) << "pdf × 1.05 accepted, p = " << scaled.p_value;
    const auto moved = chi2::compare(chi2::histogram(
                                         [&](const dvec4& u) {
                                             const dvec3 s = k.sample(u).s;
                                             return hs::direction_from_azimuth(a, s.x, hs::wrap_pi(hs::relative_azimuth(a, s) + 0.3));
                                         },
                                         opt),
                                     expected, opt);
    EXPECT_FALSE(moved.passed) << "rotated samples accepted, p = " << moved.p_value;
}

TEST(DualTwoStream, FloatKernelAgreesWithDouble) {
    const auto td = tables_of<double>(0.3);
    const auto tf = tables_of<float>(0.3);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> U;
    for (int i = 0; i < 2000; ++i) {
        const dvec3 a = direction(-85 + 170 * U(rng), -3 + 6 * U(rng));
        const double n = 1 + 10 * U(rng), m = 10 * U(rng);
        const hs::DualSourceKernel<double> kd(a, hs::dual_streams(td.view(), a.x, n, m));
        const hs::DualSourceKernel<float> kf(glm::vec3(a), hs::dual_streams(tf.view(), float(a.x), float(n), float(m)));
        const dvec4 u(U(rng), U(rng), U(rng), U(rng));
        const auto s = kf.sample(glm::vec4(u));
        ASSERT_GT(s.pdf, 0.0f);
        // the float sample's pdf is the float query's, and close to double's at that direction
        EXPECT_NEAR(s.pdf, kf.pdf(s.s), 1e-4f * s.pdf + 1e-6f);
        const double pd = kd.pdf(glm::normalize(dvec3(s.s)));
        EXPECT_NEAR(s.pdf, pd, 0.03 * pd + 1e-4) << i;
    }
}

TEST(DualTwoStream, PoissonCountsHaveTheirMeans) {
    // Stratified u: the mean of the inverse CDF is the distribution's mean.
    for (double mu : {0.05, 0.7, 3.0, 20.0, 150.0}) {
        const int N = 20000;
        double sum = 0, sum_hit = 0;
        for (int i = 0; i < N; ++i) {
            const double u = (i + 0.5) / N;
            const double k = hs::poisson_fiber_count(mu, u, false), kh = hs::poisson_fiber_count(mu, u, true);
            ASSERT_EQ(k, std::floor(k));
            ASSERT_GE(kh, 1.0);
            sum += k;
            sum_hit += kh;
        }
        const double tol = mu > 64 ? 0.01 * mu : 1e-3 * mu + 1e-4;
        EXPECT_NEAR(sum / N, mu, tol) << mu;
        EXPECT_NEAR(sum_hit / N, mu / (1 - std::exp(-mu)), tol + 1e-3) << mu;
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(hs::poisson_fiber_count(nan, 0.5, false), 0.0);
    EXPECT_EQ(hs::poisson_fiber_count(-2.0, 0.5, true), 1.0);
    EXPECT_TRUE(std::isfinite(hs::poisson_fiber_count(hs::kUnbounded<double>, 0.5, true)));
    EXPECT_GE(hs::poisson_fiber_count(1e12, 0.5, true), 1e11);  // no integer overflow
    EXPECT_GE(hs::poisson_fiber_count(hs::kUnbounded<float>, 0.5f, true), 1.0f);
    EXPECT_TRUE(std::isfinite(hs::poisson_fiber_count(3.0, nan, false)));
    EXPECT_EQ(hs::poisson_fiber_count(3.0f, 1.0f, false), hs::poisson_fiber_count(3.0f, 1.0f, false));
}

TEST(DualTwoStream, NoNaNAtExtremes) {
    const auto tf = tables_of<float>(-1);
    const float big = std::numeric_limits<float>::max(), inf = std::numeric_limits<float>::infinity(),
                nan = std::numeric_limits<float>::quiet_NaN();
    const glm::vec3 arrivals[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0.6f, 0, 0.8f}, {nan, 0, 1}, {big, big, 0}, {inf, 0, 0}};
    const float counts[] = {0, 1e-30f, 1, 1e6f, big, inf, nan, -5};
    const glm::vec4 us[] = {{0, 0, 0, 0}, {1, 1, 1, 1}, {0.5f, 0.5f, 0.5f, 0.5f}, {nan, 0.5f, 0.5f, 0.5f}, {2, -1, 3, 9}};
    for (const glm::vec3& a : arrivals) {
        for (float n : counts) {
            for (float m : counts) {
                const auto st = hs::dual_streams(tf.view(), a.x, n, m);
                ASSERT_TRUE(hs::is_finite(st.forward) && hs::is_finite(st.back)) << n << " " << m;
                ASSERT_TRUE(std::isfinite(st.spread_f) && std::isfinite(st.spread_b));
                const hs::DualSourceKernel<float> k(a, st);
                for (const glm::vec4& u : us) {
                    const auto s = k.sample(u);
                    ASSERT_TRUE(std::isfinite(s.pdf) && s.pdf >= 0);
                    if (s.pdf > 0) {
                        ASSERT_TRUE(hs::is_finite(s.s));
                    }
                    const glm::vec3 v = k.eval(s.s);
                    ASSERT_TRUE(hs::is_finite(v));
                    // The sample's value and eval_pdf are eval and pdf, bit for bit.
                    ASSERT_EQ(s.f, s.pdf > 0 ? v : glm::vec3(0));
                    for (const glm::vec3& q : arrivals) {
                        ASSERT_TRUE(hs::is_finite(k.eval(q)));
                        ASSERT_TRUE(std::isfinite(k.pdf(q)));
                        const auto ep = k.eval_pdf(q);
                        ASSERT_EQ(ep.f, k.eval(q));
                        ASSERT_EQ(ep.pdf, k.pdf(q));
                    }
                }
            }
        }
    }
}

TEST(DualTwoStream, SourceGainIsTheStacksTransmissionPlusReflection) {
    // dual_source_gain = T_N + R_N of N fibers at the entry's θ (layered_stack), 1 with no
    // fibers; a lossless stack gives 1 at every depth (what keeps the furnace when sources
    // are read beyond a stack's exit); absorbing hair falls with N toward R_∞.
    const auto lossless = tables_of<double>(-1);
    const auto blond = tables_of<double>(0.3);
    for (double theta : {-75.0, 0.0, 40.0}) {
        const double sin_t = std::sin(theta * hs::kPi<double> / 180);
        const auto el = lossless.lookup(sin_t), eb = blond.lookup(sin_t);
        dvec3 previous(1.0);
        for (double n : {0.0, 0.5, 1.0, 2.0, 7.0, 40.0, 1e4, hs::kUnbounded<double>}) {
            const dvec3 gl = hs::dual_source_gain(el, n), gb = hs::dual_source_gain(eb, n);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(gl[c], 1.0, 2e-6) << theta << " " << n;
                const auto st = hs::layered_stack(eb.a_f[c], eb.a_b[c], std::min(n, hs::kDeepStack<double>));
                EXPECT_NEAR(gb[c], st.R + st.T_, 1e-9) << theta << " " << n;
                EXPECT_LE(gb[c], previous[c] + 1e-12) << "the gain must not grow with depth";
                EXPECT_GT(gb[c], 0.0);
            }
            previous = gb;
        }
        EXPECT_LT(previous.x, 0.5) << "a deep blond stack passes on far less than the source";
        // Bad counts: NaN and negative are no fibers.
        EXPECT_EQ(hs::dual_source_gain(eb, std::numeric_limits<double>::quiet_NaN()), dvec3(1.0));
        EXPECT_EQ(hs::dual_source_gain(eb, -3.0), dvec3(1.0));
    }
    const auto tf = tables_of<float>(-1);
    for (float n : {1.0f, 12.0f, 300.0f, std::numeric_limits<float>::infinity()}) {
        const glm::vec3 g = hs::dual_source_gain(tf.view().lookup(0.3f), n);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(g[c], 1.0f, 2e-3f) << n;
    }
}

namespace {
// A density source with fibers at a uniform rate between distances a and b along any ray:
// the expected count on [0, t] is rate · |[0, t] ∩ [a, b]|.
struct SlabSource {
    double rate, a, b;
    double fibers_crossed(const dvec3&, const dvec3&, double t) const {
        const double hi = std::min(t, b), lo = a;
        return hi > lo ? rate * (hi - lo) : 0.0;
    }
};
}  // namespace

TEST(DualTwoStream, StackEndIsWhereLessThanHalfAFiberRemains) {
    const dvec3 o(0.0), d(0, 0, 1);
    // 6 fibers on [1, 4]: half a fiber remains at 4 - 0.5 / 2 = 3.75; bisection to 10/256.
    EXPECT_NEAR(hs::dual_stack_end(SlabSource{2.0, 1.0, 4.0}, o, d, 10.0), 3.75, 10.0 / 256);
    // 0.6 fibers on [1, 4]: half of them remain at 4 - 0.3 / 0.2 = 2.5.
    EXPECT_NEAR(hs::dual_stack_end(SlabSource{0.2, 1.0, 4.0}, o, d, 10.0), 2.5, 10.0 / 256);
    // Only the segment counts: fibers past max_distance are not the stack's.
    EXPECT_NEAR(hs::dual_stack_end(SlabSource{2.0, 1.0, 4.0}, o, d, 3.0), 3.0 - 0.25, 3.0 / 256);
    // No fibers, bad distances: 0.
    EXPECT_EQ(hs::dual_stack_end(SlabSource{0.0, 1.0, 4.0}, o, d, 10.0), 0.0);
    EXPECT_EQ(hs::dual_stack_end(SlabSource{2.0, 1.0, 4.0}, o, d, std::numeric_limits<double>::infinity()), 0.0);
    EXPECT_EQ(hs::dual_stack_end(SlabSource{2.0, 1.0, 4.0}, o, d, -1.0), 0.0);
    EXPECT_EQ(hs::dual_stack_end(SlabSource{2.0, 1.0, 4.0}, dvec3(std::nan("")), d, 5.0), 0.0);
}

TEST(DualTwoStream, WhiteFurnaceOnExplicitSlabsAtEveryDepth) {
    // Lossless fibers under a uniform environment of radiance 1: every hit must return 1,
    // from a sparse layer (0.3 fibers deep, where most directions are open) to a deep
    // slab, seen from above and grazing, with exact counts and with Poisson counts of the
    // density. Tolerance 1 % (the estimator's own noise here is far below).
    const dvec3 views[] = {glm::normalize(dvec3(-0.1, -0.2, 0.95)), glm::normalize(dvec3(0.2, 0.5, 0.7))};
    slab::Lighting env;
    env.furnace = true;
    for (double tau : {0.3, 1.0, 5.0, 20.0})
        for (const dvec3& wo : views) {
            const auto r = slab::compare_two_stream(params(-1), tau, env, wo, 600, 8, false);
            EXPECT_NEAR(r.exact / r.hits, 1.0, 0.01) << tau;
            EXPECT_NEAR(r.expected / r.hits, 1.0, 0.01) << tau;
            std::printf("[ furnace  ] %4.1f fibers deep, wo.z %.2f: exact counts %.4f, Poisson counts %.4f\n", tau, wo.z,
                        r.exact / r.hits, r.expected / r.hits);
        }
}

TEST(DualTwoStream, BackLitSlabAgreesWithPathTracing) {
    // Blond hair, a slab five fibers deep lit from behind and seen from the front: light
    // through hair. Tolerance 15 % on the mean over first hits, where the path estimate's
    // 2σ noise is asserted below 8 %; docs/slab.md has the sweep over depth,
    // colour and view.
    slab::Lighting back;
    back.wl = glm::normalize(dvec3(0.3, 0.35, -0.9));
    const dvec3 wo = glm::normalize(dvec3(-0.1, -0.2, 0.95));
    const auto r = slab::compare_two_stream(params(0.3), 5.0, back, wo, 40000);
    ASSERT_LT(r.path_noise(), 0.08 * r.path_mean()) << "the path-traced reference is too noisy to compare with";
    std::printf("[ slab     ] blond, 5 deep, back-lit: exact counts / path = %.3f, Poisson counts / path = %.3f "
                "(path noise %.1f %%)\n",
                r.exact / r.path, r.expected / r.path, 100 * r.path_noise() / r.path_mean());
    EXPECT_NEAR(r.exact / r.path, 1.0, 0.15);
    EXPECT_NEAR(r.expected / r.path, 1.0, 0.15);
}


namespace {

// Parallel fibers along x filling z ∈ [0, depth] and |y| ≤ half_width: the fibers a ray
// crosses are `density` times its path's length across the fibers (in the y–z plane) inside
// that region. An exact density source for dual_turn_limit's geometry.
struct FiberBlock {
    double depth = 1, half_width = 1e9, density = 10;
    double fibers_crossed(const dvec3& o, const dvec3& d, double tmax) const {
        double t0 = 0, t1 = std::min(tmax, 1e12);
        const auto clip = [&](double p, double v, double lo, double hi) {
            if (v == 0) {
                if (p < lo || p > hi) t1 = -1;
                return;
            }
            double a = (lo - p) / v, b = (hi - p) / v;
            if (a > b) std::swap(a, b);
            t0 = std::max(t0, a), t1 = std::min(t1, b);
        };
        clip(o.z, d.z, 0, depth);
        clip(o.y, d.y, -half_width, half_width);
        return t1 > t0 ? density * (t1 - t0) * std::sqrt(d.y * d.y + d.z * d.z) : 0.0;
    }
};

}  // namespace

TEST(DualTwoStream, TurnLimitIsTheSlabsTwoOverPiAndGrowsInNarrowHair) {
    // Deep in a wide slab, across it: C(φ) = C(0)/cos φ, so the limit is the six-point
    // midpoint rule of E[cos φ] over the half-circle (0.6440, within 1.2 % of 2/π).
    const dvec3 axis(1, 0, 0), across(0, 0, 1);
    double mid = 0;
    for (int k = 0; k < 6; ++k) mid += std::cos((k + 0.5) * hs::kPi<double> / 6 - hs::kPi<double> / 2) / 6;
    const FiberBlock slab{10, 1e9, 10};
    EXPECT_NEAR(hs::dual_turn_limit(slab, dvec3(0, 0, 0.5), axis, across, 1e9), mid, 1e-9);
    EXPECT_NEAR(mid, 2 / hs::kPi<double>, 0.012 * 2 / hs::kPi<double>);
    // Tilted away from the fibers' axis: the turns keep d.x, and the limit is the same.
    const dvec3 tilted = glm::normalize(dvec3(0.6, 0, 0.8));
    EXPECT_NEAR(hs::dual_turn_limit(slab, dvec3(0, 0, 0.5), axis, tilted, 1e9), mid, 1e-9);
    // A column one tenth as wide as it is deep: turned light leaves through the sides after
    // fewer fibers than along d, so the limit exceeds 1 (fewer fibers per fiber of depth).
    const FiberBlock column{10, 0.5, 10};
    const double narrow = hs::dual_turn_limit(column, dvec3(0, 0, 0.5), axis, across, 1e9);
    EXPECT_GT(narrow, 1.0);
    EXPECT_LE(narrow, hs::kMaxTurnLimit<double>);
    // Bad input gives the slab's limit, never NaN.
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(hs::dual_turn_limit(slab, dvec3(nan, 0, 0), axis, across, 1e9), hs::kSlabTurnLimit<double>);
    EXPECT_EQ(hs::dual_turn_limit(slab, dvec3(0, 0, 0.5), axis, dvec3(0, nan, 1), 1e9), hs::kSlabTurnLimit<double>);
}

TEST(DualTwoStream, TurnedDepthFollowsItsLimit) {
    // Limit 1: light that turns crosses one fiber per fiber, the straight stack; a slab's
    // 2/π gives more, a narrow volume's limit above 1 fewer; n ≤ 1 is never changed.
    for (double mu : {0.3, 0.84, 0.99})
        for (double n : {0.5, 1.0, 2.5, 10.0, 200.0}) {
            EXPECT_NEAR(hs::dual_turned_depth(n, mu, 1.0), n, 1e-9 * n) << mu << " " << n;
            const double slab = hs::dual_turned_depth(n, mu), narrow = hs::dual_turned_depth(n, mu, 2.0);
            if (n <= 1) {
                EXPECT_EQ(slab, n);
                EXPECT_EQ(narrow, n);
            } else {
                EXPECT_GT(slab, n);
                EXPECT_LT(slab, n * hs::kPi<double> / 2 + 1e-9);
                EXPECT_LT(narrow, n);
                EXPECT_GE(narrow, 1.0);
            }
        }
    EXPECT_EQ(hs::dual_turned_depth(5.0, 0.84, std::numeric_limits<double>::quiet_NaN()),
              hs::dual_turned_depth(5.0, 0.84));
}

TEST(DualTwoStream, TurnedDepthsSplitIntoNarrowAndSpread) {
    // The ballistic part Σ e_j / c_j (e_j = e^{−λj}) beside the turned depth Σ 1/c_j: the
    // total is dual_turned_depth's to the bit; n ≤ 1 is all narrow; against the plain sum
    // over every fiber (the function sums 32 and integrates the rest) within 1e-3.
    for (double mu : {0.3, 0.84, 0.97})
        for (double limit : {hs::kSlabTurnLimit<double>, 1.0, 2.0})
            for (double n : {0.0, 0.4, 1.0, 2.5, 10.0, 50.0, 200.0, 5000.0}) {
                const auto d = hs::dual_turned_depths(n, mu, limit);
                EXPECT_EQ(d.total, hs::dual_turned_depth(n, mu, limit)) << mu << " " << n;
                if (n <= 1) {
                    EXPECT_EQ(d.ballistic, n);
                    continue;
                }
                const double lambda = -std::log(mu) / (1 - hs::kSlabTurnLimit<double>);
                double total = 0, ballistic = 0;
                for (int j = 0; j < n; ++j) {
                    const double e = std::exp(-lambda * j), c = limit + (1 - limit) * e, part = std::min(1.0, n - j);
                    total += part / c;
                    ballistic += part * e / c;
                }
                EXPECT_NEAR(d.total, total, 1e-3 * total) << mu << " " << limit << " " << n;
                EXPECT_NEAR(d.ballistic, ballistic, 1e-3 * ballistic + 1e-9) << mu << " " << limit << " " << n;
                EXPECT_GE(d.ballistic, 1.0);
                EXPECT_LE(d.ballistic, d.total);
            }
}

TEST(DualTwoStream, CrossoverIsTheShareATurnCarriesAcross) {
    // Light spread evenly over [−π/2, π/2] and turned by a Gaussian δ of mean cosine μ leaves
    // the half-circle with probability E|δ| / π: against Monte Carlo of the turn (10^6
    // draws, σ ≤ 1 so that a turn past π is negligible; noise 5e-4), and the limits.
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> U(-hs::kPi<double> / 2, hs::kPi<double> / 2);
    for (double sigma : {0.2, 0.6, 1.0}) {
        std::normal_distribution<double> N(0, sigma);
        int across = 0;
        constexpr int kDraws = 1000000;
        for (int i = 0; i < kDraws; ++i) across += std::abs(U(rng) + N(rng)) > hs::kPi<double> / 2;
        const double mu = std::exp(-sigma * sigma / 2), mc = double(across) / kDraws;
        std::printf("[ crossover ] sigma %.1f: %.4f (Monte Carlo %.4f)\n", sigma, hs::dual_crossover(mu), mc);
        EXPECT_NEAR(hs::dual_crossover(mu), mc, 2e-3) << sigma;
    }
    EXPECT_EQ(hs::dual_crossover(1.0), 0.0);
    EXPECT_EQ(hs::dual_crossover(0.0), 0.5);
    EXPECT_EQ(hs::dual_crossover(-1.0), 0.5);
    EXPECT_EQ(hs::dual_crossover(std::numeric_limits<double>::quiet_NaN()), 0.5);
    // The uniform half-circle's backscatter (μ = 2/π) crosses 1/4 exactly; the Gaussian of
    // the same mean cosine within 4 %.
    EXPECT_NEAR(hs::dual_crossover(2 / hs::kPi<double>), 0.25, 0.01);
}

TEST(DualTwoStream, DiffuseTransportKeepsTheFurnaceAndShortStacks) {
    // The spread middle trades light between the two streams but keeps a_f + a_b, so
    // lossless stacks still give c_f + c_b = 1; stacks too short to have a middle (the light
    // still narrow halfway through) are the turned transport's to the bit; float and
    // double agree.
    const auto white = tables_of<double>(-1), blond = tables_of<double>(0.3);
    const auto blond_f = tables_of<float>(0.3);
    constexpr auto kDiffuse = hs::DualStackTransport::kDiffuse;
    constexpr double slab = hs::kSlabTurnLimit<double>;
    for (double sin_t : {-0.9, -0.3, 0.0, 0.5, 0.97})
        for (double n : {0.0, 0.5, 1.0, 3.0, 8.0, 40.0, 1e3, hs::kUnbounded<double>})
            for (double m : {0.0, 1.0, 6.0, 100.0}) {
                const auto s = hs::dual_streams(white.lookup(sin_t), n, m, slab, slab, kDiffuse);
                for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.forward[k] + s.back[k], 1.0, 1e-9) << n << " " << m;
                const auto e = blond.lookup(sin_t);
                const double mf = (e.mu_f.x + e.mu_f.y + e.mu_f.z) / 3;
                const auto dn = hs::dual_turned_depths(n, mf), dm = hs::dual_turned_depths(m, mf);
                const auto d = hs::dual_streams(e, n, m, slab, slab, kDiffuse), t = hs::dual_streams(e, n, m);
                if (dn.ballistic >= dn.total / 2 && dm.ballistic >= dm.total / 2) {
                    EXPECT_EQ(d.forward, t.forward) << n << " " << m;
                    EXPECT_EQ(d.back, t.back) << n << " " << m;
                }
                EXPECT_EQ(d.spread_f, t.spread_f);
                EXPECT_EQ(d.turn_f, t.turn_f);
                const auto f = hs::dual_streams(blond_f.lookup(float(sin_t)), float(n), float(m), float(slab), float(slab),
                                                kDiffuse);
                for (int k = 0; k < 3; ++k) {
                    EXPECT_NEAR(f.forward[k], d.forward[k], 1e-4 + 1e-3 * d.forward[k]) << n << " " << m;
                    EXPECT_NEAR(f.back[k], d.back[k], 1e-4 + 1e-3 * d.back[k]) << n << " " << m;
                }
            }
}

TEST(DualTwoStream, DiffuseTransportFollowsExplicitSlabsCloser) {
    // Lossless fibers ten deep lit from the viewer's side (a slab of explicit, non-overlapping
    // fibers, path-traced): the turned stack returns about 27 % too little, the diffuse one
    // about 14 % (docs/theory.md §5.7); both read against the same path estimate, so the
    // path's noise (2σ under 8 %) moves both ratios alike and not their order. Lossless walks
    // are long and their sums heavy-tailed: 20,000 paths gave 2σ = 7.4 % with GCC and 10.7 %
    // with Clang (whose rounding draws other paths), so 60,000.
    const dvec3 wl = glm::normalize(dvec3(0.3, 0.35, 0.9)), wo = glm::normalize(dvec3(-0.1, -0.2, 0.95));
    slab::Lighting front;
    front.wl = wl;
    const auto turned = slab::compare_two_stream(params(-1), 10.0, front, wo, 60000);
    const auto diffuse = slab::compare_two_stream(params(-1), 10.0, front, wo, 60000, 16, true,
                                                  hs::DualStackTransport::kDiffuse);
    ASSERT_LT(turned.path_noise(), 0.08 * turned.path_mean());
    std::printf("[ slab     ] white, 10 deep, lit from the front: Poisson counts / path = %.3f turned, %.3f diffuse "
                "(path noise %.1f %%, %.1f %%)\n",
                turned.expected / turned.path, diffuse.expected / diffuse.path,
                100 * turned.path_noise() / turned.path_mean(), 100 * diffuse.path_noise() / diffuse.path_mean());
    EXPECT_LT(std::abs(diffuse.expected / diffuse.path - 1), std::abs(turned.expected / turned.path - 1) - 0.05);
    EXPECT_NEAR(diffuse.expected / diffuse.path, 1.0, 0.25);
}

TEST(DualTwoStream, LitHairSourceKeepsTheFurnace) {
    // The hair along a source direction read as hair of albedo a_f + a_b lit by the light
    // around it: lossless hair passes t and glows 1 − t, so a furnace reads L at any depth;
    // absorbing hair glows less than the stack's 1 − t.
    const auto white = tables_of<double>(-1), brown = tables_of<double>(1.3);
    for (double theta : {-70.0, 0.0, 45.0})
        for (double count : {0.0, 0.5, 3.0, 40.0, hs::kUnbounded<double>}) {
            const double s = std::sin(theta * hs::kPi<double> / 180);
            const auto ew = white.view().lookup(s), eb = brown.view().lookup(s);
            const auto sw = hs::dual_source_stack(ew, count), sb = hs::dual_source_stack(eb, count);
            const dvec3 hw = hs::dual_source_hair(ew, sw), hb = hs::dual_source_hair(eb, sb);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(sw.t[c] + hw[c], 1.0, 1e-9) << theta << " " << count;
                EXPECT_NEAR(sw.t[c] + sw.r[c], hs::dual_source_gain(ew, count)[c], 1e-12);
                EXPECT_LE(hb[c], 1 - sb.t[c] + 1e-12);
                EXPECT_GE(hb[c], 0.0);
            }
        }
}

TEST(DualTwoStream, MisalignmentWidensTheKernelsByItsEvents) {
    // One fiber and nothing beyond: one forward event for the transmitted light, one backward
    // for the returned; misalignment m adds m (1 − μ_f) and m (1 + μ_b) to their variances
    // and leaves the streams' shares as they are.
    const auto tables = tables_of<double>(0.3);
    const auto e = tables.lookup(0.1);
    const double lim = hs::kSlabTurnLimit<double>;
    const auto plain = hs::dual_streams(e, 1.0, 0.0);
    const double mf = (e.mu_f.x + e.mu_f.y + e.mu_f.z) / 3, mb = (e.mu_b.x + e.mu_b.y + e.mu_b.z) / 3;
    for (double m : {0.1, 0.4, 2.0 / 3.0}) {
        const auto s = hs::dual_streams(e, 1.0, 0.0, lim, lim, hs::DualStackTransport::kTurned, m);
        EXPECT_NEAR(s.spread_f - plain.spread_f, m * (1 - mf), 1e-6) << m;
        EXPECT_EQ(s.forward, plain.forward);
        EXPECT_EQ(s.back, plain.back);
    }
    const auto back = hs::dual_streams(e, 1.0, 1.0), back_m = hs::dual_streams(e, 1.0, 1.0, lim, lim,
                                                                                hs::DualStackTransport::kTurned, 0.5);
    EXPECT_GT(back_m.spread_b, back.spread_b + 0.5 * (1 + mb) * 0.99);  // at least the one return
    // 0 (and NaN, negatives) change nothing to the bit; above 1 is 1.
    for (double m : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN()}) {
        const auto s = hs::dual_streams(e, 5.0, 2.0, lim, lim, hs::DualStackTransport::kTurned, m);
        const auto d = hs::dual_streams(e, 5.0, 2.0);
        EXPECT_EQ(s.spread_f, d.spread_f) << m;
        EXPECT_EQ(s.spread_b, d.spread_b) << m;
    }
    const auto one = hs::dual_streams(e, 5.0, 2.0, lim, lim, hs::DualStackTransport::kTurned, 1.0);
    const auto big = hs::dual_streams(e, 5.0, 2.0, lim, lim, hs::DualStackTransport::kTurned, 7.0);
    EXPECT_EQ(one.spread_f, big.spread_f);
    const auto inf = hs::dual_streams(e, hs::kUnbounded<double>, hs::kUnbounded<double>, lim, lim,
                                      hs::DualStackTransport::kTurned, std::numeric_limits<double>::infinity());
    EXPECT_TRUE(std::isfinite(inf.spread_f) && std::isfinite(inf.spread_b));
}

TEST(DualTwoStream, MisalignedFiberMovesTheLongitudinalAngleAsDerived) {
    // The per-event variance against the geometry itself: light travelling along d_in meets a
    // fiber whose axis is tilted by δ from the point's axis u0 (in a uniformly random
    // direction across it); the fiber keeps d·u along its own axis u and turns the rest about
    // u by χ (0 straight through, π straight back). The aligned fiber would keep θ; the
    // tilted one moves it by a variance δ² (1 − cos χ), i.e. (1 + cos φ) in the wi/wo
    // azimuth φ = π − χ that dual_streams' μ_f and μ_b average.
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> U;
    const dvec3 u0(1, 0, 0);
    const double delta = 0.02;
    for (double theta : {0.0, 30.0, 60.0})
        for (double chi : {0.3, 1.5, 2.8}) {
            const dvec3 din = direction(theta, 0.4);
            double sum = 0, sum2 = 0;
            const int n = 20000;
            for (int i = 0; i < n; ++i) {
                const double a = 2 * hs::kPi<double> * U(rng);
                const dvec3 v(0, std::cos(a), std::sin(a));
                const dvec3 u = std::cos(delta) * u0 + std::sin(delta) * v;
                // Rotate din about u by χ (Rodrigues): the component along u is kept.
                const dvec3 dout = din * std::cos(chi) + glm::cross(u, din) * std::sin(chi) +
                                   u * glm::dot(u, din) * (1 - std::cos(chi));
                const double dt = std::asin(std::clamp(dout.x, -1.0, 1.0)) - std::asin(din.x);
                sum += dt;
                sum2 += dt * dt;
            }
            const double var = sum2 / n - (sum / n) * (sum / n);
            const double expected = delta * delta * (1 - std::cos(chi));
            EXPECT_NEAR(var, expected, 0.05 * expected) << theta << " " << chi;
        }
}

TEST(DualTwoStream, MisalignmentFromTheHairsLengthTensor) {
    using M = hs::HairLengthTensor<double>;
    const dvec3 x(1, 0, 0);
    EXPECT_NEAR(hs::dual_misalignment(M::piece(2.0, x), x), 0.0, 1e-15);
    EXPECT_NEAR(hs::dual_misalignment(M::piece(2.0, dvec3(0, 1, 0)), x), 1.0, 1e-15);
    M iso = M::piece(1.0, x);
    iso += M::piece(1.0, dvec3(0, 1, 0));
    iso += M::piece(1.0, dvec3(0, 0, 1));
    EXPECT_NEAR(hs::dual_misalignment(iso, glm::normalize(dvec3(1, 2, 3))), 2.0 / 3.0, 1e-12);
    // a 30° tilt: sin² 30° = 1/4
    EXPECT_NEAR(hs::dual_misalignment(M::piece(1.0, direction(60.0, 0.0)), x), 0.25, 1e-12);
    EXPECT_EQ(hs::dual_misalignment(M{}, x), 0.0);
    EXPECT_EQ(hs::dual_misalignment(iso, dvec3(std::numeric_limits<double>::quiet_NaN())), 0.0);
}
