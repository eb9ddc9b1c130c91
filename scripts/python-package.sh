#!/usr/bin/env bash
# The Python package (crates/python): makes the virtual environment target/python-venv (or
# $SPPM_PYTHON_VENV) with the pinned maturin, numpy and pytest of
# crates/python/requirements-test.txt, builds the wheel with `maturin build --release` into
# target/wheels (pyproject.toml at the root) and installs it there. With `test`, then runs its tests (pytest).
#
# scripts/setup.sh and scripts/test.sh run it. The wheel's build shares target/ with cargo:
# after `cargo build --release` it compiles only PyO3, numpy's bindings and the package's
# own crate (BENCHMARKS.md "Python package").
set -euo pipefail
cd "$(dirname "$0")/.."
target="$(realpath -m "${CARGO_TARGET_DIR:-target}")"
venv="$(realpath -m "${SPPM_PYTHON_VENV:-$target/python-venv}")"
requirements=crates/python/requirements-test.txt

# The environment is made once and kept while the pins are the same (a copy of them is kept
# in it); a run without network then still builds and tests.
if ! cmp -s "$requirements" "$venv/requirements-test.txt" 2>/dev/null; then
    rm -rf "$venv"
    python3 -m venv "$venv"
    "$venv/bin/python" -m pip install --quiet --no-compile -r "$requirements"
    cp "$requirements" "$venv/requirements-test.txt"
fi

# abi3: one wheel, cp39-abi3, for every CPython from 3.9.
rm -f "$target"/wheels/sppm_gpu-*.whl
"$venv/bin/maturin" build --release --quiet --out "$target/wheels" --interpreter "$venv/bin/python"
"$venv/bin/python" -m pip install --quiet --no-deps --force-reinstall "$target"/wheels/sppm_gpu-*.whl

if [ "${1:-}" = test ]; then
    # The tests import the installed wheel (crates/python/python is not on the path).
    "$venv/bin/python" -m pytest -q -p no:cacheprovider crates/python/tests
fi
