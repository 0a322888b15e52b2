"""Import + first solve, in fresh interpreters: `import ccrkit`, `Model.load` of paper case I,
`model.solve("energy")`, then reading `shape.tip` (which imports numpy on first use).
Prints the median over runs of each stage's cumulative wall time.

    python python/bench/bench_import.py [--runs 20]
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

CHILD = r"""
import json, sys, time
t0 = time.perf_counter()
import ccrkit
t1 = time.perf_counter()
m = ccrkit.Model.load(sys.argv[1])
s = m.solve("energy")
t2 = time.perf_counter()
tip = s.tip
t3 = time.perf_counter()
print(json.dumps([t1 - t0, t2 - t0, t3 - t0]))
"""


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--runs", type=int, default=20)
    a = p.parse_args()
    model = str(ROOT / "models" / "paper" / "case1.toml")
    runs = []
    for _ in range(a.runs):
        out = subprocess.run([sys.executable, "-c", CHILD, model], check=True,
                             capture_output=True, text=True).stdout
        runs.append(json.loads(out))
    med = [statistics.median(r[i] for r in runs) * 1e3 for i in range(3)]
    print(f"median of {a.runs} fresh interpreters (cumulative from before `import ccrkit`):")
    print(f"  import ccrkit                      {med[0]:6.1f} ms")
    print(f"  + Model.load + solve('energy')     {med[1]:6.1f} ms")
    print(f"  + shape.tip (numpy's first import) {med[2]:6.1f} ms")


if __name__ == "__main__":
    main()
