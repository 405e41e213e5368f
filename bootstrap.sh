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

# `just lint` (run at the end of `just test`) needs clippy (`cargo clippy`) and rustfmt (`cargo fmt`).
for pair in clippy:clippy rustfmt:fmt; do
  component="${pair%%:*}" subcommand="${pair##*:}"
  if ! cargo "$subcommand" --version >/dev/null 2>&1; then
    echo "bootstrap: installing the $component component (rustup component add $component)"
    rustup component add "$component"
  fi
done
