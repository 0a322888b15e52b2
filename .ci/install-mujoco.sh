#!/usr/bin/env sh
# Install MuJoCo's Python bindings for `tests/files/urdf_mujoco.rs` (the exported URDF loads in
# MuJoCo and its forward kinematics matches the solved disks). CI runs this, then
# `CCRKIT_REQUIRE_MUJOCO=1 cargo test --release --test files urdf_mujoco::`.
set -eu
PY="${PYTHON:-python3}"
if ! command -v "$PY" >/dev/null 2>&1; then
    echo "install-mujoco: $PY not available; skipping mujoco." >&2
    exit 0
fi
SUDO=""
if [ "$(id -u)" != "0" ] && command -v sudo >/dev/null 2>&1; then
    SUDO="sudo"
fi
if "$PY" -c "import mujoco" >/dev/null 2>&1; then
    echo "install-mujoco: mujoco already installed"
    exit 0
fi
if ! "$PY" -m pip --version >/dev/null 2>&1 && command -v apt-get >/dev/null 2>&1; then
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y python3-pip
fi
# Debian's system python refuses plain `pip install` (PEP 668); retry with the override.
if ! $SUDO "$PY" -m pip install mujoco; then
    echo "install-mujoco: retrying with --break-system-packages (PEP 668)" >&2
    $SUDO "$PY" -m pip install --break-system-packages mujoco
fi
