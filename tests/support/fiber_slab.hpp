// A brute-force reference for dual scattering: a slab of explicit, parallel, infinitely long
// fibers (axis x), laterally periodic in y, between z = 0 and z = depth, lit by a directional
// light and seen by a distant camera. Because the fibers are parallel, intersections only
// depend on the rays' (y, z) components. path_radiance() path-traces the exact multiple
// scattering with the single-fiber model at the true h of every hit; the dual-scattering
// estimate at the same first hits gets what a renderer gets: a shadow ray, and the expected
// fiber counts toward the light and beyond the point from the slab's density.
#pragma once

#include <cmath>
#include <cstdint>
#include <algorithm>
#include <random>
#include <vector>

#include <glm/glm.hpp>

#include <hairscatter/dual.hpp>

namespace slab {

using glm::dvec2;
using glm::dvec3;
using glm::dvec4;

struct Hit {
    double t = 0;
    int fiber = -1;
    dvec3 p{0};
    dvec3 axis{0};  // the point of the fiber's axis (the periodic image hit) nearest p
};

class FiberSlab {
  public:
    // width and depth in fiber radii (radius 1); fibers are placed uniformly without overlap
    // until the expected number crossed by a ray perpendicular to the slab, 2ρ·depth, is tau.
    FiberSlab(double width, double depth, double tau, std::uint64_t seed) : width_(width), depth_(depth) {
        const double rho = tau / (2.0 * depth);  // fibers per unit area
        const int count = int(std::lround(rho * width * depth));
        std::mt19937_64 rng(seed);
        std::uniform_real_distribution<double> uy(0, width), uz(1.0, depth - 1.0);
        // width is rounded to whole cells so that the cell grid wraps with the fibers.
        cells_y_ = std::max(1, int(std::lround(width / kCell)));
        width_ = width = cells_y_ * kCell;
        cells_z_ = std::max(1, int(std::ceil(depth / kCell)));
        grid_.assign(std::size_t(cells_y_ * cells_z_), {});
        int tries = 0;
        while (int(centres_.size()) < count && tries++ < count * 1000) {
            const dvec2 c(uy(rng), uz(rng));
            if (overlaps(c)) continue;
            add(c);
        }
        rho_ = double(centres_.size()) / (width * depth);
    }

    double depth() const { return depth_; }
    double width() const { return width_; }
    std::size_t size() const { return centres_.size(); }
    // The expected number of fibers a ray crosses per unit of its (y, z)-projected length.
    double crossings_per_length() const { return 2.0 * rho_; }

    // The first fiber hit along o + t d (t > 0, skipping fiber `skip`), or fiber = -1.
    Hit intersect(const dvec3& o, const dvec3& d, int skip = -1) const {
        Hit best;
        const dvec2 d2(d.y, d.z);
        const double len2 = glm::dot(d2, d2);
        walk(o, d, [&](const std::vector<int>& fibers, double y_here, double t, double step) {
            for (int i : fibers) {
                if (i == skip) continue;
                const double th = hit_circle(o, d2, len2, i, y_here);
                if (th > 1e-9 && (best.fiber < 0 || th < best.t)) {
                    best.t = th;
                    best.fiber = i;
                }
            }
            return !(best.fiber >= 0 && best.t < t - 2 * step);
        });
        if (best.fiber >= 0) {
            best.p = o + best.t * d;
            const dvec2 c = nearest_image(centres_[std::size_t(best.fiber)], best.p.y);
            best.axis = dvec3(best.p.x, c.x, c.y);
        }
        return best;
    }

    // The number of fibers o + t d crosses (t > 0, fiber `skip` excluded) until it leaves
    // the slab: what a renderer that counts its shadow ray's hits knows exactly.
    int count(const dvec3& o, const dvec3& d, int skip = -1) const {
        if (d.z == 0) return 0;  // along the slab: never leaving it, no crossing counted
        const dvec2 d2(d.y, d.z);
        const double len2 = glm::dot(d2, d2);
        std::vector<int> seen;
        walk(o, d, [&](const std::vector<int>& fibers, double y_here, double, double) {
            for (int i : fibers) {
                if (i == skip || std::find(seen.begin(), seen.end(), i) != seen.end()) continue;
                if (hit_circle(o, d2, len2, i, y_here) > 1e-9) seen.push_back(i);
            }
            return true;
        });
        return int(seen.size());
    }

  private:
    static constexpr double kCell = 4.0;

    // Walks the cells the projected ray crosses until it leaves the slab (uniform steps of
    // half a cell: a fiber of radius 1 is registered in every cell its disc touches, so none
    // is missed), calling visit(fibers of the cell, y there, t, step) once per new cell
    // until it returns false.
    template <typename Visit> void walk(const dvec3& o, const dvec3& d, Visit&& visit) const {
        const double len2 = d.y * d.y + d.z * d.z;
        if (len2 < 1e-24) return;
        const double step = 0.5 * kCell / std::sqrt(len2);  // in t
        double t_end = 1e30;
        if (d.z > 0) t_end = (depth_ - o.z) / d.z;
        else if (d.z < 0) t_end = -o.z / d.z;
        if (!(t_end > 0)) return;
        // A ray nearly in the slab's plane would wander over the periodic images for ever:
        // past eight widths of lateral travel (thousands of fibers) the walk stops.
        t_end = std::min(t_end, 8.0 * width_ / std::sqrt(len2));
        int last_cell = -1;
        for (double t = 0; t <= t_end + step; t += step) {
            const int cz = int(std::floor((o.z + t * d.z) / kCell));
            const int cy = wrap_cell(int(std::floor((o.y + t * d.y) / kCell)));
            if (cz < 0 || cz >= cells_z_) continue;
            const int cell = cz * cells_y_ + cy;
            if (cell == last_cell) continue;
            last_cell = cell;
            if (!visit(grid_[std::size_t(cell)], o.y + t * d.y, t, step)) return;
        }
    }

    int wrap_cell(int cy) const { return ((cy % cells_y_) + cells_y_) % cells_y_; }
    // The periodic image of centre c nearest to the lateral position y.
    dvec2 nearest_image(const dvec2& c, double y) const {
        return dvec2(c.x + width_ * std::round((y - c.x) / width_), c.y);
    }
    // The ray's entry into fiber i's image nearest y_ref (or its neighbours), or -1.
    double hit_circle(const dvec3& o, const dvec2& d2, double len2, int i, double y_ref) const {
        const dvec2 c = nearest_image(centres_[std::size_t(i)], y_ref);
        double best = -1;
        for (int k = -1; k <= 1; ++k) {
            const dvec2 oc = dvec2(o.y, o.z) - dvec2(c.x + k * width_, c.y);
            const double b = glm::dot(oc, d2), cc = glm::dot(oc, oc) - 1.0;
            const double disc = b * b - len2 * cc;
            if (disc < 0) continue;
            const double t = (-b - std::sqrt(disc)) / len2;
            if (t > 1e-9 && (best < 0 || t < best)) best = t;
        }
        return best;
    }
    bool overlaps(const dvec2& c) const {
        for (const dvec2& o : centres_) {
            dvec2 d = c - o;
            d.x -= width_ * std::round(d.x / width_);
            if (glm::dot(d, d) < 4.0) return true;
        }
        return false;
    }
    void add(const dvec2& c) {
        const int i = int(centres_.size());
        centres_.push_back(c);
        const int z0 = int(std::floor((c.y - 1) / kCell)), z1 = int(std::floor((c.y + 1) / kCell));
        const int y0 = int(std::floor((c.x - 1) / kCell)), y1 = int(std::floor((c.x + 1) / kCell));
        for (int z = z0; z <= z1; ++z)
            for (int y = y0; y <= y1; ++y)
                if (z >= 0 && z < cells_z_) grid_[std::size_t(z * cells_y_ + wrap_cell(y))].push_back(i);
    }

    double width_, depth_, rho_ = 0;
    int cells_y_ = 1, cells_z_ = 1;
    std::vector<dvec2> centres_;
    std::vector<std::vector<int>> grid_;
};

namespace hs = hairscatter;

inline double mean(const dvec3& v) { return (v.x + v.y + v.z) / 3; }

// Four uniform numbers drawn in order (the order in which a function's arguments are
// evaluated differs between compilers, and with it the random stream).
template <typename Dist, typename Rng> glm::dvec4 draw4(Dist& u, Rng& rng) {
    glm::dvec4 r;
    for (int i = 0; i < 4; ++i) r[i] = u(rng);
    return r;
}

// A directional light from wl or, with furnace, a uniform environment of radiance 1.
struct Lighting {
    dvec3 wl{0, 0, 1};
    bool furnace = false;
};

// The exact multiple scattering leaving the slab's hit toward wo (channel mean), path-traced
// with the single-fiber model Fiber (constructed from its material and h) at the true h of
// every hit: next-event estimation of the directional light, or escapes into the
// environment; Russian roulette only, no depth cut.
template <typename Fiber = hs::ChiangFiber<double>, typename Rng>
double path_radiance(const FiberSlab& s, const typename Fiber::Material& mat, const Hit& hit, const dvec3& wo,
                     const Lighting& light, Rng& rng) {
    std::uniform_real_distribution<double> U;
    const dvec3 axis(1, 0, 0);
    double L = 0;
    dvec3 beta(1), w = wo;
    Hit cur = hit;
    for (int depth = 0;; ++depth) {
        const hs::FiberFrame<double> fr(axis, w);
        const Fiber fiber(mat, glm::dot(cur.p - cur.axis, fr.y));
        const dvec3 wo_l = fr.to_local(w);
        if (!light.furnace && s.intersect(cur.p, light.wl, cur.fiber).fiber < 0)
            L += mean(beta * fiber.eval(wo_l, fr.to_local(light.wl)));
        const auto smp = fiber.sample(wo_l, draw4(U, rng));
        if (!(smp.pdf > 0)) break;
        beta *= smp.weight;
        const dvec3 d = glm::normalize(fr.to_world(smp.wi));
        const Hit next = s.intersect(cur.p, d, cur.fiber);
        if (next.fiber < 0) {
            if (light.furnace) L += mean(beta);  // escaped into the environment
            break;
        }
        w = -d;
        cur = next;
        if (depth >= 3) {
            const double q = std::min(0.95, std::max({beta.x, beta.y, beta.z}));
            if (U(rng) >= q) break;
            beta /= q;
        }
    }
    return L;
}

// Dual scattering (both formulations) at the first hits of `paths` camera rays along -wo
// against path tracing the same slab (depth 8 tau, 2,000 fibers per 10 deep) under a
// directional light from wl: both use ChiangFiber at the true h of every hit; dual
// scattering gets a shadow ray and the expected counts toward the light and beyond the
// point from the slab's density, as a renderer would. Sums of the channel means.
struct Sums {
    double path = 0, improved = 0, zinke = 0, path_sq = 0;
    int hits = 0;
};

inline Sums compare_dual(const hs::FiberParams<double>& params, double tau, const dvec3& wl, const dvec3& wo, int paths) {
    using Dual = hs::DualScatteringBcsdf<hs::ChiangFiber<double>>;
    const hs::ChiangMaterial<double> mat(params);
    hs::DualTableOptions<double> oz;
    oz.settings = hs::DualScatteringSettings<double>::zinke2008();
    const auto improved = hs::DualScatteringTables<double>::build<hs::ChiangFiber<double>>(mat);
    const auto zinke = hs::DualScatteringTables<double>::build<hs::ChiangFiber<double>>(mat, oz);
    const slab::FiberSlab s(400, 8 * tau, tau, 7);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> U;
    const dvec3 axis(1, 0, 0);
    const double per_length = s.crossings_per_length(), proj = std::sqrt(wl.y * wl.y + wl.z * wl.z);
    Sums r;
    for (int k = 0; k < paths; ++k) {
        const slab::Hit hit = s.intersect(dvec3(0, U(rng) * s.width(), wo.z > 0 ? s.depth() : 0.0), -wo);
        if (hit.fiber < 0) continue;
        ++r.hits;
        const hs::FiberFrame<double> f0(axis, wo);
        const hs::ChiangFiber<double> fiber0(mat, glm::dot(hit.p - hit.axis, f0.y));
        const bool blocked = s.intersect(hit.p, wl, hit.fiber).fiber >= 0;
        const double up = wl.z > 0 ? (s.depth() - hit.p.z) / wl.z : hit.p.z / -wl.z;
        const double down = wl.z > 0 ? hit.p.z / wl.z : (s.depth() - hit.p.z) / -wl.z;
        hs::DualScatteringLight<double> l;
        l.direct_fraction = blocked ? 0 : 1;
        l.n = blocked ? per_length * proj * up : 0;
        l.beyond = per_length * proj * down;
        r.improved += mean(Dual(fiber0, improved).eval(f0.to_local(wo), f0.to_local(wl), l));
        l.beyond = hs::kUnbounded<double>;
        r.zinke += mean(Dual(fiber0, zinke).eval(f0.to_local(wo), f0.to_local(wl), l));

        const double L = path_radiance(s, mat, hit, wo, Lighting{wl, false}, rng);
        r.path += L;
        r.path_sq += L * L;
    }
    return r;
}

// Two-stream dual scattering at the arrival direction (dual/two_stream.hpp) against the same
// path tracer, under a directional light from wl or, with furnace, a uniform environment of
// radiance 1 (then a lossless slab's exact answer is 1 at every hit). At each first hit the
// estimator samples `arrivals` directions a from the fiber's sampler: an unobstructed a sees
// the source itself; an obstructed one gets D(a) = c_f L̃_f + c_b L̃_b, with the counts along a
// and -a either counted exactly on the slab's fibers (`exact`, what a renderer that counts
// its rays' hits knows) or drawn from Poisson distributions of the slab's expected counts
// (`expected`: what a renderer with a density grid does, poisson_fiber_count, conditioned on
// the ray along a being blocked). L̃ is the kernel at the light's
// direction, or under the environment one kernel sample of it.
struct TwoStreamSums {
    double path = 0, path_sq = 0, exact = 0, expected = 0;
    int hits = 0;
    double path_mean() const { return path / hits; }
    double path_noise() const {  // 2σ of the path mean
        const double m = path_mean();
        return 2 * std::sqrt(std::max(0.0, path_sq / hits - m * m) / hits);
    }
};

// Over any fiber model Fiber built from (material, h) that offers lobe_split (its tables'
// source), e.g. FurFiber<double>.
template <typename Fiber>
TwoStreamSums compare_two_stream(const typename Fiber::Material& mat, double tau, const Lighting& light, const dvec3& wo,
                                 int paths, int arrivals = 16, bool with_path = true,
                                 hs::DualStackTransport transport = hs::DualStackTransport::kTurned) {
    const auto tables = hs::DualScatteringTables<double>::template build<Fiber>(mat);
    const auto view = tables.view();
    const slab::FiberSlab s(400, 8 * tau, tau, 7);
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<double> U;
    const dvec3 axis(1, 0, 0);
    const double per_length = s.crossings_per_length();
    const auto expected_count = [&](const dvec3& p, const dvec3& d) {
        if (d.z == 0) return hs::kUnbounded<double>;
        const double t = d.z > 0 ? (s.depth() - p.z) / d.z : p.z / -d.z;
        return per_length * std::sqrt(d.y * d.y + d.z * d.z) * t;
    };
    TwoStreamSums r;
    for (int k = 0; k < paths; ++k) {
        const slab::Hit hit = s.intersect(dvec3(0, U(rng) * s.width(), wo.z > 0 ? s.depth() : 0.0), -wo);
        if (hit.fiber < 0) continue;
        ++r.hits;
        const hs::FiberFrame<double> f0(axis, wo);
        const Fiber fiber(mat, glm::dot(hit.p - hit.axis, f0.y));
        const auto bound = fiber.at(f0.to_local(wo));
        double exact = 0, expected = 0;
        if (!light.furnace && s.count(hit.p, light.wl, hit.fiber) == 0) {
            const double direct = mean(bound.eval(f0.to_local(light.wl)));
            exact += direct;
            expected += direct;
        }
        for (int j = 0; j < arrivals; ++j) {
            const auto smp = bound.sample(draw4(U, rng));
            if (!(smp.pdf > 0)) continue;
            const dvec3 a = glm::normalize(f0.to_world(smp.wi));
            const int n = s.count(hit.p, a, hit.fiber);
            if (n == 0) {  // unobstructed: the source itself (a directional light is never hit)
                if (light.furnace) {
                    exact += mean(smp.weight) / arrivals;
                    expected += mean(smp.weight) / arrivals;
                }
                continue;
            }
            const int m = s.count(hit.p, -a, hit.fiber);
            const hs::DualScatteringEntry<double> e = view.lookup(smp.wi.x);
            constexpr double slab_limit = hs::kSlabTurnLimit<double>;
            const hs::DualStreams<double> st[2] = {
                hs::dual_streams(e, double(n), double(m), slab_limit, slab_limit, transport),
                hs::dual_streams(e, hs::poisson_fiber_count(expected_count(hit.p, a), U(rng), true),
                                 hs::poisson_fiber_count(expected_count(hit.p, -a), U(rng), false), slab_limit, slab_limit,
                                 transport)};
            double* sums[2] = {&exact, &expected};
            const dvec4 u = draw4(U, rng);
            for (int c = 0; c < 2; ++c) {
                const hs::DualSourceKernel<double> kernel(smp.wi, st[c]);
                dvec3 source(0);
                if (light.furnace) {
                    const auto ks = kernel.sample(u);
                    if (ks.pdf > 0) source = kernel.eval(ks.s) / ks.pdf;
                } else {
                    source = kernel.eval(f0.to_local(light.wl));
                }
                *sums[c] += mean(smp.weight * source) / arrivals;
            }
        }
        r.exact += exact;
        r.expected += expected;
        if (!with_path) continue;

        const double L = path_radiance<Fiber>(s, mat, hit, wo, light, rng);
        r.path += L;
        r.path_sq += L * L;
    }
    return r;
}

// Over Chiang's fiber with these parameters.
inline TwoStreamSums compare_two_stream(const hs::FiberParams<double>& params, double tau, const Lighting& light,
                                        const dvec3& wo, int paths, int arrivals = 16, bool with_path = true,
                                        hs::DualStackTransport transport = hs::DualStackTransport::kTurned) {
    return compare_two_stream<hs::ChiangFiber<double>>(hs::ChiangMaterial<double>(params), tau, light, wo, paths,
                                                       arrivals, with_path, transport);
}

}  // namespace slab
