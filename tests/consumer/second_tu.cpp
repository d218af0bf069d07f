// Second translation unit including the library (ODR / inline check), in double.
#include <hairscatter/hairscatter.hpp>

double second_tu_value() {
    hairscatter::FiberParams<double> p;
    p.eta = 1.55;
    p.beta_m = 0.3;
    p.beta_n = 0.3;
    p.alpha = 0.035;
    p.sigma_a = hairscatter::sigma_a_from_concentrations(1.3, 0.0);

    const hairscatter::ChiangMaterial<double> mat(p);
    const hairscatter::ChiangFiber<double> fiber(mat, -0.5);
    const glm::dvec3 wo = glm::normalize(glm::dvec3(0.1, 0.9, 0.2));
    const glm::dvec3 wi = glm::normalize(glm::dvec3(0.4, -0.3, 0.8));
    const glm::dvec3 f = fiber.eval(wo, wi);
    return f.x + f.y + f.z;
}
