// hairscatter — physically based hair and fur scattering, header-only.
// The umbrella header of the single-fiber core: include this, or the individual headers
// below. Dual scattering (host-side tables, density grids) has its own: <hairscatter/dual.hpp>.
// Comments citing docs/<page>.md mean the repository's docs/ directory, which an install
// (and the libhairscatter-dev package) puts in <prefix>/share/doc/hairscatter/<page>.md.
#pragma once

#include "config.hpp"
#include "math/constants.hpp"
#include "math/functions.hpp"
#include "math/elementary.hpp"
#include "math/distributions.hpp"
#include "fiber/params.hpp"
#include "fiber/pigments.hpp"
#include "fiber/spectral.hpp"
#include "fiber/strand_variation.hpp"
#include "fiber/frame.hpp"
#include "fiber/hit.hpp"
#include "fiber/ellipse.hpp"
#include "lobes/attenuation.hpp"
#include "lobes/azimuthal.hpp"
#include "lobes/longitudinal.hpp"
#include "lobes/tilt.hpp"
#include "lobes/deon_lobes.hpp"
#include "lobes/lobe_set.hpp"
#include "lobes/lobe_controls.hpp"
#include "lobes/microfacet.hpp"
#include "math/wrapped_gaussian.hpp"
#include "models/contract.hpp"
#include "models/chiang.hpp"
#include "models/chiang_spectral.hpp"
#include "models/chiang_batch.hpp"
#include "models/deon_farfield.hpp"
#include "models/tabulated.hpp"
#include "models/marschner.hpp"
#include "models/huang.hpp"
#include "models/fur.hpp"
