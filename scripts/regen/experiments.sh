#!/usr/bin/env bash
# Regenerate the figures of docs/experiments.md into docs/experiments/, one folder per
# experiment (CSV, PNG figures and the command's printed summary in summary.txt).
#
#   bash scripts/regen/experiments.sh                 # all of them (about 17 minutes on 2 cores)
#   bash scripts/regen/experiments.sh radius compare-box   # only those named
#
# Names: radius, alpha, alpha-large-radius, passes, compare-box, compare-spheres, direct,
# radius-schedule.
# Timings depend on the machine and on whatever else runs on it.
set -euo pipefail
cd "$(dirname "$0")/../.."
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
cargo build --release -q
bin=./target/release/sppm-gpu
out=docs/experiments
refs=tests/references

run() {
    local name=$1
    shift
    mkdir -p "$out/$name"
    echo "== $name: sppm-gpu $*"
    "$bin" "$@" --out "$out/$name" | tee "$out/$name/summary.txt"
}

want() {
    [ ${#selected[@]} -eq 0 ] && return 0
    local s
    for s in "${selected[@]}"; do [ "$s" = "$1" ] && return 0; done
    return 1
}
selected=("$@")

if want radius; then
    run radius-sweep sweep scenes/cornell-box.toml --param radius --values 0.01,0.02,0.05,0.1,0.2,0.5 \
        --photons 10000 --iterations 10 --reference $refs/cornell-box.exr --downsample 8
fi
if want alpha; then
    run alpha-sweep sweep scenes/cornell-spheres.toml --param alpha --values 0.3,0.5,0.7,0.9 \
        --photons 20000 --iterations 64 --reference $refs/cornell-spheres.exr --downsample 8
fi
if want alpha-large-radius; then
    run alpha-sweep-radius-0.05 sweep scenes/cornell-spheres.toml --param alpha --values 0.3,0.5,0.7,0.9 \
        --radius 0.05 --photons 20000 --iterations 64 --reference $refs/cornell-spheres.exr --downsample 8
fi
if want passes; then
    run passes passes scenes/cornell-spheres.toml --snapshots 1,4,16,64 \
        --reference $refs/cornell-spheres.exr --downsample 8
fi
if want compare-box; then
    run compare-cornell-box compare scenes/cornell-box.toml --reference $refs/cornell-box.exr \
        --methods sppm,pt,pt-nee --time-limit 60 --downsample 8
fi
if want compare-spheres; then
    run compare-cornell-spheres compare scenes/cornell-spheres.toml --reference $refs/cornell-spheres.exr \
        --methods sppm,pt,pt-nee --time-limit 60 --downsample 8
fi
if want direct; then
    run direct-light-cornell-glossy compare scenes/cornell-glossy.toml --reference $refs/cornell-glossy.exr \
        --methods sppm,sppm-photons --time-limit 60 --downsample 8
fi
if want radius-schedule; then
    for scene in cornell-box cornell-spheres; do
        run radius-schedule-$scene sweep scenes/$scene.toml --param radius-schedule --values 0,1 --iterations 64 \
            --reference $refs/$scene.exr --downsample 1
    done
fi
