#!/usr/bin/env bash
# The Python environment of `just bench-peers` and `just bench-dynamics`: a virtual environment in
# benchmarks/peers/.venv with CasADi (its bundled IPOPT and MUMPS) and scipy (the Radau peer). Idempotent; installs Debian's python3-venv if the
# venv module is missing.
set -euo pipefail
venv=benchmarks/peers/.venv
if [ ! -x "$venv/bin/python" ]; then
  if ! python3 -m venv "$venv" 2>/dev/null; then
    rm -rf "$venv"
    echo "bench-peers: installing python3-venv"
    SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends python3-venv >/dev/null
    python3 -m venv "$venv"
  fi
fi
if ! "$venv/bin/python" -c "import casadi" 2>/dev/null; then
  echo "bench-peers: pip install casadi==3.8.2 into $venv"
  "$venv/bin/pip" install --quiet "casadi==3.8.2"
fi
if ! "$venv/bin/python" -c "import scipy" 2>/dev/null; then
  echo "bench-peers: pip install scipy==1.17.1 into $venv"
  "$venv/bin/pip" install --quiet "scipy==1.17.1"
fi
