#!/usr/bin/env bash
# Feeds BENCHMARKS.md "Scale-out" (journal: "Session 6: batches of passes (issue 15)", docs/journal/session-06.md).
# Inputs: the repository's scenes and target/release/sppm-gpu.
# The cost of splitting a render into batches (BENCHMARKS.md): N passes of a scene with the
# global radius schedule, rendered in 1, 2 and 4 batches run one after another (each its own
# process: set-up, kernel compile from Mesa's cache, the passes, writing its partial), then
# merged. Prints the wall time of each run and the merge.
#
#   bash scripts/measure/batch-scaling.sh [SCENE] [PASSES]     (default scenes/cornell-box.toml 32)
set -euo pipefail
cd "$(dirname "$0")/../.."
scene="${1:-scenes/cornell-box.toml}"
passes="${2:-32}"
cargo build --release -q
bin=target/release/sppm-gpu
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
now() { date +%s.%N; }
# Warm Mesa's shader cache first, so that every run below finds it as a second run would.
"$bin" "$scene" --radius-schedule global --iterations 1 -o "$dir/warm.exr" >/dev/null
echo "batches,wall_seconds,merge_seconds"
for batches in 1 2 4; do
    rm -f "$dir"/part-*.exr
    start=$(now)
    for ((b = 0; b < batches; b++)); do
        first=$((b * passes / batches))
        end=$(((b + 1) * passes / batches))
        "$bin" "$scene" --radius-schedule global --passes "$first..$end" --partial "$dir/part-$b.exr" >/dev/null
    done
    rendered=$(now)
    "$bin" merge "$dir"/part-*.exr -o "$dir/merged-$batches.exr" >/dev/null
    merged=$(now)
    awk -v b="$batches" -v s="$start" -v r="$rendered" -v m="$merged" 'BEGIN { printf "%d,%.2f,%.3f\n", b, r - s, m - r }'
done
"$bin" diff "$dir/merged-4.exr" "$dir/merged-1.exr"
