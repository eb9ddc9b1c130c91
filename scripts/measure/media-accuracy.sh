#!/usr/bin/env bash
# Participating media against Mitsuba 3's volpath (scenes/media/, references in
# tests/references/mitsuba/media/, 4096 spp): pt-nee and SPPM at 256x256, 8x8-block relMSE and
# channel means (`sppm-gpu diff --downsample 8`), at PASSES_PT samples and PASSES_SPPM passes.
# Feeds docs/journal/session-16.md "Participating media (issue 35)" and BENCHMARKS.md.
#   bash scripts/measure/media-accuracy.sh OUT_DIR [PASSES_PT] [PASSES_SPPM]
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:?usage: media-accuracy.sh OUT_DIR [PASSES_PT] [PASSES_SPPM]}
pt=${2:-1024}
sppm=${3:-512}
bin=${SPPM_GPU:-target/release/sppm-gpu}
mkdir -p "$out"
for name in fog-cornell murky-water; do
    for method in pt-nee sppm; do
        passes=$pt
        [ "$method" = sppm ] && passes=$sppm
        "$bin" "scenes/media/$name.xml" -o "$out/$name-$method.exr" --method "$method" --iterations "$passes" \
            --seed 7 2>&1 | tail -1
        echo "$name $method, $passes passes, against Mitsuba volpath:"
        "$bin" diff "$out/$name-$method.exr" "tests/references/mitsuba/media/$name.exr" --downsample 8
    done
done
