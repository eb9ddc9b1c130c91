#!/usr/bin/env bash
# A volumetric caustic (scenes/media/volumetric-caustic.xml: a glass sphere in fog under a small
# sphere light) that Mitsuba's path tracers cannot converge: our SPPM against pt-nee at equal
# time, against a long reference of our own SPPM whose remaining bias is bounded by a second
# long run at half the radius (the estimate's bias shrinks with the radius; what the two runs
# differ by beyond their noise is an upper bound of it), and pt-nee run as long.
# Feeds docs/journal/session-16.md "Participating media (issue 35)" and BENCHMARKS.md.
#   bash scripts/measure/volumetric-caustic.sh OUT_DIR [REFERENCE_SECONDS] [EQUAL_SECONDS] [RADIUS]
# REFERENCE_SECONDS (default 360) for each long run, EQUAL_SECONDS (default 60) for compare,
# RADIUS (default 0.04) the long runs' initial radius, the second run's half of it.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:?usage: volumetric-caustic.sh OUT_DIR [REFERENCE_SECONDS] [EQUAL_SECONDS] [RADIUS]}
long=${2:-360}
equal=${3:-60}
radius=${4:-0.04}
bin=${SPPM_GPU:-target/release/sppm-gpu}
scene=scenes/media/volumetric-caustic.xml
mkdir -p "$out"
half=$(python3 -c "print($radius / 2)")
# The long runs, with seeds of their own (compare renders with the scene's seed, 0).
"$bin" "$scene" -o "$out/sppm-long-r.exr" --method sppm --radius "$radius" --seed 101 \
    --iterations 100000000 --time-limit "$long" 2>&1 | tail -1
"$bin" "$scene" -o "$out/sppm-long-r2.exr" --method sppm --radius "$half" --seed 102 \
    --iterations 100000000 --time-limit "$long" 2>&1 | tail -1
"$bin" "$scene" -o "$out/pt-nee-long.exr" --method pt-nee --seed 103 \
    --iterations 100000000 --time-limit "$long" 2>&1 | tail -1
echo "long SPPM, radius $radius against radius $half (8x8 blocks):"
"$bin" diff "$out/sppm-long-r.exr" "$out/sppm-long-r2.exr" --downsample 8
echo "long pt-nee against the long SPPM at radius $half (8x8 blocks):"
"$bin" diff "$out/pt-nee-long.exr" "$out/sppm-long-r2.exr" --downsample 8
# Equal time against the long SPPM at the smaller radius, at full resolution; SPPM at the long
# run's radius: the automatic one (3 pixel footprints, 0.013 here) suits surfaces, while in thin
# fog the volume estimate needs a wider kernel to gather photons at all.
"$bin" compare "$scene" --reference "$out/sppm-long-r2.exr" --methods sppm,pt-nee --time-limit "$equal" --radius "$radius" \
    --out "$out/compare"
cat "$out/compare/compare.csv"
