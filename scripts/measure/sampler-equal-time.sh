#!/bin/sh
# Feeds BENCHMARKS.md "Sobol sampler (issue 26)" (docs/journal/session-12.md).
# Inputs: tests/references, BUNNY_REF; writes OUT.
# Equal time (issue 26): sppm and pt-nee with the independent and the Sobol sampler, 30 s of
# passes each at full resolution on the canonical scenes, against tests/references. One
# `compare` run per scene holds all four integrators and gives the next pass to whichever is
# furthest behind, so a change in a shared machine's load falls on all alike.
# With BUNNY_REF, also the mesh scene scenes/gallery/bunny-cube.toml at 256x256 against that
# reference (e.g. the study's mitsuba_reference.py on a copy of the file with width and
# height 256, its meshes/ beside it, --spp 1024).
# usage: scripts/measure/sampler-equal-time.sh [OUT] [SECONDS] [BUNNY_REF]   (default out/sampler, 30)
set -e
out=${1:-out/sampler}
seconds=${2:-30}
bunny_ref=${3:-}
bin=target/release/sppm-gpu
mkdir -p "$out"
run() { # NAME SCENE REFERENCE [options]
    name=$1 scene=$2 reference=$3
    shift 3
    echo "$name: load $(cut -d' ' -f1-3 /proc/loadavg) at $(date +%T)"
    $bin compare "$scene" --reference "$reference" \
        --methods sppm/independent,sppm/sobol,pt-nee/independent,pt-nee/sobol \
        --time-limit "$seconds" --iterations 1000000 --downsample 1 --out "$out/$name" "$@" > "$out/$name.log" 2>&1
    grep -E "^(sppm|pt-nee)" "$out/$name.log" | awk -v t="$seconds" '$2 >= t'
    echo "  load after: $(cut -d' ' -f1-3 /proc/loadavg)"
}
for scene in cornell-box cornell-glossy cornell-spheres; do
    run "$scene" "scenes/$scene.toml" "tests/references/$scene.exr"
done
if [ -n "$bunny_ref" ]; then
    run bunny-cube scenes/gallery/bunny-cube.toml "$bunny_ref" --width 256 --height 256
fi
