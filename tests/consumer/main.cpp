// Downstream smoke test: build a fiber, evaluate one direction pair, print it.
#include <hairscatter/hairscatter.hpp>

#include <cmath>
#include <cstdio>

double second_tu_value();  // second_tu.cpp

int main() {
    hairscatter::FiberParams<float> p;
    p.eta = 1.55f;
    p.beta_m = 0.3f;
    p.beta_n = 0.3f;
    p.alpha = 0.035f;
    p.sigma_a = hairscatter::sigma_a_from_concentrations(1.3f, 0.0f);

    const hairscatter::ChiangMaterial<float> mat(p);
    const hairscatter::ChiangFiber<float> fiber(mat, 0.25f);

    const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f));
    const glm::vec3 wi = glm::normalize(glm::vec3(-0.2f, 0.6f, -0.7f));
    const glm::vec3 f = fiber.eval(wo, wi);
    const float pdf = fiber.pdf(wo, wi);
    const double other = second_tu_value();

    std::printf("hairscatter %d.%d.%d: f = (%g, %g, %g), pdf = %g, double f.sum = %g\n",
                HAIRSCATTER_VERSION_MAJOR, HAIRSCATTER_VERSION_MINOR, HAIRSCATTER_VERSION_PATCH,
                static_cast<double>(f.x), static_cast<double>(f.y), static_cast<double>(f.z),
                static_cast<double>(pdf), other);

    const bool ok = std::isfinite(f.x) && std::isfinite(f.y) && std::isfinite(f.z) &&
                    std::isfinite(pdf) && std::isfinite(other);
    if (!ok) {
        std::fprintf(stderr, "consumer: non-finite result\n");
        return 1;
    }
    return 0;
}
