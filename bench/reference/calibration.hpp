// The calibration loop body that the speed goals are stated in ("one body of this loop
// over random a, b ∈ [0, 1)"). Shared by every benchmark program so that each
// run measures its own unit next to the code it times.
#pragma once

#include <cmath>

namespace bench_ref {

template <typename T> inline T calibration_body(T a, T b) {
    return std::exp(-a) + std::log(T(1) + b) + std::atan2(a, b) + std::sqrt(a * b) + std::sin(a) + std::cos(b) +
           std::asin(T(0.9) * a) + std::sinh(b);
}

}  // namespace bench_ref
