// hairscatter — per-lobe artistic controls, as production hair shaders offer them: a gain
// and an RGB tint per lobe (R, TT, TRT, residual), and the cuticle tilt α replaced per
// lobe. Gains and tints scale lobe p's attenuation A_p (so f, the lobe selection weights
// and the albedo all follow, and a renderer's sampler stays consistent); they break energy
// conservation on purpose: the albedo becomes Σ_p gain_p tint_p A_p (docs/controls.md).
// The defaults change nothing.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "../fiber/params.hpp"
#include "tilt.hpp"

namespace hairscatter {

// The largest accepted gain and tint channel: their product (≤ 1e12) times four lobes
// stays far from float overflow, so f and the lobe weights stay finite.
template <typename T> inline constexpr T kMaxLobeGain = T(1e6);

template <typename T> struct LobeControls {
    using V3 = glm::vec<3, T>;
    static constexpr int kLobes = 4;  // R, TT, TRT, residual

    T gain[kLobes] = {T(1), T(1), T(1), T(1)};       // [0, kMaxLobeGain]
    V3 tint[kLobes] = {V3(T(1)), V3(T(1)), V3(T(1)), V3(T(1))};  // channels in [0, kMaxLobeGain]
    // The cuticle tilt of lobe p = 0 (R), 1 (TT), 2 (TRT) in radians, used instead of
    // FiberParams::alpha where bit p of alpha_override is set (|α_p| ≤ kMaxCuticleTilt).
    // The residual is never tilted. The global tilt is FiberParams::alpha itself.
    T alpha[3] = {T(0), T(0), T(0)};
    unsigned alpha_override = 0u;

    // Replaces lobe p's tilt (p = 0 R, 1 TT, 2 TRT) by a radians.
    LobeControls& override_alpha(int p, T a) {
        alpha[p] = a;
        alpha_override |= 1u << p;
        return *this;
    }

    // Lobe p's factor on A_p: gain × tint.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE V3 weight(int p) const { return gain[p] * tint[p]; }
    // Whether lobe p's gain × tint differs from 1, and whether any lobe's does.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE bool weighted(int p) const { return weight(p) != V3(T(1)); }
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE bool has_weights() const { return weighted(0) || weighted(1) || weighted(2) || weighted(3); }

    // The tilt of lobe p given the fiber's α.
    HAIRSCATTER_HD T lobe_alpha(int p, T fiber_alpha) const {
        return p < 3 && ((alpha_override >> p) & 1u) != 0u ? alpha[p] : fiber_alpha;
    }

    // The per-lobe rotations of θo: pbrt-v4's -2α_R, α_TT, 4α_TRT (lobes/tilt.hpp) with each
    // lobe's α. Without overrides it is CuticleTilt(fiber_alpha) itself, bit for bit.
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE CuticleTilt<T> cuticle_tilt(T fiber_alpha) const {
        if (alpha_override == 0u) return CuticleTilt<T>(fiber_alpha);
        return CuticleTilt<T>(T(-2) * lobe_alpha(0, fiber_alpha), lobe_alpha(1, fiber_alpha),
                              T(4) * lobe_alpha(2, fiber_alpha));
    }
};

// A material's copy of the gains × tints, for its fiber: trivially copyable and
// device-callable. any() is false for the default controls; a fiber then skips the
// products, so the default path costs one predictable branch and gives the plain model's
// values bit for bit.
template <typename T> class LobeWeights {
  public:
    using V3 = glm::vec<3, T>;
    static constexpr int kLobes = LobeControls<T>::kLobes;

    HAIRSCATTER_HD LobeWeights() : LobeWeights(LobeControls<T>()) {}
    HAIRSCATTER_HD HAIRSCATTER_FORCE_INLINE explicit LobeWeights(const LobeControls<T>& c) : any_(c.has_weights()) {
        for (int p = 0; p < kLobes; ++p) {
            const V3 w = c.weight(p);
            for (int ch = 0; ch < kChannelLanes; ++ch) w_[p][ch] = T(1);  // the padding: 1
            for (int ch = 0; ch < 3; ++ch) w_[p][ch] = w[ch];
        }
    }
    HAIRSCATTER_HD bool any() const { return any_; }
    HAIRSCATTER_HD V3 operator[](int p) const { return V3(w_[p][0], w_[p][1], w_[p][2]); }
    // Lobe p's weight per channel lane (math/constants.hpp: kChannelLanes; padding 1).
    HAIRSCATTER_HD const T (&channel_lanes(int p) const)[kChannelLanes] { return w_[p]; }

  private:
    T w_[std::size_t(kLobes)][std::size_t(kChannelLanes)];
    bool any_ = false;
};

// Empty when the controls are valid, else one message per bad field naming it, its value
// and the allowed range. Never throws.
namespace detail {
// Every control inside its range (validate()'s test, without the message; device-callable).
template <typename T> HAIRSCATTER_HD bool controls_in_range(const LobeControls<T>& c) {
    const T max = kMaxLobeGain<T>;
    bool ok = (c.alpha_override & ~7u) == 0u;
    for (int p = 0; p < LobeControls<T>::kLobes; ++p) {
        ok = ok && in_range(c.gain[p], T(0), max);
        for (int ch = 0; ch < 3; ++ch) ok = ok && in_range(c.tint[p][ch], T(0), max);
    }
    for (int p = 0; p < 3; ++p) ok = ok && in_range(c.lobe_alpha(p, T(0)), -kMaxCuticleTilt<T>, kMaxCuticleTilt<T>);
    return ok;
}
}  // namespace detail

template <typename T> std::string validate(const LobeControls<T>& c) {
    using detail::in_range;
    const T max = kMaxLobeGain<T>;
    if (detail::controls_in_range(c)) return std::string();
    detail::Complaints bad;
    const char* lobe[4] = {"r", "tt", "trt", "residual"};
    const char* channel = "rgb";
    for (int p = 0; p < LobeControls<T>::kLobes; ++p) {
        if (!in_range(c.gain[p], T(0), max)) bad.add(std::string("gain_") + lobe[p], double(c.gain[p]), "[0, 1e6]");
        for (int ch = 0; ch < 3; ++ch)
            if (!in_range(c.tint[p][ch], T(0), max))
                bad.add(std::string("tint_") + lobe[p] + "." + channel[ch], double(c.tint[p][ch]), "[0, 1e6]");
    }
    for (int p = 0; p < 3; ++p)
        if (!in_range(c.lobe_alpha(p, T(0)), -kMaxCuticleTilt<T>, kMaxCuticleTilt<T>))
            bad.add(std::string("alpha_") + lobe[p], double(c.alpha[p]), "[-pi/8, pi/8] radians");
    if ((c.alpha_override & ~7u) != 0u)
        bad.add("alpha_override", double(c.alpha_override), "bits 0 (R), 1 (TT), 2 (TRT)");
    return bad.str();
}

// Throws std::invalid_argument with validate()'s message when the controls are bad
// (without exceptions: prints it and aborts).
template <typename T> void require_valid(const LobeControls<T>& c) { detail::throw_if_invalid(validate(c), "lobe controls"); }

// The controls, after require_valid: for a material's member-initialiser list.
template <typename T> const LobeControls<T>& validated(const LobeControls<T>& c) {
    require_valid(c);
    return c;
}

}  // namespace hairscatter
