// An independent, deliberately plain double-precision transcription of the model that
// pbrt-v4's HairBxDF implements (docs/theory.md §3), used as the reference the library is
// tested against. It shares no code with include/: I0 comes from Boost.Math, angles go
// through atan2 and trig like the paper's equations, M_p uses the paper's direct form
// for v > 0.1 and its log-space form otherwise.
#pragma once

#include <array>
#include <cmath>

#include <boost/math/special_functions/bessel.hpp>
#include <glm/glm.hpp>

namespace ref {

constexpr double kPi = 3.14159265358979323846;

struct Params {
    double eta = 1.55, beta_m = 0.3, beta_n = 0.3, alpha = 0.0;  // alpha in radians
    glm::dvec3 sigma_a{0.0};
};

// log I0 from Boost where I0 is representable, else its asymptotic series (error < 1e-13
// for x > 500).
inline double log_i0(double x) {
    if (x < 500) return std::log(boost::math::cyl_bessel_i(0, x));
    const double t = 1 / (8 * x);
    return x - 0.5 * std::log(2 * kPi * x) + std::log1p(t + 4.5 * t * t + 37.5 * t * t * t);
}

// d'Eon et al. 2011 eq. 7 and its log form.
inline double mp(double v, double sin_i, double cos_i, double sin_o, double cos_o) {
    const double a = cos_i * cos_o / v, b = sin_i * sin_o / v;
    if (v > 0.1) return std::exp(-b) * boost::math::cyl_bessel_i(0, a) / (2 * v * std::sinh(1 / v));
    return std::exp(log_i0(a) - b - 1 / v + std::log(2.0) + std::log(1 / (2 * v)));
}

inline double logistic(double x, double s) {
    x = std::abs(x);
    return std::exp(-x / s) / (s * std::pow(1 + std::exp(-x / s), 2));
}
inline double logistic_cdf(double x, double s) { return 1 / (1 + std::exp(-x / s)); }
inline double trimmed_logistic(double x, double s) {
    return logistic(x, s) / (logistic_cdf(kPi, s) - logistic_cdf(-kPi, s));
}

inline double fresnel(double cos_i, double eta) {
    const double sin_t = std::sqrt(std::max(0.0, 1 - cos_i * cos_i)) / eta;
    const double cos_t = std::sqrt(std::max(0.0, 1 - sin_t * sin_t));
    const double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    const double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

struct Model {
    Params p;
    double h;

    double v(int lobe) const {
        const double bm = p.beta_m;
        const double v0 = std::pow(0.726 * bm + 0.812 * bm * bm + 3.7 * std::pow(bm, 20), 2);
        return lobe == 0 ? v0 : lobe == 1 ? v0 / 4 : 4 * v0;
    }
    double s() const {
        const double bn = p.beta_n;
        return std::sqrt(kPi / 8) * (0.265 * bn + 1.194 * bn * bn + 5.372 * std::pow(bn, 22));
    }
    // θo rotated for lobe p: -2α (R), +α (TT), +4α (TRT), none for the residual.
    double theta_o_tilted(int lobe, double theta_o) const {
        const double shift[4] = {-2 * p.alpha, p.alpha, 4 * p.alpha, 0.0};
        return theta_o + shift[lobe];
    }
    double gamma_t(double theta_o) const {
        const double etap = std::sqrt(p.eta * p.eta - std::pow(std::sin(theta_o), 2)) / std::cos(theta_o);
        return std::asin(h / etap);
    }
    double Phi(int lobe, double theta_o) const {
        return 2 * lobe * gamma_t(theta_o) - 2 * std::asin(h) + lobe * kPi;
    }
    std::array<glm::dvec3, 4> Ap(double theta_o) const {
        const double gt = gamma_t(theta_o);
        const double theta_t = std::asin(std::sin(theta_o) / p.eta);
        const glm::dvec3 T = glm::exp(-p.sigma_a * (2 * std::cos(gt) / std::cos(theta_t)));
        const double f = fresnel(std::cos(theta_o) * std::sqrt(1 - h * h), p.eta);
        std::array<glm::dvec3, 4> a;
        a[0] = glm::dvec3(f);
        a[1] = (1 - f) * (1 - f) * T;
        a[2] = a[1] * T * f;
        for (int c = 0; c < 3; ++c) a[3][c] = (1 - T[c] * f) > 0 ? a[2][c] * f * T[c] / (1 - T[c] * f) : 0.0;
        return a;
    }
    // f with the cosine inside (pbrt's fsum), per lobe and summed.
    glm::dvec3 lobe(int l, const glm::dvec3& wo, const glm::dvec3& wi) const {
        const double theta_o = std::asin(std::clamp(wo.x, -1.0, 1.0));
        const double theta_i = std::asin(std::clamp(wi.x, -1.0, 1.0));
        double phi = std::atan2(wi.z, wi.y) - std::atan2(wo.z, wo.y);
        const double to = theta_o_tilted(l, theta_o);
        const double m = mp(v(l), std::sin(theta_i), std::cos(theta_i), std::sin(to), std::abs(std::cos(to)));
        double n = 1 / (2 * kPi);
        if (l < 3) {
            double d = phi - Phi(l, theta_o);
            while (d > kPi) d -= 2 * kPi;
            while (d < -kPi) d += 2 * kPi;
            n = trimmed_logistic(d, s());
        }
        return m * n * Ap(theta_o)[l];
    }
    glm::dvec3 f(const glm::dvec3& wo, const glm::dvec3& wi) const {
        glm::dvec3 r(0.0);
        for (int l = 0; l < 4; ++l) r += lobe(l, wo, wi);
        return r;
    }
};

inline glm::dvec3 dir(double theta, double phi) {
    return {std::sin(theta), std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi)};
}

}  // namespace ref
