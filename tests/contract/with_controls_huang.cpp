// The model contract (tests/support/contract_suite.hpp) for Huang et al. 2022 with random
// gains and tints (HuangControlsSpec, tests/support/controls_specs.hpp), float and double:
// one translation unit of contract_test.
#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

#include "support/contract_suite.hpp"
#include "support/controls_specs.hpp"

namespace contract {

using Types = ::testing::Types<specs::HuangControlsSpec<float>, specs::HuangControlsSpec<double>>;
INSTANTIATE_TYPED_TEST_SUITE_P(HuangWithControls, ModelContract, Types, NumberedFrom<0>);

}  // namespace contract
