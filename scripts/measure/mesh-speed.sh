#!/usr/bin/env bash
# Feeds BENCHMARKS.md "Issue 24 on a quiet machine, in one run" (docs/journal/session-14.md).
# Inputs: NEW and OLD binaries, STAGED, REF, MESHES, MITSUBA_TOOLS, MITSUBA_PYTHON.
# Issue 24's figures in one run, on a quiet machine, a binary before and after alternating:
#  A. pt-nee samples in 20 s on the bunny box at 128x128 (the gallery's bunny-cube.toml; Sobol
#     and independent samplers, the binary tree in the same binary), beside Mitsuba 3's `path`
#     (mitsuba_timed.py) on the same scene and cores;
#  B. `cargo bench --bench traversal`: closest hits and shadow rays through the binary tree and
#     the CWBVH on the bunny box and the glass dragon with the 48k and 871k dragons;
#  C. `sppm-gpu bench` stage times on the 871k dragon, CWBVH and binary tree alternating;
#  D. SPPM's equal-time error (30 s) on the bunny box at 256x256 against REF (a Mitsuba
#     reference of that scene, e.g. `mitsuba_reference.py SCENE REF --spp 1024`), OLD then NEW;
#  E. pt-nee on a material preview (STAGED/matpreview-diffuse_plain, scripts/measure/public-scenes.sh)
#     under its environment map and under a constant environment.
#
#   REF=bunny256-ref.exr MESHES=DIR MITSUBA_TOOLS=DIR bash scripts/measure/mesh-speed.sh NEW_BINARY OLD_BINARY [STAGED]
#
# Parts whose inputs are missing (REF, the staged preview, the meshes) are skipped.
set -uo pipefail
cd "$(dirname "$0")/../.."
new=$(realpath "${1:?usage: mesh-speed.sh NEW_BINARY OLD_BINARY [STAGED]}")
old=$(realpath "${2:?usage: mesh-speed.sh NEW_BINARY OLD_BINARY [STAGED]}")
staged=${3:-/work/public-scenes}
python=${MITSUBA_PYTHON:-/work/.venv-mi/bin/python}
tools=${MITSUBA_TOOLS:-}   # the folder holding mitsuba_timed.py (the study's shared tools); part A's Mitsuba run is skipped without it
meshes=${MESHES:-}          # the folder holding dragon_48k.obj and dragon_871k.obj (the study's shared meshes); skipped without it
[ -n "$meshes" ] && meshes=$(realpath "$meshes")
dir=$(mktemp -d)
la() { cut -d' ' -f1-3 /proc/loadavg; }
summary() { grep -E " in [0-9.]+ s" | tail -1; }
size() { sed "s/^width = .*/width = $2/; s/^height = .*/height = $2/; s#\"meshes/#\"$(pwd)/scenes/gallery/meshes/#" "$1"; }
size scenes/gallery/bunny-cube.toml 128 > "$dir/bunny128.toml"
size scenes/gallery/bunny-cube.toml 256 > "$dir/bunny256.toml"
for m in 48k 871k; do
    sed "s#file = \"meshes/dragon_11k.obj\"#file = \"$meshes/dragon_$m.obj\"#" scenes/gallery/glass-dragon.toml > "$dir/dragon$m.toml"
done
echo "== A: pt-nee, bunny box 128x128, 20 s ($(date +%T))"
for round in 1 2 3; do
    for v in sobol independent binary; do
        sampler=$v; [ $v = binary ] && sampler=sobol
        traversal=cwbvh; [ $v = binary ] && traversal=binary
        echo "$round $v (load $(la)): $(SPPM_GPU_TRAVERSAL=$traversal "$new" "$dir/bunny128.toml" -o "$dir/pt.exr" --method pt-nee \
            --time-limit 20 --iterations 1000000 --sampler $sampler 2>&1 | summary)"
    done
    echo "$round mitsuba (load $(la)): $("$python" "$tools/mitsuba_timed.py" "$dir/bunny128.toml" "$dir/mi.exr" --seconds 20 2>&1 | tail -1)"
done
echo "== B: traversal ($(date +%T))"
VARIANTS="CWBVH=0;CWBVH=1;CWBVH=0,ANY_HIT=1;CWBVH=1,ANY_HIT=1" cargo bench --bench traversal -- \
    "$dir/bunny128.toml" "$dir/dragon48k.toml" "$dir/dragon871k.toml" 2>&1 | grep "rays/s"
echo "== C: 871k dragon, SPPM stages ($(date +%T))"
for v in cwbvh binary cwbvh binary; do
    echo "-- $v (load $(la))"
    SPPM_GPU_TRAVERSAL=$v "$new" bench "$dir/dragon871k.toml" --width 256 --height 256 --iterations 4 2>&1 | grep -E "ms/pass|total"
done
if [ -s "${REF:-}" ]; then
    echo "== D: SPPM, bunny box 256x256, 30 s ($(date +%T))"
    for round in 1 2; do
        for b in old new; do
            bin=$new; [ $b = old ] && bin=$old
            r=$("$bin" "$dir/bunny256.toml" -o "$dir/eq-$b.exr" --time-limit 30 --iterations 1000000 2>&1 | summary)
            echo "$round $b (load $(la)): $r; $("$new" diff "$dir/eq-$b.exr" "$REF" 2>&1 | tr '\n' ' ')"
        done
    done
fi
preview=$staged/matpreview-diffuse_plain/docs/scenes
if [ -s "$preview/flat.xml" ]; then
    echo "== E: pt-nee on the diffuse preview, museum.exr against a constant environment, 20 s ($(date +%T))"
    python3 - "$preview/flat.xml" "$dir/constant.xml" <<'PY'
import sys
s = open(sys.argv[1]).read()
i = s.index('<emitter type="envmap"'); j = s.index('</emitter>', i) + len('</emitter>')
open(sys.argv[2], 'w').write(s[:i] + '<emitter type="constant"><rgb name="radiance" value="1.5"/></emitter>' + s[j:])
PY
    sed -i "s#<path value=\"[^\"]*\"#<path value=\"$staged/matpreview-diffuse_plain/common\"#" "$dir/constant.xml"
    for round in 1 2; do
        for v in "$preview/flat.xml" "$dir/constant.xml"; do
            echo "$round $(basename "$v") (load $(la)): $("$new" "$v" -o "$dir/env.exr" --width 240 --height 180 --method pt-nee \
                --time-limit 20 --iterations 1000000 2>&1 | summary)"
        done
    done
fi
echo "== done $(date +%T)"
rm -rf "$dir"
