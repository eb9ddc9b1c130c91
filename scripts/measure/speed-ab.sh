#!/usr/bin/env bash
# Does a change keep the kernels' speed? An old binary against a new one, alternating, ROUNDS
# rounds: SPPM (32 passes) and pt-nee (128 spp) of the canonical scenes at their own size, the
# bunny box (scenes/gallery/bunny-cube.toml at 256x256: a 3.7k-triangle rough-glass mesh) and
# the Mitsuba plastic and metals scenes; prints each run's seconds and, per scene and method,
# the median of new/old over the rounds. Feeds BENCHMARKS.md "BSDF families: one file each".
#   bash scripts/measure/speed-ab.sh OLD_BINARY NEW_BINARY [ROUNDS]
set -euo pipefail
cd "$(dirname "$0")/../.."
old=${1:?usage: speed-ab.sh OLD_BINARY NEW_BINARY [ROUNDS]}
new=${2:?usage: speed-ab.sh OLD_BINARY NEW_BINARY [ROUNDS]}
rounds=${3:-3}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
seconds() { # binary scene method passes [args...]: the render's seconds, from its summary line
    local bin=$1 scene=$2 method=$3 passes=$4
    shift 4
    "$bin" "$scene" -o "$out/x.exr" --method "$method" --iterations "$passes" "$@" 2>&1 |
        grep -oE " in [0-9.]+ s" | tail -1 | grep -oE "[0-9.]+"
}
for round in $(seq "$rounds"); do
    for s in scenes/cornell-box.toml scenes/cornell-glossy.toml scenes/cornell-spheres.toml \
        scenes/gallery/bunny-cube.toml scenes/mitsuba/plastic.xml scenes/mitsuba/metals.xml; do
        size=()
        case $s in scenes/gallery/*) size=(--width 256 --height 256) ;; esac
        for m in sppm pt-nee; do
            passes=32
            [ "$m" = pt-nee ] && passes=128
            # Alternate which binary goes first, so that neither always meets a warm cache.
            order=(old new)
            [ $((round % 2)) = 0 ] && order=(new old)
            for b in "${order[@]}"; do
                bin=$old
                [ "$b" = new ] && bin=$new
                t=$(seconds "$bin" "$s" "$m" "$passes" ${size[@]+"${size[@]}"})
                echo "$round $s $m $b $t (load $(cut -d' ' -f1 /proc/loadavg))"
                echo "$s $m $b $round $t" >>"$out/times"
            done
        done
    done
done
echo "median new/old over $rounds rounds:"
python3 - "$out/times" <<'PY'
import sys, statistics, collections
t = collections.defaultdict(dict)
for line in open(sys.argv[1]):
    s, m, b, r, sec = line.split()
    t[(s, m, r)][b] = float(sec)
by = collections.defaultdict(list)
for (s, m, r), v in t.items():
    by[(s, m)].append(v["new"] / v["old"])
for (s, m), ratios in sorted(by.items()):
    print(f"  {s} {m}: {statistics.median(ratios):.3f} ({', '.join(f'{x:.3f}' for x in ratios)})")
PY
