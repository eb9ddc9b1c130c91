#!/usr/bin/env bash
# Feeds BENCHMARKS.md "The defaults: direct_samples and the radius" (docs/journal/session-04.md).
# Inputs: the repository's scenes and references.
# The measurements behind SPPM's automatic direct_samples and radius (docs/guide/how-it-works.md, "Direct light";
# BENCHMARKS.md): each setting renders a canonical scene for the same wall time and prints
# its full-resolution relMSE against the reference.
#
#   bash scripts/measure/direct-light-defaults.sh [SECONDS] [SCENE ...]
#
# Default: 10 s each, cornell-box and cornell-glossy. Run it on an otherwise idle machine.
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-10}
shift || true
scenes=("${@:-cornell-box cornell-glossy}")
cargo build --release -q
bin=./target/release/sppm-gpu
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for scene in ${scenes[*]}; do
    for samples in 1 4 8 16; do
        for pixels in 2 3 4; do
            # The radius in pixel footprints at the look-at distance (the automatic one is 2).
            radius=$(python3 -c "
import math, tomllib
s = tomllib.load(open('scenes/$scene.toml', 'rb'))
c = s['camera']
d = math.dist(c['position'], c['look_at'])
print($pixels * 2 * d * math.tan(math.radians(c['fov']) / 2) / s['render']['height'])")
            args=(--time-limit "$seconds" --iterations 1000000 --direct-samples "$samples" --radius "$radius")
            summary=$("$bin" "scenes/$scene.toml" -o "$out/$scene.exr" "${args[@]}" | tail -1)
            err=$("$bin" diff "$out/$scene.exr" "tests/references/$scene.exr" | tail -1)
            printf '%-15s direct_samples %2d radius %d px  %s  %s\n' "$scene" "$samples" "$pixels" \
                "$(echo "$summary" | sed 's/ -> .*//')" "$err"
        done
    done
done
