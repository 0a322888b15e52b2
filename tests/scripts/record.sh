#!/usr/bin/env bash
# tests/scripts/record.sh OUTDIR [BIN]: the answers every method gives on the paper cases, the
# wall and pillar scenes, the vessel, the FTDCR robots and `predict` on FTDCR v4 val, as JSON
# shapes (and a CSV) in OUTDIR, with each run's exit code. Run it with the binary before and
# after a change, then `tests/scripts/cmp.py BEFORE AFTER [TOL]` lists every number that moved
# (timings ignored). This is how the README's "record/cmp: 0 differences" claims are made.
set -u
[ $# -ge 1 ] || { echo "usage: $0 OUTDIR [BIN (default target/release/ccrkit)]" >&2; exit 2; }
root=$(realpath "$(dirname "$0")/../..")
# OUTDIR and BIN relative to where the script is run; the default binary is the repository's.
out=$(realpath -m "$1"); bin=$(realpath -m "${2:-$root/target/release/ccrkit}")
[ -x "$bin" ] || { echo "$0: no binary at $bin (cargo build --release)" >&2; exit 2; }
cd "$root"
mkdir -p "$out"
for m in geometric geometric-squared energy cosserat kirchhoff constant-curvature; do
  for c in case1 case2 case3; do
    timeout 120 "$bin" solve models/paper/$c.toml --method $m --json "$out/$m-$c.json" >/dev/null 2>"$out/$m-$c.err"; echo $? > "$out/$m-$c.rc"
  done
  for s in wall pillar; do
    timeout 120 "$bin" solve models/paper/case1.toml --method $m --scene models/scenes/$s.toml --json "$out/$m-$s.json" >/dev/null 2>"$out/$m-$s.err"; echo $? > "$out/$m-$s.rc"
  done
done
for h in ftdcr_v4 ftdcr_v6; do
  timeout 120 "$bin" solve models/hardware/$h.toml --method energy --json "$out/energy-$h.json" >/dev/null 2>"$out/energy-$h.err"; echo $? > "$out/energy-$h.rc"
done
timeout 120 "$bin" solve models/paper/case1.toml --method energy --scene models/scenes/vessel.toml --warm-from geometric --json "$out/energy-vessel.json" >/dev/null 2>"$out/energy-vessel.err"; echo $? > "$out/energy-vessel.rc"
timeout 120 "$bin" solve models/paper/case2.toml --method geometric --scene models/scenes/pillar.toml --json "$out/geometric-case2-pillar.json" >/dev/null 2>"$out/geometric-case2-pillar.err"; echo $? > "$out/geometric-case2-pillar.rc"
timeout 120 "$bin" solve models/paper/case3.toml --method energy --scene models/scenes/wall.toml --json "$out/energy-case3-wall.json" >/dev/null 2>"$out/energy-case3-wall.err"; echo $? > "$out/energy-case3-wall.rc"
timeout 300 "$bin" predict models/hardware/ftdcr_v4.toml --data models/hardware/data/v4/tdcr_sysid_20260511-183002_val.csv --out "$out/predict-v4.csv" >/dev/null 2>"$out/predict-v4.err"; echo $? > "$out/predict-v4.rc"
