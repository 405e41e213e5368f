#!/usr/bin/env bash
# The shard/merge path of a multi-start on one machine, as it runs on a cluster: the single run,
# then 4 shards run by GNU parallel (the one-liner of docs/case-format.md), then 3 shards through
# scripts/slurm/multistart.sbatch as a simulated job array (SLURM_ARRAY_TASK_ID/COUNT set, the
# tasks run by GNU parallel); each merge must give the single run's result.json byte for byte.
# Installs Debian's `parallel` if missing. Needs target/release/spine (just build).
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v parallel >/dev/null; then
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  echo "shard-test: installing GNU parallel"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends parallel >/dev/null
fi
spine="$PWD/target/release/spine"
case_file=paper-cases/design10.json
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
"$spine" design "$case_file" --starts 24 --seed 5 --jobs 1 --deterministic --out "$dir/single" >/dev/null
parallel --will-cite --halt now,fail=1 \
  "$spine" design "$case_file" --starts 24 --seed 5 --jobs 1 --shard {}/4 --out "$dir/parallel/shard-{}" ::: 1 2 3 4 >/dev/null
"$spine" merge "$dir"/parallel/shard-* --deterministic --out "$dir/parallel/merged" >/dev/null
cmp "$dir/single/result.json" "$dir/parallel/merged/result.json"
SPINE="$spine" SLURM_ARRAY_TASK_COUNT=3 parallel --will-cite --halt now,fail=1 \
  SLURM_ARRAY_TASK_ID={} bash scripts/slurm/multistart.sbatch "$case_file" 24 "$dir/slurm" ::: 1 2 3 >/dev/null
# The sbatch script keeps the case's seed; the single run for it:
"$spine" design "$case_file" --starts 24 --jobs 1 --deterministic --out "$dir/single-slurm" >/dev/null
"$spine" merge "$dir"/slurm/shard-* --deterministic --out "$dir/slurm/merged" >/dev/null
cmp "$dir/single-slurm/result.json" "$dir/slurm/merged/result.json"
echo "shard-test: 4 shards by GNU parallel and 3 through the Slurm script merge to the single run's result.json, byte for byte"
