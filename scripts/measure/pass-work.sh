#!/usr/bin/env bash
# Equal-time error against the work of a pass, the measurement behind a device's default
# photons and camera samples a pass (`GpuContext::pass_work`): each canonical scene rendered
# for SECONDS of wall time (`--time-limit`, which counts from after the kernels' compile) by
# SPPM at each PHOTONS x SPP (camera samples a pixel a pass), relMSE against tests/references
# at full resolution and 8x8. (The path tracers' pass is one sample a pixel; the pacer groups
# short passes into one submission.) With --light-paths, bpt's and vcm's pass instead: each
# of --methods (default vcm) at each count of light subpaths a pass, the measurement behind
# their default (integrators::light::PIXELS_PER_LIGHT_PATH). Feeds BENCHMARKS.md "GPU" and
# "VCM".
#
#   bash scripts/measure/pass-work.sh [--bin SPPM_GPU] [--out DIR] [--seconds S] [--adapter SEL]
#       [--scenes "cornell-box cornell-spheres"] [--photons "100000 1000000"] [--spp "1 4"]
#       [--light-paths "4096 65536" [--methods "vcm bpt"]]
#
# Prints one row a run (also appended to OUT/pass-work.txt, or OUT/light-paths.txt): scene,
# method, the work settings, passes, seconds of render, relMSE full and 8x8.
set -u
cd "$(dirname "$0")/../.."
bin=target/release/sppm-gpu out=pass-work-out secs=3 adapter=
scenes="cornell-box cornell-spheres cornell-glossy"
photons="100000 400000 1600000 6400000" spp="1 4" light_paths= methods=vcm
while [ $# -gt 0 ]; do
    case $1 in
        --bin) bin=$2; shift 2 ;;
        --out) out=$2; shift 2 ;;
        --seconds) secs=$2; shift 2 ;;
        --adapter) adapter=$2; shift 2 ;;
        --scenes) scenes=$2; shift 2 ;;
        --photons) photons=$2; shift 2 ;;
        --spp) spp=$2; shift 2 ;;
        --light-paths) light_paths=$2; shift 2 ;;
        --methods) methods=$2; shift 2 ;;
        -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
        *) echo "pass-work.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
    esac
done
mkdir -p "$out"
table=$out/pass-work.txt
[ -n "$light_paths" ] && table=$out/light-paths.txt
[ -n "$adapter" ] && adapter_args=(--adapter "$adapter") || adapter_args=()
one() { # scene method label settings...: one render of SECONDS and its row
    local s=$1 m=$2 label=$3 img=$out/pw.exr line passes took full small
    shift 3
    line=$(timeout $((secs * 4 + 60)) "$bin" "scenes/$s.toml" -o "$img" "${adapter_args[@]}" --method "$m" "$@" \
        --iterations 100000000 --time-limit "$secs" 2>&1 | grep -E " in [0-9.]+ s" | tail -1)
    passes=$(echo "$line" | grep -oE '[0-9]+ passes,' | grep -oE '[0-9]+')
    took=$(echo "$line" | grep -oE 'in [0-9.]+ s' | grep -oE '[0-9.]+')
    full=$("$bin" diff "$img" "tests/references/$s.exr" 2>&1 | tail -1 | awk '{print $2}')
    small=$("$bin" diff "$img" "tests/references/$s.exr" --downsample 8 2>&1 | tail -1 | awk '{print $2}')
    printf '%-16s %-7s %s: %7s passes in %6s s, relMSE %10s full, %10s 8x8\n' \
        "$s" "$m" "$label" "${passes:-?}" "${took:-?}" "$full" "$small" | tee -a "$table"
    rm -f "$img"
}
for s in $scenes; do
    if [ -n "$light_paths" ]; then
        for m in $methods; do
            for n in $light_paths; do one "$s" "$m" "$(printf 'light paths %6s' "$n")" --light-paths "$n"; done
        done
        continue
    fi
    for k in $spp; do
        for p in $photons; do one "$s" sppm "$(printf 'photons %8s spp %3s' "$p" "$k")" --spp "$k" --photons "$p"; done
    done
done
