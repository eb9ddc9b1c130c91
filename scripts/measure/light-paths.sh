#!/usr/bin/env bash
# Equal-time error against bpt's and vcm's light subpaths a pass (`light_paths`), the
# measurement behind their default (integrators::light::PIXELS_PER_LIGHT_PATH): each canonical
# scene rendered for SECONDS of wall time (`--time-limit`, counted after the kernels' compile)
# by each method at each light-subpath count, relMSE against tests/references at full
# resolution and 8x8. Feeds BENCHMARKS.md "VCM" (and "GPU" on a GPU).
#
#   bash scripts/measure/light-paths.sh [--bin SPPM_GPU] [--out DIR] [--seconds S] [--adapter SEL]
#       [--scenes "cornell-box cornell-spheres"] [--methods "vcm bpt"] [--paths "4096 65536"]
#
# Prints one row a run (also appended to OUT/light-paths.txt): scene, method, light paths,
# passes, seconds of render, relMSE full and 8x8.
set -u
cd "$(dirname "$0")/../.."
bin=target/release/sppm-gpu out=light-paths-out secs=3 adapter=
scenes="cornell-box cornell-spheres cornell-glossy" methods="vcm" paths="1024 4096 16384 65536"
while [ $# -gt 0 ]; do
    case $1 in
        --bin) bin=$2; shift 2 ;;
        --out) out=$2; shift 2 ;;
        --seconds) secs=$2; shift 2 ;;
        --adapter) adapter=$2; shift 2 ;;
        --scenes) scenes=$2; shift 2 ;;
        --methods) methods=$2; shift 2 ;;
        --paths) paths=$2; shift 2 ;;
        -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
        *) echo "light-paths.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
    esac
done
mkdir -p "$out"
table=$out/light-paths.txt
[ -n "$adapter" ] && adapter_args=(--adapter "$adapter") || adapter_args=()
for s in $scenes; do
    for m in $methods; do
        for n in $paths; do
            img=$out/lp.exr
            line=$(timeout $((secs * 4 + 60)) "$bin" "scenes/$s.toml" -o "$img" "${adapter_args[@]}" --method "$m" \
                --light-paths "$n" --iterations 100000000 --time-limit "$secs" 2>&1 | grep -E " in [0-9.]+ s" | tail -1)
            passes=$(echo "$line" | grep -oE '[0-9]+ passes,' | grep -oE '[0-9]+')
            took=$(echo "$line" | grep -oE 'in [0-9.]+ s' | grep -oE '[0-9.]+')
            full=$("$bin" diff "$img" "tests/references/$s.exr" 2>&1 | tail -1 | awk '{print $2}')
            small=$("$bin" diff "$img" "tests/references/$s.exr" --downsample 8 2>&1 | tail -1 | awk '{print $2}')
            printf '%-16s %-4s light paths %6s: %7s passes in %6s s, relMSE %10s full, %10s 8x8\n' \
                "$s" "$m" "$n" "${passes:-?}" "${took:-?}" "$full" "$small" | tee -a "$table"
            rm -f "$img"
        done
    done
done
