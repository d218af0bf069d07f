#include <hairscatter/hairscatter.hpp>
#include <cstdio>
namespace hs = hairscatter;

int main() {
    hs::FiberParams<float> params;                                  // η 1.55, βm = βn = 0.3, α 2°
    params.sigma_a = hs::sigma_a_from_melanin(1.3f, 0.0f);          // brown hair
    const hs::ChiangMaterial<float> material(params);               // once per material; throws if invalid
    const glm::vec3 tangent(0, 1, 0), wo_world = glm::normalize(glm::vec3(0.3f, 0.2f, 1));
    const hs::FiberFrame<float> frame(tangent, wo_world);           // x = tangent, wo in the x–z plane
    const hs::ChiangFiber<float> fiber(material, 0.25f);            // per hit, with its offset h
    const glm::vec3 wo = frame.to_local(wo_world);
    const hs::HairSample<float> s = fiber.sample(wo, glm::vec4(0.1f, 0.5f, 0.7f, 0.3f));
    const glm::vec3 wi_world = frame.to_world(s.wi), f = fiber.eval(wo, s.wi);  // f = weight · pdf
    std::printf("wi (%.3f %.3f %.3f) pdf %.4f f.r %.4f\n", wi_world.x, wi_world.y, wi_world.z, s.pdf, f.r);
    return s.pdf > 0 && f.r > 0 ? 0 : 1;
}
