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
cargo test --quiet
python -m pytest -q "$@"
