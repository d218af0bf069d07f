// render — dual scattering (Zinke et al. 2008) at the camera ray's first hair hit, with
// the library's tables, density grid and DualScatteringFiber over the Chiang fiber (dual
// scattering is Chiang-only here whatever --model says). Self-contained on purpose: the
// whole dual-scattering integrator is this file.
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
    // What the light arriving along wi from the hair point x looks like to dual scattering.
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
                in.Le = lights.env;
                in.light_pdf = lights.pdf_env();
                dist = kInf;
            } else {
                return in;
            }
        } else if (s.intersect_opaque(sp.p, wi, std::isfinite(dist) ? dist * kShadowShorten : kInf).kind != Hit::kMiss) {
            return in;
        }
        in.visible = true;
        in.state.d_f = c_.options.d_f;
        in.state.d_b = c_.options.d_b;
        // A shadow ray decides the direct fraction; only shadowed points read the density
        // grid for the number of fibers toward the light.
        if (s.hair_occluded(sp.p, wi, dist, sp.strand)) {
            in.state.direct_fraction = 0;
            in.state.n = c_.shading.grid()->fibers_crossed(sp.p, wi, std::isfinite(dist) ? dist : hs::kUnbounded<float>);
        } else {
            in.state.direct_fraction = 1;
            in.state.n = 0;
        }
        return in;
    }

    // Dual scattering at a hair hit: the estimator chosen by --sampling.
    vec3 hair(const ShadingPoint& sp, Sampler& rng) const {
        const Lights& lights = c_.lights;
        const RenderOptions& o = c_.options;
        if (!lights.any()) return vec3(0);
        const vec3& wo_l = sp.wo();
        const hs::ChiangFiber<float> fiber(c_.shading.chiang(), sp.h());
        const auto& tables = c_.shading.tables();
        auto shade = [&](const hs::DualScatteringLight<float>& st, const vec3& wi) {
            return hs::DualScatteringFiber<float>(fiber, tables, st).eval(wo_l, sp.to_local(wi));
        };

        // The sampling density: an equal mixture of the dual BCSDF as seen by a directly lit
        // point and as seen by a point in the hair's shadow (n toward the main light), since
        // which applies is only known once a direction is chosen. Both cover the sphere.
        hs::DualScatteringLight<float> lit, shadowed;
        lit.d_f = shadowed.d_f = o.d_f;
        lit.d_b = shadowed.d_b = o.d_b;
        shadowed.direct_fraction = 0;
        const vec3 toward = lights.area ? glm::normalize(lights.area->corner +
                                                         0.5f * (lights.area->edge_u + lights.area->edge_v) - sp.p)
                                        : vec3(0, 1, 0);
        // (uniform sampling needs no mixture: skip the march)
        if (o.sampling != Sampling::kUniform)
            shadowed.n = c_.shading.grid()->fibers_crossed(sp.p, toward, hs::kUnbounded<float>);
        const hs::DualScatteringFiber<float> f_lit(fiber, tables, lit), f_shadowed(fiber, tables, shadowed);
        auto bcsdf_pdf = [&](const vec3& wi_l) {
            if (o.sampling == Sampling::kUniform) return 1.0f / (4 * kPi);
            return 0.5f * f_lit.pdf(wo_l, wi_l) + 0.5f * f_shadowed.pdf(wo_l, wi_l);
        };

        vec3 L(0);
        if (o.sampling == Sampling::kMis) {
            const float u0 = rng.u(), u1 = rng.u(), u2 = rng.u();
            const Lights::Sample ls = lights.sample(sp.p, u0, u1, u2);
            if (ls.pdf > 0) {
                const Incoming in = incoming(sp, ls.wi, ls.dist);
                if (in.visible) {
                    const float w = power_heuristic(ls.pdf, bcsdf_pdf(sp.to_local(ls.wi)));
                    L += w * shade(in.state, ls.wi) * ls.Le / ls.pdf;
                }
            }
        }
        // One BCSDF (or uniform) sample.
        vec3 wi_l;
        float pdf;
        const vec4 u = rng.u4();
        if (o.sampling == Sampling::kUniform) {
            const hs::HairSample<float> s =
                hs::UniformSphereSampling<hs::DualScatteringFiber<float>>(f_lit).sample(wo_l, u);
            wi_l = s.wi;
            pdf = s.pdf;
        } else {
            const bool first = u.x < 0.5f;
            const vec4 v(first ? 2 * u.x : 2 * u.x - 1, u.y, u.z, u.w);
            const hs::HairSample<float> s = first ? f_lit.sample(wo_l, v) : f_shadowed.sample(wo_l, v);
            wi_l = s.wi;
            pdf = bcsdf_pdf(wi_l);
        }
        if (!(pdf > 0)) return L;
        const vec3 wi = sp.to_world(wi_l);
        const Incoming in = incoming(sp, wi, 0);
        if (!in.visible || max3(in.Le) <= 0) return L;
        const float w = o.sampling == Sampling::kMis ? power_heuristic(pdf, in.light_pdf) : 1.0f;
        L += w * shade(in.state, wi) * in.Le / pdf;
        return L;
    }

    const RenderContext& c_;
};

}  // namespace

std::unique_ptr<PixelIntegrator> make_dual_integrator(const RenderContext& c) {
    return std::make_unique<DualIntegrator>(c);
}

}  // namespace render
