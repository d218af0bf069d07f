// Instructions per call of the per-hit calls, for valgrind's callgrind (a count that does
// not depend on the load of a shared machine): a material built per hit from parameters
// that differ at every input (as bench/vs_pbrt.cpp's per-hit rows), then eval or a path
// vertex, from the parts or by the fiber's per-hit calls. Runs `calls` calls of one kind
// over 4096 cycled inputs; (count at 6000 calls - count at 2000) / 4000 is one call.
//
//   per_hit_icount CALLS KIND
//   KIND: 0 per_hit + fiber + eval      1 per_hit_eval
//         2 fiber + eval (prebuilt material: the stateless eval)
//         3 per_hit + at(wo) + eval + sample   4 per_hit + at(wo) + eval_pdf + sample
//         5 per_hit_vertex (eval_pdf + sample)
//         6 per_hit alone (the material kept whole in memory, as a caller that stores it)
//
// bench/results/icount_perhit_2026-12-06.txt has the commands and the counts.
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include <hairscatter/hairscatter.hpp>

namespace hs = hairscatter;

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: per_hit_icount CALLS KIND (0 … 6: see the source)\n");
        return 2;
    }
    const long calls = std::atol(argv[1]);
    const int kind = std::atoi(argv[2]);
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> uni(0, 1);
    std::vector<hs::FiberParams<float>> params;
    std::vector<float> h;
    std::vector<glm::vec3> wo, wi;
    std::vector<glm::vec4> u;
    for (int i = 0; i < 4096; ++i) {
        const float a = uni(rng), b = uni(rng), c = uni(rng), d = uni(rng);
        hs::FiberParams<float> p;  // the ranges of bench/vs_pbrt.cpp's hit_params
        p.eta = 1.5f + 0.1f * uni(rng);
        p.beta_m = 0.25f + 0.1f * uni(rng);
        p.beta_n = 0.25f + 0.1f * uni(rng);
        p.alpha = hs::radians(1.0f + 2.0f * uni(rng));
        p.sigma_a = hs::sigma_a_from_concentrations(0.8f + uni(rng), 0.0f);
        params.push_back(p);
        h.push_back(2 * a - 1);
        wo.push_back(glm::normalize(glm::vec3(2 * a - 1, 2 * b - 1, 2 * c - 1)));
        wi.push_back(glm::normalize(glm::vec3(2 * d - 1, 2 * a - 1, 2 * b - 1)));
        u.push_back(glm::vec4(a, b, c, d));
    }
    using Fiber = hs::ChiangFiber<float>;
    const hs::ChiangMaterial<float> prebuilt(params[0]);
    float sum = 0;
    for (long k = 0; k < calls; ++k) {
        const std::size_t i = std::size_t(k) & 4095u;
        if (kind == 0) {
            const auto m = hs::ChiangMaterial<float>::per_hit(params[i]);
            sum += Fiber(m, h[i]).eval(wo[i], wi[i]).x;
        }
        if (kind == 1) sum += Fiber::per_hit_eval(params[i], h[i], wo[i], wi[i]).x;
        if (kind == 2) sum += Fiber(prebuilt, h[i]).eval(wo[i], wi[i]).x;
        if (kind == 3 || kind == 4) {
            const auto m = hs::ChiangMaterial<float>::per_hit(params[i]);
            const auto at = Fiber(m, h[i]).at(wo[i]);
            if (kind == 3) sum += at.eval(wi[i]).x;
            if (kind == 4) sum += at.eval_pdf(wi[i]).pdf;
            sum += at.sample(u[i]).pdf;
        }
        if (kind == 6) {
            const auto m = hs::ChiangMaterial<float>::per_hit(params[i]);
#if defined(__GNUC__)
            __asm__ volatile("" : : "r"(&m) : "memory");  // (the whole material is written)
#endif
            sum += m.lobe_variance(0);
        }
        if (kind == 5) {
            const auto v = Fiber::per_hit_vertex(params[i], h[i], wo[i], wi[i], u[i]);
            sum += v.light.f.x + v.light.pdf + v.next.pdf;
        }
    }
    std::printf("%g\n", double(sum));
    return 0;
}
