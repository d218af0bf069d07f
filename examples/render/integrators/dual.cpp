// render — dual scattering with the dual-scattering BCSDF (--dual improved | zinke; the
// default two-stream estimator is two_stream.cpp) at the camera ray's first hair hit: the
// library's tables, density grid and DualScatteringBcsdf over the fiber the tables were built
// from: the fur fibre with --model fur, Chiang's otherwise. Self-contained on purpose: the
// whole dual-scattering integrator is this file.
//
// Per hit: the BCSDF bound to wo once (at), sampled without knowing the light state; per
// light direction: a shadow ray for the direct fraction and two density queries, toward
// the light (n) and beyond the point along the light's direction of travel (m).
#include "integrator.hpp"

namespace render {

namespace {

namespace hs = hairscatter;
using glm::vec3;
using glm::vec4;

class DualIntegrator final : public PixelIntegrator {
  public:
    explicit DualIntegrator(const RenderContext& c) : c_(c) {}

    vec3 radiance(const vec3& o, const vec3& d, Sampler& rng) const override {
        return first_hit_direct(c_, o, d, rng, [this](const ShadingPoint& sp, Sampler& r) { return hair(sp, r); });
    }

  private:
    // What the light arriving along wi at the hair point looks like to dual scattering.
    struct Incoming {
        bool visible = false;  // no wall, ground or sphere in the way
        vec3 Le{0};
        float light_pdf = 0;  // the pdf with which the light sampler picks wi (for MIS)
        hs::DualScatteringLight<float> state;
    };
    // dist: the light sample's distance, or 0 for a direction from the BCSDF sampler (then
    // the light it reaches, if any, is found here).
    Incoming incoming(const ShadingPoint& sp, const vec3& wi, float dist) const {
        const Scene& s = c_.scene;
        const Lights& lights = c_.lights;
        Incoming in;
        if (dist == 0) {
            const Hit o = s.intersect_opaque(sp.p, wi, kInf);
            if (o.kind == Hit::kLight && o.front) {
                in.Le = lights.area->radiance;
                in.light_pdf = lights.pdf_area(wi, o.t);
                dist = o.t;
            } else if (o.kind == Hit::kMiss) {
                in.Le = lights.env_radiance(wi);
                in.light_pdf = lights.pdf_env(wi);
                dist = kInf;
            } else {
                return in;
            }
        } else if (s.intersect_opaque(sp.p, wi, std::isfinite(dist) ? dist * kShadowShorten : kInf).kind != Hit::kMiss) {
            return in;
        }
        in.visible = true;
        // A shadow ray decides the direct fraction; only shadowed points need the count
        // toward the light. The improved formulation also asks how much hair lies beyond
        // the point along the light's direction of travel (a lit point seen from the far
        // side reads only f_s: no query).
        const float direct = s.hair_occluded(sp.p, wi, dist, sp.strand) ? 0.0f : 1.0f;
        const bool forward = std::abs(hs::relative_azimuth(sp.wo(), sp.to_local(wi))) > 0.5f * kPi;
        const bool beyond = c_.shading.tables().settings().formulation == hs::DualFormulation::kImproved &&
                            !(direct == 1 && forward);
        in.state = hs::dual_light(*c_.shading.grid(), sp.p, wi, direct,
                                  std::isfinite(dist) ? dist : hs::kUnbounded<float>, beyond);
        return in;
    }

    // Dual scattering at a hair hit over the tables' fiber: the estimator chosen by --sampling.
    vec3 hair(const ShadingPoint& sp, Sampler& rng) const {
        if (!c_.lights.any()) return vec3(0);
        if (const hs::FurMaterial<float>* fur = c_.shading.models().fur())
            return hair_with(sp, hs::FurFiber<float>(*fur, sp.h()), rng);
        return hair_with(sp, hs::ChiangFiber<float>(c_.shading.models().chiang(sp.strand), sp.h()), rng);
    }

    template <class Fiber> vec3 hair_with(const ShadingPoint& sp, const Fiber& fiber, Sampler& rng) const {
        using Dual = hs::DualScatteringBcsdf<Fiber>;
        const Lights& lights = c_.lights;
        const RenderOptions& o = c_.options;
        const Dual dual(fiber, c_.shading.tables());
        const bool uniform = o.sampling == Sampling::kUniform;

        // With MIS the light sample comes first: what its shadow ray and density query found
        // is the sampler's hint for the forward spread of the light (it widens the global
        // lobes; the sampler never needs the state of the direction it draws).
        Incoming light_in;
        Lights::Sample ls;
        if (o.sampling == Sampling::kMis) {
            const float u0 = rng.u(), u1 = rng.u(), u2 = rng.u();
            ls = lights.sample(sp.p, u0, u1, u2);
            if (ls.pdf > 0) light_in = incoming(sp, ls.wi, ls.dist);
        }
        float spread = 0;
        if (light_in.visible && light_in.state.direct_fraction < 1) {
            const auto e = c_.shading.tables().view().lookup(sp.to_local(ls.wi).x);
            spread = hs::dual_forward(light_in.state, e, c_.shading.tables().settings().formulation).spread;
        }
        const typename Dual::At at = dual.at(sp.wo(), spread);
        auto bcsdf_pdf = [&](const vec3& wi_l) { return uniform ? 0.25f / kPi : at.pdf(wi_l); };
        auto shade = [&](const Incoming& in, const vec3& wi) { return at.eval(sp.to_local(wi), in.state); };

        vec3 L(0);
        if (light_in.visible) {
            const float w = power_heuristic(ls.pdf, bcsdf_pdf(sp.to_local(ls.wi)));
            L += w * shade(light_in, ls.wi) * ls.Le / ls.pdf;
        }
        // One BCSDF (or uniform) sample: chosen before the light state is known.
        const vec4 u = rng.u4();
        const hs::DualSample<float> s = uniform ? hs::uniform_sphere_sample(u.y, u.z) : at.sample(u);
        if (!(s.pdf > 0)) return L;
        const vec3 wi = sp.to_world(s.wi);
        const Incoming in = incoming(sp, wi, 0);
        if (!in.visible || max3(in.Le) <= 0) return L;
        const float w = o.sampling == Sampling::kMis ? power_heuristic(s.pdf, in.light_pdf) : 1.0f;
        L += w * shade(in, wi) * in.Le / s.pdf;
        return L;
    }

    const RenderContext& c_;
};

}  // namespace

std::unique_ptr<PixelIntegrator> make_dual_integrator(const RenderContext& c) {
    if (c.shading.options().two_stream) return make_two_stream_integrator(c);
    return std::make_unique<DualIntegrator>(c);
}

}  // namespace render
