#!/usr/bin/env bash
# Render the gallery (scenes/gallery/*.toml) into docs/gallery/, and print each render's
# summary line (passes, photons, seconds) for the table of docs/guide/gallery.md. At each
# scene's own settings, or with SECONDS as many passes as fit in that time, at WIDTH (default:
# the scene's) square.
#   bash scripts/regen/gallery.sh [SECONDS [WIDTH]]
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release -q
bin=${CARGO_TARGET_DIR:-target}/release/sppm-gpu
args=()
if [ -n "${1:-}" ]; then
    args+=(--time-limit "$1")
fi
if [ -n "${2:-}" ]; then
    args+=(--width "$2" --height "$2")
fi
for scene in scenes/gallery/*.toml; do
    name=$(basename "$scene" .toml)
    printf '%s: ' "$name"
    "$bin" "$scene" -o "docs/gallery/$name.png" ${args[@]+"${args[@]}"} 2>&1 | tail -1
done
