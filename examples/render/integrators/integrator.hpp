// render — what every integrator shares: the render context (scene, shading setup,
// options, lights), the per-camera-ray interface, and direct lighting of diffuse surfaces
// and of the camera ray's first hit (single and dual scattering).
#pragma once

#include <limits>
#include <memory>

#include <glm/glm.hpp>

#include "../lights.hpp"
#include "../render.hpp"
#include "../sampling.hpp"
#include "../scene.hpp"
#include "../shading.hpp"

namespace render {

struct RenderContext {
    const Scene& scene;
    const ShadingSetup& shading;
    const RenderOptions& options;
    Lights lights;

    RenderContext(const Scene& s, const ShadingSetup& sh, const RenderOptions& o)
        : scene(s), shading(sh), options(o), lights(s.description()) {}
};

// Radiance along one camera ray.
class PixelIntegrator {
  public:
    virtual ~PixelIntegrator() = default;
    virtual glm::vec3 radiance(const glm::vec3& o, const glm::vec3& d, Sampler& rng) const = 0;
    // The light arriving at a hair hit along a (world), seen from wo (the direction back
    // toward where the hit was seen from): for integrators that can say (the path tracer and
    // the two-stream estimator), else NaN. For diagnostics (render::arrival_profile).
    virtual glm::vec3 arrival(const Hit& hit, const glm::vec3& wo, const glm::vec3& a, Sampler& rng) const {
        (void)hit, (void)wo, (void)a, (void)rng;
        return glm::vec3(std::numeric_limits<float>::quiet_NaN());
    }
};

std::unique_ptr<PixelIntegrator> make_single_integrator(const RenderContext& c);  // single.cpp
// dual.cpp: the two-stream estimator (two_stream.cpp) or the dual-scattering BCSDF, as the
// shading setup says.
std::unique_ptr<PixelIntegrator> make_dual_integrator(const RenderContext& c);
std::unique_ptr<PixelIntegrator> make_two_stream_integrator(const RenderContext& c);  // two_stream.cpp
std::unique_ptr<PixelIntegrator> make_path_integrator(const RenderContext& c);    // path.cpp

// An integrator templated on the fiber model (Integrator<MakeFiber>(context, make)), for
// the model the shading setup chose: one instantiation per model, chosen once.
template <template <class> class Integrator>
std::unique_ptr<PixelIntegrator> make_for_model(const RenderContext& c) {
    return c.shading.models().visit([&](auto make) -> std::unique_ptr<PixelIntegrator> {
        return std::make_unique<Integrator<decltype(make)>>(c, make);
    });
}

// Lambertian surface: one sample of the area light and one cosine-distributed sample of
// the environment (a map adds one of its own samples, with MIS); everything (hair
// included) casts opaque shadows.
glm::vec3 surface_direct(const RenderContext& c, const Hit& hit, Sampler& rng);

// The camera ray's first hit lit directly; hair is shaded by hair(point, rng).
template <class HairShade>
glm::vec3 first_hit_direct(const RenderContext& c, const glm::vec3& o, const glm::vec3& d, Sampler& rng,
                           const HairShade& hair) {
    const Hit hit = c.scene.intersect(o, d, kInf);
    switch (hit.kind) {
        case Hit::kMiss: return c.lights.env_radiance(d);
        case Hit::kLight: return hit.front ? c.lights.area->radiance : glm::vec3(0);
        case Hit::kSurface: return surface_direct(c, hit, rng);
        case Hit::kHair: return hair(ShadingPoint(hit, -d), rng);
    }
    return glm::vec3(0);
}

}  // namespace render
