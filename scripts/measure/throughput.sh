#!/usr/bin/env bash
# Feeds BENCHMARKS.md "Issue 12's figures, in one run" (docs/journal/session-07.md).
# Inputs: OLD_BINARY, DRAGON_871K, MITSUBA_PYTHON and MITSUBA_TOOLS.
# Issue 12's throughput figures in one run, one command after another on an idle machine:
# pt-nee samples/s on cornell-box (256x256) beside Mitsuba 3's samples/s for the same wall time,
# the study's SPPM run (wall time, and photons/s and camera paths/s per stage from `bench`),
# and the 871k-triangle dragon (scripts/measure/big-dragon.sh).
#
# Usage: bash scripts/measure/throughput.sh [OLD_BINARY]
# With OLD_BINARY (an sppm-gpu built from an earlier commit) every sppm-gpu figure is taken for
# it too, alternating, so that before and after come from the same run. Mitsuba is run when
# MITSUBA_PYTHON (a python with mitsuba 3 and numpy) is set, with MITSUBA_TOOLS (the folder
# holding mitsuba_timed.py). DRAGON_871K names the 871k-triangle dragon's OBJ file.
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release --quiet
new=target/release/sppm-gpu
old="${1:-}"
binaries=("$new")
if [ -n "$old" ]; then binaries=("$old" "$new"); fi
out="$(mktemp -d)"
study=(scenes/cornell-spheres.toml --width 512 --height 512 --iterations 20 --photons 200000 --max-depth 32)
seconds=10

# One untimed run of each kernel set first: after a shader change Mesa compiles at the first
# dispatch (seconds on a cold shader cache), which would be charged to the new binary alone.
mesh="$(realpath "${DRAGON_871K:?set DRAGON_871K to the 871k-triangle dragon_871k.obj (the shared meshes of the study)}")"
sed "s#file = \"meshes/dragon_11k.obj\"#file = \"$mesh\"#" scenes/gallery/glass-dragon.toml > "$out/big-dragon.toml"
for bin in "${binaries[@]}"; do
    "$bin" scenes/cornell-box.toml --method pt-nee --iterations 1 -o "$out/warm.exr" > /dev/null 2>&1
    "$bin" scenes/cornell-spheres.toml --width 512 --height 512 --iterations 1 --max-depth 32 -o "$out/warm.exr" > /dev/null 2>&1
    "$bin" "$out/big-dragon.toml" --width 16 --height 16 --iterations 1 -o "$out/warm.png" > /dev/null 2>&1
done

for bin in "${binaries[@]}"; do
    echo "== $bin"
    echo "-- pt-nee, cornell-box 256x256, ${seconds} s"
    "$bin" scenes/cornell-box.toml --method pt-nee --time-limit "$seconds" -o "$out/ptnee.exr" 2>&1 | tail -1
    echo "-- the study's run: cornell-spheres 512x512, 20 x 200k photons, max_depth 32"
    /usr/bin/time -f "%e s wall" "$bin" "${study[@]}" -o "$out/study.exr" 2>&1 | tail -2
    "$bin" bench "${study[@]}" 2>&1 | grep -v "^warning"
done

if [ -n "${MITSUBA_PYTHON:-}" ]; then
    echo "== Mitsuba 3 path, cornell-box 256x256, ${seconds} s"
    "$MITSUBA_PYTHON" "${MITSUBA_TOOLS:?set MITSUBA_TOOLS to the folder holding mitsuba_timed.py}/mitsuba_timed.py" scenes/cornell-box.toml "$out/mi.exr" --seconds "$seconds" 2>&1 | tail -2
fi

for bin in "${binaries[@]}"; do
    echo "== $bin: the 871k-triangle dragon"
    /usr/bin/time -f "%e s wall" "$bin" "$out/big-dragon.toml" -o "$out/big-dragon.png" --width 256 --height 256 --iterations 16 2>&1 | grep -E "passes|wall"
done
rm -rf "$out"
