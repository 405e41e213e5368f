# Flexible spine workspace. `just --list` shows the recipes.

set shell := ["bash", "-euo", "pipefail", "-c"]

# Build everything once in release mode (the CLI, tests and benchmarks).
build:
    cargo build --release --workspace --all-targets

# Run every test (release build; unit, integration, property and CLI tests), then the Ipopt-facing
# tests again on the Ipopt 3.14 backend (`just ipopt314 test`), the Python package's tests
# (`just python`), the browser check of the HTML report (`just browser-test`), the shard/merge
# path of a multi-start under GNU parallel and the Slurm script (`just shard-test`), the docs'
# quoted numbers against fresh runs of the paper (`just docs-check`), then the lints (`just lint`).
test:
    cargo build --release --workspace --all-targets --quiet
    if cargo nextest --version >/dev/null 2>&1; then cargo nextest run --release --workspace --no-fail-fast; else cargo test --release --workspace --no-fail-fast; fi
    cargo test --release --workspace --doc --quiet
    just ipopt314 test
    just python
    just browser-test
    just shard-test
    just slurm-test
    just docs-check
    just lint

# The Python package `flexspine` (crates/spine-py): builds it from source and installs it into
# crates/spine-py/.venv (`crates/spine-py/setup.sh`: venv with numpy, pytest, maturin, then
# `pip install ./crates/spine-py`), runs its pytest suite against the CLI, and the quickstart
# example (writes results/python-quickstart/*.csv).
python:
    cargo build --release --workspace --all-targets --quiet
    ./crates/spine-py/setup.sh
    crates/spine-py/.venv/bin/python -m pytest -q crates/spine-py/tests
    crates/spine-py/.venv/bin/python examples/python/quickstart.py results/python-quickstart

# The HTML report in a real browser: installs Debian's chromium if missing, then runs the ignored
# test that builds a small report.html, loads it in headless Chromium and checks its DOM and a
# screenshot (crates/spine-cli/tests/paper_cli.rs).
browser-test:
    if ! command -v chromium >/dev/null; then \
        SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"; \
        echo "browser-test: installing chromium"; \
        $SUDO apt-get update -qq; \
        DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends chromium fonts-dejavu-core >/dev/null; \
    fi
    CHROMIUM="$(command -v chromium)" cargo test --release --quiet --workspace --test paper_cli -- --ignored report_html_renders_in_a_headless_browser

# A multi-start split into shards as on a cluster (GNU parallel, and scripts/slurm/multistart.sbatch
# as a simulated job array), merged and compared byte for byte with the single run; installs
# Debian's parallel if missing.
shard-test:
    cargo build --release --workspace --all-targets --quiet
    ./scripts/shard-merge-check.sh

# The cluster path under a real Slurm: a one-node cluster on this machine
# (scripts/slurm/local-cluster.sh: Debian's Slurm 22.05 + munge, its own conf, ports and folder),
# a job array of scripts/slurm/multistart.sbatch merged to the single run's bytes, a failed task, a
# cancelled array, and scripts/slurm/census.sh to P <= 0.05 with a failure and a resume, against
# `spine design --confidence 0.05` byte for byte. Skipped, saying why, where Slurm cannot start.
slurm-test:
    cargo build --release --workspace --all-targets --quiet
    ./scripts/slurm/cluster-check.sh

# Eq. (33) from Python beside the CLI and CasADi + IPOPT (5 and 10 links, the same start), one run.
python-bench REPEATS="5":
    cargo build --release --workspace --all-targets --quiet
    ./crates/spine-py/setup.sh
    ./benchmarks/peers/setup.sh
    crates/spine-py/.venv/bin/python benchmarks/peers/python_side_by_side.py {{REPEATS}}

# The opt-in Ipopt 3.14 backend (Ipopt 3.14.19 with MUMPS 5.8.2, METIS and OpenBLAS, from the
# `casadi` wheel on PyPI, set up in benchmarks/peers/.venv), built in target/ipopt314 with
# IPOPT_DIR. `just ipopt314 test` (run by `just test`): the binding's and eq. (33)'s tests
# (spine-ipopt, spine-design: every Ipopt call the workspace makes goes through these two crates),
# built with the `ipopt314` profile (opt-level 1: 256 s against 384 s with `release`, 2026-12-02);
# `just ipopt314 cli`: the CLI's design tests on it as well (a release build of the whole command
# line, about 5 more minutes on 2 cores, so not in `just test`); `just ipopt314 build`:
# target/ipopt314/release/spine and the benchmark binaries.
ipopt314 WHAT="test":
    ./benchmarks/peers/setup.sh
    dir="$(benchmarks/peers/.venv/bin/python -c 'import casadi, os; print(os.path.dirname(casadi.__file__))')"; \
    export IPOPT_DIR="$dir" CARGO_TARGET_DIR=target/ipopt314 RUSTFLAGS="-C link-arg=-Wl,-rpath,$dir" RUSTDOCFLAGS="-C link-arg=-Wl,-rpath,$dir"; \
    case "{{WHAT}}" in \
        test) export SPINE_EXPECT_IPOPT=3.14; cargo test --profile ipopt314 --quiet -p spine-ipopt -p spine-design --no-fail-fast ;; \
        cli) export SPINE_EXPECT_IPOPT=3.14; cargo test --release --quiet -p spine-ipopt -p spine-design --no-fail-fast && cargo test --release --quiet -p spine-cli --test design_cli ;; \
        build) cargo build --release --quiet -p spine-cli -p spine-benchmarks --bins ;; \
        *) echo "just ipopt314 test|cli|build"; exit 2 ;; \
    esac

# Run a paper case by name: `just case fig6` writes results/fig6 (result.json with checked claims, CSV, SVG, PNG).
case NAME:
    cargo run --release --quiet -p spine-cli -- case paper-cases/{{NAME}}.json --out results/{{NAME}}

# A study: `just study ck` sweeps C_K of eq. (34) over 1..1e4 (half-decades), Ipopt scaling on and off.
study NAME:
    cargo run --release --quiet -p spine-cli -- study {{NAME}} paper-cases/study-{{NAME}}.json --out results/study-{{NAME}}

# Fig. 5 as a followed sweep (beside the paper's independent solves of `just case fig5`): the
# optimum at -1 N per node followed to -20 N per node over 39 points (every 0.5 N), with a
# 20-start census at every third point (-1, -2.5, -4, …, -19.0) and the events on the way:
# results/fig5-sweep/{sweep.csv,sweep.svg,sweep.png,sweep.pdf,result.json}.
sweep-fig5:
    cargo run --release --quiet -p spine-cli -- sweep paper-cases/fig5-base.json --param loads.p_y --from -1 --to -20 --points 39 --census 20 --census-every 3 --out results/fig5-sweep

# Every figure and the C_K study, then results/REPORT.md, results/report.html (one self-contained page; a failed solver check, exit 3, is reported, not fatal) and results/report.json, then the numbers README.md and docs/ (findings, errata, contributing) quote from these runs rewritten (`spine quotes`: the `<!--q …-->` markers; a quote within its tolerance is kept, so `git diff docs/` stays empty when the runs agree).
paper:
    just paper-results results
    ./target/release/spine quotes --results results

# The paper's runs into OUT (every figure case, the C_K study, the report), as `just paper` makes them.
paper-results OUT:
    cargo build --release --workspace --all-targets --quiet
    for c in twolink fig3 fig4 fig5 fig6 fig7 fig8 fig9 fig10 fig11 fig12; do \
        echo "== $c"; code=0; ./target/release/spine case paper-cases/$c.json --out {{OUT}}/$c || code=$?; \
        if [ "$code" != 0 ] && [ "$code" != 3 ]; then exit "$code"; fi; \
    done
    echo "== study-ck"; code=0; ./target/release/spine study ck paper-cases/study-ck.json --out {{OUT}}/study-ck || code=$?; if [ "$code" != 0 ] && [ "$code" != 3 ]; then exit "$code"; fi
    ./target/release/spine report --results {{OUT}}

# The docs against the runs (run by `just test`; scripts/docs-check.sh): the paper's runs made
# afresh in target/docs-check/results, every number README.md, docs/findings.md and docs/errata.md
# quote compared with them (`spine quotes --check`, exit 3 naming each drift), and every failing
# statement of the paper linked to its explanation in docs/findings.md (report.json).
docs-check:
    cargo build --release --workspace --all-targets --quiet
    ./scripts/docs-check.sh

# Criterion benchmarks for N = 5 … 10 000 (about 10 min), then benchmarks/RESULTS.md and benchmarks/scaling.svg.
bench:
    cargo bench -p spine-benchmarks --bench scaling
    cargo run --release --quiet -p spine-benchmarks --bin bench_report

# CasADi's AD beside ours: the residual Jacobian and the Lagrangian Hessian of eq. (33) as CasADi SX
# functions (its VM and its C code compiled with gcc -O3), on the same point, N = 10, 100, 1000 by
# default; checks the values agree, writes benchmarks/peers/ad-results.json and RESULTS.md's table.
bench-ad-peers *SIZES:
    ./benchmarks/peers/setup.sh
    cargo build --release --quiet -p spine-benchmarks --bins
    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 ./target/release/bench_ad_peers benchmarks/peers/.venv/bin/python {{SIZES}}
    ./target/release/bench_report

# Global bounds on eq. (33) with SCIP 10, optional (installs the `pyscipopt` wheel, which ships
# libscip, into benchmarks/peers/.venv-scip; nothing else depends on it). CENSUS is a `spine design`
# result.json of the same case (a census's best): its J is the cutoff the derived bounds use and its
# point is checked in SCIP's equations; SCIP reports its best point, its dual (lower) bound and the
# gap within TIME seconds (benchmarks/peers/scip_global.py; FLAGS e.g. `--incumbent`).
certify CASE CENSUS TIME="600" *FLAGS:
    test -x benchmarks/peers/.venv-scip/bin/python || (python3 -m venv benchmarks/peers/.venv-scip && benchmarks/peers/.venv-scip/bin/pip install -q pyscipopt==6.3.0)
    benchmarks/peers/.venv-scip/bin/python benchmarks/peers/scip_global.py {{CASE}} {{CENSUS}} --time {{TIME}} {{FLAGS}}

# The global-bound table of benchmarks/analysis.md: for design5's loads with N = 2 … 5 links, a
# census to P <= 0.001, then SCIP with the census's point as its incumbent (TIME seconds each);
# one JSON report per N in results/certify/.
certify-table TIME="600":
    cargo build --release --quiet -p spine-cli
    mkdir -p results/certify
    for n in 2 3 4 5; do \
      case=benchmarks/peers/certify/design5-${n}links.json; [ $n = 5 ] && case=paper-cases/design5.json; \
      ./target/release/spine design $case --confidence 0.001 --jobs 2 --deterministic --out results/certify/census-$n | grep -E "^census to"; \
      just certify $case results/certify/census-$n/result.json {{TIME}} --incumbent > results/certify/scip-$n.json; \
      python3 -c "import json,sys; r=json.load(open(sys.argv[1])); print('N =', r['links'], r['status'], r['seconds'], 's, census J', r['census_J'], 'dual bound', r['dual_bound'], 'gap to census', r['gap_to_census'])" results/certify/scip-$n.json; \
    done

# A census to a stated confidence, timed (design10, seeded starts in `JOBS` worker processes until
# P(a better optimum unseen) <= P; issue 45's target: P = 0.01 in under 10 s on 2 cores).
bench-census P="0.01" JOBS="2":
    cargo build --release --quiet -p spine-cli
    start=$(date +%s.%N); ./target/release/spine design paper-cases/design10.json --confidence {{P}} --jobs {{JOBS}} --deterministic --out results/bench-census | grep -E "^census|^multi-start"; end=$(date +%s.%N); \
    echo "census to P <= {{P}} with {{JOBS}} jobs: $(awk "BEGIN { print $end - $start }") s wall"

# Eq. (33) against CasADi + IPOPT on the same case files and start points (N default 5 … 1000; about
# 20 min): ours cold and refined on both Ipopt backends, CasADi cold and through our ladder (sets up
# its own Python venv with CasADi), then the table in benchmarks/RESULTS.md.
bench-peers *SIZES:
    ./benchmarks/peers/setup.sh
    cargo build --release --quiet -p spine-benchmarks --bins
    just ipopt314 build
    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 ./target/release/bench_peers benchmarks/peers/.venv/bin/python {{SIZES}}
    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 ./target/ipopt314/release/bench_peers benchmarks/peers/.venv/bin/python {{SIZES}}
    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 ./target/release/bench_peers benchmarks/peers/.venv/bin/python --casadi-refined {{SIZES}}
    ./target/release/bench_report

# Stable fuzzing at length: every paper case mutated CASES times (default 20000, about 35 s per
# 400 000 cases) through the fuzz target's body (`spine_case::fuzz::check_bytes`); `just test`
# runs 500 per case.
fuzz-long CASES="20000":
    FUZZ_CASES={{CASES}} cargo test --release -p spine-integration-tests --test cases mutated -- --nocapture

# Fuzz the case parser for SECONDS seconds (needs the nightly toolchain; installs cargo-fuzz).
fuzz SECONDS="60":
    command -v cargo-fuzz >/dev/null || cargo install --locked cargo-fuzz
    cd fuzz && cargo +nightly fuzz run case_parser -- -max_total_time={{SECONDS}}

# Lints: clippy with every warning an error (the workspace's `[workspace.lints]`), rustfmt
# (`rustfmt.toml`), and rustdoc with every warning an error (no broken or private intra-doc
# links). Run by `just test`, hence by CI.
lint:
    cargo clippy --workspace --all-targets --quiet -- -D warnings
    cargo fmt --all --check
    RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet

# Eq. (37)'s gradients: the discrete adjoint against forward sensitivities (per gradient, N = 7,
# 20, 50) and eq. (37) by gradients (adjoint, forward) against the GA (N = 7, 50), one run; writes
# its section of benchmarks/DYNAMICS.md (about 5 min).
bench-gradients *ARGS:
    cargo build --release --quiet -p spine-benchmarks --bins
    ./target/release/dynamic_gradients {{ARGS}}

# Eq. (33) scaling table (full and reduced space) on the scaled family of PEERS.md.
# The chain against the continuum it discretises (Euler's load, the elastica), N = 10 … 10⁴:
# the table of docs/continuum.md and docs/continuum-convergence.svg.
continuum:
    cargo run --release --quiet -p spine-benchmarks --bin continuum_convergence

bench-design *SIZES:
    cargo run --release --quiet -p spine-benchmarks --bin design_scaling -- {{SIZES}}

# Dynamics, side by side with scipy: work against precision of 1 s of the scaled step response
# (PEERS.md) for N (default 5 10 20 50 100 200 500), this workspace's Radau IIA and scipy's Radau
# (benchmarks/peers/scipy_dynamics.py, in the venv of benchmarks/peers/setup.sh) at several
# tolerances; writes benchmarks/DYNAMICS.md and benchmarks/dynamics-work-precision.svg (about 10 min).
bench-dynamics *SIZES:
    ./benchmarks/peers/setup.sh
    cargo build --release --quiet -p spine-benchmarks --bins
    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 ./target/release/dynamics_scaling {{SIZES}}
