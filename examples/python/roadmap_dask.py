"""A roadmap built in shards on a Dask cluster: every worker builds one shard
(``Model.build_roadmap(shard=(k, N))``: the same seeded nodes, its share of the edges), and
``ccrkit.merge_roadmaps`` joins them into the roadmap one build gives, edge for edge. The model
pickles (its TOML text travels) and the shards come back as JSON text, so any
``dask.distributed`` cluster works, with or without a shared file system; by default a local
one with worker processes on loopback.

    python examples/python/roadmap_dask.py [--model models/plan/two_segment.toml] \\
        [--scene models/plan/vessel.toml] [--workers 2] [--samples 200] [--out target/rm.json]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import ccrkit


def local_cluster(workers: int):
    """A local cluster of `workers` worker processes on loopback, one thread each."""
    from dask.distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           host="127.0.0.1", dashboard_address=None)
    return cluster, Client(cluster)


def build_shard(model: ccrkit.Model, k: int, n: int, options: dict) -> str:
    """Shard k of n on one worker: the roadmap's JSON text."""
    return model.build_roadmap(shard=(k, n), **options)


def build_on_cluster(client, model: ccrkit.Model, shards: int, **options) -> str:
    """The roadmap of `model` built as `shards` shards on the cluster, merged (JSON text)."""
    remote = client.scatter(model, broadcast=True)
    futures = [
        client.submit(build_shard, remote, k, shards, options, pure=False) for k in range(shards)
    ]
    return ccrkit.merge_roadmaps(client.gather(futures))


def main() -> None:
    root = Path(__file__).resolve().parents[2]
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--model", default=str(root / "models" / "plan" / "two_segment.toml"))
    p.add_argument("--scene", default=str(root / "models" / "plan" / "vessel.toml"))
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--samples", type=int, default=200)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--out", default=str(root / "target" / "roadmap_dask.json"))
    a = p.parse_args()

    model = ccrkit.Model.load(a.model)
    if a.scene:
        model = model.with_scene(a.scene)
    options = dict(samples=a.samples, expand=a.samples, seed=a.seed)
    cluster, client = local_cluster(a.workers)
    try:
        t = time.perf_counter()
        merged = build_on_cluster(client, model, a.workers, **options)
        t_cluster = time.perf_counter() - t
    finally:
        client.close()
        cluster.close()
    rm = json.loads(merged)
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(merged)
    print(f"{len(rm['nodes'])} nodes, {len(rm['edges'])} edges in {a.workers} shards, "
          f"{t_cluster:.2f} s; wrote {a.out}")


if __name__ == "__main__":
    main()
