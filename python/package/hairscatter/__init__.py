"""hairscatter: physically based hair scattering, vectorised over numpy arrays.

The C++ header-only library's fiber models (Chiang, DeonFarField, Tabulated, Marschner,
Huang), their dual-scattering tables and BCSDF, and the colour and lobe controls, with
every call one C++ loop over (N, 3) arrays of directions. See docs/python.md.
"""

import numpy as _np

from ._core import (  # noqa: F401
    Chiang,
    DeonFarField,
    DualSample,
    DualScatteringBcsdf,
    DualTables,
    FiberFrame,
    FiberModel,
    Huang,
    LobeControls,
    Marschner,
    Sample,
    StrandVariation,
    Tabulated,
    __version__,
    melanin_concentrations,
    sigma_a_from_color,
    sigma_a_from_concentrations,
    sigma_a_from_dye,
    sigma_a_from_melanin,
    sigma_a_from_melanin_amount,
    sigma_a_from_melanin_redness,
    sigma_a_from_pigments,
)

#: Sample.lobe's values: the index of the lobe drawn (8: no sample).
LOBE_NAMES = ("R", "TT", "TRT", "residual", "dual_back", "dual_global", "dual_global_back", "uniform", "none")
#: DualSample.component's values.
DUAL_COMPONENT_NAMES = ("single", "back", "global", "global_back", "uniform")


def direction(theta, phi):
    """Unit directions in the fiber frame from inclination θ (sinθ = w.x) and azimuth φ.

    θ and φ (radians) broadcast against each other; the result has shape (..., 3).
    """
    theta, phi = _np.broadcast_arrays(_np.asarray(theta, dtype=float), _np.asarray(phi, dtype=float))
    c = _np.cos(theta)
    return _np.stack([_np.sin(theta), c * _np.cos(phi), c * _np.sin(phi)], axis=-1)


def angles(w):
    """(θ, φ) of fiber-frame directions w, (..., 3): θ = asin(w.x), φ = atan2(w.z, w.y)."""
    w = _np.asarray(w, dtype=float)
    n = _np.linalg.norm(w, axis=-1)
    return _np.arcsin(_np.clip(w[..., 0] / n, -1.0, 1.0)), _np.arctan2(w[..., 2], w[..., 1])
