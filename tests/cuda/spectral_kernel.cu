// CUDA compile check of the N-channel API: a path's four sampled wavelengths, σa of textured
// melanin concentrations at them, and the 4-channel Chiang fiber's eval, pdf, sample and
// bound calls, all on the device (the material built on the host, passed by value).
#include <hairscatter/hairscatter.hpp>

#include <cuda_runtime.h>

namespace hairscatter_cuda_check {

template <typename T, int N> struct SpectralOutput {
    hairscatter::SpectralValues<T, N> f, weight, bound_f, albedo;
    T pdf, sample_pdf;
    glm::vec<3, T> sample_wi;
};

namespace {

template <typename T, int N>
__global__ void shade_spectral(hairscatter::ChiangMaterial<T> mat, const hairscatter::MelaninConcentrations<T>* melanin,
                               const T* u_lambda, const glm::vec<3, T>* wo, const glm::vec<3, T>* wi,
                               const glm::vec<4, T>* u, SpectralOutput<T, N>* out, int n) {
    const int i = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
    if (i >= n) return;
    const auto lambda = hairscatter::sample_uniform_wavelengths<T, N>(u_lambda[i]);
    const auto sigma_a = hairscatter::clamped_spectral_sigma_a(melanin[i], lambda);
    const hairscatter::ChiangSpectralFiber<T, N> fiber(mat, T(2) * u_lambda[i] - T(1), sigma_a);
    SpectralOutput<T, N> r;
    r.f = fiber.eval(wo[i], wi[i]);
    r.pdf = fiber.pdf(wo[i], wi[i]);
    const auto s = fiber.sample(wo[i], u[i]);
    r.weight = s.weight;
    r.sample_pdf = s.pdf;
    r.sample_wi = s.wi;
    const auto bound = fiber.at(wo[i]);
    r.bound_f = bound.eval_pdf(wi[i]).f;
    r.albedo = bound.albedo();
    (void)bound.sample(u[i]);
    out[i] = r;
}

}  // namespace

template <typename T, int N>
void launch_spectral(const hairscatter::ChiangMaterial<T>& mat, const hairscatter::MelaninConcentrations<T>* melanin,
                     const T* u_lambda, const glm::vec<3, T>* wo, const glm::vec<3, T>* wi, const glm::vec<4, T>* u,
                     SpectralOutput<T, N>* out, int n) {
    shade_spectral<T, N><<<(n + 127) / 128, 128>>>(mat, melanin, u_lambda, wo, wi, u, out, n);
}

template void launch_spectral<float, 4>(const hairscatter::ChiangMaterial<float>&, const hairscatter::MelaninConcentrations<float>*,
                                        const float*, const glm::vec3*, const glm::vec3*, const glm::vec4*,
                                        SpectralOutput<float, 4>*, int);
template void launch_spectral<double, 4>(const hairscatter::ChiangMaterial<double>&,
                                         const hairscatter::MelaninConcentrations<double>*, const double*,
                                         const glm::dvec3*, const glm::dvec3*, const glm::dvec4*,
                                         SpectralOutput<double, 4>*, int);
template void launch_spectral<float, 1>(const hairscatter::ChiangMaterial<float>&, const hairscatter::MelaninConcentrations<float>*,
                                        const float*, const glm::vec3*, const glm::vec3*, const glm::vec4*,
                                        SpectralOutput<float, 1>*, int);

}  // namespace hairscatter_cuda_check
