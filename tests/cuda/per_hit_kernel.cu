// CUDA compile check: a material built per hit on the device (ChiangMaterial::per_hit, from
// parameters that vary per thread, as textures give them) and its fiber evaluated there, and
// the calls that build it inside (ChiangFiber::per_hit_eval, per_hit_pdf, per_hit_sample,
// per_hit_vertex).
// Built by scripts/cuda-check.sh with the other kernels (nvcc -c only; no GPU is needed).
#include <hairscatter/hairscatter.hpp>

#include <cuda_runtime.h>

namespace hairscatter_cuda_check {

template <typename T>
__global__ void evaluate_per_hit(const hairscatter::FiberParams<T>* params, const T* h, const glm::vec<3, T>* wo,
                                 const glm::vec<3, T>* wi, const glm::vec<4, T>* u, glm::vec<3, T>* f, T* pdf,
                                 int n) {
    const int i = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
    if (i >= n) return;
    const auto mat = hairscatter::ChiangMaterial<T>::per_hit(params[i]);
    const hairscatter::ChiangFiber<T> fiber(mat, h[i]);
    const auto at = fiber.at(wo[i]);
    f[i] = at.eval(wi[i]);
    pdf[i] = at.sample(u[i]).pdf + fiber.pdf(wo[i], wi[i]);
    using Fiber = hairscatter::ChiangFiber<T>;
    f[i] += Fiber::per_hit_eval(params[i], h[i], wo[i], wi[i]);
    pdf[i] += Fiber::per_hit_pdf(params[i], h[i], wo[i], wi[i]) + Fiber::per_hit_sample(params[i], h[i], wo[i], u[i]).pdf;
    pdf[i] += Fiber::per_hit_vertex(params[i], h[i], wo[i], wi[i], u[i]).next.pdf;
}

template __global__ void evaluate_per_hit<float>(const hairscatter::FiberParams<float>*, const float*,
                                                 const glm::vec<3, float>*, const glm::vec<3, float>*,
                                                 const glm::vec<4, float>*, glm::vec<3, float>*, float*, int);
template __global__ void evaluate_per_hit<double>(const hairscatter::FiberParams<double>*, const double*,
                                                  const glm::vec<3, double>*, const glm::vec<3, double>*,
                                                  const glm::vec<4, double>*, glm::vec<3, double>*, double*, int);

}  // namespace hairscatter_cuda_check
