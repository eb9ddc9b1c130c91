#!/bin/sh
# Feeds BENCHMARKS.md "Adaptive SPPM radius (issue 26)" (docs/journal/session-12.md).
# Inputs: BIN (default target/release/sppm-gpu), tests/references; writes OUT (default out/adaptive).
# Adaptive SPPM radius (issue 26): the plain per-point rule (radius_rule = "shrink") against
# the adaptive one, at equal time.
#   reference: two long renders of scenes/gallery/water.toml at 128x128 (plain rule, seeds
#     other than the comparison's), from the automatic initial radius r0 = 0.0653 and from
#     2 r0: their difference bounds the bias left in the reference.
#   water: 60 s of each rule against the first reference, one `compare` run (passes go to
#     whichever is furthest behind, so a change in the machine's load falls on both alike).
#   canonical: 30 s of each on the three canonical scenes at full resolution against
#     tests/references (the same files as the study's shared references).
# usage: scripts/measure/adaptive-radius.sh reference|water|canonical [OUT] [SECONDS]
set -e
what=$1
out=${2:-out/adaptive}
bin=${BIN:-target/release/sppm-gpu}
mkdir -p "$out"
case $what in
reference)
    seconds=${3:-900}
    $bin scenes/gallery/water.toml --width 128 --height 128 --seed 1000 --iterations 1000000 \
        --time-limit "$seconds" -o "$out/water-ref-r0.exr" > "$out/water-ref-r0.log" 2>&1 &
    $bin scenes/gallery/water.toml --width 128 --height 128 --seed 2000 --iterations 1000000 \
        --radius 0.1306 --time-limit "$seconds" -o "$out/water-ref-2r0.exr" > "$out/water-ref-2r0.log" 2>&1 &
    wait
    $bin diff "$out/water-ref-2r0.exr" "$out/water-ref-r0.exr"
    ;;
water)
    seconds=${3:-60}
    $bin compare scenes/gallery/water.toml --reference "$out/water-ref-r0.exr" --width 128 --height 128 \
        --methods sppm-shrink,sppm-adaptive --time-limit "$seconds" --iterations 1000000 --downsample 1 \
        --out "$out/water" > "$out/water.log" 2>&1
    grep -E "^sppm" "$out/water.log" | awk -v t="$seconds" '$2 >= t'
    ;;
canonical)
    seconds=${3:-30}
    for scene in cornell-box cornell-glossy cornell-spheres; do
        echo "$scene: load $(cut -d' ' -f1-3 /proc/loadavg) at $(date +%T)"
        $bin compare "scenes/$scene.toml" --reference "tests/references/$scene.exr" \
            --methods sppm-shrink,sppm-adaptive --time-limit "$seconds" --iterations 1000000 --downsample 1 \
            --out "$out/$scene" > "$out/$scene.log" 2>&1
        grep -E "^sppm" "$out/$scene.log" | awk -v t="$seconds" '$2 >= t'
    done
    ;;
esac
