// The model contract (tests/support/contract_suite.hpp) for every model in float and double
// and for subsets of the Chiang lobes (instantiated in tests/contract/*.cpp, linked into this
// executable); and the compile-time guarantees of the lobe types.
#include <memory>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include <hairscatter/hairscatter.hpp>

namespace hs = hairscatter;

namespace {

// ---- the lobe types cannot be confused ----

template <typename A, typename B, typename = void> struct can_or : std::false_type {};
template <typename A, typename B>
struct can_or<A, B, std::void_t<decltype(std::declval<A>() | std::declval<B>())>> : std::true_type {};

template <auto kSet, typename = void> struct chiang_accepts : std::false_type {};
template <auto kSet>
struct chiang_accepts<kSet, std::void_t<hs::BasicChiangFiber<float, kSet>>> : std::true_type {};

static_assert(can_or<hs::LobeSet, hs::LobeSet>::value);
static_assert(!can_or<hs::SampledLobe, hs::SampledLobe>::value, "sampled-lobe tags are not a set");
static_assert(!can_or<hs::SampledLobe, hs::LobeSet>::value);
static_assert(!std::is_convertible_v<int, hs::LobeSet> && !std::is_convertible_v<hs::SampledLobe, hs::LobeSet>);
static_assert(!std::is_convertible_v<hs::LobeSet, unsigned> && !std::is_convertible_v<hs::SampledLobe, int>);
static_assert(chiang_accepts<hs::LobeSet::kR | hs::LobeSet::kTT>::value);
static_assert(!chiang_accepts<1u>::value && !chiang_accepts<1>::value, "a lobe set is a LobeSet, not a number");
static_assert(!chiang_accepts<hs::SampledLobe::kR>::value, "a sampled-lobe tag is not a lobe set");
static_assert(std::is_same_v<hs::ChiangFiber<float>, hs::BasicChiangFiber<float, hs::LobeSet::kAll>>);

// A fiber refers to its material: a temporary material does not bind, and the fiber is small.
static_assert(!std::is_constructible_v<hs::ChiangFiber<double>, hs::ChiangMaterial<double>&&, double>);
static_assert(!std::is_constructible_v<hs::DeonFarFieldFiber<double>, hs::DeonFarFieldMaterial<double>&&>);
static_assert(!std::is_constructible_v<hs::MarschnerFiber<double>, hs::MarschnerMaterial<double>&&>);
static_assert(!std::is_constructible_v<hs::HuangFiber<double>, hs::HuangMaterial<double>&&>);
static_assert(sizeof(hs::ChiangFiber<float>) <= sizeof(void*) + 4 * sizeof(float));
// What a renderer copies to a GPU is trivially copyable.
static_assert(std::is_trivially_copyable_v<hs::ChiangMaterial<float>> &&
              std::is_trivially_copyable_v<hs::DeonFarFieldMaterial<float>> &&
              std::is_trivially_copyable_v<hs::MarschnerMaterial<float>> &&
              std::is_trivially_copyable_v<hs::HuangMaterial<float>> && std::is_trivially_copyable_v<hs::TabulatedView<float>>);

}  // namespace

TEST(SampledLobe, TagsAreTheLobeIndices) {
    EXPECT_EQ(hs::lobe_index(hs::SampledLobe::kR), 0);
    EXPECT_EQ(hs::lobe_index(hs::SampledLobe::kResidual), 3);
    for (int p = 0; p < 4; ++p) EXPECT_EQ(hs::lobe_index(hs::lobe_tag(p)), p);
    EXPECT_TRUE(hs::HairSample<float>().lobe == hs::SampledLobe::kNone);
}
