// hairscatter — dual scattering (Zinke et al. 2008): per-fiber tables, the hair density
// interface, and the dual-scattering BCSDF. Includes the single-fiber core.
#pragma once

#include "hairscatter.hpp"
#include "math/quadrature.hpp"
#include "dual/tables.hpp"
#include "dual/bcsdf.hpp"
#include "dual/density.hpp"
