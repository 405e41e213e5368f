# Flexible spine workspace. `just --list` shows the recipes.

set shell := ["bash", "-euo", "pipefail", "-c"]

# Build everything once in release mode (the CLI, tests and benchmarks).
build:
    cargo build --release --workspace --all-targets

# Run every test (release build; unit, integration, property and CLI tests).
test:
    cargo build --release --workspace --all-targets --quiet
    if cargo nextest --version >/dev/null 2>&1; then cargo nextest run --release --workspace --no-fail-fast; else cargo test --release --workspace --no-fail-fast; fi
    cargo test --release --workspace --doc --quiet

# Run a paper case by name, whatever its kind: `just case design5` runs paper-cases/design5.json into results/design5.
case NAME:
    cargo run --release --quiet -p spine-cli -- case paper-cases/{{NAME}}.json --out results/{{NAME}}

# Criterion benchmarks (equilibrium solve times and their parts for N = 10 … 1000).
bench:
    cargo bench -p spine-benchmarks --bench equilibrium

# Fuzz the case parser for SECONDS seconds (needs the nightly toolchain; installs cargo-fuzz).
fuzz SECONDS="60":
    command -v cargo-fuzz >/dev/null || cargo install --locked cargo-fuzz
    cd fuzz && cargo +nightly fuzz run case_parser -- -max_total_time={{SECONDS}}

# Lints.
lint:
    cargo clippy --workspace --all-targets -- -D warnings
    cargo fmt --all --check

# Eq. (33) scaling table (full and reduced space) on the scaled family of PEERS.md.
bench-design *SIZES:
    cargo run --release --quiet -p spine-benchmarks --bin design_scaling -- {{SIZES}}

# Dynamics: wall time, steps and evaluations to simulate 1 s of the step response for N (default 5 10 20 50).
bench-dynamics *SIZES:
    cargo run --release --quiet -p spine-benchmarks --bin dynamics_scaling -- {{SIZES}}
