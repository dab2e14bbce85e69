"""sawdrive from Python: the SAW-motor friction-drive simulator's scenes, springs, stages and sweeps.

The same capabilities, names and units as the ``sawdrive`` command line::

    import sawdrive
    s = sawdrive.Scene.default()          # the paper's motor (`sawdrive scene`)
    s.set("preload", "20 N")              # `--set preload=20N`
    r = sawdrive.dynamic(s)               # `sawdrive dynamic --set preload=20N --json`
    r.stall_thrust_n, r.no_load_speed_m_per_s, r.curve   # N, m/s, array [[speed m/s, thrust N]]

Units: SI in every result, the unit in each name (``preload_n``, ``gap_m``); scene values take
human units as text (``"20 um"``, ``"9.61 MHz"``, ``"40 N"``). Signs and definitions:
``docs/physics.md`` of the repository.

Long calls (:func:`static`, :func:`dynamic`, :func:`run`, :func:`sweep`, :func:`uq`,
:func:`design`) run without holding the GIL, show a progress line where a terminal or notebook
is attached, and raise ``KeyboardInterrupt`` on Ctrl-C without writing half a result. What stops
on Ctrl-C: a sweep starts no further point and its running points stop inside their stages (the
points it saved are kept for a rerun, as the command line's); :func:`static`, :func:`dynamic`
and :func:`run` stop before their next contact solve or speed–thrust curve point (transient
run). Not interrupted, and finished in the background first: an FEM factorisation (seconds for
the default strip), a gmsh mesh generation, the whole slider's static solve, the coupled dynamic
model; :func:`uq` finishes its samples in the background (saved for a rerun) and commits
nothing; :func:`design` finishes in the background and commits its complete results folder.
Errors are
:mod:`sawdrive.errors` exceptions with the command line's one-line messages.
"""

from __future__ import annotations

import atexit
import math
import numbers
import os
from pathlib import Path
from typing import Any, Dict, Iterator, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native

# Calls interrupted with Ctrl-C finish in the background; if the interpreter exits first, their
# scratch folders (``OUT/.sawdrive-python-*``) are removed here.
atexit.register(_native.remove_scratch_folders)
from ._progress import ProgressArg, attached as _attached, callback
from .errors import (
    ArgumentError,
    PipelineError,
    SawdriveError,
    SceneError,
    SceneFileError,
    SweepError,
    SweepPointsFailed,
)

__all__ = [
    "Scene",
    "Springs",
    "StaticResult",
    "DynamicResult",
    "RunResult",
    "SweepResult",
    "UqResult",
    "DesignResult",
    "springs",
    "static",
    "dynamic",
    "run",
    "sweep",
    "sweep_points",
    "uq",
    "design",
    "default_scene_toml",
    "DYNAMIC_MODEL_VERSION",
    "SawdriveError",
    "SceneError",
    "SceneFileError",
    "SweepError",
    "ArgumentError",
    "PipelineError",
    "SweepPointsFailed",
]

__version__ = "0.1.0"

#: Version of the dynamic model's numbers (part of a sweep point's hash).
DYNAMIC_MODEL_VERSION: int = _native.DYNAMIC_MODEL_VERSION

PathLike = Union[str, "os.PathLike[str]"]


def default_scene_toml() -> str:
    """The embedded default scene (the paper's motor) as TOML: what ``sawdrive scene`` prints."""
    return _native.default_scene_toml()


def _override_text(key: str, value: Any) -> str:
    """``value`` as ``--set`` takes it; refuses other Python types with a ValueError naming ``key``."""
    if isinstance(value, str):
        return value
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        number = float(value)
        if not math.isfinite(number):
            raise SceneError(f"{key}: {number} is not a finite number")
        return repr(number)
    raise SceneError(
        f"{key}: expected text with a unit (\"20 N\", \"50x50\"), a number or a bool, "
        f"got {type(value).__name__} {value!r}"
    )


class Scene:
    """A scene: the embedded default, optionally a TOML file, and ``key=value`` overrides.

    Build one with :meth:`Scene.default` or :meth:`Scene.load`, change it with :meth:`set`.
    Every change is checked at once (the scene is resolved): a bad key, type, unit or value
    raises :class:`~sawdrive.errors.SceneError` (a ``ValueError``) naming the key, and the
    scene keeps its earlier overrides. The scene file is read when the scene is built and at
    each :meth:`set`; the stages use that resolved scene (build the scene again after editing
    its file).
    """

    __slots__ = ("_path", "_overrides", "_native")

    def __init__(self, path: Optional[PathLike] = None, overrides: Sequence[str] = ()):
        self._path = None if path is None else os.fspath(path)
        self._overrides: List[str] = list(overrides)
        self._native = _native.NativeScene(self._path, self._overrides)

    @classmethod
    def default(cls) -> "Scene":
        """The embedded default scene: the source paper's motor (``sawdrive scene``)."""
        return cls()

    @classmethod
    def load(cls, path: PathLike) -> "Scene":
        """A TOML scene file; keys it omits come from the default scene. A relative
        ``static.mesh`` is relative to the file."""
        return cls(path)

    @property
    def path(self) -> Optional[str]:
        """The scene file, or ``None`` for the default scene."""
        return self._path

    @property
    def overrides(self) -> List[str]:
        """The ``key=value`` overrides in the order given (``--set`` each)."""
        return list(self._overrides)

    @property
    def name(self) -> str:
        """The scene's name (it names the results folder ``OUT/<name>/``)."""
        return self._native.name

    def set(self, key: str, value: Any) -> "Scene":
        """Override one scene key, as ``--set key=value``: ``s.set("preload", "20 N")``,
        ``s.set("posts.count", "50x50")``, ``s.set("effective_ratio", 0.36)``.

        ``value``: text with a unit for dimensional keys, a number or a bool otherwise. Short
        names: ``preload``, ``load``, ``friction`` (static and kinetic), ``effective_ratio``,
        ``mass``. Returns the scene (calls chain).
        """
        if not isinstance(key, str) or not key or "=" in key:
            raise SceneError(f"{key!r}: a scene key is a dotted name like posts.count")
        text = f"{key}={_override_text(key, value)}"
        self._native = _native.NativeScene(self._path, self._overrides + [text])
        self._overrides.append(text)
        return self

    def copy(self) -> "Scene":
        """An independent copy (same file, same overrides; the resolved scene is shared, it
        never changes)."""
        twin = Scene.__new__(Scene)
        twin._path, twin._overrides, twin._native = self._path, list(self._overrides), self._native
        return twin

    def resolve(self) -> Dict[str, Any]:
        """The scene resolved to SI units as a dict (``sawdrive scene --resolve --json``)."""
        return self._native.to_dict()

    def to_toml(self) -> str:
        """The resolved scene as TOML, SI units (``sawdrive scene --resolve``)."""
        return self._native.to_toml()

    def _args(self) -> Tuple[Optional[str], List[str]]:
        return self._path, list(self._overrides)

    def __repr__(self) -> str:
        source = "default" if self._path is None else repr(self._path)
        return f"Scene({source}, overrides={self._overrides!r})"


def _as_scene(scene: Union[Scene, PathLike, None]) -> Scene:
    if scene is None:
        return Scene.default()
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, (str, os.PathLike)):
        return Scene.load(scene)
    raise ArgumentError(f"scene: expected a sawdrive.Scene or a path, got {type(scene).__name__}")


class _Record:
    """A result: its fields (as the library serialises them, SI) as attributes and in ``data``."""

    def __init__(self, data: Dict[str, Any]):
        object.__setattr__(self, "data", data)

    def __getattr__(self, name: str) -> Any:
        try:
            return self.data[name]
        except KeyError:
            raise AttributeError(f"{type(self).__name__} has no field {name!r}") from None

    def __dir__(self) -> List[str]:
        return sorted(set(super().__dir__()) | set(self.data))

    def to_dict(self) -> Dict[str, Any]:
        """The fields as a plain dict (JSON-compatible, SI units)."""
        return dict(self.data)

    def __repr__(self) -> str:
        scalars = {k: v for k, v in self.data.items() if isinstance(v, (int, float, str)) and not isinstance(v, bool)}
        shown = ", ".join(f"{k}={v!r}" for k, v in list(scalars.items())[:6])
        return f"{type(self).__name__}({shown}, …)"


class Springs(_Record):
    """The four Johnson springs of one post and their series values (N/m): ``k_pn_n_per_m``,
    ``k_pt_n_per_m`` (slider, bonded), ``k_sn_n_per_m``, ``k_st_n_per_m`` (stator,
    frictional), ``k_n_n_per_m``, ``k_t_n_per_m`` (in series)."""


def _pandas():
    try:
        import pandas
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("this needs pandas: pip install pandas") from e
    return pandas


#: The dynamic stage's result (native; see its docstring): every field of ``sawdrive dynamic
#: --json`` as an attribute, ``curve`` (numpy (n, 2): speed m/s, thrust N), ``curve_frame()``,
#: ``effective_ratio``, ``effective_ratio_source``, ``folder``. Fields convert when first read.
DynamicResult = _native.DynamicResult

#: The whole pipeline's ``summary.json`` as attributes, ``curve`` and ``folder`` (native).
RunResult = _native.RunResult


class StaticResult(_Record):
    """The static stage: the report's fields as attributes (``effective_contact_ratio`` η,
    ``load_sharing``, ``contact_fraction``, ``complementarity_residual``, ``iterations``,
    ``posts_in_strip``, …), plus, for the scene's preload, numpy arrays per wave phase (rows)
    and post of the strip (columns):

    - ``phase_rad`` (phases,): wave phase of each snapshot (rad);
    - ``post_x_m`` (posts,): post position along x (m);
    - ``post_forces_n`` (phases, posts): contact force on each post tip (N, ≥ 0);
    - ``post_gaps_m`` (phases, posts): gap at each post tip (m, ≥ 0; 0 in contact);
    - ``in_contact`` (phases, posts): contact state (bool).

    Also ``effective_ratio`` (η or ``None``), ``cached``, ``content_hash``, ``notes``, ``folder``.
    """

    def __init__(self, data: Dict[str, Any]):
        report = data["report"]
        merged = dict(report)
        merged.update({k: v for k, v in data.items() if k != "report"})
        merged["report"] = report
        super().__init__(merged)
        level = next(
            (p for p in report["preloads"] if p["preload_n"] == report["preload_n"]),
            report["preloads"][0],
        )
        snapshots = level["snapshots"]

        def table(field: str, dtype) -> np.ndarray:
            rows = [[post[field] for post in s["posts"]] for s in snapshots]
            return np.array(rows, dtype=dtype).reshape(len(snapshots), -1)

        arrays = {
            "phase_rad": np.array(
                [np.nan if s["phase_rad"] is None else s["phase_rad"] for s in snapshots], dtype=np.float64
            ),
            "post_x_m": np.array([p["x_m"] for p in snapshots[0]["posts"]], dtype=np.float64),
            "post_forces_n": table("force_n", np.float64),
            "post_gaps_m": table("gap_m", np.float64),
            "in_contact": table("in_contact", bool),
        }
        for name, array in arrays.items():
            object.__setattr__(self, name, array)


class SweepResult:
    """A sweep's outcome: ``rows`` (one dict per point: ``variant``, ``grid`` values as written,
    ``values`` by column, ``wall_time_s``, ``hash``), ``folder``, ``resumed`` (points reused
    from an earlier run), ``files`` written, ``failures`` ((overrides, message) per failed point).
    :meth:`frame` gives the table of ``results.csv`` as a pandas DataFrame."""

    def __init__(self, data: Dict[str, Any]):
        self.data = data
        self.rows: List[Dict[str, Any]] = data["rows"]
        self.folder: str = data["folder"]
        self.resumed: int = data["resumed"]
        self.files: List[str] = data["files"]
        self.failures: List[Tuple[str, str]] = [tuple(f) for f in data["failures"]]

    def records(self) -> Iterator[Dict[str, Any]]:
        """One flat dict per point: variant, grid keys (as written), numeric columns (SI),
        wall_time_s, hash."""
        for row in self.rows:
            flat: Dict[str, Any] = {"variant": row["variant"]}
            flat.update(row["grid"])
            flat.update(row["values"])
            flat["wall_time_s"] = row["wall_time_s"]
            flat["hash"] = row["hash"]
            yield flat

    def frame(self):
        """The results table (the columns of ``results.csv`` and the point hash) as a pandas
        DataFrame. Needs pandas."""
        return _pandas().DataFrame(list(self.records()))

    def __len__(self) -> int:
        return len(self.rows)

    def __repr__(self) -> str:
        return f"SweepResult({len(self.rows)} points, {len(self.failures)} failed, folder={self.folder!r})"


def springs(
    scene: Union[Scene, PathLike, None] = None,
    *,
    diameter: Optional[str] = None,
    slider: str = "si",
    stator: str = "linbo3",
) -> Springs:
    """The four Johnson springs of one post (N/m).

    ``springs(scene)``: of the scene's posts and materials. ``springs(diameter="20 um",
    slider="si", stator="linbo3")``: as ``sawdrive springs --diameter 20um`` (materials ``si`` or
    ``linbo3``). Give one or the other.
    """
    if diameter is not None:
        if scene is not None:
            raise ArgumentError("springs: give a scene or diameter=, not both")
        if not isinstance(diameter, str):
            raise ArgumentError(f"--diameter {diameter!r}: give the diameter with its unit, e.g. \"20 um\"")
        return Springs(_native.post_springs(diameter, slider, stator))
    return Springs(_as_scene(scene)._native.post_springs())


def _folders(out: Optional[PathLike], cache: Union[PathLike, bool, None]) -> Tuple[Optional[str], Optional[str]]:
    """``out`` and the FEM cache folder: ``cache=None`` means ``<out>/.cache`` (as the command
    line) or none without ``out``; ``False`` none; ``True`` ``<out>/.cache``; else the folder."""
    out_text = None if out is None else os.fspath(out)
    if cache is None or cache is True:
        if cache is True and out_text is None:
            raise ArgumentError("cache=True: give out= (the cache is <out>/.cache) or a cache folder")
        cache_text = None if out_text is None else os.path.join(out_text, ".cache")
    elif cache is False:
        cache_text = None
    else:
        cache_text = os.fspath(cache)
    return out_text, cache_text


def _call(what: str, progress: ProgressArg, function, *args, **kwargs):
    if progress is False:
        return function(*args, **kwargs)
    tick, close = callback(progress, what)
    try:
        return function(*args, progress=tick, **kwargs)
    finally:
        close()


def static(
    scene: Union[Scene, PathLike, None] = None,
    *,
    out: Optional[PathLike] = None,
    cache: Union[PathLike, bool, None] = None,
    progress: ProgressArg = None,
) -> StaticResult:
    """Static FEM contact (``sawdrive static``): post forces, gaps and contact state per wave
    phase, and η. With ``out``, writes ``out/<scene>/static/`` (static.json, force chart, VTU)
    atomically; ``cache``: the FEM cache folder (default ``<out>/.cache``, none without ``out``;
    ``False``: none). ``progress``: ``None`` auto, ``True``/``False``, or a callable
    ``(elapsed_s, done, total)``. Ctrl-C: the strip stops before its next contact solve (an FEM
    factorisation or mesh generation already running finishes first, in the background; the
    whole slider's solve is not interrupted) and nothing is written."""
    out_text, cache_text = _folders(out, cache)
    return StaticResult(_call("static", progress, _native.static_stage, _as_scene(scene)._native, out_text, cache_text))


def dynamic(
    scene: Union[Scene, PathLike, None] = None,
    *,
    out: Optional[PathLike] = None,
    cache: Union[PathLike, bool, None] = None,
    progress: ProgressArg = None,
) -> DynamicResult:
    """The dynamic stick/slip model (``sawdrive dynamic``) with the scene's η, or η from the
    static stage when ``effective_ratio = "fem"``. The result's fields equal ``sawdrive dynamic
    --json`` to the last bit. With ``out``, writes ``out/<scene>/dynamic/`` atomically;
    ``cache`` and ``progress`` as for :func:`static`.

    Ctrl-C: the static stage stops before its next contact solve, the dynamic one before its
    next curve point (transient run); nothing is written. The period average with η given and no
    ``out`` (milliseconds) runs on the calling thread, and Ctrl-C is raised when it returns."""
    native = scene._native if type(scene) is Scene else _as_scene(scene)._native
    if out is None and cache is None and (progress is False or (progress is None and not _attached())):
        # The common call (nothing to write, no progress line): straight to the extension.
        return _native.dynamic_stage(native)
    out_text, cache_text = _folders(out, cache)
    return _call("dynamic", progress, _native.dynamic_stage, native, out_text, cache_text)


def run(
    scene: Union[Scene, PathLike, None] = None,
    *,
    out: Optional[PathLike] = "out",
    cache: Union[PathLike, bool, None] = None,
    progress: ProgressArg = None,
) -> RunResult:
    """The whole pipeline (``sawdrive run``): springs → static (η) → dynamic. Writes
    ``out/<scene>/`` (default ``out``, as the command line), replacing earlier results only when
    every stage succeeded and the call was not interrupted; ``out=None`` writes nothing.
    ``cache`` and ``progress`` as for :func:`static`. Ctrl-C: the pipeline stops before its next
    contact solve or curve point and its results are discarded."""
    out_text, cache_text = _folders(out, cache)
    return _call("run", progress, _native.run, _as_scene(scene)._native, out_text, cache_text)


def sweep(
    file: PathLike,
    *,
    out: PathLike = "out",
    jobs: Optional[int] = None,
    progress: ProgressArg = None,
) -> SweepResult:
    """Run a sweep file (``sawdrive sweep FILE --out OUT --jobs N``): every point through the
    pipeline in parallel, saved as ``OUT/<name>/points/<hash>.json`` (an interrupted sweep
    resumes), then ``results.csv`` and the charts. ``jobs``: worker threads, 1–256 (default:
    all cores). Raises :class:`~sawdrive.errors.SweepPointsFailed` (with ``.result``) when
    points failed. ``SweepResult.frame()`` gives the table as a DataFrame. Ctrl-C: no further
    point starts, the running ones stop before their next contact solve or curve point and are
    not saved; ``results.csv`` and the charts are not written (a rerun resumes from the saved
    points)."""
    if jobs is not None and (isinstance(jobs, bool) or not isinstance(jobs, numbers.Integral) or jobs < 0):
        raise ArgumentError(f"--jobs {jobs!r}: must be between 1 and 256 worker threads")
    data = _call("sweep", progress, _native.sweep, os.fspath(file), os.fspath(out), None if jobs is None else int(jobs))
    result = SweepResult(data)
    if result.failures:
        total = len(result.failures) + len(result.rows)
        lines = "; ".join(f"point [{o}] failed: {e}" for o, e in result.failures)
        raise SweepPointsFailed(
            f"{len(result.failures)} of {total} sweep points failed (completed points are kept; "
            f"rerun to retry): {lines}",
            result.failures,
            result,
        )
    return result


def sweep_points(file: PathLike) -> List[Dict[str, Any]]:
    """The points of a sweep file without running them: ``variant``, ``grid`` (values as
    written) and ``overrides`` (the ``key=value`` list of each point, in application order)."""
    return _native.sweep_points(os.fspath(file))


#: The outputs of a UQ or design run, with their units (the report's band names).
UQ_OUTPUTS = (
    "effective_contact_ratio",
    "stall_thrust_n",
    "no_load_speed_m_per_s",
    "max_output_power_w",
    "efficiency",
)


class UqResult(_Record):
    """A Monte Carlo UQ (``sawdrive uq --json``): every report field as an attribute —
    ``samples``, ``seed``, ``fidelity``, ``scatter`` (SI), ``input_names``, one band per output
    (``stall_thrust_n`` N, ``no_load_speed_m_per_s`` m/s, ``max_output_power_w`` W,
    ``effective_contact_ratio``, ``efficiency``: dicts with ``mean``, ``sd``, ``p5``, ``p50``,
    ``p95`` and their 95 % intervals ``p5_ci``…), ``deterministic``, ``sensitivity``,
    ``failed_samples``, ``sample_cost_s`` (s), ``wall_time_s`` (s), ``files`` — and

    - ``curve_band``: numpy array (n, 4): speed (m/s), P5, P50 and P95 of thrust (N);
    - ``folder``: the results folder ``OUT/<scene>-uq/``.
    """

    def __init__(self, data: Dict[str, Any]):
        super().__init__(data)
        band = data["curve_band"]
        table = np.column_stack(
            [np.asarray(band[k], dtype=np.float64) for k in ("speed_m_per_s", "thrust_p5_n", "thrust_p50_n", "thrust_p95_n")]
        )
        object.__setattr__(self, "curve_band", table)

    def bands_frame(self):
        """The bands as a pandas DataFrame: one row per output (index), columns ``samples``,
        ``mean``, ``sd``, ``p5``, ``p50``, ``p95`` (the output's unit) and ``deterministic``
        (the nominal run). Needs pandas."""
        nominal = dict(self.data["deterministic"])
        rows = {
            name: {**{k: self.data[name][k] for k in ("samples", "mean", "sd", "p5", "p50", "p95")},
                   "deterministic": nominal.get(name)}
            for name in UQ_OUTPUTS
        }
        return _pandas().DataFrame.from_dict(rows, orient="index")

    def samples_frame(self):
        """Every sample as a pandas DataFrame (``samples.csv`` of the results folder: sample,
        scatter_seed, the drawn inputs in SI, the outputs). Needs pandas."""
        return _pandas().read_csv(os.path.join(self.data["folder"], "samples.csv"))


class DesignResult(_Record):
    """A design study (``sawdrive design --json``): every report field as an attribute —
    ``optimum`` (``variables`` by name with unit, ``objective``, ``objective_value``,
    ``fidelity``, ``outputs``), ``baseline``, ``quantile``, ``sensitivity``, ``evaluations``,
    ``cost`` (fidelity, evaluations, mean s each), ``wall_time_s`` (s), ``files`` — and
    ``folder`` (``OUT/<name>/``). :meth:`evaluations_frame` gives every evaluation as a
    DataFrame."""

    def evaluations_frame(self):
        """Every evaluation as a pandas DataFrame: the variables (SI, named with their unit),
        ``fidelity``, ``stage``, ``objective`` (NaN when infeasible), ``feasible``,
        ``violations`` and the outputs. Needs pandas."""
        rows = []
        for e in self.data["evaluations"]:
            row: Dict[str, Any] = dict(e["variables"])
            row.update(fidelity=e["fidelity"], stage=e["stage"],
                       objective=math.nan if e["objective"] is None else e["objective"],
                       feasible=e["feasible"], violations="; ".join(e["violations"]))
            row.update(e["outputs"])
            rows.append(row)
        return _pandas().DataFrame(rows)


def _scatter_overrides(scatter: Optional[Dict[str, Any]]) -> List[str]:
    """``scatter`` as ``scatter.KEY=VALUE`` overrides; refuses other types naming the key."""
    if scatter is None:
        return []
    if not isinstance(scatter, dict):
        raise ArgumentError(f"scatter: expected a dict of [scatter] keys, got {type(scatter).__name__}")
    return [f"scatter.{key}={_override_text('scatter.' + str(key), value)}" for key, value in scatter.items()]


def uq(
    scene: Union[Scene, PathLike, None] = None,
    *,
    samples: int,
    scatter: Optional[Dict[str, Any]] = None,
    seed: int = 1,
    out: PathLike = "out",
    patch: bool = False,
    progress: ProgressArg = None,
) -> UqResult:
    """Monte Carlo bands of a scene under scatter (``sawdrive uq SCENE --samples N --seed S
    --out OUT [--patch]``): each sample a whole-slider contact solve and a dynamic curve, in
    parallel; writes ``OUT/<scene>-uq/`` (summary.json, samples.csv, charts) when complete.

    ``scene``: a :class:`Scene` or a scene file; a file's ``[scatter]`` section is read (a path
    given directly may hold one). ``scatter``: ``[scatter]`` keys to set, with units as text
    named by scene key (``{"posts.height_scatter": "5 nm", "friction": 0.03, "load.preload": "2 N"}``). ``samples`` ≥ 1;
    ``seed``: same seed, same bits. ``patch``: the cheaper periodic-patch contact model.
    Samples are saved as they finish, so a rerun after an interrupt resumes.

    Ctrl-C: raises at once; the samples still finish in the background and are saved (a rerun
    resumes them), but the results folder is never committed by an interrupted call.
    """
    if isinstance(samples, bool) or not isinstance(samples, numbers.Integral) or samples < 1:
        raise ArgumentError(f"--samples {samples!r}: must be ≥ 1")
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or seed < 0:
        raise ArgumentError(f"--seed {seed!r}: must be an integer ≥ 0")
    if isinstance(scene, Scene):
        path, overrides = scene._args()
    elif scene is None or isinstance(scene, (str, os.PathLike)):
        path, overrides = (None if scene is None else os.fspath(scene)), []
    else:
        raise ArgumentError(f"scene: expected a sawdrive.Scene or a path, got {type(scene).__name__}")
    overrides = overrides + _scatter_overrides(scatter)
    data = _call("uq", progress, _native.uq, path, overrides, int(samples), int(seed), os.fspath(out), bool(patch))
    return UqResult(data)


def design(file: PathLike, *, out: PathLike = "out", progress: ProgressArg = None) -> DesignResult:
    """The texture optimiser (``sawdrive design FILE --out OUT``): a cheap-model search, then
    the finalists and the optimum confirmed with the whole-slider model; writes ``OUT/<name>/``
    (summary.json, evaluations, charts) when complete.

    Ctrl-C: the library has no cancellation point in a design study yet; it finishes in the
    background and then commits its complete results folder.
    """
    return DesignResult(_call("design", progress, _native.design, os.fspath(file), os.fspath(out)))
