// The cases of the physical fiber reference (physical_fiber.hpp), its cache file, and the
// comparison of a model against it: relative L1 over the sphere of outgoing directions of
// f's averages over the reference's bins. Shared by tests/huang_physical_test.cpp and the
// tool that writes the cache (tests/tools/physical_fiber_tool.cpp).
#pragma once

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <boost/math/quadrature/gauss.hpp>
#include <glm/glm.hpp>

#include "physical_fiber.hpp"

namespace phys_fiber {

// Blond hair's absorption (eumelanin 1.3, per unit radius; the library's melanin mapping
// for the renderer's "blond" preset), written out so that the reference does not call the
// library.
inline constexpr double kBlond[3] = {0.5447, 0.9061, 1.781};

struct Case {
    double aspect = 1, psi_deg = 0, roughness = 0.3, theta_deg = 0, tilt_deg = 2, eta = 1.55;
    std::string name() const {
        char b[128];
        std::snprintf(b, sizeof(b), "b%.2g_psi%g_beta%.2g_theta%g", aspect, psi_deg, roughness, theta_deg);
        return b;
    }
    glm::dvec3 wo() const {
        const double t = theta_deg * kPi / 180;
        return {std::sin(t), 0.0, std::cos(t)};  // the renderer's frame: wo in the x–z plane
    }
    Fiber fiber() const {
        Fiber f;
        f.eta = eta;
        f.roughness = roughness;
        f.tilt = tilt_deg * kPi / 180;
        f.aspect = aspect;
        f.orientation = psi_deg * kPi / 180;
        f.sigma_a = glm::dvec3(kBlond[0], kBlond[1], kBlond[2]);
        return f;
    }
};

// The grid of docs/models.md: round and b/a 0.5 at ψ 0/45/90°, roughness 0.1 and 0.3,
// θo 0/30/75°; each case holds the lossless fiber (channel 0) and blond (channels 1–3).
inline std::vector<Case> physical_cases() {
    std::vector<Case> cases;
    const double shapes[4][2] = {{1, 0}, {0.5, 0}, {0.5, 45}, {0.5, 90}};
    for (const auto& s : shapes)
        for (double beta : {0.1, 0.3})
            for (double theta : {0.0, 30.0, 75.0}) {
                Case c;
                c.aspect = s[0];
                c.psi_deg = s[1];
                c.roughness = beta;
                c.theta_deg = theta;
                cases.push_back(c);
            }
    return cases;
}

// f per bin and channel, as cached: the reference's estimate and a noise estimate.
struct CachedCase {
    Case c;
    int n_u = 0, n_phi = 0;
    double rays = 0;
    std::vector<double> f;           // [bin][4] 1/sr
    double lobe_energy[kLobes][4]{};  // per ray
    double noise_l1[4]{};            // relative L1 of the estimate's noise (from two halves)
    double at(int bin, int ch) const { return f[std::size_t(bin * 4 + ch)]; }
};

// Traces a case on `threads` threads; the noise from two independent halves.
inline CachedCase trace_case(const Case& c, long long rays, int n_u, int n_phi, int threads, std::uint64_t seed) {
    const Tracer tracer(c.fiber());
    const int parts = 2 * std::max(1, threads / 2);  // an even number: two halves
    std::vector<Histogram> h(std::size_t(parts), Histogram(n_u, n_phi));
    std::vector<std::thread> pool;
    for (int t = 0; t < parts; ++t)
        pool.emplace_back([&, t] { tracer.trace(c.wo(), rays / parts, seed * 1000003u + std::uint64_t(t), h[std::size_t(t)]); });
    for (auto& th : pool) th.join();
    Histogram half[2] = {Histogram(n_u, n_phi), Histogram(n_u, n_phi)}, all(n_u, n_phi);
    for (int t = 0; t < parts; ++t) {
        half[t % 2].add(h[std::size_t(t)]);
        all.add(h[std::size_t(t)]);
    }
    CachedCase r;
    r.c = c;
    r.n_u = n_u;
    r.n_phi = n_phi;
    r.rays = all.rays;
    const int bins = n_u * n_phi;
    r.f.resize(std::size_t(bins) * 4);
    for (int ch = 0; ch < 4; ++ch) {
        double diff = 0, sum = 0;
        for (int b = 0; b < bins; ++b) {
            r.f[std::size_t(b * 4 + ch)] = all.f(b, ch);
            diff += std::fabs(half[0].f(b, ch) - half[1].f(b, ch));
            sum += all.f(b, ch);
        }
        r.noise_l1[ch] = sum > 0 ? 0.5 * diff / sum : 0;
        for (int l = 0; l < kLobes; ++l) r.lobe_energy[l][ch] = all.lobe_energy[l][ch] / all.rays;
    }
    return r;
}

inline void write_cache(const std::string& path, const std::vector<CachedCase>& cases, const std::string& comment) {
    std::ofstream out(path);
    if (!out) throw std::runtime_error("cannot write " + path);
    out << "# hairscatter physical fiber reference, version 1: " << comment << "\n";
    out << "# per case: parameters, rays, noise (relative L1: lossless, R, G, B), lobe energies per ray\n";
    out << "# (R, TT, TRT, higher; 4 channels each), then f per bin (1/sr; 4 channels), bins in\n";
    out << "# sin(theta) (slow) and the absolute azimuth atan2(z, y) (fast), equal solid angle\n";
    char buf[256];
    for (const CachedCase& c : cases) {
        std::snprintf(buf, sizeof(buf), "case %.17g %.17g %.17g %.17g %.17g %.17g %d %d %.17g\n", c.c.aspect, c.c.psi_deg,
                      c.c.roughness, c.c.theta_deg, c.c.tilt_deg, c.c.eta, c.n_u, c.n_phi, c.rays);
        out << buf;
        std::snprintf(buf, sizeof(buf), "noise %.4g %.4g %.4g %.4g\n", c.noise_l1[0], c.noise_l1[1], c.noise_l1[2], c.noise_l1[3]);
        out << buf;
        out << "lobes";
        for (int l = 0; l < kLobes; ++l)
            for (int ch = 0; ch < 4; ++ch) {
                std::snprintf(buf, sizeof(buf), " %.6g", c.lobe_energy[l][ch]);
                out << buf;
            }
        out << "\n";
        for (int b = 0; b < c.n_u * c.n_phi; ++b) {
            std::snprintf(buf, sizeof(buf), "%.5g %.5g %.5g %.5g\n", c.at(b, 0), c.at(b, 1), c.at(b, 2), c.at(b, 3));
            out << buf;
        }
    }
}

inline std::vector<CachedCase> read_cache(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path + " (scripts/physical-reference.sh writes it)");
    std::vector<CachedCase> cases;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream s(line);
        std::string tag;
        s >> tag;
        if (tag != "case") throw std::runtime_error(path + ": expected a case line, read '" + line + "'");
        CachedCase c;
        s >> c.c.aspect >> c.c.psi_deg >> c.c.roughness >> c.c.theta_deg >> c.c.tilt_deg >> c.c.eta >> c.n_u >> c.n_phi >> c.rays;
        if (!s || c.n_u < 1 || c.n_phi < 1 || c.n_u * c.n_phi > 1 << 20) throw std::runtime_error(path + ": bad case line");
        std::getline(in, line);
        std::istringstream ns(line);
        ns >> tag >> c.noise_l1[0] >> c.noise_l1[1] >> c.noise_l1[2] >> c.noise_l1[3];
        if (!ns || tag != "noise") throw std::runtime_error(path + ": bad noise line");
        std::getline(in, line);
        std::istringstream ls(line);
        ls >> tag;
        for (int l = 0; l < kLobes; ++l)
            for (int ch = 0; ch < 4; ++ch) ls >> c.lobe_energy[l][ch];
        if (!ls || tag != "lobes") throw std::runtime_error(path + ": bad lobes line");
        c.f.resize(std::size_t(c.n_u * c.n_phi) * 4);
        for (double& v : c.f)
            if (!(in >> v)) throw std::runtime_error(path + ": truncated bins");
        std::getline(in, line);
        cases.push_back(std::move(c));
    }
    if (cases.empty()) throw std::runtime_error(path + ": no case");
    return cases;
}

// A model's f (RGB) averaged over each bin of the cached case, for `eval(wo, wi)` returning
// RGB. Each bin is
// integrated in θ (not sin θ: lobes near the poles are narrow in sin θ) by 3-point
// Gauss–Legendre panels no wider than `panel` radians, and in φ by 3 points.
template <typename Eval>
std::vector<glm::dvec3> model_bins(const CachedCase& c, const Eval& eval, double panel = 0.05) {
    static const double gx[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
    static const double gw[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    const int bins = c.n_u * c.n_phi;
    std::vector<glm::dvec3> out(std::size_t(bins), glm::dvec3(0.0));
    const glm::dvec3 wo = c.c.wo();
    const double dp = 2 * kPi / c.n_phi, dw = (2.0 / c.n_u) * dp;
    for (int iu = 0; iu < c.n_u; ++iu) {
        const double t0 = std::asin(std::max(-1.0, -1 + 2.0 * iu / c.n_u));
        const double t1 = std::asin(std::min(1.0, -1 + 2.0 * (iu + 1) / c.n_u));
        const int panels = std::max(1, int(std::ceil((t1 - t0) / panel)));
        const double width = (t1 - t0) / panels;
        for (int ip = 0; ip < c.n_phi; ++ip) {
            const double p0 = -kPi + dp * ip;
            glm::dvec3 acc(0.0);
            for (int k = 0; k < panels; ++k)
                for (int i = 0; i < 3; ++i) {
                    const double theta = t0 + width * (k + 0.5 * (1 + gx[i]));
                    const double st = std::sin(theta), ct = std::cos(theta);
                    for (int j = 0; j < 3; ++j) {
                        const double phi = p0 + 0.5 * dp * (1 + gx[j]);
                        const glm::dvec3 wi(st, ct * std::cos(phi), ct * std::sin(phi));
                        const glm::dvec3 f = eval(wo, wi);
                        acc += (0.5 * width * gw[i] * 0.5 * dp * gw[j] * ct) * f;  // dω = cos θ dθ dφ
                    }
                }
            out[std::size_t(iu * c.n_phi + ip)] = acc / dw;
        }
    }
    return out;
}
struct ModelError {
    double l1 = 0;                            // relative L1: Σ |f_model − f_ref| / Σ f_ref over bins
    double energy_model = 0, energy_ref = 0;  // ∫ f dω of each
};
// Relative L1 of the model bins' channel mch against the cache's channel ch.
inline ModelError compare(const CachedCase& c, const std::vector<glm::dvec3>& model, int mch, int ch) {
    ModelError e;
    double diff = 0;
    const double dw = (2.0 / c.n_u) * (2 * kPi / c.n_phi);
    for (int b = 0; b < c.n_u * c.n_phi; ++b) {
        const double m = model[std::size_t(b)][mch];
        diff += std::fabs(m - c.at(b, ch));
        e.energy_model += m * dw;
        e.energy_ref += c.at(b, ch) * dw;
    }
    e.l1 = diff * dw / e.energy_ref;
    return e;
}

}  // namespace phys_fiber

