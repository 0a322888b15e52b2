#!/usr/bin/env sh
# Install the external URDF checkers used by `tests/files/urdf.rs`:
#   - `check_urdf` from Debian/Ubuntu's liburdfdom-tools (urdfdom's parser),
#   - the `yourdfpy` Python module (an independent URDF forward-kinematics library),
#   - the `pybullet` Python module (a URDF client replaying waypoints, tests/files/urdf_replay.rs).
# CI runs this, then `CCRKIT_REQUIRE_URDF_TOOLS=1 cargo test --release --test files urdf`.
set -eu

SUDO=""
if [ "$(id -u)" != "0" ] && command -v sudo >/dev/null 2>&1; then
    SUDO="sudo"
fi

if command -v apt-get >/dev/null 2>&1; then
    $SUDO apt-get update
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y liburdfdom-tools
else
    echo "install-urdf-tools: apt-get not available; skipping liburdfdom-tools (check_urdf)." >&2
fi

PY="${PYTHON:-python3}"
if command -v "$PY" >/dev/null 2>&1; then
    if ! "$PY" -m pip --version >/dev/null 2>&1 && command -v apt-get >/dev/null 2>&1; then
        DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y python3-pip
    fi
    # Debian's system python refuses plain `pip install` (PEP 668); retry with the override.
    if ! $SUDO "$PY" -m pip install yourdfpy pybullet; then
        echo "install-urdf-tools: retrying with --break-system-packages (PEP 668)" >&2
        $SUDO "$PY" -m pip install --break-system-packages yourdfpy pybullet
    fi
else
    echo "install-urdf-tools: $PY not available; skipping yourdfpy." >&2
fi
