"""A workspace sweep on a local Dask cluster (worker processes on loopback) equals the
single-process result bit for bit."""

import importlib.util

import numpy as np
import pytest

import ccrkit
from conftest import ROOT


def example():
    path = ROOT / "examples" / "python" / "workspace_dask.py"
    spec = importlib.util.spec_from_file_location("workspace_dask", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_dask_sweep_equals_single_process(case1):
    pytest.importorskip("dask.distributed")
    ws = example()
    shorten = ws.sweep_inputs(case1, 600)
    chunk = 32
    cluster, client = ws.local_cluster(2)
    try:
        assert len(client.scheduler_info()["workers"]) == 2
        got = ws.sweep_on_cluster(client, case1, shorten, "energy", chunk, piece_chunks=3)
    finally:
        client.close()
        cluster.close()
    want = ccrkit.solve_batch(case1, shorten=shorten, chunk=chunk)
    assert len(got) == 600 and got.ok.sum() > 500
    for k in ("tips", "iterations", "residual", "tensions", "converged"):
        assert np.array_equal(getattr(got, k), getattr(want, k), equal_nan=True), k
    assert list(got.status) == list(want.status) and got.errors == want.errors
