"""Type stubs of ccrkit's native module (PyO3). Units: metres, newtons, radians."""

from __future__ import annotations

from os import PathLike
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, PathLike]
_Vec = Union[npt.ArrayLike, Sequence[float]]
_Setting = Union[str, int, float, bool]

class SolveError(Exception):
    """Every ccrkit error."""

    kind: str
    field: Optional[str]
    reason: str
    cable: Optional[str]
    section: Optional[int]
    method: Optional[str]
    iterations: Optional[int]
    residual: Optional[float]
    obstacle: Optional[str]
    path: Optional[str]
    target: Optional[List[float]]
    closest: Optional[List[float]]
    distance: Optional[float]
    samples: Optional[int]

class InvalidInput(SolveError):
    """An input or setting is not valid (``field`` names it)."""

class ModelError(InvalidInput):
    """A model or scene file cannot be read, parsed or used (``field``, ``path``)."""

class Infeasible(SolveError):
    """No shape reaches the actuation (``cable``, ``section``)."""

class NotConverged(SolveError):
    """A solver stopped short of its tolerance (``method``, ``iterations``, ``residual``)."""

class Obstructed(SolveError):
    """An obstacle makes the shape impossible (``obstacle``, ``section``)."""

class Unsupported(SolveError):
    """The method cannot represent this robot, load or obstacle (``method``)."""

class ContactBudget(Unsupported):
    """More distinct obstacles within reach of the robot than a solve may query (``field``:
    ``obstacles``, ``reason``: the count, the limit and what to do)."""

class Unreachable(SolveError):
    """reach found no actuation putting the tip on the target: ``target``, ``closest`` (the
    closest tip found), ``distance`` [m]; ``result`` is that closest answer."""

    result: Reach

class NoPath(SolveError):
    """plan found no clear path to the goal (``samples`` drawn, ``reason``)."""

class ExportError(SolveError):
    """An export cannot be written (``path``)."""

class Shape:
    """A solved robot; arrays are float64 in metres, base frame."""

    @property
    def method(self) -> str: ...
    @property
    def insertion(self) -> Optional[float]:
        """Insertion through the model's port [m] (None without a port)."""
    @property
    def rotation(self) -> Optional[float]:
        """Rotation about the port axis [rad] (None without a port)."""
    @property
    def disk_positions(self) -> npt.NDArray[np.float64]:
        """(n+1, 3) disk centres [m]."""
    @property
    def disk_rotations(self) -> npt.NDArray[np.float64]:
        """(n+1, 3, 3): ``[d, i, j]`` is row i, column j of disk d's rotation."""
    @property
    def disk_s(self) -> npt.NDArray[np.float64]:
        """(n+1,) arc length of every disk along the undeformed backbone [m]."""
    @property
    def tip(self) -> npt.NDArray[np.float64]:
        """(3,) tip position [m]."""
    @property
    def backbone(self) -> npt.NDArray[np.float64]:
        """(m, 3) dense backbone samples [m]."""
    @property
    def cable_paths(self) -> Dict[str, npt.NDArray[np.float64]]:
        """Cable name -> (k, 3) hole positions at the disks it passes [m]."""
    @property
    def tensions(self) -> npt.NDArray[np.float64]:
        """(cables,) tensions [N], NaN where the method computes none."""
    @property
    def shortenings(self) -> npt.NDArray[np.float64]:
        """(cables,) path-length change of each cable [m], whatever drove the solve; NaN where none."""
    @property
    def slack(self) -> List[bool]: ...
    @property
    def contacts(self) -> List[Dict[str, Any]]:
        """obstacle, feature, disk, section, point_robot, point_obstacle, normal, distance, reaction."""
    @property
    def report(self) -> Dict[str, Any]:
        """The ``report`` object of ``to_json()``."""
    @property
    def converged(self) -> bool: ...
    @property
    def stable(self) -> Optional[bool]: ...
    @property
    def error_estimate(self) -> Optional[float]:
        """Estimated tip distance from the converged rod [m] (``estimate=True``), or None."""
    @property
    def jacobian(self) -> Optional[Dict[str, Any]]:
        """``inputs`` [(cable, input)], ``position`` and ``tangent`` (3, k) arrays; or None."""
    def to_json(self) -> str:
        """The command line's ``ccrkit solve --json`` text."""
    @staticmethod
    def from_json(text: str) -> Shape: ...

class Model:
    """A parsed, validated model file (robot, actuation, obstacles); immutable, pickles."""

    @staticmethod
    def load(path: _Path) -> Model: ...
    @staticmethod
    def from_toml(text: str, base_dir: Optional[_Path] = None) -> Model: ...
    def with_scene(self, path: _Path) -> Model: ...
    @property
    def name(self) -> str: ...
    @property
    def cables(self) -> List[str]: ...
    @property
    def sections(self) -> int: ...
    @property
    def cable_lengths(self) -> npt.NDArray[np.float64]:
        """(cables,) undeformed straight-chord lengths [m]."""
    @property
    def shorten(self) -> npt.NDArray[np.float64]:
        """(cables,) the file's shortenings [m], NaN where none."""
    @property
    def tension(self) -> npt.NDArray[np.float64]:
        """(cables,) the file's tensions [N], NaN where none."""
    @property
    def obstacles(self) -> List[str]: ...
    @property
    def source(self) -> Optional[str]: ...
    def solve(
        self,
        method: Optional[str] = None,
        shorten: Optional[_Vec] = None,
        tension: Optional[_Vec] = None,
        *,
        insertion: Optional[float] = None,
        rotation: Optional[float] = None,
        steps: int = 1,
        warm_from: Optional[str] = None,
        estimate: bool = False,
        tolerance: Optional[float] = None,
        check_unique: bool = False,
        **settings: _Setting,
    ) -> Shape: ...
    def export_urdf(
        self,
        path: _Path,
        shape: Shape,
        mode: str = "articulated",
        cables: bool = False,
        name: Optional[str] = None,
    ) -> List[str]:
        """Write ``shape`` (solved on this model) as URDF to ``path``, with the SRDF and the
        joint values beside it in ``articulated`` mode; returns the paths written. Atomic,
        folders created; an output onto one of the model's files (model, scene, mesh) or two
        on one file is an ``InvalidInput`` with ``field == "path"``, raised before writing."""

    def reach(
        self,
        tip: _Vec,
        tangent: Optional[_Vec] = None,
        *,
        method: Optional[str] = None,
        margin: Optional[float] = None,
        allow_contact: bool = False,
        tolerance: float = 1e-7,
        starts: int = 16,
        max_iterations: int = 60,
        require: bool = True,
        **settings: _Setting,
    ) -> Reach:
        """Least-effort actuation (sum of shorten² [m²]) within the model's limits putting the
        tip on ``tip`` [m] (and the tip tangent along ``tangent``), ``margin`` [m] clear of the
        obstacles unless ``allow_contact``; ``ccrkit reach``. Raises ``Unreachable`` when not
        reached, unless ``require=False``."""
    def plan(
        self,
        to_tip: Optional[_Vec] = None,
        to_actuation: Optional[_Vec] = None,
        from_actuation: Optional[_Vec] = None,
        *,
        method: Optional[str] = None,
        seed: int = 1,
        margin: Optional[float] = None,
        max_samples: int = 5000,
        roadmap: Optional[_Path] = None,
        **settings: _Setting,
    ) -> Plan:
        """A clear path of actuations from ``from_actuation`` (default: the file's) to one
        goal, ``to_tip`` [m] or ``to_actuation`` [m] ([N] in tension space: a method driven
        by tension, e.g. ``control="force"``); ``ccrkit plan`` (RRT-Connect, or a query of
        the ``roadmap`` file). Through a port an actuation may end with the insertion [m]
        and rotation [rad] (default: the file's), and the plan gives them per waypoint. Raises
        ``NoPath`` when none is found."""
    def build_roadmap(
        self,
        out: Optional[_Path] = None,
        *,
        method: Optional[str] = None,
        samples: int = 400,
        expand: int = 400,
        spread: float = 0.1,
        neighbours: int = 8,
        seed: int = 1,
        margin: Optional[float] = None,
        shard: Optional[Tuple[int, int]] = None,
        **settings: _Setting,
    ) -> str:
        """A roadmap for ``plan(roadmap=…)``, as ``ccrkit roadmap build``: its JSON text, also
        written to ``out`` when given (atomically; onto one of the model's files it is an
        ``InvalidInput`` with ``field == "out"``, raised before building). ``shard=(k, N)``
        builds only shard ``k`` of ``N`` (``merge_roadmaps`` joins them into the roadmap one
        build gives). Releases the GIL."""

class Reach:
    """The answer of ``Model.reach`` (or the closest one, ``reached == False``)."""

    @property
    def reached(self) -> bool: ...
    @property
    def target(self) -> npt.NDArray[np.float64]:
        """(3,) target tip [m]."""
    @property
    def tip(self) -> npt.NDArray[np.float64]:
        """(3,) tip of the answer [m]."""
    @property
    def tip_error_m(self) -> float: ...
    @property
    def tangent_error_rad(self) -> Optional[float]: ...
    @property
    def shorten(self) -> npt.NDArray[np.float64]:
        """(cables,) shortenings [m]."""
    @property
    def insertion(self) -> Optional[float]:
        """Insertion of the answer [m] (None without a port)."""
    @property
    def rotation(self) -> Optional[float]:
        """Rotation of the answer [rad] (None without a port)."""
    @property
    def tensions(self) -> npt.NDArray[np.float64]:
        """(cables,) tensions of the answer [N], NaN where none."""
    @property
    def effort_m2(self) -> float: ...
    @property
    def min_clearance_m(self) -> Optional[float]: ...
    @property
    def shape(self) -> Shape: ...
    @property
    def iterations(self) -> int: ...
    @property
    def starts(self) -> int: ...
    @property
    def solves(self) -> int: ...
    @property
    def sensitivities(self) -> str:
        """``exact`` or ``finite-differences``."""
    @property
    def reason(self) -> str: ...
    def to_json(self) -> str:
        """The command line's ``ccrkit reach --json`` text."""

class Plan:
    """The answer of ``Model.plan``: waypoints clear of the obstacles by the margin."""

    @property
    def shorten(self) -> npt.NDArray[np.float64]:
        """(waypoints, cables) shortenings [m]: the inputs, or in tension space the
        path-length changes the tensions made."""
    @property
    def tensions(self) -> npt.NDArray[np.float64]:
        """(waypoints, cables) tensions [N]: the inputs in tension space, else the tensions
        the shortenings made (NaN where the method reports none)."""
    @property
    def space(self) -> str:
        """``"shortening"`` or ``"tension"``: chosen by ``method`` and its ``control``
        setting, as for ``reach``."""
    @property
    def insertion(self) -> Optional[npt.NDArray[np.float64]]:
        """(waypoints,) insertions [m] (None without a port)."""
    @property
    def rotation(self) -> Optional[npt.NDArray[np.float64]]:
        """(waypoints,) rotations [rad] (None without a port)."""
    @property
    def tips(self) -> npt.NDArray[np.float64]:
        """(waypoints, 3) tips [m]."""
    @property
    def clearances(self) -> npt.NDArray[np.float64]:
        """(waypoints,) measured clearance of each waypoint [m]."""
    @property
    def shapes(self) -> List[Shape]: ...
    @property
    def cables(self) -> List[str]: ...
    @property
    def margin_m(self) -> float: ...
    @property
    def min_clearance_m(self) -> float: ...
    @property
    def certified_clearance_m(self) -> float: ...
    @property
    def seed(self) -> int: ...
    @property
    def statistics(self) -> Dict[str, Any]: ...
    def to_json(self) -> str:
        """The command line's ``ccrkit plan --json`` text."""
    def trajectory_csv(self) -> str:
        """The command line's ``ccrkit plan --trajectory`` text."""

def methods() -> List[Dict[str, Any]]: ...
def merge_roadmaps(parts: List[str], out: Optional[_Path] = None) -> str:
    """The roadmap the shards ``parts`` (JSON texts of ``Model.build_roadmap(shard=(k, N))``,
    all N, any order) make together, edge for edge the roadmap one build gives; written to
    ``out`` when given (``ccrkit roadmap merge``)."""

#: The method used when none is named (the core's default).
DEFAULT_METHOD: str
#: Every outcome of a solve, as batch rows and studies name it (the core's ``Status``).
STATUSES: Tuple[str, ...]
def _solve_batch(
    model: Model,
    shorten: Optional[npt.ArrayLike] = None,
    tension: Optional[npt.ArrayLike] = None,
    method: Optional[str] = None,
    threads: Optional[int] = None,
    warm_start: bool = True,
    chunk: int = 64,
    full: bool = False,
    steps: int = 1,
    insertion: Optional[npt.ArrayLike] = None,
    rotation: Optional[npt.ArrayLike] = None,
    estimate: bool = False,
    **settings: _Setting,
) -> Dict[str, Any]: ...
