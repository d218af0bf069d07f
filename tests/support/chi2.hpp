// Chi-square goodness-of-fit harness for direction samplers (after Mitsuba 3's chi2.py):
// histogram the sampled directions over (sinθ, φ) — an equal-area parameterisation, so a
// cell's solid angle is Δsinθ·Δφ — integrate the pdf over every cell with adaptive
// cubature, pool cells expected to hold fewer than 5 samples, and compare with the
// chi-square distribution at a Bonferroni-corrected significance level.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <boost/math/distributions/chi_squared.hpp>
#include <glm/glm.hpp>

namespace chi2 {

constexpr double kPi = 3.14159265358979323846;

struct Options {
    int theta_bins = 24;         // bins over sinθ ∈ [-1, 1]
    int phi_bins = 48;           // bins over φ ∈ [-π, π]
    std::int64_t samples = 400000;
    double significance = 0.01;  // before the Bonferroni correction
    int num_tests = 1;           // how many tests share the significance level
    std::uint64_t seed = 7;
    // Each cell is split at least 4^(min_depth + 1) ways, and further while a split changes
    // its part by more than 1e-6 relative, to max_depth. Starting at 1 rather than 2 changed
    // no expected count by more than 1.6e-6 relative (the float pdfs' rounding) over the 103
    // tables of the Chiang and dual-scattering tests, and the chi-square statistic by at most
    // 1.2e-8, at a quarter of the pdf evaluations.
    int min_depth = 1;
    int max_depth = 7;
    // Azimuths in [-π, π] at which the pdf may jump (a tabulated density's bin edges): every
    // cell is cut there before the cubature, so that each piece is smooth and converges in a
    // few levels instead of refining to max_depth around the step. The cells, the samples and
    // so the test's power are unchanged; only the cost of the expected counts falls.
    std::vector<double> phi_breaks;
};

struct Result {
    bool passed = false;
    double statistic = 0, p_value = 0;
    int dof = 0;
    double expected_total = 0;  // ∫ pdf over the sphere: 1 for a normalised pdf
    std::int64_t invalid = 0;   // samples with non-finite directions or pdf ≤ 0
    std::string report;         // the observed and expected tables when it fails
};

// Adaptive tensor Gauss–Legendre cubature of pdf(x = sinθ, φ) over one cell.
class CellIntegrator {
  public:
    CellIntegrator(std::function<double(double, double)> pdf, int min_depth, int max_depth)
        : pdf_(std::move(pdf)), min_depth_(min_depth), max_depth_(max_depth) {}

    double integrate(double x0, double x1, double p0, double p1) const {
        return refine(x0, x1, p0, p1, gl(x0, x1, p0, p1), 0);
    }

  private:
    double gl(double x0, double x1, double p0, double p1) const {
        // 5-point Gauss–Legendre in each dimension.
        static const double node[5] = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                       0.5384693101056831, 0.9061798459386640};
        static const double weight[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                         0.4786286704993665, 0.2369268850561891};
        const double xm = 0.5 * (x0 + x1), xr = 0.5 * (x1 - x0);
        const double pm = 0.5 * (p0 + p1), pr = 0.5 * (p1 - p0);
        double s = 0;
        for (int i = 0; i < 5; ++i)
            for (int j = 0; j < 5; ++j) s += weight[i] * weight[j] * pdf_(xm + xr * node[i], pm + pr * node[j]);
        return s * xr * pr;
    }
    double refine(double x0, double x1, double p0, double p1, double whole, int depth) const {
        const double xm = 0.5 * (x0 + x1), pm = 0.5 * (p0 + p1);
        const double q[4] = {gl(x0, xm, p0, pm), gl(xm, x1, p0, pm), gl(x0, xm, pm, p1), gl(xm, x1, pm, p1)};
        const double parts = q[0] + q[1] + q[2] + q[3];
        if (depth >= max_depth_ ||
            (depth >= min_depth_ && std::abs(parts - whole) <= 1e-6 * std::abs(parts) + 1e-12))
            return parts;
        return refine(x0, xm, p0, pm, q[0], depth + 1) + refine(xm, x1, p0, pm, q[1], depth + 1) +
               refine(x0, xm, pm, p1, q[2], depth + 1) + refine(xm, x1, pm, p1, q[3], depth + 1);
    }
    std::function<double(double, double)> pdf_;
    int min_depth_, max_depth_;
};

// The sampled side of a test: the histogram of sample's directions over the cells
// (row-major, i over sinθ, j over φ) and the samples that were not unit vectors.
struct Histogram {
    std::vector<double> observed;
    std::int64_t invalid = 0;
};

// The pdf's side: the expected count of every cell (opt.samples × the pdf's integral over it).
struct Expected {
    std::vector<double> counts;
    // The same table for pdf × s, without integrating again: what integrating s·pdf gives
    // to rounding (the cubature's refinement test is relative, so it splits the same cells).
    Expected scaled(double s) const {
        Expected e = *this;
        for (double& c : e.counts) c *= s;
        return e;
    }
};

// sample: (u0..u3) → direction (unit vector in the fiber frame) or a zero vector if the
// sampler declined. A negative control that changes only the pdf reuses the histogram.
inline Histogram histogram(const std::function<glm::dvec3(const glm::dvec4&)>& sample, const Options& opt) {
    const int nx = opt.theta_bins, np = opt.phi_bins;
    auto cell_of = [&](const glm::dvec3& w) {
        const double x = std::clamp(w.x, -1.0, 1.0);
        const double phi = std::atan2(w.z, w.y);
        const int i = std::min(nx - 1, std::max(0, int((x + 1) * 0.5 * nx)));
        const int j = std::min(np - 1, std::max(0, int((phi + kPi) / (2 * kPi) * np)));
        return i * np + j;
    };
    Histogram h;
    h.observed.assign(std::size_t(nx * np), 0.0);
    std::mt19937_64 rng(opt.seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (std::int64_t k = 0; k < opt.samples; ++k) {
        // One at a time: the order in which function arguments are evaluated differs
        // between compilers, and the same stream should give the same test everywhere.
        glm::dvec4 u;
        for (int k = 0; k < 4; ++k) u[k] = uni(rng);
        const glm::dvec3 w = sample(u);
        const double len2 = glm::dot(w, w);
        if (!std::isfinite(len2) || std::abs(len2 - 1) > 1e-3) {
            ++h.invalid;
            continue;
        }
        h.observed[std::size_t(cell_of(w))] += 1;
    }
    return h;
}

// pdf: direction → density in solid angle. A negative control that changes only the
// sampler, or scales the pdf (Expected::scaled), reuses this table.
inline Expected expected_counts(const std::function<double(const glm::dvec3&)>& pdf, const Options& opt) {
    const int nx = opt.theta_bins, np = opt.phi_bins;
    const CellIntegrator integ(
        [&](double x, double phi) {
            const double c = std::sqrt(std::max(0.0, 1 - x * x));
            return pdf(glm::dvec3(x, c * std::cos(phi), c * std::sin(phi)));
        },
        opt.min_depth, opt.max_depth);
    std::vector<double> breaks = opt.phi_breaks;
    std::sort(breaks.begin(), breaks.end());
    Expected e;
    e.counts.assign(std::size_t(nx * np), 0.0);
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < np; ++j) {
            const double x0 = -1 + 2.0 * i / nx, x1 = -1 + 2.0 * (i + 1) / nx;
            const double p0 = -kPi + 2 * kPi * j / np, p1 = -kPi + 2 * kPi * (j + 1) / np;
            double sum = 0, from = p0;
            for (double b : breaks)
                if (b > from && b < p1) {
                    sum += integ.integrate(x0, x1, from, b);
                    from = b;
                }
            e.counts[std::size_t(i * np + j)] = (sum + integ.integrate(x0, x1, from, p1)) * double(opt.samples);
        }
    return e;
}

// The test itself, from a histogram and an expected table made with the same options.
inline Result compare(const Histogram& h, const Expected& e, const Options& opt) {
    const int np = opt.phi_bins, cells = opt.theta_bins * np;
    const std::vector<double>& observed = h.observed;
    const std::vector<double>& expected = e.counts;
    Result r;
    r.invalid = h.invalid;
    for (double x : expected) r.expected_total += x;
    r.expected_total /= double(opt.samples);

    // Pool the cells expected to hold fewer than 5 samples into one. The chi-square
    // approximation needs at least 5 expected in every cell, the pool included: a pool
    // still below 5 is merged into the kept cell with the smallest expectation (otherwise a
    // single legitimate tail sample in a pool expecting 0.005 would read as p = 1e-25).
    double pool_obs = double(r.invalid), pool_exp = 0, stat = 0;
    std::vector<double> kept_obs, kept_exp;
    for (int c = 0; c < cells; ++c) {
        if (expected[c] < 5) {
            pool_obs += observed[c];
            pool_exp += expected[c];
        } else {
            kept_obs.push_back(observed[c]);
            kept_exp.push_back(expected[c]);
        }
    }
    bool impossible = false;  // samples where the pdf integrates to exactly zero
    if (pool_exp > 0 || pool_obs > 0) {
        if (pool_exp <= 0) {
            impossible = true;
        } else if (pool_exp >= 5 || kept_exp.empty()) {
            kept_obs.push_back(pool_obs);
            kept_exp.push_back(pool_exp);
        } else {
            const auto smallest = std::min_element(kept_exp.begin(), kept_exp.end()) - kept_exp.begin();
            kept_obs[std::size_t(smallest)] += pool_obs;
            kept_exp[std::size_t(smallest)] += pool_exp;
        }
    }
    for (std::size_t c = 0; c < kept_exp.size(); ++c)
        stat += (kept_obs[c] - kept_exp[c]) * (kept_obs[c] - kept_exp[c]) / kept_exp[c];
    if (impossible) stat = 1e30;
    const int kept = int(kept_exp.size());
    r.statistic = stat;
    r.dof = std::max(1, kept - 1);
    r.p_value = boost::math::cdf(boost::math::complement(boost::math::chi_squared(r.dof), stat));
    r.passed = r.p_value >= opt.significance / opt.num_tests && r.invalid == 0;

    if (!r.passed) {
        std::ostringstream os;
        os << "chi2 = " << stat << ", dof = " << r.dof << ", p = " << r.p_value
           << ", expected total = " << r.expected_total << ", invalid samples = " << r.invalid
           << "\nworst cells (i over sinθ, j over φ: observed / expected):\n";
        std::vector<int> order(cells);
        for (int c = 0; c < cells; ++c) order[c] = c;
        std::sort(order.begin(), order.end(), [&](int a, int b) {
            auto dev = [&](int c) {
                return expected[c] > 0 ? std::abs(observed[c] - expected[c]) / std::sqrt(expected[c]) : observed[c];
            };
            return dev(a) > dev(b);
        });
        for (int k = 0; k < std::min(cells, 12); ++k)
            os << "  (" << order[k] / np << ", " << order[k] % np << "): " << observed[order[k]] << " / "
               << expected[order[k]] << "\n";
        r.report = os.str();
    }
    return r;
}

// sample against pdf in one call.
inline Result test(const std::function<glm::dvec3(const glm::dvec4&)>& sample,
                   const std::function<double(const glm::dvec3&)>& pdf, const Options& opt) {
    return compare(histogram(sample, opt), expected_counts(pdf, opt), opt);
}

}  // namespace chi2
