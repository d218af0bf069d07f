// The whole library compiled with -fno-exceptions (tests/CMakeLists.txt): validate()
// reports bad parameters without throwing, the models work, and a material made from bad
// parameters anyway stops the program with the message (HAIRSCATTER_THROW in config.hpp
// aborts) instead of failing to compile. Returns 0 when all of that holds.
#include <hairscatter/dual.hpp>
#include <hairscatter/hairscatter.hpp>

#include <cstdio>
#include <string>

#if defined(__unix__) || defined(__APPLE__)
#include <csignal>
#include <sys/wait.h>
#include <unistd.h>
#define HAS_FORK 1
#endif

#if !defined(HAIRSCATTER_NO_EXCEPTIONS)
#error "this translation unit must be built without exceptions (-fno-exceptions)"
#endif

namespace hs = hairscatter;

int main() {
    int failures = 0;
    auto expect = [&](bool ok, const char* what) {
        if (!ok) {
            std::fprintf(stderr, "no_exceptions: FAILED: %s\n", what);
            ++failures;
        }
    };

    hs::FiberParams<float> bad;
    bad.beta_m = 2.0f;
    const std::string msg = hs::validate(bad);
    expect(msg.find("beta_m") != std::string::npos, "validate() names beta_m");

    hs::FiberParams<float> p;
    p.sigma_a = hs::sigma_a_from_concentrations(1.3f, 0.0f);
    expect(hs::validate(p).empty(), "validate() accepts the defaults");
    const hs::ChiangMaterial<float> m(p);
    const hs::ChiangFiber<float> fiber(m, 0.25f);
    const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, 0.2f, 1.0f)), wi = glm::normalize(glm::vec3(-0.3f, -0.2f, -1.0f));
    const glm::vec3 f = fiber.eval(wo, wi);
    expect(f.x > 0.0f && hs::is_finite(f), "Chiang eval is positive and finite");
    const hs::TabulatedMaterial<float> tab(p, hs::TabulatedOptions::coarse());
    expect(hs::TabulatedFiber<float>(tab).pdf(wo, wi) > 0.0f, "tabulated pdf is positive");

    // The controls' non-throwing checks.
    hs::HairPigments<float> pigments;
    pigments.redness = 1.5f;
    expect(hs::validate(pigments).find("redness") != std::string::npos, "validate(HairPigments) names redness");
    hs::StrandVariation<float> variation;
    variation.melanin = {0.6f, 0.2f};
    expect(hs::validate(variation).find("melanin") != std::string::npos, "validate(StrandVariation) names melanin");
    hs::LobeControls<float> controls;
    controls.gain[1] = -1.0f;
    expect(hs::validate(controls).find("gain_tt") != std::string::npos, "validate(LobeControls) names gain_tt");

#if HAS_FORK
    // A material from bad parameters: the child must die of SIGABRT (the message goes to
    // stderr), not run on with garbage.
    std::fflush(nullptr);
    const pid_t child = fork();
    if (child == 0) {
        const hs::ChiangMaterial<float> never(bad);
        std::printf("no_exceptions: the bad material was built (%f)\n", double(never.params().beta_m));
        std::_Exit(0);
    }
    int status = 0;
    expect(child > 0 && waitpid(child, &status, 0) == child, "fork and wait");
    expect(WIFSIGNALED(status) && WTERMSIG(status) == SIGABRT, "a bad material aborts the program");
#endif

    std::printf("no_exceptions: %s\n", failures == 0 ? "ok" : "FAILED");
    return failures == 0 ? 0 : 1;
}
