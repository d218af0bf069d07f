# Type stubs of the package hairscatter: the extension's names (_core.pyi) and the helpers
# written in Python (__init__.py).
from typing import Any, Tuple

import numpy as np
import numpy.typing as npt

from ._core import Chiang as Chiang
from ._core import DeonFarField as DeonFarField
from ._core import DualSample as DualSample
from ._core import DualScatteringBcsdf as DualScatteringBcsdf
from ._core import DualTables as DualTables
from ._core import FiberFrame as FiberFrame
from ._core import FiberModel as FiberModel
from ._core import Huang as Huang
from ._core import LobeControls as LobeControls
from ._core import Marschner as Marschner
from ._core import Sample as Sample
from ._core import StrandVariation as StrandVariation
from ._core import Tabulated as Tabulated
from ._core import __version__ as __version__
from ._core import melanin_concentrations as melanin_concentrations
from ._core import sigma_a_from_color as sigma_a_from_color
from ._core import sigma_a_from_concentrations as sigma_a_from_concentrations
from ._core import sigma_a_from_dye as sigma_a_from_dye
from ._core import sigma_a_from_melanin as sigma_a_from_melanin
from ._core import sigma_a_from_melanin_amount as sigma_a_from_melanin_amount
from ._core import sigma_a_from_melanin_redness as sigma_a_from_melanin_redness
from ._core import sigma_a_from_pigments as sigma_a_from_pigments

LOBE_NAMES: Tuple[str, ...]
DUAL_COMPONENT_NAMES: Tuple[str, ...]

def direction(theta: npt.ArrayLike, phi: npt.ArrayLike) -> npt.NDArray[np.float64]: ...
def angles(w: npt.ArrayLike) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
