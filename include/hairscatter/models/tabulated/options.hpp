// hairscatter — the tabulated far-field model's options: the tables' resolution and how M_p
// is evaluated (models/tabulated.hpp), and the placement of the table's rows over cosθo.
#pragma once

#include "../../config.hpp"
#include "../../lobes/farfield_quadrature.hpp"

namespace hairscatter {

// The table's resolution, fixed at construction.
//   phi_samples:   nodes over |φ| ∈ [0, π], equispaced (N_p is even in φ: the h rule is
//                  symmetric);
//   theta_samples: rows over cosθo ∈ [0, 1] (N_p·A_p depends on θo through η', the
//                  Fresnel cosine and the chord: smooth in cosθo and even in θo), placed at
//                  cosθo = y(1 + 2y)/3 for equispaced y, five times denser at grazing, where
//                  the curvature of Fresnel's F → 1 dominates the interpolation error, than
//                  at normal incidence (halves the error of equispaced rows);
//   h_nodes:       Gauss–Legendre nodes in γ of each row's h integral
//                  (lobes/farfield_quadrature.hpp), or kAutoNodes (0, the default) for
//                  FarFieldQuadrature::auto_nodes(β_n): 34 at β_n = 0.3, 24 for β_n ≥ 0.4,
//                  more for narrower detectors; options() reports the count used (build
//                  times: docs/performance.md).
// The default keeps the relative L1 error against the exact far-field model (64 h nodes)
// near 5e-4 for β_n ≥ 0.3 (tests/tabulated_test.cpp states the figures per resolution);
// narrower azimuthal lobes need proportionally more φ samples (the automatic h node count
// grows with them, as the exact model's does).
// How M_p is evaluated: kExact, d'Eon's formula per call (lobes/longitudinal.hpp); kTable,
// lobes/longitudinal_table.hpp's table of m_rows rows over |θo'| ∈ [0, π/2] and m_nodes
// nodes per row, renormalised per θo' so that the furnace stays exactly 1 and sampled by
// inverting the same piecewise-linear density (faster: no exponential or Bessel function
// per call; see TabulatedFiber for the cost and the accuracy).
enum class TabulatedLongitudinal { kExact, kTable };

struct TabulatedOptions {
    static constexpr int kMaxPhiSamples = 4096;
    static constexpr int kMaxThetaSamples = 1024;
    static constexpr int kMaxLongitudinalRows = 1024;
    static constexpr int kMaxLongitudinalNodes = 8192;

    static constexpr int kAutoNodes = FarFieldQuadrature<double>::kAutoNodes;

    int phi_samples = 96;
    int theta_samples = 28;
    int h_nodes = kAutoNodes;
    TabulatedLongitudinal longitudinal = TabulatedLongitudinal::kExact;
    int m_rows = 48;
    int m_nodes = 192;

    // The shipped resolutions besides the default: a quarter of its memory (and the fewest
    // h nodes auto_nodes ever picks, for the cheapest build), and four times it (h nodes
    // fixed at the accuracy tests' reference count).
    static constexpr TabulatedOptions coarse() { return {48, 16, 24}; }
    static constexpr TabulatedOptions fine() { return {192, 56, 64}; }
    // The speed preset: the default azimuthal table with M_p tabulated.
    static constexpr TabulatedOptions fast() { return {96, 28, kAutoNodes, TabulatedLongitudinal::kTable, 48, 192}; }
};

// Row y ∈ [0, 1] of the table ↔ cosθo (see theta_samples above).
HAIRSCATTER_HD inline double tabulated_row_cos(double y) { return y * (1 + 2 * y) / 3; }

}  // namespace hairscatter
