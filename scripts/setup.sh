#!/usr/bin/env bash
# Set up on a fresh Debian machine and render the Cornell box: installs lavapipe, builds the
# renderer (release), renders scenes/cornell-box.toml to cornell-box.png, and builds the
# Python package's wheel into target/wheels, installed in target/python-venv.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cargo build --release
"${CARGO_TARGET_DIR:-target}/release/sppm-gpu" scenes/cornell-box.toml -o cornell-box.png
bash scripts/python-package.sh
