#!/usr/bin/env bash
# Feeds BENCHMARKS.md "pbrt-v4 scenes" (issue 44): scenes of gonsolo/bitterli in their pbrt-v4
# form, read by the pbrt-v4 reader, each rendered small against Tungsten's render (the
# collection's reference) box-downsampled to the same size.
#
#   bash scripts/measure/pbrt-scenes.sh OUT_DIR [SECONDS] [MIRRORS] [SCENE...]
#
# MIRRORS (default /work/.mirror) holds gonsolo+bitterli/repo (the `fetch` tool's layout);
# each scene's pbrt/ folder is staged under OUT_DIR/bitterli (files the mirror lacks are
# listed). SECONDS (default 60) is each render's time limit. Prints, per scene, the render's
# last line and `sppm-gpu diff --downsample 8` (8x8 blocks) against the reference.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:?usage: pbrt-scenes.sh OUT_DIR [SECONDS] [MIRRORS] [SCENE...]}
secs=${2:-60}
mirrors=${3:-/work/.mirror}
shift $(($# < 3 ? $# : 3))
bin=${SPPM_GPU:-target/release/sppm-gpu}
. scripts/measure/lib.sh
mkdir -p "$out"
out=$(cd "$out" && pwd)

# name | reference downsampling factor | width | height | extra options (the method and depth
# where the file's are not Tungsten's: see BENCHMARKS "pbrt-v4 scenes")
table=$(cat <<'T'
cornell-box|8|128|128|--max-depth 64
veach-mis|5|256|144|
veach-bidir|8|128|128|
coffee|5|160|200|
water-caustic|8|128|128|--photons 50000
volumetric-caustic|8|128|128|--method sppm
T
)
want=" $* "
while IFS='|' read -r name k w h opts; do
    [ $# -eq 0 ] || [[ $want == *" $name "* ]] || continue
    stage_one "$mirrors" "$out/bitterli" "$name" gonsolo+bitterli "see the scene's LICENSE.txt" "$name/pbrt" >&2
    dir=$out/bitterli/$name/$name/pbrt
    python3 - "$dir/TungstenRender.exr" "$out/$name-ref.exr" "$k" <<'PY'
# Box-downsamples an EXR by an integer factor (means of k x k blocks, in f64).
import sys, OpenEXR, Imath, numpy as np
src, dst, k = sys.argv[1], sys.argv[2], int(sys.argv[3])
f = OpenEXR.InputFile(src)
dw = f.header()['dataWindow']
w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
pt = Imath.PixelType(Imath.PixelType.FLOAT)
ch = [np.frombuffer(f.channel(c, pt), dtype=np.float32).reshape(h, w).copy() for c in 'RGB']
# Tungsten's half-float EXRs overflow to +inf where a firefly passes 65504 (water-caustic has
# one such texel): such a texel takes the mean of its finite neighbours, and is reported.
for c, a in zip('RGB', ch):
    for y, x in np.argwhere(~np.isfinite(a)):
        n = a[max(y - 1, 0):y + 2, max(x - 1, 0):x + 2]
        a[y, x] = n[np.isfinite(n)].mean()
        print(f'{src}: {c} at ({x}, {y}) not finite, set to its neighbours\' mean {a[y, x]:.4g}', file=sys.stderr)
assert w % k == 0 and h % k == 0, (w, h, k)
ch = [c.reshape(h // k, k, w // k, k).astype(np.float64).mean(axis=(1, 3)).astype(np.float32) for c in ch]
hd = OpenEXR.Header(w // k, h // k)
hd['channels'] = {c: Imath.Channel(pt) for c in 'RGB'}
o = OpenEXR.OutputFile(dst, hd)
o.writePixels({c: a.tobytes() for c, a in zip('RGB', ch)})
o.close()
PY
    # shellcheck disable=SC2086
    "$bin" "$dir/scene-v4.pbrt" --width "$w" --height "$h" --time-limit "$secs" --iterations 100000000 $opts \
        -o "$out/$name.exr" 2>&1 | tail -1
    echo "$name ($w x $h${opts:+, $opts}) against Tungsten: $("$bin" diff "$out/$name.exr" "$out/$name-ref.exr" --downsample 8)"
done <<< "$table"
