#!/usr/bin/env bash
# Per-solve instruction counts (callgrind) of the rows of benches/batch.rs: the plain Rust
# loop, the core's solve_batch on one thread, and the Python package's solve_batch on one
# thread. Each is run with 1000 and 2000 rows; the difference / 1000 is the cost of one
# solve with everything around it (start-up, imports, numpy conversion) cancelled out.
#   python/bench/callgrind_batch.sh   (needs valgrind, the example built, ccrkit installed)
set -euo pipefail
cd "$(dirname "$0")/../.."
T="${CARGO_TARGET_DIR:-target}"
PY="${PYTHON:-python3}"
cargo build --release --example batch_loop >/dev/null
count() { # instructions of one run
  local out; out=$(mktemp)
  valgrind --tool=callgrind --callgrind-out-file="$out" "$@" >/dev/null 2>&1
  callgrind_annotate "$out" 2>/dev/null | awk '/PROGRAM TOTALS/ {gsub(",", "", $1); print $1}'
  rm -f "$out"
}
script() { echo "import sys, numpy as np, ccrkit
sys.path.insert(0, 'python/bench'); from bench_batch import grid
m = ccrkit.Model.load('models/paper/case1.toml')
b = ccrkit.solve_batch(m, shorten=grid(m)[:$1], threads=1, chunk=64); assert b.ok.all()"; }
for what in loop batch python; do
  if [ "$what" = python ]; then
    a=$(count "$PY" -c "$(script 1000)"); b=$(count "$PY" -c "$(script 2000)")
  else
    a=$(count "$T/release/examples/batch_loop" 1000 "$what"); b=$(count "$T/release/examples/batch_loop" 2000 "$what")
  fi
  echo "$what: $(( (b - a) / 1000 )) instructions per solve (1000 rows: $a, 2000 rows: $b)"
done
