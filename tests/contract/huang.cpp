// The model contract (tests/support/contract_suite.hpp) for Huang et al. 2022, float and
// double, plain and with random lobe controls (tests/support/controls_specs.hpp): one
// translation unit of contract_test (tests/contract/*.cpp). Both suites in one unit
// instantiate the model's code once (a third less compile time than two units).
#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

#include "support/contract_suite.hpp"
#include "support/controls_specs.hpp"
#include "support/model_specs.hpp"

namespace hs = hairscatter;

namespace contract {

using Plain = ::testing::Types<specs::HuangSpec<float>, specs::HuangSpec<double>>;
INSTANTIATE_TYPED_TEST_SUITE_P(AllModels, ModelContract, Plain, NumberedFrom<8>);

using WithControls = ::testing::Types<specs::HuangControlsSpec<float>, specs::HuangControlsSpec<double>>;
INSTANTIATE_TYPED_TEST_SUITE_P(HuangWithControls, ModelContract, WithControls, NumberedFrom<0>);

}  // namespace contract
