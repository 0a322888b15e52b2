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


def roadmap_example():
    path = ROOT / "examples" / "python" / "roadmap_dask.py"
    spec = importlib.util.spec_from_file_location("roadmap_dask", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_dask_roadmap_shards_equal_one_build(case1, tmp_path):
    pytest.importorskip("dask.distributed")
    import json

    rd = roadmap_example()
    ball = tmp_path / "ball.toml"
    ball.write_text(
        'clearance = 0.0005\n[[obstacles]]\nname = "ball"\nshape = "sphere"\n'
        "position = [0.064, 0.111, 0.104]\nradius = 0.012\n"
    )
    model = case1.with_scene(str(ball))
    options = dict(samples=30, expand=30, neighbours=5)
    whole = json.loads(model.build_roadmap(str(tmp_path / "whole.json"), **options))
    cluster, client = rd.local_cluster(2)
    try:
        merged = json.loads(rd.build_on_cluster(client, model, 3, **options))
    finally:
        client.close()
        cluster.close()
    assert len(whole["edges"]) > 10
    for k in ("nodes", "edges", "edge_clearance", "robot_fingerprint", "scene", "seed"):
        assert merged[k] == whole[k], k
    assert "shard" not in merged
    # A shard alone is not a roadmap; a merge of one shard of three names the missing ones.
    part = model.build_roadmap(shard=(1, 3), **options)
    with pytest.raises(ccrkit.ModelError, match="shard 0/3 is missing"):
        ccrkit.merge_roadmaps([part])
    with pytest.raises(ccrkit.SolveError, match="merge the shards"):
        (tmp_path / "part.json").write_text(part)
        model.plan(to_actuation=whole["nodes"][0]["u"], roadmap=str(tmp_path / "part.json"))
    # The whole roadmap written to `out` answers.
    p = model.plan(to_actuation=whole["nodes"][0]["u"], roadmap=str(tmp_path / "whole.json"))
    assert len(p.shorten) >= 1
