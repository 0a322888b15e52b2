"""Workspace sweep on a Dask cluster: Halton samples of the cable shortenings of a model,
``ccrkit.solve_batch`` mapped over pieces of the sweep on the workers, the pieces joined in
order. The model pickles (its TOML text travels), so any ``dask.distributed`` cluster works;
by default a local one with worker processes on loopback.

Pieces are whole numbers of ``chunk`` rows, so warm starts run exactly as in one
``solve_batch`` call: the cluster's answer equals the single-process one bit for bit.

    python examples/python/workspace_dask.py [--model models/paper/case1.toml] \\
        [--samples 4096] [--workers 2] [--out target/workspace.png]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

import ccrkit

PRIMES = (2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53)


def radical_inverse(i: int, base: int) -> float:
    """The i-th van der Corput number in `base` (a Halton coordinate)."""
    f, r = 1.0, 0.0
    while i > 0:
        f /= base
        r += f * (i % base)
        i //= base
    return r


def sweep_inputs(model: ccrkit.Model, samples: int, max_fraction: float = 0.10) -> np.ndarray:
    """(samples, cables) shortenings [m]: Halton points in [0, max_fraction] of each cable's
    undeformed length, sample 1.. (0 is the straight robot)."""
    k = len(model.cables)
    if k > len(PRIMES):
        raise ValueError(f"at most {len(PRIMES)} cables, got {k}")
    u = np.array([[radical_inverse(i + 1, PRIMES[c]) for c in range(k)] for i in range(samples)])
    return u * max_fraction * model.cable_lengths


def solve_piece(model: ccrkit.Model, shorten: np.ndarray, method: str, chunk: int) -> ccrkit.Batch:
    """One piece on one worker (one thread: the cluster provides the parallelism)."""
    return ccrkit.solve_batch(model, shorten=shorten, method=method, threads=1, chunk=chunk)


def sweep_on_cluster(client, model, shorten, method="energy", chunk=64, piece_chunks=4):
    """Map `solve_piece` over pieces of `piece_chunks * chunk` rows and join the answers."""
    piece = piece_chunks * chunk
    remote_model = client.scatter(model, broadcast=True)
    futures = [
        client.submit(solve_piece, remote_model, shorten[i:i + piece], method, chunk, pure=False)
        for i in range(0, len(shorten), piece)
    ]
    return ccrkit.Batch.concat(client.gather(futures))


def local_cluster(workers: int):
    """A local cluster of worker processes on loopback, one thread each."""
    from dask.distributed import Client, LocalCluster

    cluster = LocalCluster(
        n_workers=workers,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=None,
    )
    return cluster, Client(cluster)


def main() -> None:
    root = Path(__file__).resolve().parents[2]
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--model", default=str(root / "models" / "paper" / "case1.toml"))
    p.add_argument("--samples", type=int, default=4096)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--method", default="energy")
    p.add_argument("--chunk", type=int, default=64)
    p.add_argument("--out", default=str(root / "target" / "workspace_dask.png"))
    a = p.parse_args()

    model = ccrkit.Model.load(a.model)
    shorten = sweep_inputs(model, a.samples)
    cluster, client = local_cluster(a.workers)
    try:
        t = time.perf_counter()
        batch = sweep_on_cluster(client, model, shorten, a.method, a.chunk)
        t_cluster = time.perf_counter() - t
    finally:
        client.close()
        cluster.close()
    t = time.perf_counter()
    single = ccrkit.solve_batch(model, shorten=shorten, method=a.method, threads=1, chunk=a.chunk)
    t_single = time.perf_counter() - t
    same = np.array_equal(batch.tips, single.tips, equal_nan=True)
    print(f"{len(batch)} samples of {model.name} with {a.method}: {batch.counts()}")
    print(f"cluster ({a.workers} workers) {t_cluster:.2f} s, one process one thread {t_single:.2f} s")
    print(f"cluster result equals the single-process one: {same}")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ok = batch.ok
    fig, ax = plt.subplots(1, 2, figsize=(10, 4.5))
    ax[0].scatter(batch.tips[ok, 0] * 1e3, batch.tips[ok, 1] * 1e3, s=2)
    ax[0].set(xlabel="tip x [mm]", ylabel="tip y [mm]", title="workspace, top view")
    ax[0].set_aspect("equal")
    ax[1].scatter(np.hypot(batch.tips[ok, 0], batch.tips[ok, 1]) * 1e3, batch.tips[ok, 2] * 1e3, s=2)
    ax[1].set(xlabel="tip distance from axis [mm]", ylabel="tip z [mm]", title="side view")
    fig.suptitle(f"{model.name}: {ok.sum()} of {len(batch)} samples solved ({a.method})")
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(a.out, dpi=120)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
