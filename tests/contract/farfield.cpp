// The model contract (tests/support/contract_suite.hpp) for d'Eon et al. 2011's far-field
// model, float and double: one translation unit of contract_test (tests/contract/*.cpp).
#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

#include "support/contract_suite.hpp"
#include "support/model_specs.hpp"

namespace hs = hairscatter;

namespace contract {

using Types = ::testing::Types<specs::FarFieldSpec<float>, specs::FarFieldSpec<double>>;
INSTANTIATE_TYPED_TEST_SUITE_P(AllModels, ModelContract, Types, NumberedFrom<2>);

}  // namespace contract
