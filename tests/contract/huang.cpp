// The model contract (tests/support/contract_suite.hpp) for Huang et al. 2022, float and
// double: one translation unit of contract_test (tests/contract/*.cpp).
#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

#include "support/contract_suite.hpp"
#include "support/model_specs.hpp"

namespace hs = hairscatter;

namespace contract {

using Types = ::testing::Types<specs::HuangSpec<float>, specs::HuangSpec<double>>;
INSTANTIATE_TYPED_TEST_SUITE_P(AllModels, ModelContract, Types, NumberedFrom<8>);

}  // namespace contract
