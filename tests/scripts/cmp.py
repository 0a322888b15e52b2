#!/usr/bin/env python3
"""tests/scripts/cmp.py BEFORE AFTER [TOL]: every number that differs by more than TOL (default 0)
between two record.sh outputs (JSON shapes, exit codes, predict CSV); timing fields ignored.
Prints the first five per file, a count per file and `differences: N`."""
import json, os, sys, math
if len(sys.argv) < 3:
    sys.exit("usage: cmp.py BEFORE AFTER [TOL]")
a, b = sys.argv[1], sys.argv[2]
tol = float(sys.argv[3]) if len(sys.argv) > 3 else 0.0
SKIP = ("time", "elapsed", "seconds", "micros", "_us", "_ms", "_s")
def walk(x, y, path, diffs):
    if isinstance(x, dict) and isinstance(y, dict):
        for k in sorted(set(x) | set(y)):
            if any(s in k for s in SKIP) and k not in ("shape",):
                continue
            if k not in x or k not in y:
                diffs.append((path + "/" + k, "missing on one side", None)); continue
            walk(x[k], y[k], path + "/" + k, diffs)
    elif isinstance(x, list) and isinstance(y, list):
        if len(x) != len(y):
            diffs.append((path, f"len {len(x)} vs {len(y)}", None)); return
        for i, (p, q) in enumerate(zip(x, y)):
            walk(p, q, f"{path}[{i}]", diffs)
    elif isinstance(x, (int, float)) and isinstance(y, (int, float)) and not isinstance(x, bool):
        d = abs(x - y)
        if d > tol and not (math.isnan(x) and math.isnan(y)):
            diffs.append((path, f"{x} vs {y}", d))
    elif x != y:
        diffs.append((path, f"{str(x)[:60]} vs {str(y)[:60]}", None))
for d in (a, b):
    if not os.path.isdir(d):
        sys.exit(f"cmp.py: {d} is not a folder (a record.sh OUTDIR)")
RECORD = (".rc", ".json", ".csv")
fa = {f for f in os.listdir(a) if f.endswith(RECORD)}
fb = {f for f in os.listdir(b) if f.endswith(RECORD)}
if not fa or not fb:
    sys.exit(f"cmp.py: {a if not fa else b} holds no record.sh output (.rc/.json/.csv): nothing to compare")
total = 0
for f in sorted(fb - fa):
    print("only in", b + ":", f); total += 1
for f in sorted(fa):
    pa, pb = os.path.join(a, f), os.path.join(b, f)
    if not os.path.exists(pb):
        print("only in", a + ":", f); total += 1; continue
    if f.endswith(".rc"):
        if open(pa).read() != open(pb).read():
            print(f, "exit", open(pa).read().strip(), "->", open(pb).read().strip()); total += 1
    elif f.endswith(".csv"):
        la, lb = open(pa).read().splitlines(), open(pb).read().splitlines()
        nd = sum(1 for x, y in zip(la, lb) if x != y) + abs(len(la) - len(lb))
        if nd:
            print(f, nd, "differing lines")
        total += nd
    elif f.endswith(".json"):
        try:
            x, y = json.load(open(pa)), json.load(open(pb))
        except Exception as e:
            print(f, "unreadable", e); total += 1; continue
        diffs = []
        walk(x, y, "", diffs)
        for p, m, d in diffs[:5]:
            print(f, p, m)
        if diffs:
            mx = max((d for _, _, d in diffs if d is not None), default=None)
            print(f, len(diffs), "differences, max abs", mx)
        total += len(diffs)
print("differences:", total)
