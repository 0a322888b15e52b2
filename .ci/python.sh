#!/usr/bin/env bash
# CI for the Python package (python/): a fresh venv, the package installed with the README's
# one command (`pip install ./python`, a maturin build of the PyO3 crate), then pytest
# (every API item against the CLI, the batch, pickling, the Dask cluster test, the examples).
# Reuses the root build's target/ so the core and its dependencies compile once.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/target}"
venv="$CARGO_TARGET_DIR/ci-python-venv"
rm -rf "$venv"
python3 -m venv "$venv"
"$venv/bin/python" -m pip install -q --upgrade pip
"$venv/bin/python" -m pip install -q pytest "dask[distributed]" matplotlib
echo "== pip install ./python"
"$venv/bin/python" -m pip install ./python
echo "== python crate: cargo fmt --check"
cargo fmt --check --manifest-path python/Cargo.toml
# The CLI the tests compare with (built by `cargo test --release` already; cheap if so).
cargo build --release --bin ccrkit
export CCRKIT_BIN="$CARGO_TARGET_DIR/release/ccrkit" CCRKIT_REQUIRE_CLI=1
echo "== pytest python/tests"
cd python && "$venv/bin/python" -m pytest -q -p no:cacheprovider tests
