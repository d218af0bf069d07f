// CUDA compile check of dual scattering: the tables' view, the dual BCSDF (eval, pdf,
// sample, the bound at(wo)), the per-point helpers, the density grid's view and the
// two-stream estimator (streams, source kernel, Poisson counts) in device code. Built by scripts/cuda-check.sh (nvcc -c only; no GPU is needed or used).
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
    // A path's continuation: the sample with its weight, the light state along the sampled
    // direction from the grid (in the fiber frame here, for the compile check).
    const auto w = at.sample_with(u[i], [&](const glm::vec<3, T>& d) {
        return hairscatter::dual_light(grid, x[i], d, T(0));
    });
    f[i] = at.eval(wi[i], light) + dual.eval(wo[i], wi[i], light) + w.weight;
    pdf[i] = at.pdf(wi[i]) + s.pdf + dual.pdf(wo[i], s.wi);
}

// The two-stream estimator's per-arrival work over any device-side density source (the
// grid's march or the count field's lookup): counts drawn from the source's expectation,
// the streams and the source kernel's eval, pdf and sample.
template <typename T, typename Source>
__global__ void two_stream(hairscatter::DualTablesView<T> tables, Source source, const glm::vec<3, T>* x,
                           const glm::vec<3, T>* a, const glm::vec<4, T>* u, glm::vec<3, T>* f, T* pdf, int n) {
    const int i = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
    if (i >= n) return;
    const T fibers = hairscatter::poisson_fiber_count(source.fibers_crossed(x[i], a[i], hairscatter::kUnbounded<T>), u[i].x, true);
    const T beyond = hairscatter::poisson_fiber_count(source.fibers_crossed(x[i], -a[i], hairscatter::kUnbounded<T>), u[i].y, false);
    // The stacks' turn limits from the source around the point (the fiber's axis is x here).
    const glm::vec<3, T> axis(T(1), T(0), T(0));
    const T limit_n = hairscatter::dual_turn_limit(source, x[i], axis, a[i], hairscatter::kUnbounded<T>);
    const T limit_m = hairscatter::dual_turn_limit(source, x[i], axis, -a[i], hairscatter::kUnbounded<T>);
    const hairscatter::DualScatteringEntry<T> entry = tables.lookup(a[i].x);
    const hairscatter::DualSourceKernel<T> k(a[i], hairscatter::dual_streams(entry, fibers, beyond, limit_n, limit_m));
    const auto s = k.sample(u[i]);
    const hairscatter::DualSourceStack<T> st = hairscatter::dual_source_stack(entry, fibers);
    f[i] = k.eval(s.s) * st.t + hairscatter::dual_source_hair(entry, st);
    pdf[i] = s.pdf + k.pdf(a[i]);
}

#define HAIRSCATTER_TWO_STREAM(T, Source)                                                                       \
    template __global__ void two_stream<T, Source>(hairscatter::DualTablesView<T>, Source, const glm::vec<3, T>*, \
                                                   const glm::vec<3, T>*, const glm::vec<4, T>*, glm::vec<3, T>*, \
                                                   T*, int);
HAIRSCATTER_TWO_STREAM(float, hairscatter::DensityGridView<float>)
HAIRSCATTER_TWO_STREAM(double, hairscatter::DensityGridView<double>)
HAIRSCATTER_TWO_STREAM(float, hairscatter::DirectionalCountFieldView<float>)
HAIRSCATTER_TWO_STREAM(double, hairscatter::DirectionalCountFieldView<double>)
#undef HAIRSCATTER_TWO_STREAM

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
