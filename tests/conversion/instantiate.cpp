// Part of the header check (tests/CMakeLists.txt): every class template of the public
// headers instantiated for float and double, with the warnings a renderer that includes
// the headers with -I (not -isystem) may turn on: -Wconversion -Wsign-conversion. GCC
// reports most conversions where a template is defined, Clang where it is instantiated;
// this translation unit gives Clang its instantiations. Compiled only, never run.
#include <hairscatter/dual.hpp>

namespace hs = hairscatter;

#define HAIRSCATTER_INSTANTIATE(T)                                              \
    template class hs::ChiangMaterial<T>;                                       \
    template class hs::BasicChiangFiber<T, hs::LobeSet::kAll>;                  \
    template class hs::BasicChiangFiber<T, hs::LobeSet::kR>;                    \
    template class hs::FiberModel<hs::ChiangFiber<T>, T>;                       \
    template class hs::BoundFiber<hs::ChiangFiber<T>>;                          \
    template class hs::BasicChiangSpectralFiber<T, 3, hs::LobeSet::kAll>;       \
    template class hs::BasicChiangSpectralFiber<T, 4, hs::LobeSet::kAll>;       \
    template class hs::BasicChiangSpectralFiber<T, 5, hs::LobeSet::kR>;         \
    template struct hs::SpectralValues<T, 4>;                                   \
    template class hs::ChiangBatch<T>;                                          \
    template class hs::DeonFarFieldMaterial<T>;                                 \
    template class hs::DeonFarFieldFiber<T>;                                    \
    template class hs::FiberModel<hs::DeonFarFieldFiber<T>, T>;                 \
    template class hs::BoundFiber<hs::DeonFarFieldFiber<T>>;                    \
    template class hs::FurMaterial<T>;                                          \
    template class hs::FurFiber<T>;                                             \
    template class hs::FiberModel<hs::FurFiber<T>, T>;                          \
    template class hs::BoundFiber<hs::FurFiber<T>>;                             \
    template class hs::HuangMaterial<T>;                                        \
    template class hs::HuangFiber<T>;                                           \
    template class hs::FiberModel<hs::HuangFiber<T>, T>;                        \
    template class hs::BoundFiber<hs::HuangFiber<T>>;                           \
    template class hs::MarschnerMaterial<T>;                                    \
    template class hs::MarschnerFiber<T>;                                       \
    template class hs::FiberModel<hs::MarschnerFiber<T>, T>;                    \
    template class hs::BoundFiber<hs::MarschnerFiber<T>>;                       \
    template class hs::TabulatedMaterial<T>;                                    \
    template class hs::TabulatedView<T>;                                        \
    template class hs::TabulatedFiber<T>;                                       \
    template class hs::FiberModel<hs::TabulatedFiber<T>, T>;                    \
    template class hs::BoundFiber<hs::TabulatedFiber<T>>;                       \
    template class hs::DualScatteringTables<T>;                                 \
    template class hs::SpectralDualTables<T>;                                   \
    template class hs::DualScatteringBcsdf<hs::ChiangFiber<T>>;                 \
    template class hs::DualScatteringBcsdf<hs::TabulatedFiber<T>>;              \
    template class hs::DensityGrid<T>;                                          \
    template class hs::DensityGridView<T>;                                      \
    template class hs::DirectionalCountField<T>;                                \
    template class hs::DirectionalCountFieldView<T>;                            \
    template class hs::DualSourceKernel<T>;                                     \
    template class hs::FiberParamBounds<T>;

HAIRSCATTER_INSTANTIATE(float)
HAIRSCATTER_INSTANTIATE(double)

// The member templates a renderer calls: the tables built from each model.
template <typename T> void build_tables() {
    const hs::ChiangMaterial<T> chiang{hs::FiberParams<T>{}};
    (void)hs::DualScatteringTables<T>::template build<hs::ChiangFiber<T>>(chiang);
}
template void build_tables<float>();
template void build_tables<double>();

// The spectral helpers a renderer calls.
template <typename T> void spectral_inputs() {
    const hs::SpectralValues<T, 4> l = hs::sample_uniform_wavelengths<T, 4>(T(0.3));
    (void)hs::spectral_sigma_a(hs::MelaninConcentrations<T>{T(1), T(0)}, l);
    (void)hs::clamped_spectral_sigma_a(hs::MelaninConcentrations<T>{T(1), T(0)}, l);
}
template void spectral_inputs<float>();
template void spectral_inputs<double>();
