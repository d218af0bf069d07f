// The model contract (tests/support/contract_suite.hpp) for subsets of the Chiang lobes
// (the primary lobes, R with TT), float and double: one translation unit of contract_test
// (tests/contract/*.cpp).
#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

#include "support/contract_suite.hpp"
#include "support/model_specs.hpp"

namespace hs = hairscatter;

namespace contract {

constexpr hs::LobeSet kPrimary = hs::LobeSet::kPrimary, kRTT = hs::LobeSet::kR | hs::LobeSet::kTT;
using Types = ::testing::Types<specs::ChiangSpec<float, kPrimary>, specs::ChiangSpec<double, kPrimary>, specs::ChiangSpec<float, kRTT>,
                                specs::ChiangSpec<double, kRTT>>;
INSTANTIATE_TYPED_TEST_SUITE_P(ChiangLobeSubsets, ModelContract, Types, NumberedFrom<6>);

}  // namespace contract
