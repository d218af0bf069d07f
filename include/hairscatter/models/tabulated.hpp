// hairscatter — d'Eon et al. 2011's far-field fiber with the azimuthal lobes tabulated:
// N_p·A_p, integrated over h exactly as models/deon_farfield.hpp does, is computed once per
// material on a grid over (|φ|, cosθo) and interpolated bilinearly; M_p is the exact
// energy-conserving lobe (lobes/longitudinal.hpp) with the cuticle tilt on θo (docs/theory.md
// §3.3). For renderers that shade many fibers with shared parameters: the per-call cost no
// longer grows with the number of h nodes.
//
// The umbrella header of the model, by concern:
//   tabulated/options.hpp   TabulatedOptions: the resolution and how M_p is evaluated;
//   tabulated/view.hpp      TabulatedView: the tables' layout and lookups (device side);
//   tabulated/material.hpp  TabulatedMaterial: validation, the table build, ownership (host);
//   tabulated/fiber.hpp     TabulatedFiber: eval, pdf and sample over a view.
#pragma once

#include "tabulated/fiber.hpp"
#include "tabulated/material.hpp"
#include "tabulated/options.hpp"
#include "tabulated/view.hpp"
