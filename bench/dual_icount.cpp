// Instructions per call of the dual-scattering BCSDF over ChiangFiber<float> and of the
// single fiber alone, for valgrind's callgrind (a count independent of the load of a
// shared machine): each call as dual_bench's BM_Shade makes it (the fiber of the hit, then
// a stateless eval or sample; a shadowed point, 5 fibers toward the light, 10 beyond).
// The difference between two call counts, divided by their difference, is one call without
// the setup; scripts/bench.sh --programs runs it. Uses only the API that predates the
// lanes, so that it also builds against older headers.
//
//   dual_icount CALLS KIND      KIND: 0 single eval, 1 dual eval, 2 single sample, 3 dual sample
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include <hairscatter/dual.hpp>

namespace hs = hairscatter;

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: dual_icount CALLS KIND (0/1 single/dual eval, 2/3 single/dual sample)\n");
        return 2;
    }
    const long calls = std::atol(argv[1]);
    const int kind = std::atoi(argv[2]);
    hs::FiberParams<float> p;
    p.sigma_a = hs::sigma_a_from_concentrations(0.3f, 0.0f);
    const hs::ChiangMaterial<float> material(p);
    const auto tables = hs::DualScatteringTables<float>::build<hs::ChiangFiber<float>>(material);
    hs::DualScatteringLight<float> light;
    light.n = 5;
    light.beyond = 10;
    light.direct_fraction = 0;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> uni(0, 1);
    std::vector<glm::vec3> wo, wi;
    std::vector<glm::vec4> u;
    std::vector<float> h;
    for (int i = 0; i < 1024; ++i) {
        const float a = uni(rng), b = uni(rng), c = uni(rng), d = uni(rng);
        wo.push_back(glm::normalize(glm::vec3(2 * a - 1, 2 * b - 1, 2 * c - 1)));
        wi.push_back(glm::normalize(glm::vec3(2 * d - 1, 2 * a - 1, 2 * b - 1)));
        u.push_back(glm::vec4(a, b, c, d));
        h.push_back(2 * c - 1);
    }
    float sum = 0;
    for (long k = 0; k < calls; ++k) {
        const std::size_t i = std::size_t(k) & 1023;
        const hs::ChiangFiber<float> fiber(material, h[i]);
        // The dual BCSDF only in its own cases: its construction (the tables' view) is part
        // of a dual call, not of a single-fiber one.
        using Dual = hs::DualScatteringBcsdf<hs::ChiangFiber<float>>;
        switch (kind) {
            case 0: sum += fiber.eval(wo[i], wi[i]).x; break;
            case 1: sum += Dual(fiber, tables).eval(wo[i], wi[i], light).x; break;
            case 2: sum += fiber.sample(wo[i], u[i]).pdf; break;
            default: sum += Dual(fiber, tables).sample(wo[i], u[i]).pdf; break;
        }
    }
    std::printf("%g\n", double(sum));  // keeps the calls
    return 0;
}
