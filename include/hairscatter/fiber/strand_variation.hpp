// hairscatter — deterministic per-strand variation: a strand id and a seed mapped to a
// melanin amount, a redness and a roughness scale within user ranges, by a stateless
// integer hash (no generator to carry, the same value on every thread, pass and device).
// Real hair varies from strand to strand; Cycles' principled hair ("Random Color",
// "Random Roughness") and RenderMan's PxrHairColor ("randomMelanin") randomise the same
// quantities.
#pragma once

#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../math/functions.hpp"
#include "params.hpp"
#include "pigments.hpp"

namespace hairscatter {

// The PCG hash of Jarzynski & Olano 2020 (their "pcg": one LCG step, then PCG's RXS-M-XS
// output permutation): a bijection of the 32-bit integers whose outputs pass their
// statistical tests even for consecutive inputs, at two multiplications.
HAIRSCATTER_HD constexpr std::uint32_t pcg_hash(std::uint32_t v) {
    const std::uint32_t state = v * 747796405u + 2891336453u;
    const std::uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// The hash of (strand, seed, stream): the seed's hash offsets the strand (a different
// permutation of the strands per seed), and each stream hashes once more, so that a
// strand's quantities are drawn independently of each other.
HAIRSCATTER_HD constexpr std::uint32_t strand_hash(std::uint32_t strand, std::uint32_t seed, std::uint32_t stream) {
    return pcg_hash(pcg_hash(strand + pcg_hash(seed)) + stream);
}

// A hash as a uniform number in [0, 1): its top 24 bits, exact in float and double.
template <typename T> HAIRSCATTER_HD constexpr T hash_to_unit(std::uint32_t h) {
    return T(h >> 8u) * T(1.0 / 16777216.0);
}

// A closed interval [lo, hi].
template <typename T> struct Interval {
    T lo, hi;
};

// One strand's draw.
template <typename T> struct StrandTraits {
    T melanin;          // melanin amount, in the variation's melanin interval
    T redness;          // redness, in its redness interval
    T roughness_scale;  // factor on β_m and β_n, in its roughness_scale interval
};

// What varies from strand to strand, each uniformly within its interval; an interval with
// lo = hi holds the quantity fixed. The defaults vary nothing (HairPigments' defaults).
template <typename T> struct StrandVariation {
    std::uint32_t seed = 0;
    Interval<T> melanin{T(0.8), T(0.8)};         // ⊂ [0, 1]
    Interval<T> redness{T(0), T(0)};             // ⊂ [0, 1]
    Interval<T> roughness_scale{T(1), T(1)};     // lo > 0; hi ≤ kMaxRoughnessScale

    static constexpr std::uint32_t kMelaninStream = 0u, kRednessStream = 1u, kRoughnessStream = 2u;

    // Strand `strand`'s quantities: three hashes, no state. lo + (hi - lo) u can round one
    // ulp above hi; the min keeps the draw inside its interval.
    HAIRSCATTER_HD StrandTraits<T> at(std::uint32_t strand) const {
        auto draw = [&](const Interval<T>& r, std::uint32_t stream) {
            const T v = r.lo + (r.hi - r.lo) * hash_to_unit<T>(strand_hash(strand, seed, stream));
            return v < r.hi ? v : r.hi;
        };
        return {draw(melanin, kMelaninStream), draw(redness, kRednessStream),
                draw(roughness_scale, kRoughnessStream)};
    }
};

// The largest accepted roughness scale: β × 1000 covers kMinRoughness to 1.
template <typename T> inline constexpr T kMaxRoughnessScale = T(1000);

// Empty when the variation is valid, else one message per bad interval naming it, its
// bounds and the allowed range. Never throws.
template <typename T> std::string validate(const StrandVariation<T>& v) {
    using detail::in_range;
    auto ok = [](const Interval<T>& r, T lo, T hi) { return in_range(r.lo, lo, hi) && in_range(r.hi, r.lo, hi); };
    const bool scale_ok = ok(v.roughness_scale, T(0), kMaxRoughnessScale<T>) && v.roughness_scale.lo > T(0);
    if (ok(v.melanin, T(0), T(1)) && ok(v.redness, T(0), T(1)) && scale_ok) return std::string();
    detail::Complaints bad;
    auto complain = [&](const char* name, const Interval<T>& r, const char* range) {
        std::ostringstream m;
        m << name << " = [" << double(r.lo) << ", " << double(r.hi) << "] is not an interval lo <= hi inside " << range;
        bad.add_text(m.str());
    };
    if (!ok(v.melanin, T(0), T(1))) complain("melanin", v.melanin, "[0, 1]");
    if (!ok(v.redness, T(0), T(1))) complain("redness", v.redness, "[0, 1]");
    if (!scale_ok) complain("roughness_scale", v.roughness_scale, "(0, 1000]");
    return bad.str();
}

// Throws std::invalid_argument with validate()'s message when the variation is bad
// (without exceptions: prints it and aborts).
template <typename T> void require_valid(const StrandVariation<T>& v) {
    detail::throw_if_invalid(validate(v), "strand variation");
}

// base with β_m and β_n times a strand's roughness scale, clamped into [kMinRoughness, 1] so
// that every strand's parameters stay valid; σa kept (for hair coloured another way).
template <typename T> HAIRSCATTER_HD FiberParams<T> strand_roughness(const FiberParams<T>& base, T roughness_scale) {
    FiberParams<T> p = base;
    p.beta_m = clamp(base.beta_m * roughness_scale, kMinRoughness<T>, T(1));
    p.beta_n = clamp(base.beta_n * roughness_scale, kMinRoughness<T>, T(1));
    return p;
}

// One strand's fiber parameters: strand_roughness, and σa from the strand's melanin and
// redness plus the dye's absorption at the strand's β_n (base.sigma_a is replaced). For
// valid base parameters, variation and dye (channels in (0, 1]) the result is valid.
template <typename T>
HAIRSCATTER_HD FiberParams<T> strand_params(const FiberParams<T>& base, const StrandTraits<T>& s,
                                            const glm::vec<3, T>& dye = glm::vec<3, T>(T(1))) {
    FiberParams<T> p = strand_roughness(base, s.roughness_scale);
    p.sigma_a = sigma_a_from_pigments(HairPigments<T>{s.melanin, s.redness, dye}, p.beta_n);
    return p;
}

}  // namespace hairscatter
