// CUDA compile check: the batched Chiang API (models/chiang_batch.hpp) with one thread per
// hit, as a wavefront renderer's shading kernel runs it: the structure-of-arrays query in
// device memory, each thread shading its hit with the *_at calls. Built by
// scripts/cuda-check.sh with the other kernels (nvcc -c only; no GPU is needed).
#include <hairscatter/hairscatter.hpp>

#include <cuda_runtime.h>

namespace hairscatter_cuda_check {

template <typename T>
__global__ void shade_batch(const hairscatter::ChiangMaterial<T>* material, hairscatter::ChiangBatchQuery<T> q,
                            hairscatter::ChiangBatchSampleQuery<T> sq, hairscatter::Arrays3<T> f, T* pdf,
                            hairscatter::ChiangBatchSamples<T> samples) {
    const std::size_t i = std::size_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i >= q.n) return;
    const hairscatter::ChiangBatch<T> batch(*material);
    batch.eval_pdf_at(q, i, f, pdf);
    batch.sample_at(sq, i, samples);
}

template __global__ void shade_batch<float>(const hairscatter::ChiangMaterial<float>*, hairscatter::ChiangBatchQuery<float>,
                                            hairscatter::ChiangBatchSampleQuery<float>, hairscatter::Arrays3<float>,
                                            float*, hairscatter::ChiangBatchSamples<float>);
template __global__ void shade_batch<double>(const hairscatter::ChiangMaterial<double>*,
                                             hairscatter::ChiangBatchQuery<double>,
                                             hairscatter::ChiangBatchSampleQuery<double>, hairscatter::Arrays3<double>,
                                             double*, hairscatter::ChiangBatchSamples<double>);

}  // namespace hairscatter_cuda_check
