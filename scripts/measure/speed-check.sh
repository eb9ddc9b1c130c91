#!/usr/bin/env bash
# Feeds BENCHMARKS.md "The canonical scenes keep their speed (issue 23's last item)" (docs/journal/session-13.md).
# Inputs: OLD and NEW binaries, as arguments.
# Do the canonical scenes keep their speed? An old binary against a new one (with the
# independent and the Sobol sampler), alternating, ROUNDS rounds (default 2): sppm 32 passes
# and pt-nee 128 spp of each canonical scene at its own size; prints each run's summary line.
#   bash scripts/measure/speed-check.sh OLD_BINARY NEW_BINARY [ROUNDS]
# (An old binary from before the `--sampler` option runs without it.)
set -euo pipefail
cd "$(dirname "$0")/../.."
old=${1:?usage: speed-check.sh OLD_BINARY NEW_BINARY [ROUNDS]}
new=${2:?usage: speed-check.sh OLD_BINARY NEW_BINARY [ROUNDS]}
rounds=${3:-2}
out=$(mktemp -d)
for round in $(seq "$rounds"); do
    for s in cornell-box cornell-glossy cornell-spheres; do
        for m in sppm pt-nee; do
            it=32
            [ "$m" = pt-nee ] && it=128
            for b in old new-independent new-sobol; do
                case $b in
                    old) cmd=("$old") ;;
                    new-independent) cmd=("$new" --sampler independent) ;;
                    new-sobol) cmd=("$new" --sampler sobol) ;;
                esac
                line=$("${cmd[@]}" "scenes/$s.toml" -o "$out/x.exr" --method "$m" --iterations "$it" 2>&1 | grep -E " in [0-9.]+ s" | tail -1)
                echo "$round $s $m $b: $line (load $(cut -d' ' -f1 /proc/loadavg))"
            done
        done
    done
done
rm -rf "$out"
