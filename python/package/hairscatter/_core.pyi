# Type stubs of the extension module hairscatter._core (python/src/*.cpp).
# tests/python/test_stubs.py checks that they name every class, method and argument.
from typing import Any, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

ArrayLike = npt.ArrayLike
Array = npt.NDArray[Any]
DType = Union[str, type, np.dtype[Any]]
Vec3 = Union[Sequence[float], npt.NDArray[Any]]

__version__: str

def sigma_a_from_concentrations(eumelanin: float, pheomelanin: float = 0.0) -> npt.NDArray[np.float64]: ...
def sigma_a_from_melanin(eumelanin: float, pheomelanin: float = 0.0) -> npt.NDArray[np.float64]: ...
def melanin_concentrations(melanin: float, redness: float = 0.0) -> Tuple[float, float]: ...
def sigma_a_from_melanin_amount(melanin: float, redness: float = 0.0) -> npt.NDArray[np.float64]: ...
def sigma_a_from_melanin_redness(melanin: float, redness: float = 0.0) -> npt.NDArray[np.float64]: ...
def sigma_a_from_dye(dye: Vec3, beta_n: float = 0.3) -> npt.NDArray[np.float64]: ...
def sigma_a_from_color(color: Vec3, beta_n: float = 0.3) -> npt.NDArray[np.float64]: ...
def sigma_a_from_pigments(
    melanin: float = 0.8, redness: float = 0.0, dye: Vec3 = (1.0, 1.0, 1.0), beta_n: float = 0.3
) -> npt.NDArray[np.float64]: ...

class LobeControls:
    def __init__(self, **kwargs: Union[float, Vec3, None]) -> None: ...
    @property
    def gain(self) -> Tuple[float, float, float, float]: ...
    @property
    def tint(self) -> npt.NDArray[np.float64]: ...
    @property
    def alpha(self) -> Tuple[Optional[float], Optional[float], Optional[float]]: ...
    def validate(self) -> str: ...

class StrandVariation:
    def __init__(
        self,
        seed: int = 0,
        melanin: Tuple[float, float] = (0.8, 0.8),
        redness: Tuple[float, float] = (0.0, 0.0),
        roughness_scale: Tuple[float, float] = (1.0, 1.0),
    ) -> None: ...
    def at(self, strand: int) -> dict[str, float]: ...
    def params(
        self,
        strand: int,
        eta: float = 1.55,
        beta_m: float = 0.3,
        beta_n: float = 0.3,
        alpha: float = 0.03490658503988659,
        dye: Vec3 = (1.0, 1.0, 1.0),
    ) -> dict[str, Any]: ...

class FiberFrame:
    def __init__(self, tangent: Vec3, reference: Vec3) -> None: ...
    @staticmethod
    def facing(tangent: Vec3, reference: Vec3, wo: Vec3) -> FiberFrame: ...
    @property
    def x(self) -> npt.NDArray[np.float64]: ...
    @property
    def y(self) -> npt.NDArray[np.float64]: ...
    @property
    def z(self) -> npt.NDArray[np.float64]: ...
    def to_local(self, w: ArrayLike) -> npt.NDArray[np.float64]: ...
    def to_world(self, w: ArrayLike) -> npt.NDArray[np.float64]: ...

class Sample:
    @property
    def wi(self) -> Array: ...
    @property
    def weight(self) -> Array: ...
    @property
    def pdf(self) -> Union[Array, float]: ...
    @property
    def lobe(self) -> npt.NDArray[np.int8]: ...

class DualTables:
    @property
    def dtype(self) -> np.dtype[Any]: ...
    @property
    def size(self) -> int: ...
    @property
    def psi_samples(self) -> int: ...
    @property
    def lobes(self) -> int: ...
    @property
    def h_nodes(self) -> int: ...
    @property
    def formulation(self) -> str: ...
    def arrays(self) -> dict[str, Array]: ...
    def lookup(self, theta: ArrayLike) -> dict[str, Array]: ...
    def save(self, path: str) -> None: ...
    @staticmethod
    def load(path: str, dtype: DType = "float64") -> DualTables: ...

class FiberModel:
    @property
    def dtype(self) -> np.dtype[Any]: ...
    @property
    def near_field(self) -> bool: ...
    @property
    def params(self) -> dict[str, Any]: ...
    def eval(self, wo: ArrayLike, wi: ArrayLike, h: Optional[ArrayLike] = None) -> Array: ...
    def pdf(self, wo: ArrayLike, wi: ArrayLike, h: Optional[ArrayLike] = None) -> Union[Array, float]: ...
    def eval_pdf(
        self, wo: ArrayLike, wi: ArrayLike, h: Optional[ArrayLike] = None
    ) -> Tuple[Array, Union[Array, float]]: ...
    def sample(self, wo: ArrayLike, u: ArrayLike, h: Optional[ArrayLike] = None) -> Sample: ...
    def albedo(self, wo: ArrayLike, h: Optional[ArrayLike] = None) -> Array: ...
    def lobe_split(
        self, wo: ArrayLike, h: Optional[ArrayLike] = None, centre: ArrayLike = 0.0
    ) -> Tuple[Array, Array]: ...
    def dual_tables(
        self,
        theta_samples: int = 64,
        psi_samples: int = 33,
        h_nodes: int = 32,
        formulation: str = "improved",
        d_f: Optional[float] = None,
        d_b: Optional[float] = None,
    ) -> DualTables: ...

class Chiang(FiberModel):
    def __init__(
        self,
        *,
        eta: float = 1.55,
        beta_m: float = 0.3,
        beta_n: float = 0.3,
        alpha: float = 0.03490658503988659,
        sigma_a: Vec3 = (0.0, 0.0, 0.0),
        lobes: Union[str, Sequence[str]] = "all",
        controls: Optional[LobeControls] = None,
        dtype: DType = "float64",
    ) -> None: ...

class DeonFarField(FiberModel):
    def __init__(
        self,
        *,
        eta: float = 1.55,
        beta_m: float = 0.3,
        beta_n: float = 0.3,
        alpha: float = 0.03490658503988659,
        sigma_a: Vec3 = (0.0, 0.0, 0.0),
        nodes: int = 0,
        controls: Optional[LobeControls] = None,
        dtype: DType = "float64",
    ) -> None: ...

class Tabulated(FiberModel):
    def __init__(
        self,
        *,
        eta: float = 1.55,
        beta_m: float = 0.3,
        beta_n: float = 0.3,
        alpha: float = 0.03490658503988659,
        sigma_a: Vec3 = (0.0, 0.0, 0.0),
        preset: Optional[str] = None,
        phi_samples: int = 96,
        theta_samples: int = 28,
        h_nodes: int = 0,
        longitudinal: str = "exact",
        m_rows: int = 48,
        m_nodes: int = 192,
        controls: Optional[LobeControls] = None,
        dtype: DType = "float64",
    ) -> None: ...

class Marschner(FiberModel):
    def __init__(
        self,
        *,
        eta: float = 1.55,
        sigma_a: Vec3 = (0.0, 0.0, 0.0),
        alpha_r: float = -0.1308996938995747,
        beta_r: float = 0.1308996938995747,
        beta_n: float = 0.3,
        eccentricity: float = 1.0,
        caustic_width: float = 0.2617993877991494,
        caustic_gain: float = 0.5,
        caustic_fade: float = 0.3,
        caustic_dh_max: float = 0.5,
        nodes: int = 7,
        controls: Optional[LobeControls] = None,
        dtype: DType = "float64",
    ) -> None: ...

class Huang(FiberModel):
    def __init__(
        self,
        *,
        eta: float = 1.55,
        roughness: float = 0.3,
        alpha: float = 0.03490658503988659,
        sigma_a: Vec3 = (0.0, 0.0, 0.0),
        aspect_ratio: float = 1.0,
        orientation: float = 0.0,
        offset_nodes: int = 0,
        tt_points: int = 0,
        trt_per_tt: int = 0,
        controls: Optional[LobeControls] = None,
        dtype: DType = "float64",
    ) -> None: ...

class DualSample:
    @property
    def wi(self) -> Array: ...
    @property
    def pdf(self) -> Union[Array, float]: ...
    @property
    def component(self) -> npt.NDArray[np.int8]: ...
    @property
    def f(self) -> Array: ...
    @property
    def weight(self) -> Array: ...

class DualScatteringBcsdf:
    def __init__(self, model: FiberModel, tables: DualTables) -> None: ...
    @property
    def model(self) -> FiberModel: ...
    def eval(
        self,
        wo: ArrayLike,
        wi: ArrayLike,
        h: Optional[ArrayLike] = None,
        direct_fraction: ArrayLike = 1.0,
        n: ArrayLike = 0.0,
        beyond: ArrayLike = ...,
    ) -> Array: ...
    def pdf(
        self, wo: ArrayLike, wi: ArrayLike, h: Optional[ArrayLike] = None, spread: ArrayLike = 0.0
    ) -> Union[Array, float]: ...
    def sample(
        self,
        wo: ArrayLike,
        u: ArrayLike,
        h: Optional[ArrayLike] = None,
        spread: ArrayLike = 0.0,
        direct_fraction: ArrayLike = 1.0,
        n: ArrayLike = 0.0,
        beyond: ArrayLike = ...,
    ) -> DualSample: ...
