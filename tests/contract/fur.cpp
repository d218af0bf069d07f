// The model contract (tests/support/contract_suite.hpp) for the fur fibre (Yan et al. 2015,
// 2017), float and double: one translation unit of contract_test (tests/contract/*.cpp).
#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

#include "support/contract_suite.hpp"
#include "support/model_specs.hpp"

namespace hs = hairscatter;

namespace contract {

using Plain = ::testing::Types<specs::FurSpec<float>, specs::FurSpec<double>>;
INSTANTIATE_TYPED_TEST_SUITE_P(AllModels, ModelContract, Plain, NumberedFrom<10>);

}  // namespace contract
