// The model contract (tests/support/contract_suite.hpp) for the tabulated fiber, float and
// double: one translation unit of contract_test (tests/contract/*.cpp).
#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

#include "support/contract_suite.hpp"
#include "support/model_specs.hpp"

namespace hs = hairscatter;

namespace contract {

using Types = ::testing::Types<specs::TabulatedSpec<float>, specs::TabulatedSpec<double>>;
INSTANTIATE_TYPED_TEST_SUITE_P(AllModels, ModelContract, Types, NumberedFrom<4>);

}  // namespace contract
