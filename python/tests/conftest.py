"""Shared fixtures: the repository's models and the command-line binary to compare with."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
MODELS = ROOT / "models"


def _cli():
    """The `ccrkit` binary: $CCRKIT_BIN, else the build under $CARGO_TARGET_DIR or target/."""
    if os.environ.get("CCRKIT_BIN"):
        return os.environ["CCRKIT_BIN"]
    targets = [os.environ.get("CARGO_TARGET_DIR"), str(ROOT / "target")]
    for t in filter(None, targets):
        p = Path(t) / "release" / "ccrkit"
        if p.is_file():
            return str(p)
    return shutil.which("ccrkit")


@pytest.fixture(scope="session")
def cli():
    """Run the CLI; skipped (with a note) when it is not built, unless CI requires it."""
    exe = _cli()
    if exe is None:
        msg = "ccrkit CLI not built (cargo build --release); CLI comparisons skipped"
        if os.environ.get("CCRKIT_REQUIRE_CLI") == "1":
            pytest.fail(msg)
        pytest.skip(msg)

    def run(*args):
        out = subprocess.run([exe, *map(str, args)], check=True, capture_output=True, text=True)
        return out.stdout

    return run


@pytest.fixture(scope="session")
def case1_path():
    return MODELS / "paper" / "case1.toml"


@pytest.fixture(scope="session")
def case1(case1_path):
    import ccrkit

    return ccrkit.Model.load(case1_path)
