"""Success and time of cold plans in the vessel (targets: success on >= 95 % of seeded random
feasible queries in the example scenes; cold plan <= 1 s).

Feasible queries: seeded uniform samples of the two-segment robot's limits box
(models/plan/two_segment.toml: +-4 mm proximal, +-3 mm distal) that are admissible inside the
tube (a plan from a sample to itself is refused with InvalidInput otherwise), then every pair
of them planned cold with RRT-Connect (seed 1). Most pairs' straight actuation path leaves the
tube. Usage: python python/bench/vessel_queries.py [SAMPLES=1500] [ROOT=.]
"""

import sys

import numpy as np

import ccrkit

samples = int(sys.argv[1]) if len(sys.argv) > 1 else 1500
root = sys.argv[2] if len(sys.argv) > 2 else "."
model = ccrkit.Model.load(f"{root}/models/plan/two_segment.toml")
model = model.with_scene(f"{root}/models/plan/vessel.toml")
hi = np.array([0.004, 0.004, 0.004, 0.003, 0.003, 0.003])
rng = np.random.default_rng(7)
nodes = []
for u in rng.uniform(-hi, hi, size=(samples, 6)):
    try:
        model.plan(to_actuation=u, from_actuation=u)
        nodes.append(u)
    except ccrkit.InvalidInput:
        pass
print(f"{len(nodes)} of {samples} samples admissible")
ok, times, detours = 0, [], 0
pairs = [(i, j) for i in range(len(nodes)) for j in range(i + 1, len(nodes))]
for i, j in pairs:
    try:
        p = model.plan(to_actuation=nodes[j], from_actuation=nodes[i], seed=1)
    except ccrkit.NoPath as e:
        print(f"pair {i} {j}: {e}")
        continue
    ok += 1
    times.append(p.statistics["time_s"])
    detours += p.statistics["samples"] > 0  # the straight edge was refused
times.sort()
print(
    f"{ok} of {len(pairs)} queries answered ({detours} needed a detour); cold plan time: "
    f"median {times[len(times) // 2]:.3f} s, max {times[-1]:.3f} s"
)
