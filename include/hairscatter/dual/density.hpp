// hairscatter — how much hair lies between a shading point and the light (docs/theory.md
// §5.2, Zinke et al. 2008's global multiple scattering). The umbrella header, by concern:
//   density_source.hpp     the density-source interface and dual_light(), which turns a
//                          source's counts into the BCSDF's per-point light state;
//   density_grid_view.hpp  the shipped grid's queries: trilinear lookup and the march of
//                          the fiber count along a ray (device side);
//   density_grid.hpp       the shipped grid itself, built from strands (host side);
//   count_field.hpp        counts along any direction precomputed from any source, so
//                          that a count is a lookup (host build, device queries).
#pragma once

#include "count_field.hpp"
#include "density_grid.hpp"
#include "density_grid_view.hpp"
#include "density_source.hpp"
