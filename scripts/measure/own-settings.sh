#!/usr/bin/env bash
# Feeds BENCHMARKS.md "Accuracy" (journal: "Accuracy at the scenes' own settings (issue 2)", docs/journal/sessions-01-02.md).
# Inputs: the repository's scenes and tests/references; writes out/.
# The figures in BENCHMARKS.md: each canonical scene at its own settings against its
# reference (8x8 box-downsampled), and the 512x512 speed run. Writes images to out/.
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release -q
bin=./target/release/sppm-gpu
mkdir -p out
for s in furnace cornell-box cornell-spheres cornell-glossy point-light textured depth-of-field; do
    $bin scenes/$s.toml -o out/$s.exr
    factor=8; [ $s = furnace ] && factor=1
    $bin diff out/$s.exr tests/references/$s.exr --downsample $factor
done
for s in cornell-box cornell-spheres; do
    $bin scenes/$s.toml -o out/$s-512.exr --width 512 --height 512 --iterations 20 --photons 200000 --max-depth 32
done
