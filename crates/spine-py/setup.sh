#!/usr/bin/env bash
# The Python front's environment: a virtual environment in crates/spine-py/.venv with numpy, pypdf,
# pytest and maturin, and the `flexspine` package built from this checkout and installed into it
# (`pip install ./crates/spine-py`, linking the system Ipopt). Idempotent: pip rebuilds only what
# changed (cargo's incremental build in target/). Installs Debian's python3-venv if missing.
set -euo pipefail
cd "$(dirname "$0")/../.."
venv=crates/spine-py/.venv
if [ ! -x "$venv/bin/python" ]; then
  if ! python3 -m venv "$venv" 2>/dev/null; then
    rm -rf "$venv"
    echo "python: installing python3-venv"
    SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends python3-venv >/dev/null
    python3 -m venv "$venv"
  fi
fi
if ! "$venv/bin/python" -c "import numpy, pytest, maturin, pypdf" 2>/dev/null; then
  echo "python: pip install numpy pytest maturin pypdf into $venv"
  "$venv/bin/pip" install --quiet --upgrade pip
  "$venv/bin/pip" install --quiet "numpy>=1.22" "pytest>=7" "maturin>=1.9,<2" "pypdf>=4"
fi
# The package itself, from source: maturin is already in the venv, so no isolated build
# environment is downloaded; cargo rebuilds only what changed.
PATH="$PWD/$venv/bin:$PATH" "$venv/bin/pip" install --quiet --no-build-isolation --force-reinstall --no-deps ./crates/spine-py
