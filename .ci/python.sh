#!/usr/bin/env bash
# CI for the Python package (python/): a fresh venv, the package installed with the README's
# command plus its test extra (`pip install "./python[test]"`, a maturin build of the PyO3 crate;
# the extra is pytest and the `dask` extra the examples need), then pytest
# (every API item against the CLI, the batch, pickling, the Dask cluster test, the examples).
# Shares the root build's target/: most dependencies are reused, but pyo3's proc macros unify
# other features of syn/serde and numpy adds num-complex's defaults, so the core, nalgebra,
# parry and clarabel compile a second time for the wheel (~5 min on two loaded cores).
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/target}"
venv="$CARGO_TARGET_DIR/ci-python-venv"
rm -rf "$venv"
python3 -m venv "$venv"
"$venv/bin/python" -m pip install -q --upgrade pip
echo "== pip install ./python[test] (the package with its test extra: pytest, the examples' dask and matplotlib)"
"$venv/bin/python" -m pip install "./python[test]"
echo "== python crate: cargo fmt --check"
cargo fmt --check --manifest-path python/Cargo.toml
# The CLI the tests compare with (built by `cargo test --release` already; cheap if so).
cargo build --release --bin ccrkit
export CCRKIT_BIN="$CARGO_TARGET_DIR/release/ccrkit" CCRKIT_REQUIRE_CLI=1
echo "== pytest python/tests"
# `pytest` (not `python -m pytest`, which puts the working directory first on sys.path, where
# the source folder python/ccrkit without the built _native would shadow the installed package).
cd python && "$venv/bin/pytest" -q -p no:cacheprovider tests
