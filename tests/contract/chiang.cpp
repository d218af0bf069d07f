// The model contract (tests/support/contract_suite.hpp) for Chiang et al. 2016, float and
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

using Plain = ::testing::Types<specs::ChiangSpec<float, hs::LobeSet::kAll>, specs::ChiangSpec<double, hs::LobeSet::kAll>>;
INSTANTIATE_TYPED_TEST_SUITE_P(AllModels, ModelContract, Plain, NumberedFrom<0>);

using WithControls = ::testing::Types<specs::ControlsSpec<specs::ChiangControls<float>>,
                               specs::ControlsSpec<specs::ChiangControls<double>>>;
INSTANTIATE_TYPED_TEST_SUITE_P(ChiangWithControls, ModelContract, WithControls, NumberedFrom<0>);

}  // namespace contract
