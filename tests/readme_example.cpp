#include <hairscatter/hairscatter.hpp>
#include <cstdio>
namespace hs = hairscatter;

int main() {
    hs::FiberParams<float> params;                                  // η 1.55, βm = βn = 0.3, α 2°
    params.sigma_a = hs::sigma_a_from_concentrations(1.3f, 0.0f);          // brown hair
    const hs::ChiangMaterial<float> material(params);               // once per material; throws if invalid
    const glm::vec3 tangent(0, 1, 0), wo_world = glm::normalize(glm::vec3(0.3f, 0.2f, 1));
    const hs::FiberFrame<float> frame(tangent, wo_world);           // x = tangent, wo in the x–z plane
    const hs::ChiangFiber<float> fiber(material, 0.25f);            // per hit, with its offset h
    const auto hit = fiber.at(frame.to_local(wo_world));            // the wo terms, once per hit
    const glm::vec3 light = frame.to_local(glm::normalize(glm::vec3(-0.3f, -0.2f, -1)));
    const glm::vec3 f_light = hit.eval(light);                      // cosine inside: Lo += f · Li / pdf_light
    const hs::HairSample<float> s = hit.sample(glm::vec4(0.1f, 0.5f, 0.7f, 0.3f));  // your sampler's numbers
    const glm::vec3 wi_world = frame.to_world(s.wi);                // continue the path; throughput *= s.weight
    std::printf("f_light.r %.4f | wi (%.3f %.3f %.3f) pdf %.4f weight.r %.4f\n", f_light.r, wi_world.x,
                wi_world.y, wi_world.z, s.pdf, s.weight.r);
    return s.pdf > 0 && f_light.r >= 0 ? 0 : 1;
}
