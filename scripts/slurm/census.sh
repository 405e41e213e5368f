#!/usr/bin/env bash
# A census of eq. (33) to a stated confidence on a Slurm cluster: batches of 100 seeded starts as
# job arrays, each followed by a merge job (a dependency on the array) that submits the next batch
# until P(a better optimum unseen) <= P, as `spine design CASE --confidence P` does on one machine
# (the same rule; the same result.json bytes with --deterministic).
#
#   scripts/slurm/census.sh [options] CASE.json P OUT
#     --tasks T          shards per batch (array tasks; default 4), one CPU each unless
#                        --cpus-per-task is given in SBATCH_ARGS
#     --max-batches M    the cap: at most M batches (100 M seeded starts, `--starts 100M` of the
#                        single run); default: the single run's cap, 1000 batches
#     --deterministic    result.json without timings (same input, same bytes)
#     --wait             stay until the census ends and exit as `spine merge` did (0: reached)
#
# Run it on a login node; it submits batch B's array and its merge job and returns (with --wait,
# it waits). Extra sbatch options (partition, account, time) go in $SBATCH_ARGS. `spine` is taken
# from $SPINE, else from PATH.
#
# OUT holds:
#   batch-B/shard-K/shard.json   shard K of batch B (written whole, or not at all)
#   census/result.json           the census merged over batches 1..B after each batch (the last
#                                one is the answer; `spine report` and Python read it as any result)
#   census.status                one line: running (which batch), reached, ended (the cap or an
#                                unclean census) or failed (why)
#   logs/                        each task's and each merge's output
#
# Resume after a failure (a task that failed, a cancelled array, a lost node): run the same
# command again. Batches whose shards are all complete are kept; the missing shards of the first
# incomplete batch are submitted again, and the census goes on from there.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

# A refusal: why, on one line, exit 2, nothing submitted and nothing written.
refuse() {
  echo "error: census: $*; nothing submitted" >&2
  echo "usage: $0 [--tasks T] [--max-batches M] [--deterministic] [--wait] CASE.json P OUT" >&2
  exit 2
}

# Internal modes, run inside jobs: --task B ... (one shard of batch B), --merge B ... (after batch B).
mode=drive
tasks=4
max_batches=""
deterministic=""
wait=""
batch=""
args=()
# The value of option $1 (the next argument), refused when it is missing or is another option.
value_of() {
  [ $# -ge 2 ] && [ -n "$2" ] && [[ "$2" != --* ]] || refuse "$1 needs a value"
}
while [ $# -gt 0 ]; do
  case "$1" in
    --tasks) value_of "$@"; tasks="$2"; shift 2 ;;
    --max-batches) value_of "$@"; max_batches="$2"; shift 2 ;;
    --deterministic) deterministic=1; shift ;;
    --wait) wait=1; shift ;;
    --task | --merge) value_of "$@"; mode="${1#--}"; batch="$2"; shift 2 ;;
    -*) refuse "unknown option $1" ;;
    *) args+=("$1"); shift ;;
  esac
done
[ ${#args[@]} -eq 3 ] || refuse "CASE.json, P and OUT expected, got ${#args[@]} argument(s)"
case_file="${args[0]}" p="${args[1]}" out="${args[2]}"
[[ "$tasks" =~ ^[1-9][0-9]{0,4}$ ]] || refuse "--tasks: a whole number 1..99999 expected, got '$tasks'"
if [ -n "$max_batches" ]; then
  [[ "$max_batches" =~ ^[1-9][0-9]{0,2}$|^1000$ ]] || refuse "--max-batches: a whole number 1..1000 expected, got '$max_batches'"
fi
[[ "$p" =~ ^[0-9.eE+-]+$ ]] || refuse "P: a probability strictly between 0 and 1 expected (e.g. 0.05), got '$p'"
[ -f "$case_file" ] || refuse "CASE: no such file: $case_file"
spine="${SPINE:-$(command -v spine || true)}"
[ -x "$spine" ] || refuse "no spine program (set SPINE or put spine in PATH)"
case_file="$(realpath "$case_file")"
out="$(realpath -m "$out")"
spine="$(realpath "$spine")"
export SPINE="$spine"
name="spine-census-$(printf '%s' "$(realpath -m "$out")" | cksum | cut -d' ' -f1)"

# OUT is census.sh's own folder: never the working directory, the case's folder or one above it,
# never inside this repository (results are not sources), and, when it already holds files, only
# a folder this script made (its marker), so that census.status and logs/ never land among a
# user's files.
marker="$out/.spine-census"
repo="$(cd "$here/../.." && pwd -P)"
case_dir="$(dirname "$case_file")"
[ "$out" != "$(pwd -P)" ] || refuse "OUT is the working directory; give a folder of its own"
case "$case_dir/" in "$out"/*) refuse "OUT ($out) holds the case file; give a folder of its own" ;; esac
case "$out/" in "$repo"/*) refuse "OUT ($out) is inside the repository ($repo); give a folder outside it" ;; esac
if [ -e "$out" ] && ! [ -d "$out" ]; then refuse "OUT ($out) is a file"; fi
if [ -d "$out" ] && [ -n "$(ls -A "$out")" ] && ! [ -f "$marker" ]; then
  refuse "OUT ($out) holds files census.sh did not write (no $marker); give a new or empty folder"
fi

# The single run's options: the confidence and, with --max-batches, the cap on starts.
design_opts=(--confidence "$p")
[ -n "$max_batches" ] && design_opts+=(--starts "$((max_batches * 100))")

status() {
  mkdir -p "$out"
  printf '%s\n' "$*" >"$out/census.status.tmp"
  mv "$out/census.status.tmp" "$out/census.status"
}

# The same command with the internal mode, quoted for sbatch --wrap.
self() {
  local cmd=(bash "$here/census.sh" --tasks "$tasks")
  [ -n "$max_batches" ] && cmd+=(--max-batches "$max_batches")
  [ -n "$deterministic" ] && cmd+=(--deterministic)
  cmd+=("$@" "$case_file" "$p" "$out")
  printf '%q ' "${cmd[@]}"
}

shard_complete() { [ -f "$1/shard.json" ] && grep -q '"complete":true' "$1/shard.json"; }

# Submits the shards of batch $1 not yet complete, and the merge that follows them.
submit_batch() {
  local b="$1" missing=() k array_id merge_id
  for k in $(seq "$tasks"); do shard_complete "$out/batch-$b/shard-$k" || missing+=("$k"); done
  mkdir -p "$out/logs"
  local dependency=()
  if [ ${#missing[@]} -gt 0 ]; then
    local list
    list="$(IFS=,; echo "${missing[*]}")"
    # shellcheck disable=SC2086 # SBATCH_ARGS is a list of options
    array_id="$(sbatch --parsable --job-name="$name" --array="$list" ${SBATCH_ARGS:-} \
      --output="$out/logs/batch-$b-shard-%a.log" --wrap "$(self --task "$b")")"
    dependency=(--dependency="afterok:${array_id%%;*}" --kill-on-invalid-dep=yes)
  fi
  # shellcheck disable=SC2086
  merge_id="$(sbatch --parsable --job-name="$name" "${dependency[@]}" ${SBATCH_ARGS:-} \
    --output="$out/logs/merge-$b.log" --wrap "$(self --merge "$b")")"
  status "running: batch $b (shards ${missing[*]:-none} submitted${array_id:+ as job ${array_id%%;*}}, merge job ${merge_id%%;*})"
  echo "census: batch $b submitted (${#missing[@]} of $tasks shards; merge job ${merge_id%%;*})"
}

# Merges batches 1..$1 into OUT/census; prints the next batch, if the census goes on.
merge_upto() {
  local b="$1" shards=() j k code=0 log
  for j in $(seq "$b"); do
    for k in $(seq "$tasks"); do shards+=("$out/batch-$j/shard-$k"); done
  done
  log="$("$spine" merge "${shards[@]}" ${deterministic:+--deterministic} --out "$out/census" 2>&1)" || code=$?
  if [ "$mode" = merge ]; then
    printf '%s\n' "$log" >&2 # the merge job's log
  else
    mkdir -p "$out/logs"
    printf '%s\n' "$log" >"$out/logs/resume-merge-$b.log"
  fi
  local next
  next="$(printf '%s\n' "$log" | sed -n 's/^next batch: \([0-9]*\)$/\1/p')"
  if [ "$code" -eq 0 ]; then
    status "reached: P(a better optimum unseen) <= $p after batch $b; $out/census/result.json"
  elif [ "$code" -eq 3 ] && [ -n "$next" ]; then
    echo "$next"
  elif [ "$code" -eq 3 ]; then
    status "ended: the census stopped at its cap or is not clean (exit 3); $out/census/result.json"
  else
    status "failed: spine merge of batches 1..$b exited $code (see $out/logs)"
    return 1
  fi
}

case "$mode" in
  task)
    k="${SLURM_ARRAY_TASK_ID:?run as a job array}"
    exec "$spine" design "$case_file" "${design_opts[@]}" --batch "$batch" --shard "$k/$tasks" \
      --jobs "${SLURM_CPUS_PER_TASK:-1}" --out "$out/batch-$batch/shard-$k"
    ;;
  merge)
    next="$(merge_upto "$batch")"
    [ -n "$next" ] && submit_batch "$next"
    exit 0
    ;;
esac

# The driver: check what the jobs will run, find where the census stands, submit what comes next.
# `spine design --check` is the task's own command (batch 1, shard 1) solving nothing: the case is
# a design case, P is a probability in (0, 1), the cap fits; its refusal is this script's.
check="$("$spine" design "$case_file" "${design_opts[@]}" --batch 1 --shard "1/$tasks" --check \
  --out "$out/batch-1/shard-1" 2>&1 >/dev/null)" || { check="${check#error: }"; refuse "spine design --check: ${check% (see --help)}"; }
command -v sbatch >/dev/null || refuse "no sbatch here (run it where Slurm is)"
mkdir -p "$out"
[ -f "$marker" ] || printf '%s\n' "# written by scripts/slurm/census.sh: this folder is a census's (batch-*/, census/, census.status, logs/)" >"$marker"
if squeue -h -n "$name" -o %i 2>/dev/null | grep -q .; then
  echo "census: jobs of this census are still queued or running ($name); not submitting again" >&2
  [ -z "$wait" ] && exit 1
else
  b=1
  while [ -d "$out/batch-$b" ]; do
    all=1
    for k in $(seq "$tasks"); do shard_complete "$out/batch-$b/shard-$k" || { all=""; break; }; done
    [ -n "$all" ] || break
    b=$((b + 1))
  done
  next=1
  if [ "$b" -gt 1 ]; then
    # Batches 1..b-1 are complete: is the census done, or does it go on (with batch b)?
    next="$(merge_upto $((b - 1)))" || exit 1
  fi
  if [ -n "$next" ]; then
    submit_batch "$next"
  else
    echo "census: already done: $(cat "$out/census.status")"
  fi
fi
[ -n "$wait" ] || exit 0
while squeue -h -n "$name" -o %i 2>/dev/null | grep -q .; do sleep 2; done
line="$(cat "$out/census.status" 2>/dev/null || echo "failed: no status")"
echo "census: $line"
case "$line" in
  reached:*) exit 0 ;;
  ended:*) exit 3 ;;
  running:*)
    status "failed: the jobs of ${line#running: } ended without a merge (a task failed or was cancelled; see $out/logs); run the same command again to resume"
    echo "census: $(cat "$out/census.status")" >&2
    exit 1
    ;;
  *) exit 1 ;;
esac
