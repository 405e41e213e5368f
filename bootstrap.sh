#!/usr/bin/env bash
# Fresh-machine setup for the flexible-spine workspace (Debian bookworm, Rust installed).
# Idempotent and quiet when everything is already there.
set -euo pipefail

need_pkgs=()
for p in coinor-libipopt-dev pkg-config; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || need_pkgs+=("$p")
done
if [ ${#need_pkgs[@]} -gt 0 ]; then
  echo "bootstrap: installing Debian packages: ${need_pkgs[*]}"
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${need_pkgs[@]}" >/dev/null
fi

if ! command -v just >/dev/null 2>&1; then
  echo "bootstrap: installing just (cargo install --locked just)"
  cargo install --locked --quiet just
fi

# `just lint` (run at the end of `just test`) needs clippy and rustfmt.
for c in clippy rustfmt; do
  if ! cargo "$c" --version >/dev/null 2>&1; then
    echo "bootstrap: installing the $c component (rustup component add $c)"
    rustup component add "$c"
  fi
done
