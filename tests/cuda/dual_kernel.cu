// CUDA compile check of dual scattering: the tables' view, the dual BCSDF (eval, pdf,
// sample, the bound at(wo)), the per-point helpers and the density grid's view in device
// code. Built by scripts/cuda-check.sh (nvcc -c only; no GPU is needed or used).
#include <hairscatter/dual.hpp>

#include <cuda_runtime.h>

namespace hairscatter_cuda_check {

namespace {

// The tables are built on the host; their arrays are copied to device memory and the view
// (DualScatteringTables::with_arrays) is passed by value; the material through a pointer.
template <typename T>
__global__ void shade_dual(const hairscatter::ChiangMaterial<T>* mat, hairscatter::DualTablesView<T> tables,
                           hairscatter::DensityGridView<T> grid, const glm::vec<3, T>* x, const glm::vec<3, T>* wo,
                           const glm::vec<3, T>* wi, const glm::vec<4, T>* u, glm::vec<3, T>* f, T* pdf, int n) {
    const int i = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
    if (i >= n) return;
    const T h = T(2) * (T(i) + T(0.5)) / T(n) - T(1);
    const hairscatter::ChiangFiber<T> fiber(*mat, h);
    const hairscatter::DualScatteringBcsdf<hairscatter::ChiangFiber<T>> dual(fiber, tables);
    hairscatter::DualScatteringLight<T> light;
    light.direct_fraction = T(0);
    light.n = grid.fibers_crossed(x[i], wi[i], hairscatter::kUnbounded<T>);
    light.beyond = grid.fibers_crossed(x[i], -wi[i], hairscatter::kUnbounded<T>);
    const auto at = dual.at(wo[i], T(0.01));
    const auto s = at.sample(u[i]);
    f[i] = at.eval(wi[i], light) + dual.eval(wo[i], wi[i], light);
    pdf[i] = at.pdf(wi[i]) + s.pdf + dual.pdf(wo[i], s.wi);
}

template __global__ void shade_dual<float>(const hairscatter::ChiangMaterial<float>*, hairscatter::DualTablesView<float>,
                                           hairscatter::DensityGridView<float>, const glm::vec<3, float>*,
                                           const glm::vec<3, float>*, const glm::vec<3, float>*,
                                           const glm::vec<4, float>*, glm::vec<3, float>*, float*, int);
template __global__ void shade_dual<double>(const hairscatter::ChiangMaterial<double>*, hairscatter::DualTablesView<double>,
                                            hairscatter::DensityGridView<double>, const glm::vec<3, double>*,
                                            const glm::vec<3, double>*, const glm::vec<3, double>*,
                                            const glm::vec<4, double>*, glm::vec<3, double>*, double*, int);

}  // namespace

}  // namespace hairscatter_cuda_check
