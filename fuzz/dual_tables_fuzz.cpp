// libFuzzer target: DualScatteringTables<float>::load on any file contents, then read-only
// use of what loaded (lookups over θ, finite inputs and NaN). Either it loads or it throws
// std::runtime_error naming the file; a crash or sanitizer report is a finding.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>

#include <unistd.h>

#include <hairscatter/dual.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::string path = "/tmp/hairscatter_dual_fuzz_" + std::to_string(long(getpid())) + ".hsdt";
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) std::abort();
    if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
    std::fclose(f);
    hairscatter::DualScatteringTables<float> t;
    try {
        t = hairscatter::DualScatteringTables<float>::load(path);
    } catch (const std::runtime_error&) {
        return 0;
    }
    for (float theta : {-1.5707964f, -1.0f, -0.2f, 0.0f, 0.7f, 1.5707964f}) {
        const auto e = t.lookup(theta);
        (void)e;
    }
    // The loaded tables drive the dual BCSDF: eval, pdf and sample must stay in bounds.
    static const hairscatter::ChiangMaterial<float> material{hairscatter::FiberParams<float>{}};
    const hairscatter::ChiangFiber<float> fiber(material, 0.3f);
    const hairscatter::DualScatteringBcsdf<hairscatter::ChiangFiber<float>> dual(fiber, t);
    hairscatter::DualScatteringLight<float> light;
    light.direct_fraction = 0.0f;
    light.n = 3.0f;
    light.beyond = 5.0f;
    const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, 0.8f, 0.2f)), wi = glm::normalize(glm::vec3(-0.2f, 0.1f, 0.9f));
    const auto at = dual.at(wo, 0.05f);
    const glm::vec3 value = at.eval(wi, light);
    const float p = at.pdf(wi) + at.sample(glm::vec4(0.3f, 0.6f, 0.2f, 0.9f)).pdf;
    if (!(value.x >= 0.0f && p >= 0.0f)) std::abort();  // finite tables never give NaN or negative values
    return 0;
}
