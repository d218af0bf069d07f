// CUDA compile check: the HAIRSCATTER_HD API must be usable in device code.
// Built with `scripts/cuda-check.sh` (nvcc -c only; no GPU is needed or used).
//
// ChiangMaterial is host-only (it validates its parameters and may throw), so
// the material is built on the host and passed to the kernel by value; the
// fiber is constructed and evaluated on the device.
#include <hairscatter/hairscatter.hpp>
#include <hairscatter/dual/density.hpp>

#include <cuda_runtime.h>

namespace hairscatter_cuda_check {

template <typename T>
struct KernelOutput {
    glm::vec<3, T> f;
    T pdf;
    glm::vec<3, T> sample_wi;
    glm::vec<3, T> sample_weight;
    T sample_pdf;
    int sample_lobe;
    glm::vec<3, T> bound_f;     // through fiber.at(wo): the per-hit bound object
    T bound_sample_pdf;
};

namespace {

template <typename T>
__global__ void evaluate_fiber(hairscatter::ChiangMaterial<T> mat, const glm::vec<3, T>* wo,
                               const glm::vec<3, T>* wi, const glm::vec<4, T>* u,
                               KernelOutput<T>* out, int n) {
    const int i = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
    if (i >= n) {
        return;
    }
    // Offset h in (-1, 1) across the fiber width, as a curve intersector's v (the hit helpers
    // and the frame that faces the viewer are device code too).
    const T v = (T(i) + T(0.5)) / T(n);
    const glm::vec<3, T> tangent(T(1), T(0), T(0));
    const hairscatter::FiberFrame<T> frame =
        hairscatter::FiberFrame<T>::facing(tangent, glm::vec<3, T>(T(0), T(0), T(-1)), wo[i]);
    const T h = hairscatter::FiberHit<T>::from_v(tangent, wo[i], v, frame.y).h;
    const hairscatter::ChiangFiber<T> fiber(mat, h);

    KernelOutput<T> r;
    r.f = fiber.eval(wo[i], wi[i]);
    r.pdf = fiber.pdf(wo[i], wi[i]);
    const auto s = fiber.sample(wo[i], u[i]);
    r.sample_wi = s.wi;
    r.sample_weight = s.weight;
    r.sample_pdf = s.pdf;
    r.sample_lobe = static_cast<int>(s.lobe);
    const auto at = fiber.at(wo[i]);
    r.bound_f = at.eval(wi[i]);
    r.bound_sample_pdf = at.sample(u[i]).pdf + at.pdf(wi[i]) + at.eval_pdf(wi[i]).pdf;
    out[i] = r;
}

// The shipped density grid is queried on the device through its trivially copyable view
// (cells copied to device memory by the renderer), as is any renderer's own source.
template <typename T>
__global__ void fibers_toward_light(hairscatter::DensityGridView<T> grid, const glm::vec<3, T>* x,
                                    const glm::vec<3, T>* to_light, T* n, int count) {
    const int i = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
    if (i < count) n[i] = grid.fibers_crossed(x[i], to_light[i], hairscatter::kUnbounded<T>);
}
template __global__ void fibers_toward_light<float>(hairscatter::DensityGridView<float>, const glm::vec<3, float>*,
                                                    const glm::vec<3, float>*, float*, int);

// The far-field fiber needs no h; it reads its material (node tables) through a pointer,
// so the renderer copies the material to device memory once.
template <typename T>
__global__ void evaluate_far_field(const hairscatter::DeonFarFieldMaterial<T>* mat, const glm::vec<3, T>* wo,
                                   const glm::vec<3, T>* wi, const glm::vec<4, T>* u, glm::vec<3, T>* f, T* pdf,
                                   int n) {
    const int i = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
    if (i >= n) return;
    const hairscatter::DeonFarFieldFiber<T> fiber(*mat);
    f[i] = fiber.eval(wo[i], wi[i]);
    pdf[i] = fiber.pdf(wo[i], wi[i]) + fiber.sample(wo[i], u[i]).pdf;
}
template __global__ void evaluate_far_field<float>(const hairscatter::DeonFarFieldMaterial<float>*,
                                                   const glm::vec<3, float>*, const glm::vec<3, float>*,
                                                   const glm::vec<4, float>*, glm::vec<3, float>*, float*, int);
template __global__ void evaluate_far_field<double>(const hairscatter::DeonFarFieldMaterial<double>*,
                                                    const glm::vec<3, double>*, const glm::vec<3, double>*,
                                                    const glm::vec<4, double>*, glm::vec<3, double>*, double*, int);

// Huang et al. 2022's microfacet fiber: like the far field, it reads its material (nodes
// and reflectance tables, a few KB) through a pointer to a device copy; eval, pdf, sample
// and the bound object at(wo).
template <typename T>
__global__ void evaluate_huang(const hairscatter::HuangMaterial<T>* mat, const glm::vec<3, T>* wo,
                               const glm::vec<3, T>* wi, const glm::vec<4, T>* u, glm::vec<3, T>* f, T* pdf, int n) {
    const int i = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
    if (i >= n) return;
    const hairscatter::HuangFiber<T> fiber(*mat);
    f[i] = fiber.eval(wo[i], wi[i]) + fiber.at(wo[i]).eval(wi[i]) + fiber.albedo(wo[i]);
    pdf[i] = fiber.pdf(wo[i], wi[i]) + fiber.sample(wo[i], u[i]).pdf;
}
template __global__ void evaluate_huang<float>(const hairscatter::HuangMaterial<float>*, const glm::vec<3, float>*,
                                               const glm::vec<3, float>*, const glm::vec<4, float>*,
                                               glm::vec<3, float>*, float*, int);
template __global__ void evaluate_huang<double>(const hairscatter::HuangMaterial<double>*, const glm::vec<3, double>*,
                                                const glm::vec<3, double>*, const glm::vec<4, double>*,
                                                glm::vec<3, double>*, double*, int);

// A preview fiber that keeps R only (lobes/lobe_set.hpp): compiled out on the device too.
template <typename T>
__global__ void evaluate_r_only(hairscatter::ChiangMaterial<T> mat, const glm::vec<3, T>* wo,
                                const glm::vec<3, T>* wi, const glm::vec<4, T>* u, glm::vec<3, T>* f, T* pdf, int n) {
    const int i = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
    if (i >= n) return;
    const hairscatter::BasicChiangFiber<T, hairscatter::LobeSet::kR> fiber(mat, T(0.3));
    f[i] = fiber.eval(wo[i], wi[i]);
    pdf[i] = fiber.pdf(wo[i], wi[i]) + fiber.sample(wo[i], u[i]).pdf + fiber.at(wo[i]).eval(wi[i]).x;
}
template __global__ void evaluate_r_only<float>(hairscatter::ChiangMaterial<float>, const glm::vec<3, float>*,
                                                const glm::vec<3, float>*, const glm::vec<4, float>*,
                                                glm::vec<3, float>*, float*, int);

// Per-strand variation and pigments on the device: each thread hashes its strand id to
// melanin, redness and a roughness scale, and maps them to σa (fiber/strand_variation.hpp).
template <typename T>
__global__ void strand_absorption(hairscatter::StrandVariation<T> variation, hairscatter::FiberParams<T> base,
                                  glm::vec<3, T> dye, glm::vec<3, T>* sigma_a, T* beta_m, int n) {
    const int i = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
    if (i >= n) return;
    const hairscatter::FiberParams<T> p =
        hairscatter::strand_params(base, variation.at(static_cast<std::uint32_t>(i)), dye);
    sigma_a[i] = p.sigma_a + hairscatter::sigma_a_from_melanin_amount(T(0.5), T(0.2));
    beta_m[i] = p.beta_m;
}
template __global__ void strand_absorption<float>(hairscatter::StrandVariation<float>, hairscatter::FiberParams<float>,
                                                  glm::vec<3, float>, glm::vec<3, float>*, float*, int);
template __global__ void strand_absorption<double>(hairscatter::StrandVariation<double>,
                                                   hairscatter::FiberParams<double>, glm::vec<3, double>,
                                                   glm::vec<3, double>*, double*, int);

// The tabulated far-field fiber reads its table through a trivially copyable view of
// device memory (material.view(device_copy_of_data)).
template <typename T>
__global__ void evaluate_tabulated(hairscatter::TabulatedView<T> view, const glm::vec<3, T>* wo,
                                   const glm::vec<3, T>* wi, const glm::vec<4, T>* u, glm::vec<3, T>* f, T* pdf,
                                   int n) {
    const int i = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
    if (i >= n) return;
    const hairscatter::TabulatedFiber<T> fiber(view);
    f[i] = fiber.eval(wo[i], wi[i]) + fiber.albedo(wo[i]);
    const auto at = fiber.at(wo[i]);
    pdf[i] = fiber.pdf(wo[i], wi[i]) + fiber.sample(wo[i], u[i]).pdf + at.eval_pdf(wi[i]).pdf + at.sample(u[i]).pdf;
}
template __global__ void evaluate_tabulated<float>(hairscatter::TabulatedView<float>, const glm::vec<3, float>*,
                                                   const glm::vec<3, float>*, const glm::vec<4, float>*,
                                                   glm::vec<3, float>*, float*, int);
template __global__ void evaluate_tabulated<double>(hairscatter::TabulatedView<double>, const glm::vec<3, double>*,
                                                    const glm::vec<3, double>*, const glm::vec<4, double>*,
                                                    glm::vec<3, double>*, double*, int);

// Marschner 2003 (root solving, caustics): the material (≈ 0.9 KB) goes to the kernel by
// value; the fiber needs no h.
template <typename T>
__global__ void evaluate_marschner(hairscatter::MarschnerMaterial<T> mat, const glm::vec<3, T>* wo,
                                   const glm::vec<3, T>* wi, const glm::vec<4, T>* u, glm::vec<3, T>* f, T* pdf,
                                   int n) {
    const int i = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
    if (i >= n) return;
    const hairscatter::MarschnerFiber<T> fiber(mat);
    f[i] = fiber.eval(wo[i], wi[i]) + fiber.eval_pdf(wo[i], wi[i]).f;
    const hairscatter::HairSample<T> s = fiber.sample(wo[i], u[i]);
    pdf[i] = fiber.pdf(wo[i], wi[i]) + s.pdf + s.weight.x;
}
template __global__ void evaluate_marschner<float>(hairscatter::MarschnerMaterial<float>, const glm::vec<3, float>*,
                                                   const glm::vec<3, float>*, const glm::vec<4, float>*,
                                                   glm::vec<3, float>*, float*, int);
template __global__ void evaluate_marschner<double>(hairscatter::MarschnerMaterial<double>, const glm::vec<3, double>*,
                                                    const glm::vec<3, double>*, const glm::vec<4, double>*,
                                                    glm::vec<3, double>*, double*, int);

template <typename T>
hairscatter::ChiangMaterial<T> make_material() {
    hairscatter::FiberParams<T> p;
    p.eta = T(1.55);
    p.beta_m = T(0.3);
    p.beta_n = T(0.3);
    p.alpha = T(0.035);
    p.sigma_a = hairscatter::sigma_a_from_concentrations(T(1.3), T(0));
    hairscatter::LobeControls<T> controls;  // gains and a tilt override reach the device copy
    controls.gain[2] = T(1.5);
    controls.override_alpha(0, T(0.05));
    return hairscatter::ChiangMaterial<T>(p, controls);
}

}  // namespace

// Host-side launchers (never run in CI: there is no GPU; this file only has to compile).
template <typename T>
cudaError_t launch_evaluate_fiber(const glm::vec<3, T>* d_wo, const glm::vec<3, T>* d_wi,
                                  const glm::vec<4, T>* d_u, KernelOutput<T>* d_out, int n,
                                  cudaStream_t stream) {
    const hairscatter::ChiangMaterial<T> mat = make_material<T>();
    constexpr int block = 128;
    const int grid = (n + block - 1) / block;
    evaluate_fiber<T><<<grid, block, 0, stream>>>(mat, d_wo, d_wi, d_u, d_out, n);
    return cudaGetLastError();
}

// Explicit float and double instantiations.
template cudaError_t launch_evaluate_fiber<float>(const glm::vec<3, float>*, const glm::vec<3, float>*,
                                                  const glm::vec<4, float>*, KernelOutput<float>*, int,
                                                  cudaStream_t);
template cudaError_t launch_evaluate_fiber<double>(const glm::vec<3, double>*, const glm::vec<3, double>*,
                                                   const glm::vec<4, double>*, KernelOutput<double>*, int,
                                                   cudaStream_t);

}  // namespace hairscatter_cuda_check
