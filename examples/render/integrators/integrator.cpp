// render — direct lighting of diffuse surfaces, shared by the integrators.
#include "integrator.hpp"

namespace render {

glm::vec3 surface_direct(const RenderContext& c, const Hit& hit, Sampler& rng) {
    const Lights& lights = c.lights;
    const float u1 = rng.u(), u2 = rng.u(), u3 = rng.u(), u4 = rng.u();
    const glm::vec3 x = hit.p + kSurfaceOffset * hit.n;
    glm::vec3 L(0);
    if (lights.area) {
        // sample() with u0 = 0 picks the area light; its pdf includes the selection p_area.
        const Lights::Sample ls = lights.sample(hit.p, 0.0f, u1, u2);
        const float cos_i = glm::dot(hit.n, ls.wi);
        if (ls.pdf > 0 && cos_i > 0 && !c.scene.occluded(x, ls.wi, ls.dist * kShadowShorten))
            L += hit.albedo * (cos_i / kPi) * ls.Le * lights.p_area / ls.pdf;
    }
    if (max3(lights.env) > 0 && !c.scene.occluded(x, cosine_hemisphere(hit.n, u3, u4), kInf))
        L += hit.albedo * lights.env;  // f cos / pdf = albedo
    return L;
}

}  // namespace render
