// The model contract (tests/support/contract_suite.hpp) for subsets of the Chiang lobes
// (R alone, TT alone, TRT with the residual), float and double: one translation unit of
// contract_test (tests/contract/*.cpp).
#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

#include "support/contract_suite.hpp"
#include "support/model_specs.hpp"

namespace hs = hairscatter;

namespace contract {

constexpr hs::LobeSet kR = hs::LobeSet::kR, kTT = hs::LobeSet::kTT;
constexpr hs::LobeSet kTrtResidual = hs::LobeSet::kTRT | hs::LobeSet::kResidual;
using Types = ::testing::Types<specs::ChiangSpec<float, kR>, specs::ChiangSpec<double, kR>, specs::ChiangSpec<float, kTT>,
                                specs::ChiangSpec<double, kTT>, specs::ChiangSpec<float, kTrtResidual>,
                                specs::ChiangSpec<double, kTrtResidual>>;
INSTANTIATE_TYPED_TEST_SUITE_P(ChiangLobeSubsets, ModelContract, Types, NumberedFrom<0>);

}  // namespace contract
