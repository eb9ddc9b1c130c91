#!/usr/bin/env bash
# Feeds BENCHMARKS.md "Glossy surfaces converge" (docs/journal/sessions-01-02.md).
# Inputs: the repository's scenes and references.
# SPPM on cornell-glossy at its own settings, stopped after 4, 8, 16, 32 and 64 passes:
# relMSE against the reference (8x8 downsampled) should fall as passes grow.
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release -q
mkdir -p out
for n in 4 8 16 32 64; do
    ./target/release/sppm-gpu scenes/cornell-glossy.toml -o out/cornell-glossy-$n.exr --iterations $n > /dev/null
    printf '%3d passes: ' $n
    ./target/release/sppm-gpu diff out/cornell-glossy-$n.exr tests/references/cornell-glossy.exr --downsample 8
done
