// Instructions per call of the Chiang model's default path, for valgrind's callgrind: a
// count that does not depend on the load of a shared machine, where the timings of
// chiang_bench vary by ±10 %. Runs `calls` calls of one kind over 4096 cycled inputs;
// the difference between two call counts, divided by their difference, is the cost of one
// call without the setup (bench/results/controls_*.txt has the commands). Uses only the API
// that predates the lobe controls, so that scripts/bench.sh --headers REV can build it
// against older headers.
//
//   chiang_icount CALLS KIND      KIND: 0 eval, 1 sample, 2 at(wo) + pdf
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include <hairscatter/hairscatter.hpp>

namespace hs = hairscatter;

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: chiang_icount CALLS KIND (0 eval, 1 sample, 2 at(wo) + pdf)\n");
        return 2;
    }
    const long calls = std::atol(argv[1]);
    const int kind = std::atoi(argv[2]);
    hs::FiberParams<float> p;
    p.sigma_a = hs::sigma_a_from_concentrations(1.3f, 0.2f);
    const hs::ChiangMaterial<float> material(p);
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> uni(0, 1);
    std::vector<hs::ChiangFiber<float>> fibers;
    std::vector<glm::vec3> wo, wi;
    std::vector<glm::vec4> u;
    for (int i = 0; i < 4096; ++i) {
        const float a = uni(rng), b = uni(rng), c = uni(rng), d = uni(rng);
        fibers.emplace_back(material, 2 * a - 1);
        wo.push_back(glm::normalize(glm::vec3(2 * a - 1, 2 * b - 1, 2 * c - 1)));
        wi.push_back(glm::normalize(glm::vec3(2 * d - 1, 2 * a - 1, 2 * b - 1)));
        u.push_back(glm::vec4(a, b, c, d));
    }
    float sum = 0;
    for (long k = 0; k < calls; ++k) {
        const std::size_t i = std::size_t(k) & 4095u;
        if (kind == 0) sum += fibers[i].eval(wo[i], wi[i]).x;
        if (kind == 1) sum += fibers[i].sample(wo[i], u[i]).pdf;
        if (kind == 2) sum += fibers[i].at(wo[i]).pdf(wi[i]);
    }
    std::printf("%g\n", double(sum));
    return 0;
}
