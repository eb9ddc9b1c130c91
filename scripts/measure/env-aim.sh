#!/usr/bin/env bash
# Feeds BENCHMARKS.md "Environment photons (issue 25)" (docs/journal/session-12.md).
# Inputs: PUBLIC_SCENES (staged by public-scenes.sh), OUTDIR.
# Environment photons aimed at the visible points (issue 25, BENCHMARKS.md "Session 12",
# "Environment photons"): SPPM at equal time with SPPM_ENV_AIM=0 (the whole disk) and 0.9,
# alternating, against long references, relMSE of 8x8 blocks (4x4 for the 240x180 preview).
#   bash scripts/measure/env-aim.sh [SECONDS] [OUTDIR]
# The references: scenes/mitsuba/sky.xml at 256x192 by Mitsuba 3.9.1's path (8192 spp, 1025 s) in
# OUTDIR/sky-mi-path.exr (the study's mitsuba_xml.py scenes/mitsuba/sky.xml
# OUTDIR/sky-mi-path.exr --spp 8192 --chunk 128 --width 256 --height 192);
# the material previews' (scripts/measure/public-scenes.sh) ref.exr beside them.
set -euo pipefail
cd "$(dirname "$0")/../.."
secs="${1:-60}"
out="${2:-out/env-aim}"
bin="${SPPM_GPU:-target/release/sppm-gpu}"
pub="${PUBLIC_SCENES:-/work/public-scenes}"
mkdir -p "$out"
run() { # name scene reference downsample [options]
    for aim in 0 0.9 0.9 0; do
        SPPM_ENV_AIM=$aim "$bin" "$2" --time-limit "$secs" --iterations 1000000 "${@:5}" -o "$out/$1-aim$aim.exr" 2>&1 | tail -1
        "$bin" diff "$out/$1-aim$aim.exr" "$3" --downsample "$4" | sed "s/^/$1 aim $aim: /"
    done
}
run sky scenes/mitsuba/sky.xml "$out/sky-mi-path.exr" 8 --width 256 --height 192
run diffuse_plain "$pub/matpreview-diffuse_plain/docs/scenes/bsdf_diffuse_plain.xml" "$pub/matpreview-diffuse_plain/ref.exr" 4 --width 240 --height 180
run matpreview "$pub/mitsuba-matpreview/scenes/matpreview/matpreview.xml" "$pub/mitsuba-matpreview/ref.exr" 8 --width 256 --height 192
