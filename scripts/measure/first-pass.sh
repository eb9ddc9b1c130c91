#!/usr/bin/env bash
# Time to the first pass (issue 41): for each scene, the kernels' compile time (`--stats`,
# measured by the warm-up before a time-limited render's clock starts) and the process's wall
# time, on a cold shader cache (a fresh XDG_CACHE_HOME), a second run of the same scene, and
# a run after moving one sphere (a geometry edit: small scenes bake their BVH into the kernels).
# Usage: bash scripts/measure/first-pass.sh [BINARY]
set -euo pipefail
bin=${1:-target/release/sppm-gpu}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export XDG_CACHE_HOME="$work/cache"
run() { # label scene
    local start end compile
    start=$(date +%s.%N)
    compile=$("$bin" "$2" -o "$work/out.exr" --width 64 --height 64 --time-limit 0.5 --stats 2>/dev/null | sed -n 's/^kernels compiled in \([0-9.]*\) s.*/\1/p')
    end=$(date +%s.%N)
    printf '%-34s %-10s compile %6s s  process %6.2f s\n' "$(basename "$2")" "$1" "$compile" "$(echo "$end - $start" | bc)"
}
for scene in scenes/cornell-box.toml scenes/cornell-spheres.toml scenes/gallery/bunny-cube.toml scenes/mitsuba/box.xml; do
    rm -rf "$XDG_CACHE_HOME"
    run cold "$scene"
    run second "$scene"
done
# A geometry edit of a small scene (one sphere's radius) after a run of the scene as it was.
rm -rf "$XDG_CACHE_HOME"
cp scenes/cornell-spheres.toml "$work/edited.toml"
run cold "$work/edited.toml"
run second "$work/edited.toml"
sed -i '0,/^radius = 0.4$/s//radius = 0.38/' "$work/edited.toml"
run edited "$work/edited.toml"
run second "$work/edited.toml"
