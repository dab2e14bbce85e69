"""Type stubs of `sawdrive` (units in the names: _n newtons, _m metres, _m_per_s m/s, _s seconds,
_rad radians, _n_per_m N/m)."""

import os
from typing import Any, Callable, Dict, Iterator, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from .errors import (
    ArgumentError as ArgumentError,
    PipelineError as PipelineError,
    SawdriveError as SawdriveError,
    SceneError as SceneError,
    SceneFileError as SceneFileError,
    SweepError as SweepError,
    SweepPointsFailed as SweepPointsFailed,
)

PathLike = Union[str, os.PathLike[str]]
ProgressArg = Union[None, bool, Callable[[float, Optional[int], Optional[int]], None]]
SceneArg = Union["Scene", PathLike, None]

__version__: str
DYNAMIC_MODEL_VERSION: int

def default_scene_toml() -> str: ...

class Scene:
    def __init__(self, path: Optional[PathLike] = None, overrides: Sequence[str] = ()) -> None: ...
    @classmethod
    def default(cls) -> Scene: ...
    @classmethod
    def load(cls, path: PathLike) -> Scene: ...
    @property
    def path(self) -> Optional[str]: ...
    @property
    def overrides(self) -> List[str]: ...
    @property
    def name(self) -> str: ...
    def set(self, key: str, value: Union[str, int, float, bool]) -> Scene: ...
    def copy(self) -> Scene: ...
    def resolve(self) -> Dict[str, Any]: ...
    def to_toml(self) -> str: ...

class _Record:
    data: Dict[str, Any]
    def __getattr__(self, name: str) -> Any: ...
    def to_dict(self) -> Dict[str, Any]: ...

class Springs(_Record):
    k_pn_n_per_m: float
    k_pt_n_per_m: float
    k_sn_n_per_m: float
    k_st_n_per_m: float
    k_n_n_per_m: float
    k_t_n_per_m: float

class _CurveResult(_Record):
    curve: npt.NDArray[np.float64]  # (n, 2): speed m/s, thrust N
    @property
    def curve_points(self) -> List[Dict[str, float]]: ...
    def curve_frame(self) -> Any: ...  # pandas.DataFrame

class DynamicResult(_CurveResult):
    stall_thrust_n: float
    no_load_speed_m_per_s: float
    efficiency: float
    stick_fraction: float
    friction_limit_n: float
    crest_speed_m_per_s: float
    effective_post_count: float
    model: str  # "periodic-average" | "transient" | "coupled"
    model_reason: str  # lumped runs: why this lumped model
    dynamics_reason: str  # why the lumped or the coupled model ran (model.dynamics, auto's criterion)
    lumped_error_estimate: Optional[float]  # relative; None when η is given
    model_error_estimate: Optional[float]  # relative error of the model that ran
    warnings: List[Any]
    wall_time_s: float
    effective_ratio: float
    effective_ratio_source: str  # "given" | "fem"
    folder: Optional[str]

class RunResult(_CurveResult):
    stall_thrust_n: float
    no_load_speed_m_per_s: float
    efficiency: float
    stick_fraction: float
    effective_contact_ratio: float
    effective_contact_ratio_source: str
    effective_post_count: float
    model: str
    model_reason: str
    lumped_error_estimate: Optional[float]  # relative; None when η is given
    coupled: Optional[Dict[str, Any]]  # the coupled model's figures when it ran
    springs: Dict[str, float]
    timings: Dict[str, float]
    files: List[str]
    folder: Optional[str]

class StaticResult(_Record):
    effective_contact_ratio: Optional[float]
    effective_ratio: Optional[float]
    load_sharing: float
    contact_fraction: float
    complementarity_residual: float
    iterations: int
    posts_in_strip: int
    posts_total: int
    preload_n: float
    cached: bool
    content_hash: str
    notes: List[str]
    folder: Optional[str]
    report: Dict[str, Any]
    phase_rad: npt.NDArray[np.float64]  # (phases,)
    post_x_m: npt.NDArray[np.float64]  # (posts,)
    post_forces_n: npt.NDArray[np.float64]  # (phases, posts)
    post_gaps_m: npt.NDArray[np.float64]  # (phases, posts)
    in_contact: npt.NDArray[np.bool_]  # (phases, posts)

class SweepResult:
    data: Dict[str, Any]
    rows: List[Dict[str, Any]]
    folder: str
    resumed: int
    files: List[str]
    failures: List[Tuple[str, str]]
    def records(self) -> Iterator[Dict[str, Any]]: ...
    def frame(self) -> Any: ...  # pandas.DataFrame
    def __len__(self) -> int: ...

def springs(
    scene: SceneArg = None, *, diameter: Optional[str] = None, slider: str = "si", stator: str = "linbo3"
) -> Springs: ...
def static(
    scene: SceneArg = None, *, out: Optional[PathLike] = None,
    cache: Union[PathLike, bool, None] = None, progress: ProgressArg = None,
) -> StaticResult: ...
def dynamic(
    scene: SceneArg = None, *, out: Optional[PathLike] = None,
    cache: Union[PathLike, bool, None] = None, progress: ProgressArg = None,
) -> DynamicResult: ...
def run(
    scene: SceneArg = None, *, out: Optional[PathLike] = "out",
    cache: Union[PathLike, bool, None] = None, progress: ProgressArg = None,
) -> RunResult: ...
def sweep(
    file: PathLike, *, out: PathLike = "out", jobs: Optional[int] = None, progress: ProgressArg = None
) -> SweepResult: ...
def sweep_points(file: PathLike) -> List[Dict[str, Any]]: ...

UQ_OUTPUTS: Tuple[str, ...]

class UqResult(_Record):
    samples: int
    seed: int
    fidelity: str
    scatter: Dict[str, Any]  # SI: height_scatter_m, tilt_x_m, tilt_y_m, bow_m, friction, preload_n, diameter_m
    input_names: List[str]
    effective_contact_ratio: Dict[str, Any]  # band: samples, mean, sd, p5, p50, p95, p5_ci, ...
    stall_thrust_n: Dict[str, Any]  # band (N)
    no_load_speed_m_per_s: Dict[str, Any]  # band (m/s)
    max_output_power_w: Dict[str, Any]  # band (W)
    efficiency: Dict[str, Any]  # band
    deterministic: List[Tuple[str, float]]
    sensitivity: List[Tuple[str, List[Dict[str, Any]]]]
    resumed_samples: int
    failed_samples: List[Tuple[int, str]]
    sample_cost_s: float
    wall_time_s: float
    files: List[str]
    folder: str
    curve_band: npt.NDArray[np.float64]  # (n, 4): speed m/s, thrust P5, P50, P95 (N)
    def bands_frame(self) -> Any: ...  # pandas.DataFrame
    def samples_frame(self) -> Any: ...  # pandas.DataFrame

class DesignResult(_Record):
    name: str
    optimum: Dict[str, Any]  # variables (SI, unit in the name), objective, objective_value, fidelity, outputs
    baseline: Optional[Dict[str, Any]]
    quantile: Optional[float]
    sensitivity: List[Dict[str, Any]]
    evaluations: List[Dict[str, Any]]
    cost: List[Tuple[str, int, float]]  # fidelity, evaluations, mean wall time each (s)
    wall_time_s: float
    files: List[str]
    folder: str
    def evaluations_frame(self) -> Any: ...  # pandas.DataFrame

def uq(
    scene: SceneArg = None, *, samples: int, scatter: Optional[Dict[str, Any]] = None, seed: int = 1,
    out: PathLike = "out", patch: bool = False, progress: ProgressArg = None,
) -> UqResult: ...
def design(file: PathLike, *, out: PathLike = "out", progress: ProgressArg = None) -> DesignResult: ...
