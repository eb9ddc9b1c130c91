#!/usr/bin/env bash
# Do two binaries render the same images, pixel for pixel? Each scene that covers a BSDF
# family (canonical TOML scenes, and the Mitsuba test scenes with metals, plastics, thin and
# rough glass, null), with sppm, pt-nee and pt, a few passes at a fixed seed, by OLD and NEW;
# the EXRs are compared as pixels (their bytes differ run to run: the exr crate's block order).
# Feeds BENCHMARKS.md "BSDF families: one file each" (a behaviour-preserving refactor).
#   bash scripts/measure/same-images.sh OLD_BINARY NEW_BINARY
set -euo pipefail
cd "$(dirname "$0")/../.."
old=${1:?usage: same-images.sh OLD_BINARY NEW_BINARY}
new=${2:?usage: same-images.sh OLD_BINARY NEW_BINARY}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
status=0
for s in scenes/cornell-box.toml scenes/cornell-glossy.toml scenes/cornell-spheres.toml scenes/textured.toml \
    scenes/point-light.toml scenes/mitsuba/metals.xml scenes/mitsuba/plastic.xml scenes/mitsuba/tinted.xml \
    scenes/mitsuba/null.xml scenes/mitsuba/legacy.xml scenes/mitsuba/box.xml scenes/mitsuba/envmap.xml; do
    for m in sppm pt-nee pt; do
        for b in old new; do
            bin=$old
            [ "$b" = new ] && bin=$new
            rm -f "$out/$b.exr"
            "$bin" "$s" -o "$out/$b.exr" --method "$m" --iterations 4 --seed 7 --width 96 --height 96 >"$out/$b.log" 2>&1 ||
                { echo "$s $m: $b failed: $(tail -1 "$out/$b.log")"; status=1; continue 2; }
        done
        verdict=$(python3 - "$out/old.exr" "$out/new.exr" <<'PY'
import sys, numpy as np, OpenEXR, Imath
def px(p):
    f = OpenEXR.InputFile(p); dw = f.header()['dataWindow']
    return np.stack([np.frombuffer(f.channel(c, Imath.PixelType(Imath.PixelType.FLOAT)), np.float32) for c in 'RGB'])
a, b = px(sys.argv[1]), px(sys.argv[2])
same = np.array_equal(a.view(np.uint32), b.view(np.uint32))
print("identical" if same else f"DIFFERENT: {np.sum(a != b)} values, max |diff| {np.max(np.abs(a - b)):.3g}, mean {a.mean():.6g} vs {b.mean():.6g}")
PY
)
        echo "$s $m: $verdict"
        case $verdict in identical) ;; *) status=1 ;; esac
    done
done
exit $status
