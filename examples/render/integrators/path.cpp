// render — a path tracer through fibers (any model) and Lambertian surfaces: the
// multiple-scattering reference. Unbiased: paths end by Russian roulette on the
// throughput only (a lossless fiber's throughput stays 1, so light hair is never cut
// short); max_depth is a safety cap so deep (4096 by default) that it never matters.
#include "integrator.hpp"

#include <algorithm>

namespace render {

namespace {

using glm::vec3;
namespace hs = hairscatter;

template <class MakeFiber> class PathIntegrator final : public PixelIntegrator {
  public:
    PathIntegrator(const RenderContext& c, MakeFiber make)
        : c_(c), make_(make), amplifies_(c.shading.options().fiber_extras.amplifies()) {}

    vec3 radiance(const vec3& camera, const vec3& dir, Sampler& rng) const override {
        return trace(camera, dir, kNoStrand, rng);
    }
    vec3 arrival(const Hit& hit, const vec3&, const vec3& a, Sampler& rng) const override {
        return trace(hit.p, a, hit.strand, rng);
    }

  private:
    // The radiance arriving at o from direction d (along −d), the strand `ignore` unseen
    // near o (the fiber o lies on).
    vec3 trace(const vec3& from, const vec3& dir, std::uint32_t ignore, Sampler& rng) const {
        const Scene& scene = c_.scene;
        const Lights& lights = c_.lights;
        const RenderOptions& opt = c_.options;
        const bool mis = opt.sampling == Sampling::kMis;
        vec3 o = from, d = dir, L(0), beta(1);
        float prev_pdf = 0;  // pdf of the direction that led here (0: camera, no MIS)
        for (int depth = 0; depth < opt.max_depth; ++depth) {
            const Hit hit = scene.intersect(o, d, kInf, ignore);
            if (hit.kind == Hit::kMiss) {
                const float w = mis && prev_pdf > 0 ? power_heuristic(prev_pdf, lights.pdf_env(d)) : 1.0f;
                L += beta * lights.env_radiance(d) * w;
                break;
            }
            if (hit.kind == Hit::kLight) {
                if (hit.front) {
                    const float w = mis && prev_pdf > 0 ? power_heuristic(prev_pdf, lights.pdf_area(d, hit.t)) : 1.0f;
                    L += beta * lights.area->radiance * w;
                }
                break;
            }
            if (hit.kind == Hit::kHair) {
                const ShadingPoint sp(hit, -d);
                const auto fiber = hairscatter_examples::bind_fiber(make_(sp.h(), sp.strand), sp.wo());
                // Lobe gains above 1 can make a fiber return more light than it receives, and
                // the sum over bounces then diverges. As in dual scattering (its tables and its
                // integrator), the fiber the camera sees keeps its gains and every other fiber
                // scatters at most what it receives: f / max(1, albedo(wo)) per channel.
                if (amplifies_ && depth > 0) beta /= glm::max(fiber.albedo(), vec3(1.0f));
                if (mis && lights.any()) {
                    const float u0 = rng.u(), u1 = rng.u(), u2 = rng.u();
                    const Lights::Sample ls = lights.sample(sp.p, u0, u1, u2);
                    if (ls.pdf > 0 && !scene.occluded(sp.p, ls.wi, ls.dist * kShadowShorten, sp.strand)) {
                        const auto ep = fiber.eval_pdf(sp.to_local(ls.wi));
                        L += beta * ep.f * ls.Le * power_heuristic(ls.pdf, ep.pdf) / ls.pdf;
                    }
                }
                const hs::HairSample<float> s = opt.sampling == Sampling::kUniform ? uniform(fiber, rng.u4())
                                                                                   : fiber.sample(rng.u4());
                if (!(s.pdf > 0)) break;
                beta *= s.weight;
                prev_pdf = s.pdf;
                o = sp.p;
                d = sp.to_world(s.wi);
                ignore = sp.strand;
            } else {  // Lambertian surface
                const vec3 x = hit.p + kSurfaceOffset * hit.n;
                if (mis && lights.any()) {
                    const float u0 = rng.u(), u1 = rng.u(), u2 = rng.u();
                    const Lights::Sample ls = lights.sample(hit.p, u0, u1, u2);
                    const float cos_i = glm::dot(hit.n, ls.wi);
                    if (ls.pdf > 0 && cos_i > 0 && !scene.occluded(x, ls.wi, ls.dist * kShadowShorten)) {
                        const float pdf_b = cos_i / kPi;
                        L += beta * hit.albedo * (cos_i / kPi) * ls.Le * power_heuristic(ls.pdf, pdf_b) / ls.pdf;
                    }
                }
                const float u1 = rng.u(), u2 = rng.u();
                d = cosine_hemisphere(hit.n, u1, u2);
                prev_pdf = std::max(glm::dot(hit.n, d), 0.0f) / kPi;
                if (!(prev_pdf > 0)) break;
                beta *= hit.albedo;  // f cos / pdf = albedo
                o = x;
                ignore = kNoStrand;
            }
            // Russian roulette on the throughput (after three bounces): a path survives with
            // probability q = min(1, max β) and carries β / q, so the estimate stays unbiased
            // and a path whose throughput has not fallen (lossless hair) is never ended.
            if (depth >= 3) {
                const float q = std::min(1.0f, max3(beta));
                if (q < 1) {
                    if (rng.u() >= q) break;
                    beta /= q;
                }
            }
            if (!finite3(beta)) break;
        }
        return L;
    }

    // Uniform directions on the sphere (the baseline of --sampling uniform).
    template <class Bound> static hs::HairSample<float> uniform(const Bound& fiber, const glm::vec4& u) {
        hs::HairSample<float> s;
        s.wi = uniform_sphere(u.y, u.z);
        s.pdf = 1.0f / (4 * kPi);
        s.weight = fiber.eval(s.wi) / s.pdf;
        s.lobe = hs::SampledLobe::kUniform;
        return s;
    }

    const RenderContext& c_;
    MakeFiber make_;
    bool amplifies_;
};

}  // namespace

std::unique_ptr<PixelIntegrator> make_path_integrator(const RenderContext& c) { return make_for_model<PathIntegrator>(c); }

}  // namespace render
