// The examples' shared vocabulary (examples/common): the lobe list ↔ lobe set ↔ template
// argument mapping for every subset, the model names, and where σa comes from.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include <common/fiber_models.hpp>
#include <common/options.hpp>

namespace {

namespace ex = hairscatter_examples;
namespace hs = hairscatter;

TEST(ExamplesCommon, EveryLobeSetMapsToItsTemplateArgument) {
    for (unsigned set = 1; set <= ex::LobeBits::kAll; ++set) {
        const std::string list = ex::lobes_to_string(set);
        EXPECT_EQ(ex::parse_lobes(list), set) << list;
        const unsigned kept = ex::with_chiang_lobes(set, [](auto s) {
            using Fiber = hs::BasicChiangFiber<float, decltype(s)::value>;
            unsigned k = 0;
            for (int p = 0; p < 4; ++p) k |= Fiber::keeps(p) ? 1u << p : 0u;
            return k;
        });
        EXPECT_EQ(kept, set) << list;
        unsigned sum = 0;
        for (unsigned lobe : ex::each_lobe(set)) sum += lobe;
        EXPECT_EQ(sum, set) << list;
    }
    EXPECT_EQ(ex::parse_lobes("all"), ex::LobeBits::kAll);
    EXPECT_EQ(ex::parse_lobes("primary"), ex::LobeBits::kPrimary);
    EXPECT_EQ(ex::parse_lobes("trt,r"), ex::LobeBits::kR | ex::LobeBits::kTRT);
    EXPECT_THROW(ex::with_chiang_lobes(0u, [](auto) { return 0; }), std::invalid_argument);
    EXPECT_THROW(ex::with_chiang_lobes(16u, [](auto) { return 0; }), std::invalid_argument);
    for (const char* bad : {"", "R,", "R,XX", "TTT", "R;TT"}) EXPECT_THROW(ex::parse_lobes(bad), std::invalid_argument) << bad;
}

TEST(ExamplesCommon, ModelNames) {
    for (const char* name : {"chiang", "farfield", "tabulated", "marschner"})
        EXPECT_STREQ(ex::to_string(ex::parse_model(name)), name);
    EXPECT_THROW(ex::parse_model("pbrt"), std::invalid_argument);
    hs::FiberParams<float> p;
    EXPECT_THROW(ex::FiberModels<float>(ex::FiberModel::kTabulated, ex::LobeBits::kR, p), std::invalid_argument);
    EXPECT_NO_THROW(ex::FiberModels<float>(ex::FiberModel::kChiang, ex::LobeBits::kR, p));
}

TEST(ExamplesCommon, WhereSigmaAComesFrom) {
    ex::HairColourOptions c;
    const glm::dvec3 blond = hs::sigma_a_from_melanin(0.3, 0.0);
    EXPECT_EQ(ex::sigma_a_of(c, "blond", 0.3), blond);  // the program's default preset
    c.preset = "white";
    EXPECT_EQ(ex::sigma_a_of(c, "blond", 0.3), glm::dvec3(0.0));
    c.preset = "purple";
    EXPECT_THROW(ex::sigma_a_of(c, "blond", 0.3), std::invalid_argument);
    c = ex::HairColourOptions{};
    c.eumelanin = 1.3;
    EXPECT_EQ(ex::sigma_a_of(c, "blond", 0.3), hs::sigma_a_from_melanin(1.3, 0.0));
    c.pheomelanin = 0.5;
    EXPECT_EQ(ex::sigma_a_of(c, "blond", 0.3), hs::sigma_a_from_melanin(1.3, 0.5));
    for (double bad : {-1.0, std::nan("")}) {
        c.eumelanin = bad;
        EXPECT_THROW(ex::sigma_a_of(c, "blond", 0.3), std::invalid_argument) << bad;
    }
    c = ex::HairColourOptions{};
    c.pheomelanin = 0.5;  // without eumelanin
    EXPECT_THROW(ex::sigma_a_of(c, "blond", 0.3), std::invalid_argument);
    c = ex::HairColourOptions{};
    c.sigma_a = {0.1, 0.2, 0.3};
    EXPECT_EQ(ex::sigma_a_of(c, "blond", 0.3), glm::dvec3(0.1, 0.2, 0.3));
    c.sigma_a = {0.1, -0.2, 0.3};
    EXPECT_THROW(ex::sigma_a_of(c, "blond", 0.3), std::invalid_argument);
}

}  // namespace
