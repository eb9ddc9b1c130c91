#!/bin/sh
# Equal time (issue 26): sppm and pt-nee with the independent and the Sobol sampler, 30 s of
# passes each at full resolution on the canonical scenes, against ../shared/references. One
# `compare` run per scene holds all four integrators and gives the next pass to whichever is
# furthest behind, so a change in a shared machine's load falls on all alike.
# usage: scripts/sampler-equal-time.sh [OUT] [SECONDS]   (default out/sampler, 30)
set -e
out=${1:-out/sampler}
seconds=${2:-30}
bin=target/release/sppm-gpu
mkdir -p "$out"
for scene in cornell-box cornell-glossy cornell-spheres; do
    echo "$scene: load $(cut -d' ' -f1-3 /proc/loadavg) at $(date +%T)"
    $bin compare "scenes/$scene.toml" --reference "../shared/references/$scene.exr" \
        --methods sppm/independent,sppm/sobol,pt-nee/independent,pt-nee/sobol \
        --time-limit "$seconds" --iterations 1000000 --downsample 1 --out "$out/$scene" > "$out/$scene.log" 2>&1
    grep -E "^(sppm|pt-nee)" "$out/$scene.log" | awk -v t="$seconds" '$2 >= t'
    echo "  load after: $(cut -d' ' -f1-3 /proc/loadavg)"
done
