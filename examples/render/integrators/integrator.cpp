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
    if (!lights.has_env()) return L;
    const Environment& env = *lights.env;
    const glm::vec3 d = cosine_hemisphere(hit.n, u3, u4);
    if (env.constant()) {
        if (!c.scene.occluded(x, d, kInf)) L += hit.albedo * env.radiance(d);  // f cos / pdf = albedo
        return L;
    }
    // A map: its own sample and the cosine sample, weighed by the power heuristic (a
    // softbox is too small a target for the cosine alone).
    const float pdf_d = std::max(glm::dot(hit.n, d), 0.0f) / kPi;
    if (pdf_d > 0 && !c.scene.occluded(x, d, kInf)) L += hit.albedo * env.radiance(d) * power_heuristic(pdf_d, env.pdf(d));
    const float u5 = rng.u(), u6 = rng.u();
    const Environment::Sample es = env.sample(u5, u6);
    const float cos_i = glm::dot(hit.n, es.wi);
    if (es.pdf > 0 && cos_i > 0 && !c.scene.occluded(x, es.wi, kInf))
        L += hit.albedo * (cos_i / kPi) * es.Le * power_heuristic(es.pdf, cos_i / kPi) / es.pdf;
    return L;
}

}  // namespace render
