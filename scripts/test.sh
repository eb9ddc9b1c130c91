#!/usr/bin/env bash
# Run every check CI runs: formatting (rustfmt.toml) and lints (clippy, warnings as errors)
# first, then every test. Installs lavapipe first when no Vulkan driver is present: the GPU
# tests need an adapter, and under CI=true they fail without one instead of skipping.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
# rustfmt and clippy come with rustup's default profile; add them where they are missing.
cargo fmt --version >/dev/null 2>&1 || rustup component add rustfmt
cargo clippy --version >/dev/null 2>&1 || rustup component add clippy
cargo fmt --all -- --check
cargo clippy --release --all-targets --workspace -- -D warnings
# The API docs build without a warning (broken or redundant links, private items linked).
# In the release profile, so that rustdoc reads the dependencies' metadata clippy just built
# (the dev profile would check every dependency again: 3 of CI's 21 minutes, BENCHMARKS.md "CI's time on two cores").
RUSTDOCFLAGS="-D warnings" cargo doc --release --no-deps --workspace
# lavapipe compiles each kernel for 4 lanes instead of 8 (LP_NATIVE_VECTOR_WIDTH; GPU drivers
# ignore it): the suite's kernels compile once each from a cold cache, and narrower code
# compiles faster for about the same run time (BENCHMARKS.md "Tests and CI").
export LP_NATIVE_VECTOR_WIDTH="${LP_NATIVE_VECTOR_WIDTH:-128}"
cargo test --release --workspace
# The Python package: its wheel (maturin) in a virtual environment, and its tests (pytest).
bash scripts/python-package.sh test
