#!/usr/bin/env bash
# Run every test. Installs lavapipe first when no Vulkan driver is present: the GPU tests need
# an adapter, and under CI=true they fail without one instead of skipping.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cargo test --release --workspace
