#!/usr/bin/env bash
# The cluster path under a real Slurm (a one-node cluster on this machine, local-cluster.sh):
#   1. scripts/slurm/multistart.sbatch as a job array (sbatch --wait), merged: the single run's
#      result.json byte for byte;
#   2. a task that fails (its output folder is a user's, which spine refuses to write into): sbatch
#      reports it, the merge names the missing shard, the user's file is untouched;
#   3. a cancelled array (scancel while the tasks run): no shard half-written, the merge refuses;
#   4. scripts/slurm/census.sh to P = 0.05 on design10 with one shard of batch 2 failing: the census
#      stops and says so; run again, it resumes and ends with the bytes of
#      `spine design --confidence 0.05` on one machine.
# Skipped (exit 0, with the reason) only where a one-node Slurm cannot be started (not root, no
# packages). Needs target/release/spine (just build). Stops the daemons it started (none, when the
# one-node cluster was up before it).
set -euo pipefail
cd "$(dirname "$0")/../.."
root="$PWD"
code=0
up_before=""
scripts/slurm/local-cluster.sh status 2>/dev/null && up_before=1
scripts/slurm/local-cluster.sh start || code=$?
if [ "$code" -eq 77 ]; then
  echo "slurm-test: SKIPPED: no one-node Slurm on this machine (reason above)"
  exit 0
elif [ "$code" -ne 0 ]; then
  exit "$code"
fi
SLURM_CONF="$(scripts/slurm/local-cluster.sh conf)"
export SLURM_CONF SPINE="$root/target/release/spine"
dir="$(mktemp -d)"
cleanup() {
  scancel -n spine-multistart >/dev/null 2>&1 || true
  cd "$root"
  rm -rf "$dir"
  # A cluster that was up before the test stays up.
  [ -n "$up_before" ] || scripts/slurm/local-cluster.sh stop >/dev/null
}
trap cleanup EXIT
case_file="$root/paper-cases/design10.json"
fail() {
  echo "slurm-test: FAILED: $*" >&2
  exit 1
}
# Waits (at most $2 s) until no job named $1 is queued or running.
drain() {
  local t=0
  while squeue -h -n "$1" -o %i | grep -q .; do
    [ "$t" -lt "$(($2 * 5))" ] || fail "jobs named $1 still queued after $2 s"
    sleep 0.2
    t=$((t + 1))
  done
}

# 1. The array, merged, against the single run.
cd "$dir"
"$SPINE" design "$case_file" --starts 24 --jobs 1 --deterministic --out single >/dev/null
timeout 300 sbatch --wait --quiet --array=1-2 "$root/scripts/slurm/multistart.sbatch" "$case_file" 24 "$dir/array" ||
  fail "the job array did not end well (logs: $(cat spine-multistart-*.log))"
"$SPINE" merge array/shard-* --deterministic --out array/merged >/dev/null
cmp single/result.json array/merged/result.json || fail "the merged array differs from the single run"
echo "slurm-test: a 2-task job array of multistart.sbatch merges to the single run's result.json, byte for byte"

# 2. A failed task: shard 2's folder is a user's, with a file in it.
mkdir -p failed/shard-2
echo "a user's notes" >failed/shard-2/notes.txt
if timeout 300 sbatch --wait --quiet --array=1-2 "$root/scripts/slurm/multistart.sbatch" "$case_file" 24 "$dir/failed"; then
  fail "sbatch --wait said the array with a failed task ended well"
fi
grep -q "error: " spine-multistart-*_2.log || fail "task 2's log has no error: $(cat spine-multistart-*_2.log)"
code=0
merged="$("$SPINE" merge failed/shard-1 failed/shard-2 --out failed/merged 2>&1)" || code=$?
[ "$code" -eq 2 ] || fail "the merge with a failed shard exited $code: $merged"
[ "$(cat failed/shard-2/notes.txt)" = "a user's notes" ] && [ "$(ls failed/shard-2)" = notes.txt ] ||
  fail "the user's folder changed: $(ls -a failed/shard-2)"
[ ! -e failed/merged ] || fail "a refused merge wrote failed/merged"
echo "slurm-test: a failed task: sbatch --wait exits non-zero, the merge refuses (exit 2: ${merged#error: }), the user's folder is untouched"

# 3. A cancelled array: each task either wrote its whole shard or nothing.
job="$(sbatch --parsable --array=1-2 "$root/scripts/slurm/multistart.sbatch" "$case_file" 4000 "$dir/cancelled")"
job="${job%%;*}"
for _ in $(seq 150); do
  [ "$(squeue -h -j "$job" -t R -o %i | wc -l)" -ge 2 ] && break
  sleep 0.2
done
sleep 2
scancel "$job"
drain spine-multistart 120
for k in 1 2; do
  shard="cancelled/shard-$k"
  if [ -e "$shard" ]; then
    leftovers="$(find "$shard" -mindepth 1 ! -name shard.json ! -name .spine-output)"
    [ -z "$leftovers" ] || fail "a cancelled task left $leftovers"
    if [ -e "$shard/shard.json" ]; then
      python3 -c 'import json,sys; json.load(open(sys.argv[1]))' "$shard/shard.json" || fail "$shard/shard.json is not whole"
    fi
  fi
done
code=0
merged="$("$SPINE" merge cancelled/shard-1 cancelled/shard-2 --out cancelled/merged 2>&1)" || code=$?
[ "$code" -ne 0 ] || fail "the merge of a cancelled array succeeded"
echo "slurm-test: a cancelled array leaves no half-written shard; the merge refuses it (exit $code)"

# 4. The census to a stated confidence, with a failure on the way and a resume.
"$SPINE" design "$case_file" --confidence 0.05 --jobs 2 --deterministic --out census-single >/dev/null
# The census's folder as census.sh marks it, with a file of the test's in one shard's folder: spine
# refuses to write that shard, so batch 2 fails.
mkdir -p census/batch-2/shard-2
echo "# written by scripts/slurm/census.sh (the test stands in for its first run)" >census/.spine-census
echo "in the way" >census/batch-2/shard-2/notes.txt
code=0
timeout 600 "$root/scripts/slurm/census.sh" --tasks 2 --deterministic --wait "$case_file" 0.05 "$dir/census" || code=$?
[ "$code" -eq 1 ] || fail "the census with a failing shard exited $code"
grep -q "^failed:" census/census.status || fail "census.status: $(cat census/census.status)"
rm census/batch-2/shard-2/notes.txt # the test's own file
start=$(date +%s)
timeout 600 "$root/scripts/slurm/census.sh" --tasks 2 --deterministic --wait "$case_file" 0.05 "$dir/census" ||
  fail "the resumed census exited non-zero: $(cat census/census.status)"
grep -q "^reached:" census/census.status || fail "census.status: $(cat census/census.status)"
cmp census-single/result.json census/census/result.json || fail "the cluster census differs from the single run's"
batches=$(ls -d census/batch-* | wc -l)
echo "slurm-test: the census to P <= 0.05 on design10 stopped at a failed shard of batch 2, resumed, reached it in $batches batches ($(($(date +%s) - start)) s after the resume) with the single run's result.json, byte for byte"
