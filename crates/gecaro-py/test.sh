#!/usr/bin/env bash
# The Python package's tests: builds and installs `gecaro` into a fresh
# virtual environment (as a user would: pip install ./crates/gecaro-py), runs
# the pytest suite against it and the command line, then the Python examples.
set -euo pipefail
cd "$(dirname "$0")/../.."

venv="$PWD/target/python-test-venv"
rm -rf "$venv"
python3 -m venv "$venv"
"$venv/bin/python" -m pip install --quiet --upgrade pip
"$venv/bin/python" -m pip install --quiet -r crates/gecaro-py/requirements-test.txt
# Built in the dev profile, on the artifacts `cargo test --workspace` left in
# the shared target folder (a release build would compile everything again);
# they fit only while gecaro-py's feature pins hold (see its Cargo.toml).
python3 crates/gecaro-py/feature_pins.py
MATURIN_PEP517_ARGS="--profile dev" CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/target}" \
    "$venv/bin/python" -m pip install --quiet ./crates/gecaro-py

# The command line the results are compared with, as the README's test
# command builds it: `cargo build --bin gecaro` alone would unify other
# features than the whole workspace's tests do and compile nalgebra, faer,
# tokio … again (3 minutes of CI); after that command this rebuilds nothing.
cargo test --workspace --locked --no-run
export GECARO_CLI="$PWD/target/debug/gecaro"

(cd crates/gecaro-py && "$venv/bin/python" -m pytest -q)

# The type stubs against the compiled module, and the examples against the stubs.
(cd target && "$venv/bin/python" -m mypy.stubtest --ignore-disjoint-bases gecaro)
"$venv/bin/python" -m mypy --strict --no-incremental examples/python
for example in examples/python/*.py; do
    echo "== $example"
    "$venv/bin/python" "$example"
done

# The numpy reference of docs/performance.md ("The numpy reference") lands on
# gecaro's solution, both ways of its Jacobian: 500 configurations, one run
# (a check of the reference, not a timing).
reference_data="$PWD/target/numpy-reference-500.csv"
rm -f "$reference_data"
"$GECARO_CLI" generate stanford --method position --count 500 --noise 1e-5 --seed 1 \
    --output "$reference_data" >/dev/null
"$venv/bin/python" crates/gecaro-py/bench/numpy_reference.py "$GECARO_CLI" \
    robots/stanford.toml "$reference_data" 1e-5 1
