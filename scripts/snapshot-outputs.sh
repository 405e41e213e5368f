#!/usr/bin/env bash
# Runs every paper case and every subcommand with `--deterministic` into OUT (one folder each),
# recording each exit code in OUT/exit-codes.txt. Two snapshots of the same tree are byte-identical;
# compare a snapshot before and after a refactor with `diff -r BEFORE AFTER`.
#   scripts/snapshot-outputs.sh OUT [SPINE_BINARY]
set -uo pipefail
out="${1:?usage: scripts/snapshot-outputs.sh OUT [SPINE_BINARY]}"
spine="${2:-./target/release/spine}"
cd "$(dirname "$0")/.."
mkdir -p "$out"
: > "$out/exit-codes.txt"
run() {
    local name="$1"; shift
    "$spine" "$@" --out "$out/$name" --deterministic > "$out/$name.stdout" 2> "$out/$name.stderr"
    echo "$name $?" >> "$out/exit-codes.txt"
    # Printed wall times differ between runs; keep the rest of stdout comparable.
    sed -i -E 's/[0-9]+\.[0-9]+ s(,|\)| in|$)/<t> s\1/g' "$out/$name.stdout"
}
for c in paper-cases/*.json; do
    name="$(basename "$c" .json)"
    run "case-$name" case "$c"
done
run equilibrium-arch10 equilibrium paper-cases/arch10.json
python3 -c 'import json; print(json.dumps(json.load(open("paper-cases/twolink.json"))["base"]))' > "$out/twolink-case.json"
run twolink-base twolink "$out/twolink-case.json"
run twolink-wrong-kind twolink paper-cases/arch10.json
run design-design5-multistart design paper-cases/design5.json --starts 3 --seed 7
run design-design5-reduced design paper-cases/design5.json --formulation reduced
run simulate-step5 simulate paper-cases/step5.json
run damping-damping5 damping paper-cases/damping5.json
run periodic-periodic7-pattern periodic paper-cases/periodic7.json --method pattern
run study-ck-design5 study ck paper-cases/design5.json --values 1,100
run missing-file equilibrium does-not-exist.json
