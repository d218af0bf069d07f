// hairscatter — dual scattering (Zinke et al. 2008): per-fiber tables, the hair density
// interface, the dual-scattering BCSDF and the two-stream estimator at the arrival direction.
// Includes the single-fiber core.
#pragma once

#include "hairscatter.hpp"
#include "math/quadrature.hpp"
#include "dual/tables.hpp"
#include "dual/spectral_tables.hpp"
#include "dual/bcsdf.hpp"
#include "dual/two_stream.hpp"
#include "dual/density.hpp"
