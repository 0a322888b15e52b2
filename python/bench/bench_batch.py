"""solve_batch from Python on the rows of `cargo bench --bench batch`: 10 000 energy solves of
paper case I over a 100 x 100 grid of shortenings (20-100 % of the file's), warm-started
along blocks of 64 rows, on 1 and 2 threads. Prints the median wall time per solve and the
process CPU time per solve (user + system: robust on a shared machine).

    python python/bench/bench_batch.py [--repeat 5]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

import numpy as np

import ccrkit

ROOT = Path(__file__).resolve().parents[2]
SIDE = 100


def grid(model: ccrkit.Model) -> np.ndarray:
    """The bench's rows: cable A scaled by 0.2 + 0.8 i/99, cable B by 0.2 + 0.8 j/99."""
    f = 0.2 + 0.8 * np.arange(SIDE) / (SIDE - 1)
    a, b = np.meshgrid(f, f, indexing="ij")
    return np.column_stack([a.ravel() * model.shorten[0], b.ravel() * model.shorten[1]])


def measure(model, rows, threads, repeat):
    walls, cpus = [], []
    for _ in range(repeat):
        c0, t0 = os.times(), time.perf_counter()
        b = ccrkit.solve_batch(model, shorten=rows, threads=threads, chunk=64)
        wall = time.perf_counter() - t0
        c1 = os.times()
        assert b.ok.all(), b.counts()
        walls.append(wall)
        cpus.append((c1.user - c0.user) + (c1.system - c0.system))
    return statistics.median(walls), statistics.median(cpus)


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--repeat", type=int, default=5)
    a = p.parse_args()
    model = ccrkit.Model.load(ROOT / "models" / "paper" / "case1.toml")
    rows = grid(model)
    n = len(rows)
    one = measure(model, rows, 1, a.repeat)
    two = measure(model, rows, 2, a.repeat)
    us = lambda s: s / n * 1e6  # noqa: E731
    print(f"{n} energy solves of case I, median of {a.repeat}:")
    print(f"  1 thread : {us(one[0]):7.2f} us/solve wall, {us(one[1]):7.2f} us/solve CPU")
    print(f"  2 threads: {us(two[0]):7.2f} us/solve wall, {us(two[1]):7.2f} us/solve CPU")
    print(f"  speed-up on 2 threads (wall): {one[0] / two[0]:.2f}x")


if __name__ == "__main__":
    main()
