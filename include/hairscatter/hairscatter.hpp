// hairscatter — physically based hair and fur scattering, header-only.
// The umbrella header: include this, or the individual headers below.
#pragma once

#include "config.hpp"
#include "math/constants.hpp"
#include "math/functions.hpp"
#include "math/elementary.hpp"
#include "math/distributions.hpp"
#include "fiber/params.hpp"
#include "fiber/frame.hpp"
#include "lobes/attenuation.hpp"
#include "lobes/azimuthal.hpp"
#include "lobes/longitudinal.hpp"
#include "lobes/tilt.hpp"
#include "models/chiang.hpp"
#include "math/quadrature.hpp"
#include "dual/tables.hpp"
