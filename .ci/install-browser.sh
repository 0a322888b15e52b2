#!/usr/bin/env sh
# Install headless Chromium (Debian's `chromium` package) for the 3-D view's browser test
# (`tests/files/view.rs`). CI runs this, then the tests with CCRKIT_REQUIRE_BROWSER=1.
set -eu

SUDO=""
if [ "$(id -u)" != "0" ] && command -v sudo >/dev/null 2>&1; then
    SUDO="sudo"
fi

if command -v chromium >/dev/null 2>&1; then
    chromium --version
    exit 0
fi
if command -v apt-get >/dev/null 2>&1; then
    $SUDO apt-get update
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends chromium
    chromium --version
else
    echo "install-browser: apt-get not available; the browser checks of tests/files/view.rs will be skipped." >&2
fi
