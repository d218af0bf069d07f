// docs/integration.md's spectral example: four wavelengths per path, as pbrt-v4's
// SampledWavelengths and Mitsuba 3's spectral variants shade them. It returns 0 when its
// checks pass (the tests run it; the page quotes it verbatim).
#include <hairscatter/hairscatter.hpp>

#include <cmath>
#include <cstdio>
#include <random>

namespace hs = hairscatter;

int main() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    auto next = [&] { return u01(rng); };
    auto uniform_sphere = [&] {
        const float z = 1 - 2 * next(), r = std::sqrt(std::fmax(0.0f, 1 - z * z)), phi = 6.2831853f * next();
        return glm::vec3(z, r * std::cos(phi), r * std::sin(phi));
    };

    // Once per parameter set, on the host: the geometry (its own σa is not read).
    const hs::ChiangMaterial<float> material(hs::FiberParams<float>{});
    // Per strand (a texture, say): melanin concentrations, pbrt-v4's and Mitsuba 3's.
    const hs::MelaninConcentrations<float> melanin{1.3f, 0.2f};

    // Per camera path: four wavelengths (pbrt-v4's SampledWavelengths::SampleUniform), each
    // with density hs::uniform_wavelength_pdf<float>() = 1 / 470 nm, and σa at them
    // (no checks, device-callable; hs::spectral_sigma_a checks on the host).
    const hs::SpectralValues<float, 4> lambda = hs::sample_uniform_wavelengths<float, 4>(next());
    const hs::SpectralValues<float, 4> sigma_a = hs::clamped_spectral_sigma_a(melanin, lambda);

    // Per hit: the fiber at h with the path's σa, bound at wo; eval, pdf and sample as in
    // RGB, with SpectralValues<float, 4> where RGB has vec3. Here: the mean sample weight
    // (f / pdf per wavelength) estimates ∫ f dω, which must match the closed-form albedo.
    double sampled[4] = {}, albedo[4] = {};
    const int hits = 100000;
    for (int i = 0; i < hits; ++i) {
        const hs::ChiangSpectralFiber<float, 4> fiber(material, 2 * next() - 1, sigma_a);
        const auto at = fiber.at(uniform_sphere());
        const hs::SpectralSample<float, 4> s = at.sample(glm::vec4(next(), next(), next(), next()));
        const hs::SpectralValues<float, 4> a = at.albedo();
        for (int c = 0; c < 4; ++c) {
            sampled[c] += s.weight[c];  // 0 when the sample failed (pdf 0): the path ends
            albedo[c] += a[c];
        }
    }
    int failures = 0;
    for (int c = 0; c < 4; ++c) {
        std::printf("%.1f nm: sigma_a %.4f, albedo %.4f, sampled / albedo %.4f\n", double(lambda[c]),
                    double(sigma_a[c]), albedo[c] / hits, sampled[c] / albedo[c]);
        failures += std::fabs(sampled[c] / albedo[c] - 1) < 0.02 ? 0 : 1;
        for (int d = 0; d < 4; ++d)  // melanin absorbs shorter wavelengths more
            failures += lambda[c] < lambda[d] && !(sigma_a[c] > sigma_a[d]) ? 1 : 0;
    }
    return failures == 0 ? 0 : 1;
}
