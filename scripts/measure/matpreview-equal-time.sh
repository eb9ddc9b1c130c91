#!/usr/bin/env bash
# Feeds BENCHMARKS.md "Material previews at equal time (issue 25)" (docs/journal/session-13.md).
# Inputs: BINARY, DEST (staged previews), MITSUBA_TOOLS, MITSUBA_PYTHON.
# Equal time on Mitsuba's material previews (issue 25): sppm, pt-nee and Mitsuba 3 `path`
# (LLVM, the same cores), SECONDS each (default 60), one after another, on three previews
# staged by scripts/measure/public-scenes.sh, at the size of their references (240x180, Mitsuba's
# scenes/matpreview 256x192), then relMSE at full resolution and in 4x4 blocks and the
# channel means against each preview's reference (DEST/NAME/ref.exr, Mitsuba `path` 1,024
# spp: its own noise is a floor under every figure here).
#
#   bash scripts/measure/matpreview-equal-time.sh BINARY [DEST [SECONDS]]
#
# Mitsuba reads the previews' sensor from the top file only, so each is first flattened
# (scripts/regen/mitsuba-flatten.py) beside its original. The load average is printed before each
# run: on a shared machine the three renderers may not see the same load.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=$(realpath "${1:?usage: matpreview-equal-time.sh BINARY [DEST [SECONDS]]}")
dest=${2:-/work/public-scenes}
seconds=${3:-60}
python=${MITSUBA_PYTHON:-/work/.venv-mi/bin/python}
tools=${MITSUBA_TOOLS:?set MITSUBA_TOOLS to the folder holding mitsuba_timed.py (the shared tools of the study)}
cd "$dest"
eq() { # NAME SCENE WIDTH HEIGHT
    local n=$1 s=$2 w=$3 h=$4 flat
    flat=$(dirname "$n/$s")/flat-$(basename "$s")
    python3 "$here/../regen/mitsuba-flatten.py" "$n/$s" "$flat"
    for m in sppm pt-nee; do
        echo "== $n $m, load $(cut -d' ' -f1-3 /proc/loadavg), $(date +%T)"
        "$bin" "$n/$s" -o "$n/eq-${m/-/}.exr" --width "$w" --height "$h" --method "$m" \
            --time-limit "$seconds" --iterations 1000000 2>&1 | grep -vE 'clip|gamma|warning' | tail -1
    done
    echo "== $n mitsuba, load $(cut -d' ' -f1-3 /proc/loadavg), $(date +%T)"
    "$python" "$tools/mitsuba_xml.py" "$flat" "$n/eq-mitsuba.exr" --width "$w" --height "$h" \
        --seconds "$seconds" --chunk 16 2>&1 | tail -1
    for o in sppm ptnee mitsuba; do
        echo "   $o full: $("$bin" diff "$n/eq-$o.exr" "$n/ref.exr" 2>&1 | tr '\n' ' ')"
        echo "   $o 4x4:  $("$bin" diff "$n/eq-$o.exr" "$n/ref.exr" --downsample 4 2>&1 | tr '\n' ' ')"
    done
}
eq matpreview-roughconductor_copper docs/scenes/bsdf_roughconductor_copper.xml 240 180
eq matpreview-dielectric_glass docs/scenes/bsdf_dielectric_glass.xml 240 180
eq mitsuba-matpreview scenes/matpreview/matpreview.xml 256 192
