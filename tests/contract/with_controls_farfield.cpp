// The model contract (tests/support/contract_suite.hpp) for d'Eon et al. 2011's far-field
// model with non-default lobe controls (gains, tints, tilts:
// tests/support/controls_specs.hpp), float and double: one translation unit of
// contract_test.
#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

#include "support/contract_suite.hpp"
#include "support/controls_specs.hpp"

namespace contract {

using Types = ::testing::Types<specs::ControlsSpec<specs::FarFieldControls<float>>,
                               specs::ControlsSpec<specs::FarFieldControls<double>>>;
INSTANTIATE_TYPED_TEST_SUITE_P(FarFieldWithControls, ModelContract, Types, NumberedFrom<0>);

}  // namespace contract
