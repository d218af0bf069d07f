// hairscatter — which lobes a model keeps: a compile-time bit set over R, TT, TRT and the
// residual (all orders p ≥ 3, Chiang et al. 2016 §4.1). A lobe that is off is compiled
// out: its A_p, tilt, Φ(p, h), M_p and N_p are never computed, and sampling picks only
// among the kept lobes. Dropping lobes drops their energy (the furnace falls below 1).
//
// A scoped enum of its own, so that a set cannot be confused with a lobe index or with
// the SampledLobe tag a sample carries (models/contract.hpp): BasicChiangFiber<float,
// LobeSet::kR | LobeSet::kTT> compiles, BasicChiangFiber<float, 1> does not.
#pragma once

#include "../config.hpp"

namespace hairscatter {

enum class LobeSet : unsigned {
    kNone = 0u,
    kR = 1u << 0,
    kTT = 1u << 1,
    kTRT = 1u << 2,
    kResidual = 1u << 3,
    kPrimary = (1u << 0) | (1u << 1) | (1u << 2),  // R + TT + TRT, no residual
    kAll = (1u << 4) - 1u,
};

HAIRSCATTER_HD constexpr LobeSet operator|(LobeSet a, LobeSet b) { return LobeSet(unsigned(a) | unsigned(b)); }
HAIRSCATTER_HD constexpr LobeSet operator&(LobeSet a, LobeSet b) { return LobeSet(unsigned(a) & unsigned(b)); }
HAIRSCATTER_HD constexpr LobeSet operator~(LobeSet a) { return LobeSet(~unsigned(a) & unsigned(LobeSet::kAll)); }

// Whether the set keeps lobe p (0 R, 1 TT, 2 TRT, 3 residual).
HAIRSCATTER_HD constexpr bool keeps_lobe(LobeSet set, int p) { return ((unsigned(set) >> p) & 1u) != 0u; }

// Lanes: a model that evaluates its kept lobes side by side stores them densely, lane
// k = 0 … lobe_count(set) - 1 holding the k-th kept lobe in the order R, TT, TRT, residual.
HAIRSCATTER_HD constexpr int lobe_count(LobeSet set) {
    int n = 0;
    for (int p = 0; p < 4; ++p) n += keeps_lobe(set, p) ? 1 : 0;
    return n;
}
// The lobe of lane k (k < lobe_count(set)).
HAIRSCATTER_HD constexpr int lane_lobe(LobeSet set, int k) {
    if ((unsigned(set) & (unsigned(set) + 1u)) == 0u) return k;  // R, R+TT, …: lane k is lobe k
    int p = 0;
    for (int seen = -1; p < 4; ++p)
        if (keeps_lobe(set, p) && ++seen == k) break;
    return p;
}
// The lane of a kept lobe p.
HAIRSCATTER_HD constexpr int lobe_lane(LobeSet set, int p) {
    int k = 0;
    for (int q = 0; q < p; ++q) k += keeps_lobe(set, q) ? 1 : 0;
    return k;
}

}  // namespace hairscatter
