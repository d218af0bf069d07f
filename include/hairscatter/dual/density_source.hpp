// hairscatter — the density-source interface of dual scattering (docs/theory.md §5.2,
// Zinke et al. 2008's global multiple scattering): how much hair lies between a shading
// point and the light, asked of any type that can answer, and turned into the per-point
// light state the dual-scattering BCSDF reads (dual/settings.hpp).
//
// A density source is any type D with the member
//
//     T fibers_crossed(const glm::vec<3, T>& origin, const glm::vec<3, T>& direction,
//                      T max_distance) const;
//
// that returns the expected number n ≥ 0 of fibers a ray crosses between origin and
// origin + max_distance·direction (direction is a unit vector; max_distance may be
// kUnbounded<T>, meaning "until the ray leaves the hair"). Nothing else is required: a
// renderer with an OpenVDB grid or a deep-opacity map wraps it in such a type and passes
// it to dual_light(); DensityGrid (dual/density_grid.hpp) is the one shipped with the
// library. The forward transmittance and spread that follow from n are dual_forward's
// (dual/bcsdf.hpp: conditioned on the shadow ray having been blocked in the improved
// formulation, a_f^n in Zinke 2008's).
#pragma once

#include <type_traits>
#include <utility>

#include <glm/glm.hpp>

#include "../config.hpp"
#include "settings.hpp"

namespace hairscatter {

namespace detail {
template <typename D, typename T, typename = void> struct is_density_source_impl : std::false_type {};
template <typename D, typename T>
struct is_density_source_impl<
    D, T,
    std::void_t<decltype(std::declval<const D&>().fibers_crossed(std::declval<const glm::vec<3, T>&>(),
                                                                 std::declval<const glm::vec<3, T>&>(),
                                                                 std::declval<T>()))>>
    : std::is_convertible<decltype(std::declval<const D&>().fibers_crossed(std::declval<const glm::vec<3, T>&>(),
                                                                           std::declval<const glm::vec<3, T>&>(),
                                                                           std::declval<T>())),
                          T> {};
}  // namespace detail

// True when D answers density queries in real type T (see the top of this header).
template <typename D, typename T> struct is_density_source : detail::is_density_source_impl<D, T> {};
template <typename D, typename T> inline constexpr bool is_density_source_v = is_density_source<D, T>::value;

// The light state at x for the light along wi (unit), from any density source: the
// direct fraction the renderer's shadow ray found, the count n toward the light (up to
// max_distance, the light's distance; asked only when hair blocks some of the light) and,
// when with_beyond, the count beyond x along the light's direction of travel (-wi; only
// the improved formulation reads it, and a renderer may skip it where it cannot matter).
// Host and device when D's fibers_crossed is (nvcc would otherwise warn for a host-only D).
#if defined(__NVCC__)
#pragma nv_exec_check_disable
#endif
template <typename D, typename T>
HAIRSCATTER_HD DualScatteringLight<T> dual_light(const D& density, const glm::vec<3, T>& x, const glm::vec<3, T>& wi,
                                                 T direct_fraction, T max_distance = kUnbounded<T>,
                                                 bool with_beyond = true) {
    static_assert(is_density_source_v<D, T>,
                  "hairscatter: not a density source: the type needs a member "
                  "T fibers_crossed(const glm::vec<3, T>& origin, const glm::vec<3, T>& direction, "
                  "T max_distance) const (see hairscatter/dual/density_source.hpp)");
    DualScatteringLight<T> light;
    light.direct_fraction = direct_fraction;
    light.n = direct_fraction < T(1) ? T(density.fibers_crossed(x, wi, max_distance)) : T(0);
    if (with_beyond) light.beyond = T(density.fibers_crossed(x, -wi, kUnbounded<T>));
    return light;
}

}  // namespace hairscatter
