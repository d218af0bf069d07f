// CUDA compile check: the fur fibre (models/fur.hpp) in device code — construction, the
// bound eval and sample, albedo, lobe_split, and the material's h_break (the dual tables'
// split over h); the medulla and rough-cortex tables are read on the device. The material is
// host-only (it validates and simulates its tables) and is passed by pointer. Built by
// scripts/cuda-check.sh (nvcc -c only).
#include <hairscatter/hairscatter.hpp>
#include <hairscatter/models/fur.hpp>
#include <cuda_runtime.h>
template <typename T>
__global__ void fur_eval(const hairscatter::FurMaterial<T>* mat, const glm::vec<3, T>* wo, const glm::vec<3, T>* wi,
                         const glm::vec<4, T>* u, glm::vec<3, T>* f, T* pdf) {
    const int i = int(blockIdx.x * blockDim.x + threadIdx.x);
    const hairscatter::FurFiber<T> fiber(*mat, T(0.3));
    const auto at = fiber.at(wo[i]);
    f[i] = at.eval(wi[i]) + fiber.albedo(wo[i]);
    pdf[i] = at.sample(u[i]).pdf + fiber.lobe_split(wo[i]).backward[0] + mat->h_break(wo[i].x);
}
template __global__ void fur_eval<float>(const hairscatter::FurMaterial<float>*, const glm::vec3*, const glm::vec3*,
                                         const glm::vec4*, glm::vec3*, float*);
template __global__ void fur_eval<double>(const hairscatter::FurMaterial<double>*, const glm::dvec3*, const glm::dvec3*,
                                          const glm::dvec4*, glm::dvec3*, double*);
