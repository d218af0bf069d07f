// hairscatter — dual scattering's per-render settings and per-point state, each value with
// one owner: the settings (formulation, density factors) are fixed when the tables are
// built and travel with them; the per-point state is only what a renderer learns at a hit
// (was the shadow ray blocked, how much hair lies toward the light and beyond the point).
#pragma once

#include <limits>

#include <glm/glm.hpp>

#include "../config.hpp"

namespace hairscatter {

// Which dual-scattering formulation the tables and the BCSDF implement (docs/dual.md).
//   kImproved  the default: Zinke et al. 2008's global term with the forward-scattered light
//              spread over a half-circle of azimuths around the light's direction (the
//              window W_p of each lobe instead of a forward-only average), the forward
//              transmittance conditioned on the shadow ray having been blocked, the local
//              backscattering summed to all orders by the 1D adding formula over the hair
//              that lies beyond the point, and density factors d_f = d_b = 1.
//   kZinke2008 the paper's text (Zinke et al. 2008 eqs. 6–15): forward-only global lobes,
//              T_f = a_f^n with the grid's unconditional n, A_b = A_1 + A_3, d_f = d_b = 0.7.
enum class DualFormulation : int { kImproved = 0, kZinke2008 = 1 };

template <typename T> struct DualScatteringSettings {
    DualFormulation formulation = DualFormulation::kImproved;
    T d_f = T(1);  // forward density factor (multiplies the scattered term once)
    T d_b = T(1);  // backward density factor (multiplies f_back; enters σ_b)

    static DualScatteringSettings improved() { return {}; }
    static DualScatteringSettings zinke2008() { return {DualFormulation::kZinke2008, T(0.7), T(0.7)}; }
};

// kUnbounded<T>: "until the ray leaves the hair" for a density source's max_distance, and
// "a deep volume" for DualScatteringLight::beyond. A constexpr variable, so device code may
// read it (numeric_limits' members are host functions to a CUDA compiler).
template <typename T> inline constexpr T kUnbounded = std::numeric_limits<T>::infinity();

// What the renderer knows at one shading point about the light arriving along one wi.
template <typename T> struct DualScatteringLight {
    // 1 if a shadow ray from the point reaches the light past all hair, 0 if hair blocks
    // it; values between mix the two states linearly.
    T direct_fraction = T(1);
    // The expected number of fibers a ray from the point toward the light crosses, as a
    // density source reports it (unconditional; the improved formulation conditions it on
    // the shadow ray having been blocked).
    T n = T(0);
    // n is one ray's exact count (a renderer that counts the fibers its shadow ray crosses),
    // not an expectation: the improved formulation uses it as it is. Conditioning an exact
    // count again would read one fiber as 1.58 (E[N | N ≥ 1] of a Poisson mean of 1).
    bool exact_count = false;
    // The expected number of fibers beyond the point along the light's direction of travel
    // (a density query along -wi): how much hair is there to scatter light back. Only the
    // improved formulation reads it; kUnbounded means a deep volume.
    T beyond = kUnbounded<T>;
    // A renderer that accumulated T_f = Π a_f and σ̄²_f = Σ β̄²_f itself (a deep opacity
    // map) sets use_transmittance; n is then ignored.
    bool use_transmittance = false;
    glm::vec<3, T> T_f{T(1)};
    T sigma2_f = T(0);
};

}  // namespace hairscatter
