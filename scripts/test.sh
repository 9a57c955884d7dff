#!/usr/bin/env bash
# Installs brdf-rs and its test dependencies into ./.venv, then runs every test:
# the Rust unit tests (cargo test) and the Python suite (pytest).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
. .venv/bin/activate
python -m pip install --quiet --upgrade pip
echo "installing brdf-rs with its test dependencies (the first build compiles the Rust core: a few minutes)"
python -m pip install --quiet -e ".[test]"
# The unit tests only (--lib): the crate has no doc tests or tests/*.rs, and its one
# example (examples/eval_kernel.rs, a timing tool no test runs) would cost a second debug
# build of the whole crate to link it; cargo clippy --all-targets checks it.
cargo test --lib --quiet
# The Python suite in parallel processes (pytest-xdist), each test file in one process so
# that a module's fixtures are computed once: on 2 cores about half the serial time.
# Up to 4 processes (the Rust core runs its own thread pool in each); pass -n 0 to run
# serially.
python -m pytest -q -n auto --maxprocesses 4 --dist loadfile "$@"
