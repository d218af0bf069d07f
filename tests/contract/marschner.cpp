// The model contract (tests/support/contract_suite.hpp) for Marschner et al. 2003, float
// and double: one translation unit of contract_test (tests/contract/*.cpp).
#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

#include "support/contract_suite.hpp"
#include "support/model_specs.hpp"

namespace hs = hairscatter;

namespace contract {

using Types = ::testing::Types<specs::MarschnerSpec<float>, specs::MarschnerSpec<double>>;
INSTANTIATE_TYPED_TEST_SUITE_P(AllModels, ModelContract, Types, NumberedFrom<6>);

}  // namespace contract
