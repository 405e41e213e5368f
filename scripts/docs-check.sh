#!/usr/bin/env bash
# The docs against fresh runs of the paper (`just docs-check`, part of `just test`): the paper's
# runs made in target/docs-check/results as `just paper` makes them, then every number README.md,
# docs/findings.md and docs/errata.md quote compared with them (`spine quotes --check`: exit 3
# naming each drift), and every failing statement of the paper linked to its explanation in
# docs/findings.md (results/report.json lists the failing statements with their anchor).
set -euo pipefail
cd "$(dirname "$0")/.."
out=target/docs-check/results
mkdir -p target/docs-check
if ! just paper-results "$out" > target/docs-check/paper.log 2>&1; then
    tail -50 target/docs-check/paper.log
    echo "docs-check: the paper's runs failed (target/docs-check/paper.log)" >&2
    exit 1
fi
./target/release/spine quotes --results "$out" --check
python3 - "$out/report.json" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
failing = report["failing"]
bad = [f"{f['case']} [{f['scope']}] {f['statement']}" for f in failing if f["why"] is None]
print(f"{len(failing) - len(bad)} of {len(failing)} failing statements of the paper explained in docs/findings.md")
if bad:
    sys.exit("docs-check: no explanation in docs/findings.md for:\n  " + "\n  ".join(bad))
PY
