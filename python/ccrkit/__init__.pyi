from typing import Optional

import numpy.typing as npt

from ._native import (
    ContactBudget as ContactBudget,
    ExportError as ExportError,
    Infeasible as Infeasible,
    InvalidInput as InvalidInput,
    Model as Model,
    ModelError as ModelError,
    NoPath as NoPath,
    NotConverged as NotConverged,
    Obstructed as Obstructed,
    Plan as Plan,
    Reach as Reach,
    Shape as Shape,
    SolveError as SolveError,
    Unreachable as Unreachable,
    Unsupported as Unsupported,
    merge_roadmaps as merge_roadmaps,
    methods as methods,
    DEFAULT_METHOD as DEFAULT_METHOD,
    STATUSES as STATUSES,
)
from .batch import Batch as Batch

__version__: str

def solve_batch(
    model: Model,
    shorten: Optional[npt.ArrayLike] = None,
    tension: Optional[npt.ArrayLike] = None,
    method: Optional[str] = None,
    threads: Optional[int] = None,
    warm_start: bool = True,
    *,
    chunk: int = 64,
    full: bool = False,
    steps: int = 1,
    insertion: Optional[npt.ArrayLike] = None,
    rotation: Optional[npt.ArrayLike] = None,
    estimate: bool = False,
    **settings: object,
) -> Batch: ...
