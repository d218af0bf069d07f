// hairscatter — which lobes a model keeps: a compile-time bit set over R, TT, TRT and the
// residual (all orders p ≥ 3, Chiang et al. 2016 §4.1). A lobe that is off is compiled
// out: its A_p, tilt, Φ(p, h), M_p and N_p are never computed, and sampling picks only
// among the kept lobes. Dropping lobes drops their energy (the furnace falls below 1).
#pragma once

#include "../config.hpp"

namespace hairscatter {

struct Lobes {
    static constexpr unsigned kR = 1u << 0;
    static constexpr unsigned kTT = 1u << 1;
    static constexpr unsigned kTRT = 1u << 2;
    static constexpr unsigned kResidual = 1u << 3;
    static constexpr unsigned kPrimary = kR | kTT | kTRT;  // R + TT + TRT, no residual
    static constexpr unsigned kAll = kPrimary | kResidual;
};

// Whether the set keeps lobe p (0 R, 1 TT, 2 TRT, 3 residual).
HAIRSCATTER_HD constexpr bool keeps_lobe(unsigned set, int p) { return ((set >> p) & 1u) != 0u; }

}  // namespace hairscatter
