"""ccrkit: shapes of cable-driven continuum robots, from Python.

A thin layer over ccrkit's Rust core (``ccrkit._native``, built with PyO3 and maturin)::

    import ccrkit
    model = ccrkit.Model.load("models/paper/case1.toml")
    shape = model.solve("energy")                       # the file's actuation
    shape = model.solve("energy", shorten=[0.007, 0.005], sub_arcs=8)
    batch = ccrkit.solve_batch(model, shorten=rows)     # rows: (N, cables) [m]
    r = model.reach([0.06, 0.057, 0.151])               # least-effort actuation to a tip
    p = model.with_scene("scene.toml").plan(to_tip=[...], seed=1)   # a clear path to it

Units are SI (metres, newtons, radians). Every error is a ``ccrkit.SolveError``.
numpy is imported only when an array is made, so ``import ccrkit`` stays fast.
"""

from __future__ import annotations

from ._native import (
    DEFAULT_METHOD,
    STATUSES,
    ContactBudget,
    ExportError,
    Infeasible,
    InvalidInput,
    Model,
    ModelError,
    NoPath,
    NotConverged,
    Obstructed,
    Plan,
    Reach,
    Shape,
    SolveError,
    Unreachable,
    Unsupported,
    merge_roadmaps,
    methods,
)
from ._native import _solve_batch
from .batch import Batch

__all__ = [
    "DEFAULT_METHOD",
    "Batch",
    "ContactBudget",
    "ExportError",
    "Infeasible",
    "InvalidInput",
    "Model",
    "ModelError",
    "NoPath",
    "NotConverged",
    "Obstructed",
    "Plan",
    "Reach",
    "STATUSES",
    "Shape",
    "SolveError",
    "Unreachable",
    "Unsupported",
    "merge_roadmaps",
    "methods",
    "solve_batch",
]

__version__ = "0.1.0"


def solve_batch(
    model,
    shorten=None,
    tension=None,
    method=None,
    threads=None,
    warm_start=True,
    *,
    chunk=64,
    full=False,
    steps=1,
    insertion=None,
    rotation=None,
    estimate=False,
    **settings,
):
    """Solve many actuations of one model, in parallel, without the GIL.

    ``shorten`` [m] and/or ``tension`` [N] are (N, cables) arrays, one row per solve, one
    column per cable in ``model.cables`` order; NaN gives that cable no input of that kind
    in that row (a cable with neither is free). The model's own actuation is not used.
    For a model with a ``[port]``, ``insertion`` [m] and ``rotation`` [rad] are (N,) arrays,
    one value per row (NaN or omitted: full insertion, no rotation); the batch returns each
    row's as solved (``Batch.insertion``, ``Batch.rotation``).

    Rows are cut into blocks of ``chunk``; inside a block each row starts from the previous
    solved row (``warm_start``), blocks run in parallel on ``threads`` threads (default: one
    per core). Blocks depend on ``chunk`` only, so the result is the same on any number of
    threads, and a sweep cut into pieces whose lengths are multiples of ``chunk`` gives the
    same rows as one call. A row that fails is recorded in ``status`` (never raised); only a
    call that cannot run at all (unknown method or setting, wrong array shape) raises.

    ``method=None`` is ``DEFAULT_METHOD`` (the core's default, ``energy``). ``full=True``
    also keeps every row's disk frames. ``estimate=True`` adds each row's estimated tip
    distance from the converged reference rod [m] (``Batch.error_estimate``; for ``energy``
    read from each answer alone, else one extra solve per row, as
    ``Model.solve(estimate=True)``). Other keywords are the method's settings by
    name, as in ``Model.solve``.
    """
    raw = _solve_batch(
        model,
        shorten=shorten,
        tension=tension,
        method=method,
        threads=threads,
        warm_start=warm_start,
        chunk=chunk,
        full=full,
        steps=steps,
        insertion=insertion,
        rotation=rotation,
        estimate=estimate,
        **settings,
    )
    return Batch._from_native(raw, list(model.cables))
