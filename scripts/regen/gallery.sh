#!/usr/bin/env bash
# Render the gallery (scenes/gallery/*.toml) at their own settings into docs/gallery/, and
# print each render's summary line (passes, photons, seconds) for the table of docs/guide/gallery.md.
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release -q
for scene in scenes/gallery/*.toml; do
    name=$(basename "$scene" .toml)
    printf '%s: ' "$name"
    ./target/release/sppm-gpu "$scene" -o "docs/gallery/$name.png"
done
