#!/usr/bin/env bash
# Render the references of the Mitsuba XML test scenes (scenes/mitsuba/*.xml) with Mitsuba 3
# itself into tests/references/mitsuba/, through MITSUBA_TOOLS/mitsuba_xml.py (its docstring
# says how to set up the venv: pip install mitsuba==3.9.1 numpy, apt-get install libllvm19).
#   MITSUBA_TOOLS=DIR MITSUBA_PYTHON=/path/to/venv/bin/python bash scripts/regen/mitsuba-references.sh [SPP]
set -euo pipefail
cd "$(dirname "$0")/../.."
python="${MITSUBA_PYTHON:-.venv-mi/bin/python}"
tools="${MITSUBA_TOOLS:?set MITSUBA_TOOLS to the folder holding mitsuba_xml.py (the shared tools of the study)}"
spp="${1:-8192}"
mkdir -p tests/references/mitsuba
for scene in box lights legacy metals spot textures plastic constant tinted lens null envmap; do
    "$python" "$tools/mitsuba_xml.py" "scenes/mitsuba/$scene.xml" "tests/references/mitsuba/$scene.exr" \
        --spp "$spp" --chunk 64
done
# sky.xml's caustic is found by BSDF sampling alone: twice the samples.
"$python" "$tools/mitsuba_xml.py" scenes/mitsuba/sky.xml tests/references/mitsuba/sky.exr \
    --spp $((2 * spp)) --chunk 256
# null.xml again at Mitsuba's max_depth 2 (direct light only): the floor under the null slab
# is black there.
"$python" "$tools/mitsuba_xml.py" scenes/mitsuba/null.xml tests/references/mitsuba/null-direct.exr \
    --spp "$spp" --chunk 64 -D max_depth=2
