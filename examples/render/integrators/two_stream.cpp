// render — dual scattering by the two-stream estimator at the arrival direction
// (hairscatter/dual/two_stream.hpp, docs/dual.md): hair-to-hair transport in closed form,
// everything else traced as the path tracer traces it.
//
// At a hair point: one light sample, which lights the fiber directly where no hair is in
// the way and is the light-sampled half of the source kernel's estimate; one arrival
// direction a from the fiber's own sampler, which sees the source itself where no hair is
// in the way, or else gets D(a) = c_f L̃_f + c_b L̃_b from the counts along a and beyond,
// with L̃ estimated by that light sample and one kernel sample (MIS) traced to whatever lies
// outside the hair. Surfaces are path-traced (next-event estimation and a cosine bounce)
// and the hair their bounces reach is shaded by this estimator again: light that the
// ground or a head reflects reaches the hair, and the hair's light reaches them. Every
// vertex continues one path at most, so the cost per sample is bounded by kMaxDepth.
// With traced vertices (ShadingOptions::traced_vertices, --dual-vertices N), a path's first
// N vertices are traced as the path tracer traces them and the estimator shades from there.
#include "integrator.hpp"
#include "local_plane.hpp"

#include <algorithm>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace render {

namespace {

namespace hs = hairscatter;
using glm::vec3;

class TwoStreamIntegrator final : public PixelIntegrator {
  public:
    explicit TwoStreamIntegrator(const RenderContext& c)
        : c_(c),
          tables_(c.shading.tables().view()),
          field_(c.shading.field() ? c.shading.field()->view() : hs::DirectionalCountFieldView<float>()),
          amplifies_(c.shading.options().fiber_extras.amplifies()) {
        const ShadingOptions& o = c.shading.options();
        if (o.glow_points > 0 && o.counts != DualCounts::kExact && c.shading.grid()) build_glow(o.glow_points);
    }

    vec3 radiance(const vec3& o, const vec3& d, Sampler& rng) const override {
        return at_hit(c_.scene.intersect(o, d, kInf), d, 0, 0.0f, rng);
    }
    // The light arriving at a hair hit along a as this integrator estimates it at a path's
    // first vertex: traced to the next hit when vertices are traced, else the two-stream
    // arrival (render::arrival_profile compares it with the path tracer's).
    vec3 arrival(const Hit& hit, const vec3& wo, const vec3& a, Sampler& rng) const override {
        if (c_.shading.options().traced_vertices > 0)
            return at_hit(c_.scene.intersect(hit.p, a, kInf, hit.strand), a, 1, 0.0f, rng);
        return arrival_uniform(ShadingPoint(hit, wo), a, rng);
    }

  private:
    // Hair and surface vertices a path may visit (Russian roulette ends most earlier).
    static constexpr int kMaxDepth = 8;

    static float mis(float chosen, float other) { return chosen > 0 ? power_heuristic(chosen, other) : 1.0f; }

    // The radiance leaving `hit` back along d. chosen_pdf: the density of the strategy that
    // chose d where light sampling could have chosen it too (0: nothing to weigh).
    vec3 at_hit(const Hit& hit, const vec3& d, int depth, float chosen_pdf, Sampler& rng) const {
        const Lights& lights = c_.lights;
        switch (hit.kind) {
            case Hit::kMiss: return lights.env_radiance(d) * mis(chosen_pdf, lights.pdf_env(d));
            case Hit::kLight:
                return hit.front ? lights.area->radiance * mis(chosen_pdf, lights.pdf_area(d, hit.t)) : vec3(0);
            case Hit::kSurface: return depth < kMaxDepth ? surface(hit, depth, rng) : vec3(0);
            case Hit::kHair: return depth < kMaxDepth ? hair(ShadingPoint(hit, -d), depth, rng) : vec3(0);
        }
        return vec3(0);
    }

    // A Lambertian surface: next-event estimation (hair casts shadows: the light that gets
    // through it arrives by the bounce, as the hair's own radiance) and a cosine bounce.
    vec3 surface(const Hit& hit, int depth, Sampler& rng) const {
        const Lights& lights = c_.lights;
        const vec3 x = hit.p + kSurfaceOffset * hit.n;
        vec3 L(0);
        if (lights.any()) {
            const float u0 = rng.u(), u1 = rng.u(), u2 = rng.u();
            const Lights::Sample ls = lights.sample(hit.p, u0, u1, u2);
            const float cos_i = glm::dot(hit.n, ls.wi);
            if (ls.pdf > 0 && cos_i > 0 && !c_.scene.occluded(x, ls.wi, ls.dist * kShadowShorten))
                L += hit.albedo * (cos_i / kPi) * ls.Le * power_heuristic(ls.pdf, cos_i / kPi) / ls.pdf;
        }
        // Russian roulette after two vertices, on the albedo (the throughput's factor here).
        const float q = depth < 2 ? 1.0f : std::min(1.0f, max3(hit.albedo));
        if (!(rng.u() < q)) return L;
        const float u1 = rng.u(), u2 = rng.u();
        const vec3 d = cosine_hemisphere(hit.n, u1, u2);
        const float pdf = std::max(glm::dot(hit.n, d), 0.0f) / kPi;
        if (!(pdf > 0)) return L;
        return L + hit.albedo / q * at_hit(c_.scene.intersect(x, d, kInf), d, depth + 1, pdf, rng);
    }

    // A stack of fibers along d from o: how many, and how far along d they end.
    struct Stack {
        float n = 0, end = 0;
    };

    // The distance along d from o to where the density source's box ends (0 outside it).
    template <class View> static float box_distance(const View& v, const vec3& o, const vec3& d) {
        float t0 = 0, t1 = kInf;
        for (int k = 0; k < 3; ++k) {
            const float inv = 1.0f / d[k];
            float a = (v.box_min()[k] - o[k]) * inv, b = (v.box_max()[k] - o[k]) * inv;
            if (a > b) std::swap(a, b);
            if (!(a == a) || !(b == b)) continue;  // d[k] = 0 with o on a face: no bound from this axis
            t0 = std::max(t0, a), t1 = std::min(t1, b);
        }
        return t1 > t0 ? t1 : 0.0f;
    }

    // The fibers along d from o up to `tmax` (kInf: unbounded): counted on the hair up to
    // `limit` (past which the stacks no longer change); a Poisson draw from the grid's
    // expectation given that a ray found hair; or a Poisson draw from the count field's
    // expectation (a lookup). found_hair: a ray along d already found hair, so the count is at
    // least 1 (without it, grid counts cast that ray themselves). With want_end, where the stack ends:
    // the last fiber's hit (exact counts) or where less than half a fiber remains expected
    // (hs::dual_stack_end on the grid or the field).
    Stack fibers(const vec3& o, const vec3& d, float tmax, std::uint32_t ignore, std::uint32_t limit, bool found_hair,
                 bool want_end, Sampler& rng) const {
        const float bound = std::isfinite(tmax) ? tmax : hs::kUnbounded<float>;
        Stack st;
        switch (c_.shading.options().counts) {
            case DualCounts::kExact:
                st.n = float(c_.scene.count_hair(o, d, tmax, ignore, limit, want_end ? &st.end : nullptr));
                return st;
            case DualCounts::kGrid: {
                const float u = rng.u();
                if (!found_hair && !c_.scene.hair_occluded(o, d, tmax, ignore)) return st;
                const hs::DensityGridView<float> grid = c_.shading.grid()->view();
                st.n = hs::poisson_fiber_count(grid.fibers_crossed(o, d, bound), u, true);
                if (want_end && st.n > 0) st.end = stack_end(o, d, tmax);
                return st;
            }
            case DualCounts::kField:
                st.n = hs::poisson_fiber_count(field_.fibers_crossed(o, d, bound), rng.u(), found_hair);
                if (want_end && st.n > 0) st.end = stack_end(o, d, tmax);
                return st;
        }
        return st;
    }

    // Where the grid's or the field's expected fibers along d from o end (up to tmax).
    float stack_end(const vec3& o, const vec3& d, float tmax) const {
        if (c_.shading.options().counts == DualCounts::kField)
            return field_.stack_end(o, d, std::isfinite(tmax) ? tmax : hs::kUnbounded<float>);
        const hs::DensityGridView<float> grid = c_.shading.grid()->view();
        return hs::dual_stack_end(grid, o, d, std::min(tmax, box_distance(grid, o, d)));
    }

    // Exact counts stop past a depth where T_N < 1e-3 and R_N is within 1e-3 of R_∞ (more
    // fibers change nothing); grid and field counts cost the same at any depth.
    std::uint32_t count_limit(const hs::DualScatteringEntry<float>& entry) const {
        return c_.shading.options().counts == DualCounts::kExact
                   ? std::uint32_t(std::ceil(hs::dual_count_limit(entry, 1e-3f)))
                   : 0xffffffffu;
    }

    // The stack beyond a face along s (hs::dual_source_stack): what it transmits of L(s) and
    // reflects of the light on the face's own side: the fibers from the face `from` along s,
    // up to the first surface at t_surface from the shading point p (kInf: none).
    hs::DualSourceStack<float> source_stack(const vec3& from, const vec3& p, const vec3& s, const vec3& s_local,
                                            float t_surface, Sampler& rng) const {
        const float tmax = std::isfinite(t_surface) ? std::max(t_surface - glm::dot(from - p, s), 0.0f) : kInf;
        if (!(tmax > 0)) return {};
        const hs::DualScatteringEntry<float> entry = entry_at(s_local.x);
        const Stack k = fibers(from, s, tmax, kNoStrand, count_limit(entry), false, false, rng);
        return hs::dual_source_stack(entry, k.n);
    }

    // The tables' entry for a stack along a direction whose sin θ in the fiber's frame is
    // sin_theta: by default (--dual-stacks inclined) the entry whose layers return only the
    // share of the backscatter that travels back along the stack (hs::dual_stack_entry), or
    // with --dual-stacks planar the 1D stack's (every backward event returns).
    hs::DualScatteringEntry<float> entry_at(float sin_theta) const {
        const hs::DualScatteringEntry<float> e = tables_.lookup(sin_theta);
        return c_.shading.options().inclined_stacks ? hs::dual_stack_entry(e) : e;
    }

    // The hair's mean radiance around x (trilinear between the grid's cell centres, over the
    // cells that hold hair points), or −1 where none is held.
    vec3 glow(const vec3& x) const {
        if (glow_.empty()) return vec3(-1);
        const vec3 q = (x - glow_lo_) / glow_cell_ - 0.5f;
        const glm::ivec3 i0 = glm::ivec3(glm::floor(q));
        const vec3 f = q - vec3(i0);
        vec3 sum(0);
        float w = 0;
        for (int c = 0; c < 8; ++c) {
            const glm::ivec3 i = glm::clamp(i0 + glm::ivec3(c & 1, (c >> 1) & 1, c >> 2), glm::ivec3(0), glow_res_ - 1);
            const float wc = ((c & 1) ? f.x : 1 - f.x) * ((c & 2) ? f.y : 1 - f.y) * ((c & 4) ? f.z : 1 - f.z);
            const std::size_t k = glow_index(i);
            if (glow_n_[k] > 0) sum += wc * glow_[k], w += wc;
        }
        return w > 1e-3f ? sum / w : vec3(-1);
    }

    std::size_t glow_index(const glm::ivec3& i) const {
        return std::size_t(i.x) + std::size_t(glow_res_.x) * (std::size_t(i.y) + std::size_t(glow_res_.y) * std::size_t(i.z));
    }

    // The glow volume: per cell of the density grid, the mean radiance arriving at hair
    // points in it, over uniform directions (the fluence over 4π). Random rays from random
    // points of the hair's box find the points, `per_cell` rays per cell on average; at each,
    // one uniform direction's arrival by this estimator (with the hair along source
    // directions read as before: no glow yet). The lights must not move after it is built:
    // the renderer builds it with the integrator, for each render.
    void build_glow(int per_cell) {
        const hs::DensityGridView<float> g = c_.shading.grid()->view();
        glow_res_ = g.resolution();
        glow_lo_ = g.box_min();
        const vec3 extent = g.box_max() - g.box_min();
        glow_cell_ = extent / vec3(glow_res_);
        const std::size_t cells = std::size_t(glow_res_.x) * std::size_t(glow_res_.y) * std::size_t(glow_res_.z);
        constexpr std::size_t kChunk = 4096;
        const std::size_t chunks = (cells * std::size_t(per_cell) + kChunk - 1) / kChunk;
        std::vector<std::vector<std::pair<std::size_t, vec3>>> parts(chunks);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t ci = r.begin(); ci != r.end(); ++ci) {
                Pcg32 pcg(0x9107u + ci, ci);
                Sampler rng{pcg};
                for (std::size_t k = 0; k < kChunk; ++k) {
                    const vec3 o = glow_lo_ + vec3(rng.u(), rng.u(), rng.u()) * extent;
                    const vec3 d = uniform_sphere(rng.u(), rng.u());
                    const vec3 a = uniform_sphere(rng.u(), rng.u());
                    const Hit hit = c_.scene.intersect(o, d, kInf);
                    if (hit.kind != Hit::kHair) continue;
                    const glm::ivec3 cell = glm::ivec3(glm::floor((hit.p - glow_lo_) / glow_cell_));
                    if (glm::any(glm::lessThan(cell, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(cell, glow_res_)))
                        continue;
                    const vec3 L = arrival_uniform(ShadingPoint(hit, -d), a, rng);
                    if (std::isfinite(L.x) && std::isfinite(L.y) && std::isfinite(L.z))
                        parts[ci].push_back({glow_index(cell), L});
                }
            }
        });
        std::vector<vec3> sum(cells, vec3(0));
        std::vector<std::uint32_t> n(cells, 0);
        for (const auto& part : parts)
            for (const auto& [k, L] : part) sum[k] += L, ++n[k];
        // Each cell's value from its 3 × 3 × 3 neighbourhood's points: the light around hair
        // varies over several cells, and a few points per cell would leave their noise in
        // the image as a fixed pattern. A plane fitted to the neighbours' means (LocalPlane),
        // read at the cell's centre, rather than their mean: at a lit face the outer
        // neighbours hold no hair and the inner ones are darker, so a mean reads the face's
        // hair as deeper hair (the dense blond block of 12,000 strands 2 points too dark),
        // where the plane follows the light's slope. Exact in a furnace (all means equal).
        std::vector<vec3> mean(cells, vec3(0));
        std::vector<std::uint32_t> points(cells, 0);
        for (int z = 0; z < glow_res_.z; ++z)
            for (int y = 0; y < glow_res_.y; ++y)
                for (int x = 0; x < glow_res_.x; ++x) {
                    const std::size_t k = glow_index(glm::ivec3(x, y, z));
                    if (n[k] == 0) continue;  // no hair here: nothing to read
                    LocalPlane plane;
                    for (int dz = -1; dz <= 1; ++dz)
                        for (int dy = -1; dy <= 1; ++dy)
                            for (int dx = -1; dx <= 1; ++dx) {
                                const glm::ivec3 j(x + dx, y + dy, z + dz);
                                if (glm::any(glm::lessThan(j, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(j, glow_res_)))
                                    continue;
                                const std::size_t i = glow_index(j);
                                if (n[i] > 0) plane.add(glm::dvec3(dx, dy, dz), glm::dvec3(sum[i]) / double(n[i]), n[i]);
                            }
                    mean[k] = vec3(plane.at_centre());
                    points[k] = plane.points();
                }
        glow_ = std::move(mean);
        glow_n_ = std::move(points);
    }

    // The light arriving at sp along a, with nothing to weigh it against (a uniform direction).
    vec3 arrival_uniform(const ShadingPoint& sp, const vec3& a, Sampler& rng) const {
        const Scene& scene = c_.scene;
        const Hit source = scene.intersect_opaque(sp.p, a, kInf);
        const float t_source = source.kind == Hit::kMiss ? kInf : source.t;
        if (!scene.hair_occluded(sp.p, a, t_source, sp.strand)) return at_hit(source, a, 1, 0.0f, rng);
        Lights::Sample ls;
        bool open = false;
        if (c_.lights.any()) {
            const float u0 = rng.u(), u1 = rng.u(), u2 = rng.u();
            ls = c_.lights.sample(sp.p, u0, u1, u2);
            if (ls.pdf > 0) {
                const float tmax = std::isfinite(ls.dist) ? ls.dist * kShadowShorten : kInf;
                open = scene.intersect_opaque(sp.p, ls.wi, tmax).kind == Hit::kMiss;
            }
        }
        return blocked_arrival(sp, a, sp.to_local(a), source, t_source, ls, open, 0, 0.0f, rng);
    }

    // The fiber the tables were built from: fur's with --model fur, else Chiang's.
    vec3 hair(const ShadingPoint& sp, int depth, Sampler& rng) const {
        if (const hs::FurMaterial<float>* fur = c_.shading.models().fur())
            return hair_of(sp, hs::FurFiber<float>(*fur, sp.h()).at(sp.wo()), depth, rng);
        return hair_of(sp, hs::ChiangFiber<float>(c_.shading.models().chiang(sp.strand), sp.h()).at(sp.wo()), depth, rng);
    }

    template <class Bound> vec3 hair_of(const ShadingPoint& sp, const Bound& bound, int depth, Sampler& rng) const {
        // Lobe gains above 1: the fiber the camera sees keeps them, any other scatters at most
        // what it receives (as the tables' fibers do; path.cpp).
        const vec3 cap = amplifies_ && depth > 0 ? 1.0f / glm::max(bound.albedo(), vec3(1.0f)) : vec3(1.0f);
        return cap * hair_unscaled(sp, bound, depth, rng);
    }

    template <class Bound> vec3 hair_unscaled(const ShadingPoint& sp, const Bound& bound, int depth, Sampler& rng) const {
        const Scene& scene = c_.scene;
        const Lights& lights = c_.lights;
        vec3 L(0);

        // One light sample: `open` when no surface is in its way (the kernel's half),
        // direct light when no hair is either.
        Lights::Sample ls;
        bool open = false;
        if (lights.any()) {
            const float u0 = rng.u(), u1 = rng.u(), u2 = rng.u();
            ls = lights.sample(sp.p, u0, u1, u2);
            if (ls.pdf > 0) {
                const float tmax = std::isfinite(ls.dist) ? ls.dist * kShadowShorten : kInf;
                // One shadow ray through everything, as single scattering casts; only when it
                // is blocked does a ray through the surfaces alone say whether hair blocked it.
                if (!scene.occluded(sp.p, ls.wi, tmax, sp.strand)) {
                    open = true;
                    const auto ep = bound.eval_pdf(sp.to_local(ls.wi));
                    L += ep.f * ls.Le * power_heuristic(ls.pdf, ep.pdf) / ls.pdf;
                } else if (depth >= c_.shading.options().traced_vertices) {
                    // (Only the estimator reads `open`: a traced vertex does not.)
                    open = scene.intersect_opaque(sp.p, ls.wi, tmax).kind == Hit::kMiss;
                }
            }
        }

        // One arrival direction from the fiber's sampler. Along it, the first surface (a ray
        // through the surfaces alone: the source, and the counts' bound) and whether any hair
        // lies before it (an any-hit ray through the hair alone, cheaper than a closest hit
        // through both): where none does, the direction is open and sees the source itself;
        // else the fibers are counted or looked up (a blocked ray has at least one fiber). The
        // hair ray sees the hair as the light sample's shadow ray does, so that the two halves
        // of the direct light see the same hair.
        const hs::HairSample<float> s = bound.sample(rng.u4());
        if (!(s.pdf > 0)) return L;
        const vec3 a = sp.to_world(s.wi);
        // The path's first vertices traced as the path tracer traces them (the light sample
        // above is their next-event estimate): the two-stream estimate starts past them.
        if (depth < c_.shading.options().traced_vertices)
            return L + s.weight * at_hit(scene.intersect(sp.p, a, kInf, sp.strand), a, depth + 1, s.pdf, rng);
        const Hit source = scene.intersect_opaque(sp.p, a, kInf);
        const float t_source = source.kind == Hit::kMiss ? kInf : source.t;
        if (!scene.hair_occluded(sp.p, a, t_source, sp.strand))
            return L + s.weight * at_hit(source, a, depth + 1, s.pdf, rng);
        return L + s.weight * blocked_arrival(sp, a, s.wi, source, t_source, ls, open, depth, s.pdf, rng);
    }

    // The light arriving at sp along a (a_local in its frame), where a ray along a found hair
    // before the first surface (`source`, at t_source): the two streams of the stacks along ±a
    // with their sources estimated by the light sample ls (open: no surface in its way) and one
    // kernel sample. chosen_pdf: the density a was chosen with, for MIS where a turns out open.
    vec3 blocked_arrival(const ShadingPoint& sp, const vec3& a, const vec3& a_local, const Hit& source, float t_source,
                         const Lights::Sample& ls, bool open, int depth, float chosen_pdf, Sampler& rng) const {
        const Scene& scene = c_.scene;
        const hs::DualScatteringEntry<float> entry = entry_at(a_local.x);
        const std::uint32_t limit = count_limit(entry);
        const bool beyond = c_.shading.options().source == DualSource::kBeyondExit;
        const bool exact = c_.shading.options().counts == DualCounts::kExact;
        const Stack n = fibers(sp.p, a, t_source, sp.strand, limit, true, beyond, rng);
        if (n.n == 0) return at_hit(source, a, depth + 1, chosen_pdf, rng);

        // Behind the point, along −a, the same two rays: hair before the first surface, or no
        // fibers there. (With field counts this matters beyond the rays' cost: the field
        // spreads the hair's faces over a lattice spacing, so at a point on a face a lookup
        // alone expects about half a fiber outside it, and a fiber drawn there takes T_m of the
        // light the face's own side sends back in: dense blond blocks and the scalp were 7–11 %
        // too dark; docs/dual.md.) The far stack's end is found only when a source direction
        // needs it (exact counts find it with the count, at no extra cost).
        const Hit behind = scene.intersect_opaque(sp.p, -a, kInf);
        const float t_behind = behind.kind == Hit::kMiss ? kInf : behind.t;
        Stack m;
        if (scene.hair_occluded(sp.p, -a, t_behind, sp.strand))
            m = fibers(sp.p, -a, t_behind, sp.strand, limit, true, beyond && exact, rng);
        bool m_end_known = !beyond || exact || m.n == 0;
        // How many fibers turning light crosses per fiber of the stacks: a slab's 2/π in the
        // limit, or what the hair's shape around the point gives (hs::dual_turn_limit).
        const ShadingOptions& opt = c_.shading.options();
        float limit_n = hs::kSlabTurnLimit<float>, limit_m = hs::kSlabTurnLimit<float>;
        if (opt.shape_depth) {
            const vec3 axis = sp.to_world(vec3(1, 0, 0));
            const auto shape_limit = [&](const vec3& d) {
                if (opt.counts == DualCounts::kField)
                    return hs::dual_turn_limit(field_, sp.p, axis, d, hs::kUnbounded<float>);
                // Grid counts, and exact counts too: the limit is the hair's expected shape
                // (one ray's integer count along a turned direction sees the gaps between
                // fibers, and made the back-lit blond slab ten deep +100 %).
                // Every turned direction is marched to where it leaves the grid's box: a bound
                // measured along d would cut the turned directions short (they cross more
                // of the hair than d does) and read a thin layer as one light leaves sideways.
                return hs::dual_turn_limit(c_.shading.grid()->view(), sp.p, axis, d, hs::kUnbounded<float>);
            };
            if (n.n > 1) limit_n = shape_limit(a);
            if (m.n > 1) limit_m = shape_limit(-a);
        }
        // Curly hair: the kernels widen by the misalignment of the hair around the point.
        const float misalignment =
            opt.misaligned_kernels && c_.shading.grid()
                ? hs::dual_misalignment(c_.shading.grid()->view().tensor_density(sp.p), sp.to_world(vec3(1, 0, 0)))
                : 0.0f;
        const hs::DualSourceKernel<float> kernel(
            a_local, hs::dual_streams(entry, n.n, m.n, limit_n, limit_m, opt.transport, misalignment));
        // Sources beyond the exits (the default): light from s enters the stack on a's side
        // past its last fiber (K_f's half-circle) and the far stack past its own (K_b's),
        // through whatever hair lies there along s (docs/theory.md §5.7). With the glow
        // volume, hair along s is read as lit hair (hs::dual_source_hair), and where no fiber
        // lies behind the point its own side's hair along s is counted too.
        const float r = c_.scene.description().hair.radius;
        const bool lit_hair = opt.glow_points > 0 && !exact;
        struct Source {
            hs::DualSourceStack<float> st;
            vec3 face{0};
        };
        const auto source_of = [&](const vec3& d, const vec3& d_local, float t_surface) {
            Source src;
            if (!beyond) return src;
            const bool forward = a_local.y * d_local.y + a_local.z * d_local.z > 0;  // K_f's half-circle
            if (forward) {
                src.face = sp.p + a * (n.end + 2 * r);
            } else if (m.n == 0) {  // nothing beyond the point on that side
                src.face = sp.p;
                if (!lit_hair) return src;
                // Whether hair lies along d is a ray (the field spreads the faces; §5.8).
                const float tmax = std::isfinite(t_surface) ? t_surface : kInf;
                if (!c_.scene.hair_occluded(sp.p, d, tmax, sp.strand)) return src;
                const hs::DualScatteringEntry<float> e = entry_at(d_local.x);
                src.st = hs::dual_source_stack(e, fibers(sp.p, d, tmax, sp.strand, count_limit(e), true, false, rng).n);
                return src;
            } else {
                if (!m_end_known) {
                    m.end = stack_end(sp.p, -a, t_behind);
                    m_end_known = true;
                }
                src.face = sp.p - a * (m.end + 2 * r);
            }
            src.st = source_stack(src.face, sp.p, d, d_local, t_surface, rng);
            return src;
        };
        // With a glow around the face, the light sample estimates the transmitted part t L(s)
        // alone and the kernel's sample adds the lit hair's h L̄ (a term of its own, without
        // MIS); without one, both estimate (t + r) L(s).
        vec3 source_light(0);
        if (open) {
            const vec3 dl = sp.to_local(ls.wi);
            const auto kl = kernel.eval_pdf(dl);
            if (kl.pdf > 0) {
                const Source src = source_of(ls.wi, dl, ls.dist);
                const vec3 g = glow(src.face).x >= 0 ? src.st.t : src.st.t + src.st.r;
                source_light += kl.f * g * ls.Le * power_heuristic(ls.pdf, kl.pdf) / ls.pdf;
            }
        }
        const auto ks = kernel.sample(rng.u4());
        if (ks.pdf > 0) {
            const vec3 d = sp.to_world(ks.s);
            const Hit h = scene.intersect_opaque(sp.p, d, kInf);
            const Source src = source_of(d, ks.s, h.kind == Hit::kMiss ? kInf : h.t);
            const vec3 around = glow(src.face);
            const vec3 L = at_hit(h, d, depth + 1, ks.pdf, rng);
            if (around.x >= 0)
                source_light += ks.f / ks.pdf * (src.st.t * L + hs::dual_source_hair(tables_.lookup(ks.s.x), src.st) * around);
            else
                source_light += ks.f / ks.pdf * (src.st.t + src.st.r) * L;
        }
        return source_light;
    }

    const RenderContext& c_;
    hs::DualTablesView<float> tables_;
    hs::DirectionalCountFieldView<float> field_;
    bool amplifies_;
    std::vector<vec3> glow_;               // the hair's mean radiance per grid cell (empty: none)
    std::vector<std::uint32_t> glow_n_;    // hair points behind each cell's mean
    glm::ivec3 glow_res_{0};
    vec3 glow_lo_{0}, glow_cell_{1};
};

}  // namespace

std::unique_ptr<PixelIntegrator> make_two_stream_integrator(const RenderContext& c) {
    return std::make_unique<TwoStreamIntegrator>(c);
}

}  // namespace render
