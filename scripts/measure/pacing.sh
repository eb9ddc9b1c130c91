#!/usr/bin/env bash
# Feeds BENCHMARKS.md "Pacing: time limit, Ctrl-C and throughput". Does the render loop keep
# a time limit and answer Ctrl-C on the device's completed work, at the old speed? An old
# binary against a new one, alternating, ROUNDS rounds (default 2), on cornell-box:
#   - throughput: sppm 32 passes, pt-nee 128 spp (the summary line of each);
#   - pt-nee and sppm (PHOTONS photons a pass, default 1000000) under --time-limit LIMIT
#     (default 5): the process's wall time against the limit, and the passes done;
#   - SIGINT after LIMIT seconds of a long render: seconds from the signal to the exit, and
#     whether the image was written.
#   bash scripts/measure/pacing.sh OLD_BINARY NEW_BINARY [ROUNDS]
# Either binary may be the same file (one binary's figures alone). SIZE (default: the
# scene's 256) sets --width and --height.
set -euo pipefail
cd "$(dirname "$0")/../.."
old=${1:?usage: pacing.sh OLD_BINARY NEW_BINARY [ROUNDS]}
new=${2:?usage: pacing.sh OLD_BINARY NEW_BINARY [ROUNDS]}
rounds=${3:-2}
limit=${LIMIT:-5}
photons=${PHOTONS:-1000000}
size=()
[ -n "${SIZE:-}" ] && size=(--width "$SIZE" --height "$SIZE")
scene=scenes/cornell-box.toml
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
now() { date +%s.%N; }
summary() { grep -E " in [0-9.]+ s" | tail -1; }
for round in $(seq "$rounds"); do
    for b in old new; do
        bin=$old
        [ $b = new ] && bin=$new
        for m in sppm pt-nee; do
            it=32
            [ $m = pt-nee ] && it=128
            echo "$round $b throughput $m: $("$bin" $scene "${size[@]}" -o "$out/t.exr" --method $m --iterations $it 2>&1 | summary)"
        done
        for m in pt-nee sppm; do
            extra=()
            [ $m = sppm ] && extra=(--photons "$photons")
            t0=$(now)
            line=$("$bin" $scene "${size[@]}" -o "$out/l.exr" --method $m "${extra[@]}" --iterations 1000000 --time-limit "$limit" 2>&1 | summary)
            t1=$(now)
            echo "$round $b time-limit $limit $m: wall $(echo "$t1 - $t0" | bc) s: $line"
        done
        rm -f "$out/i.exr"
        "$bin" $scene "${size[@]}" -o "$out/i.exr" --method pt-nee --iterations 1000000 >"$out/i.log" 2>&1 &
        pid=$!
        sleep "$limit"
        t0=$(now)
        kill -INT $pid
        code=0
        wait $pid || code=$?
        t1=$(now)
        written=no
        [ -s "$out/i.exr" ] && written=yes
        echo "$round $b SIGINT: exit $code after $(echo "$t1 - $t0" | bc) s, image written: $written; $(grep -E '^interrupted' "$out/i.log" | head -1)"
    done
done
