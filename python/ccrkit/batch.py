"""The result of ``ccrkit.solve_batch``: plain numpy arrays, so it pickles and concatenates."""

from __future__ import annotations

from ._native import STATUSES  # noqa: F401  (the core's outcome vocabulary)


class Batch:
    """Rows of a batch solve, in input order.

    Attributes:
        method: the method's name.
        cables: cable names (the columns of ``tensions``).
        tips: (N, 3) tip positions [m], NaN where the row failed.
        status: (N,) str array, one of ``STATUSES`` per row.
        errors: list of N error messages (None where the row solved).
        iterations: (N,) int64, iterations of each solve.
        residual: (N,) float64, final residual (NaN where the method did not say).
        converged: (N,) bool.
        tensions: (N, cables) cable tensions [N], NaN where not computed or failed.
        disk_positions: (N, n+1, 3) [m] with ``full=True``, else None.
        disk_rotations: (N, n+1, 3, 3) with ``full=True``, else None.
        insertion: (N,) insertion through the model's port [m] of each row as solved (full
            insertion where the row gave none), NaN for a model without a port.
        rotation: (N,) rotation about the port axis [rad] (0 where the row gave none), NaN
            for a model without a port.
        error_estimate: (N,) estimated tip distance from the converged reference rod [m]
            with ``estimate=True``; NaN where not asked, failed, or the model part is unknown.
    """

    __slots__ = (
        "method",
        "cables",
        "tips",
        "status",
        "errors",
        "iterations",
        "residual",
        "converged",
        "tensions",
        "disk_positions",
        "disk_rotations",
        "insertion",
        "rotation",
        "error_estimate",
    )

    def __init__(self, method, cables, tips, status, errors, iterations, residual,
                 converged, tensions, disk_positions=None, disk_rotations=None,
                 insertion=None, rotation=None, error_estimate=None):
        import numpy as np

        self.method = method
        self.cables = list(cables)
        self.tips = np.asarray(tips, dtype=float)
        self.status = np.asarray(status, dtype=str)
        self.errors = list(errors)
        self.iterations = np.asarray(iterations, dtype=np.int64)
        self.residual = np.asarray(residual, dtype=float)
        self.converged = np.asarray(converged, dtype=bool)
        self.tensions = np.asarray(tensions, dtype=float)
        self.disk_positions = disk_positions
        self.disk_rotations = disk_rotations
        n = len(self.status)
        self.insertion = np.full(n, np.nan) if insertion is None else np.asarray(insertion, dtype=float)
        self.rotation = np.full(n, np.nan) if rotation is None else np.asarray(rotation, dtype=float)
        self.error_estimate = (
            np.full(n, np.nan) if error_estimate is None else np.asarray(error_estimate, dtype=float)
        )

    @classmethod
    def _from_native(cls, raw, cables):
        return cls(
            raw["method"],
            cables,
            raw["tips"],
            raw["status"],
            raw["errors"],
            raw["iterations"],
            raw["residual"],
            raw["converged"],
            raw["tensions"],
            raw.get("disk_positions"),
            raw.get("disk_rotations"),
            raw.get("insertion"),
            raw.get("rotation"),
            raw.get("error_estimate"),
        )

    def __len__(self):
        return len(self.status)

    @property
    def ok(self):
        """(N,) bool mask of the rows that solved."""
        return self.status == "ok"

    def counts(self):
        """How many rows have each status (only statuses that occur)."""
        out = {}
        for s in self.status:
            out[str(s)] = out.get(str(s), 0) + 1
        return out

    @staticmethod
    def concat(batches):
        """One batch of the rows of several (e.g. chunks solved on a Dask cluster), in order."""
        import numpy as np

        batches = list(batches)
        if not batches:
            raise ValueError("concat needs at least one batch")
        first = batches[0]
        full = all(b.disk_positions is not None for b in batches)
        return Batch(
            first.method,
            first.cables,
            np.concatenate([b.tips for b in batches]),
            np.concatenate([b.status for b in batches]),
            [e for b in batches for e in b.errors],
            np.concatenate([b.iterations for b in batches]),
            np.concatenate([b.residual for b in batches]),
            np.concatenate([b.converged for b in batches]),
            np.concatenate([b.tensions for b in batches]),
            np.concatenate([b.disk_positions for b in batches]) if full else None,
            np.concatenate([b.disk_rotations for b in batches]) if full else None,
            np.concatenate([b.insertion for b in batches]),
            np.concatenate([b.rotation for b in batches]),
            np.concatenate([b.error_estimate for b in batches]),
        )

    def __getstate__(self):
        return {k: getattr(self, k) for k in self.__slots__}

    def __setstate__(self, state):
        for k in self.__slots__:
            setattr(self, k, state.get(k))
        # A batch pickled before insertion, rotation or estimates were kept lacks them: NaN.
        import numpy as np

        for k in ("insertion", "rotation", "error_estimate"):
            if getattr(self, k) is None:
                setattr(self, k, np.full(len(self.status), np.nan))

    def __repr__(self):
        return f"Batch(method={self.method!r}, rows={len(self)}, status={self.counts()})"
