// Checks of the dual BCSDF's layer batches, shared by the baseline tests
// (dual_bcsdf_test) and the -march=native ones (native/lanes_native_test), which reach the
// eight-lane float batch.
#pragma once

#include <cstring>
#include <limits>

#include <gtest/gtest.h>

#include <hairscatter/dual.hpp>

namespace dual_checks {

namespace hs = hairscatter;

// The BCSDF computes the stacks above and below a point as one batch of eight lanes: each
// lane must give what the stack of its own depth gives alone, bit for bit (float, where
// the batch is one AVX vector, and double), at every kind of depth: none, a fraction,
// whole, huge, infinite and NaN, and for opaque and lossless layers.
template <typename T> void two_depth_stacks() {
    const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
    const T depths[] = {T(0), T(0.25), T(1), T(1.5), T(6), T(1e5), T(1e13), inf, nan, T(-2)};
    for (const T af : {T(0), T(0.3), T(0.9), T(1)})
        for (const T ab : {T(0), T(0.05), T(0.1)}) {
            hs::DualScatteringEntry<T> e;
            e.a_f = glm::vec<3, T>(af, af * T(0.8), af * T(0.5));
            e.a_b = glm::vec<3, T>(ab, ab * T(0.5), ab * T(0.8));
            const hs::DualLayers<T> l = hs::dual_layers(e);
            for (const T a : depths)
                for (const T b : depths) {
                    glm::vec<3, T> Ra, Ta, Rb, Tb, R2a, T2a, R2b;
                    l.stacks(a, Ra, Ta);
                    l.stacks(b, Rb, Tb);
                    l.stacks(a, b, R2a, T2a, R2b);
                    for (int c = 0; c < 3; ++c) {
                        EXPECT_EQ(std::memcmp(&Ra[c], &R2a[c], sizeof(T)), 0) << af << " " << ab << " " << a << " " << c;
                        EXPECT_EQ(std::memcmp(&Ta[c], &T2a[c], sizeof(T)), 0) << af << " " << ab << " " << a << " " << c;
                        EXPECT_EQ(std::memcmp(&Rb[c], &R2b[c], sizeof(T)), 0) << af << " " << ab << " " << b << " " << c;
                    }
                }
        }
}

}  // namespace dual_checks
