// The cases of the physical fur reference (physical_fur.hpp) that the tests compare the fur
// model with, and their cache (tests/data/physical_fur.txt): f per bin over the sphere, for
// a lossless (channel 0) and a blond (channels 1–3) cortex. The comparison itself is
// physical_fiber_cases.hpp's (model_bins, compare: relative L1 over the bins). Written by
// `physical_fur_tool cache --out tests/data/physical_fur.txt` (tests/tools/physical_fur_tool.cpp).
#pragma once

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <glm/glm.hpp>

#include "physical_fiber_cases.hpp"
#include "physical_fur.hpp"

namespace phys_fur {

// The cortex: η 1.55, tilt 2°, GGX roughness 0.17, the α whose single-interface R lobe has
// the width of the model's R at β_m = 0.3 (fur_roughness_tool: 16.2–17.0° against 16.5–16.7°
// at θo 0–30°; GGX 0.3 is 22.5–23.7° wide, about twice as rough); or, where the medulla's
// light is compared alone, nearly smooth (0.02) and untilted: the smooth, untilted cylinder
// is what the model's unscattered paths and its medulla tables assume (a 2° tilt of the
// microfacets' mean normal pushes internal rays near the critical angle into total internal
// reflection, which sends 8–16 % more light into the medulla; docs/models.md).
// docs/fur_physical.md's table keeps GGX 0.3.
inline constexpr double kMatchedRoughness = 0.17;

struct FurCase {
    double kappa = 0, sigma_s = 0, g = 0, theta_deg = 0, roughness = kMatchedRoughness, tilt_deg = 2;
    std::string name() const {
        char b[112];
        std::snprintf(b, sizeof(b), "k%.1f_s%g_g%g_theta%g_r%g_t%g", kappa, sigma_s, g, theta_deg, roughness, tilt_deg);
        return b;
    }
    // The hair case that carries θ, η, roughness and tilt for phys_fiber::model_bins.
    phys_fiber::Case cortex_case() const {
        phys_fiber::Case c;
        c.theta_deg = theta_deg;
        c.roughness = roughness;
        c.tilt_deg = tilt_deg;
        return c;
    }
    Fur fur() const {
        Fur f;
        const phys_fiber::Case c = cortex_case();
        f.cortex = c.fiber();  // blond σa^c; channel 0 is the lossless one
        f.kappa = kappa;
        f.sigma_s = sigma_s;
        f.g = g;
        return f;
    }
};

// A subset of docs/fur_physical.md's grid: every medulla size with σs^m 1 and 10 at θ 0°
// and 30°, grazing 75° for two medullas, a forward-scattering medulla, and no medulla; then
// the nearly smooth cortex at θ 30° and 75° for every medulla size and σs^m.
inline std::vector<FurCase> fur_cases() {
    std::vector<FurCase> cases;
    cases.push_back({0.0, 0, 0, 30});
    for (double kappa : {0.3, 0.6, 0.9})
        for (double sigma_s : {1.0, 10.0})
            for (double theta : {0.0, 30.0}) cases.push_back({kappa, sigma_s, 0, theta});
    cases.push_back({0.6, 10, 0, 75});
    cases.push_back({0.9, 1, 0, 75});
    cases.push_back({0.6, 1, 0.5, 30});
    for (double kappa : {0.3, 0.6, 0.9})
        for (double sigma_s : {1.0, 10.0}) cases.push_back({kappa, sigma_s, 0, 30, 0.02, 0});
    cases.push_back({0.6, 10, 0, 75, 0.02, 0});
    cases.push_back({0.9, 1, 0.5, 75, 0.02, 0});
    return cases;
}

struct FurCached {
    FurCase fur;
    phys_fiber::CachedCase bins;       // f per bin, every class (its lobe energies unused)
    phys_fiber::CachedCase scattered;  // f per bin of the light scattered in the medulla
    double classes[kClasses][4]{};  // energy per class and channel, per ray
};

inline FurCached trace_fur_case(const FurCase& fc, long long rays, int n_u, int n_phi, int threads, std::uint64_t seed) {
    const Tracer tracer(fc.fur());
    const int parts = 2 * std::max(1, threads / 2);  // an even number: two halves for the noise
    std::vector<Histogram> h(std::size_t(parts), Histogram(n_u, n_phi));
    std::vector<std::thread> pool;
    const phys_fiber::Case cc = fc.cortex_case();
    for (int t = 0; t < parts; ++t)
        pool.emplace_back([&, t] { tracer.trace(cc.wo(), rays / parts, seed * 1000003u + std::uint64_t(t), h[std::size_t(t)]); });
    for (auto& th : pool) th.join();
    Histogram half[2] = {Histogram(n_u, n_phi), Histogram(n_u, n_phi)}, all(n_u, n_phi);
    for (int t = 0; t < parts; ++t) {
        half[t % 2].add(h[std::size_t(t)]);
        all.add(h[std::size_t(t)]);
    }
    FurCached r;
    r.fur = fc;
    r.bins.c = cc;
    r.bins.n_u = n_u;
    r.bins.n_phi = n_phi;
    r.bins.rays = all.rays;
    const int bins = n_u * n_phi;
    r.scattered = r.bins;
    for (int cls : {-1, int(kScattered)}) {
        phys_fiber::CachedCase& out = cls < 0 ? r.bins : r.scattered;
        out.f.resize(std::size_t(bins) * 4);
        for (int ch = 0; ch < 4; ++ch) {
            double diff = 0, sum = 0;
            for (int b = 0; b < bins; ++b) {
                out.f[std::size_t(b * 4 + ch)] = all.f(b, ch, cls);
                diff += std::fabs(half[0].f(b, ch, cls) - half[1].f(b, ch, cls));
                sum += all.f(b, ch, cls);
            }
            out.noise_l1[ch] = sum > 0 ? 0.5 * diff / sum : 0;
        }
    }
    for (int ch = 0; ch < 4; ++ch)
        for (int l = 0; l < kClasses; ++l) r.classes[l][ch] = all.lobe_energy[l][ch] / all.rays;
    return r;
}

inline void write_fur_cache(const std::string& path, const std::vector<FurCached>& cases, const std::string& comment) {
    std::ofstream out(path);
    if (!out) throw std::runtime_error("cannot write " + path);
    out << "# hairscatter physical fur reference, version 3: " << comment << "\n";
    out << "# per case: kappa sigma_s g theta roughness tilt n_u n_phi rays; noise (relative L1: lossless, R, G, B) of\n";
    out << "# every class, then of the scattered one; energy per ray of R, TT, TRT, higher, scattered\n";
    out << "# (4 channels each); then per bin f of every class and f of the scattered class (1/sr;\n";
    out << "# 4 channels each), bins in sin(theta) (slow) and atan2(z, y) (fast)\n";
    char buf[256];
    for (const FurCached& c : cases) {
        std::snprintf(buf, sizeof(buf), "fur %.17g %.17g %.17g %.17g %.17g %.17g %d %d %.17g\n", c.fur.kappa, c.fur.sigma_s,
                      c.fur.g, c.fur.theta_deg, c.fur.roughness, c.fur.tilt_deg, c.bins.n_u, c.bins.n_phi, c.bins.rays);
        out << buf;
        std::snprintf(buf, sizeof(buf), "noise %.4g %.4g %.4g %.4g %.4g %.4g %.4g %.4g\n", c.bins.noise_l1[0],
                      c.bins.noise_l1[1], c.bins.noise_l1[2], c.bins.noise_l1[3], c.scattered.noise_l1[0],
                      c.scattered.noise_l1[1], c.scattered.noise_l1[2], c.scattered.noise_l1[3]);
        out << buf << "classes";
        for (int l = 0; l < kClasses; ++l)
            for (int ch = 0; ch < 4; ++ch) {
                std::snprintf(buf, sizeof(buf), " %.6g", c.classes[l][ch]);
                out << buf;
            }
        out << "\n";
        for (int b = 0; b < c.bins.n_u * c.bins.n_phi; ++b) {
            std::snprintf(buf, sizeof(buf), "%.5g %.5g %.5g %.5g %.5g %.5g %.5g %.5g\n", c.bins.at(b, 0), c.bins.at(b, 1),
                          c.bins.at(b, 2), c.bins.at(b, 3), c.scattered.at(b, 0), c.scattered.at(b, 1),
                          c.scattered.at(b, 2), c.scattered.at(b, 3));
            out << buf;
        }
    }
}

inline std::vector<FurCached> read_fur_cache(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path + " (physical_fur_tool cache writes it)");
    std::vector<FurCached> cases;
    std::string line, tag;
    if (!std::getline(in, line) || line.rfind("# hairscatter physical fur reference, version 3:", 0) != 0)
        throw std::runtime_error(path + ": not a version 3 fur cache (physical_fur_tool cache writes it)");
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream s(line);
        FurCached c;
        s >> tag >> c.fur.kappa >> c.fur.sigma_s >> c.fur.g >> c.fur.theta_deg >> c.fur.roughness >> c.fur.tilt_deg >> c.bins.n_u >> c.bins.n_phi >>
            c.bins.rays;
        if (!s || tag != "fur" || c.bins.n_u < 1 || c.bins.n_phi < 1 || c.bins.n_u * c.bins.n_phi > 1 << 20)
            throw std::runtime_error(path + ": bad case line '" + line + "'");
        c.bins.c = c.fur.cortex_case();
        c.scattered = c.bins;
        std::getline(in, line);
        std::istringstream ns(line);
        ns >> tag;
        for (double& v : c.bins.noise_l1) ns >> v;
        for (double& v : c.scattered.noise_l1) ns >> v;
        if (!ns || tag != "noise") throw std::runtime_error(path + ": bad noise line");
        std::getline(in, line);
        std::istringstream ls(line);
        ls >> tag;
        for (int l = 0; l < kClasses; ++l)
            for (int ch = 0; ch < 4; ++ch) ls >> c.classes[l][ch];
        if (!ls || tag != "classes") throw std::runtime_error(path + ": bad classes line");
        const std::size_t bins = std::size_t(c.bins.n_u * c.bins.n_phi);
        c.bins.f.resize(bins * 4);
        c.scattered.f.resize(bins * 4);
        for (std::size_t b = 0; b < bins; ++b)
            for (phys_fiber::CachedCase* out : {&c.bins, &c.scattered})
                for (int ch = 0; ch < 4; ++ch)
                    if (!(in >> out->f[b * 4 + std::size_t(ch)])) throw std::runtime_error(path + ": truncated bins");
        std::getline(in, line);
        cases.push_back(std::move(c));
    }
    if (cases.empty()) throw std::runtime_error(path + ": no case");
    return cases;
}

}  // namespace phys_fur
