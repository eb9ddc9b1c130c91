#!/usr/bin/env bash
# Feeds BENCHMARKS.md "pbrt-v4 scenes" (issue 44): scenes of gonsolo/bitterli in their pbrt-v4
# form rendered by pbrt-v4 itself (the format's own renderer, built here by
# scripts/measure/pbrt-v4/build.sh) and by sppm-gpu's pbrt-v4 reader at the same small size,
# then compared: `sppm-gpu diff --downsample K` (KxK blocks: 8, 7 for the killeroos' 175
# pixels) and each channel's mean over pbrt-v4's.
#
#   bash scripts/measure/pbrt-v4-references.sh OUT_DIR [SPP] [SECONDS] [MIRRORS] [SCENE...]
#
# SPP (default 4096) is pbrt-v4's samples a pixel (`--spp`; pbrt-v4 renders on every core,
# spectrally, with the file's sampler but for `pmj02bn`, whose tables the build stands in
# for: there the file's sampler becomes `zsobol`); SECONDS (default 60) our render's time
# limit; MIRRORS (default /work/.mirror) holds gonsolo+bitterli/repo. pbrt-v4's render
# (OUT_DIR/NAME-pbrt.exr) is kept and not made again. The binary: $PBRT (default
# /tmp/pbrt-build/build/pbrt).
#
# pbrt-v4 renders spectrally: an RGB reflectance or emission becomes a smooth spectrum, and
# the products of spectra along a path are not the products of their RGB values that an RGB
# renderer forms, so coloured scenes differ by a few percent in a channel. With GRAY=1 every
# RGB value of the files (reflectances, emission, eta and k, media) becomes the mean of its
# three, and a named spectrum of a conductor a grey one: constant spectra, whose products are
# the same either way, so the two renders of that scene must agree within their noise
# (outputs NAME-gray-pbrt.exr, NAME-gray.exr).
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:?usage: pbrt-v4-references.sh OUT_DIR [SPP] [SECONDS] [MIRRORS] [SCENE...]}
spp=${2:-4096}
secs=${3:-60}
mirrors=${4:-/work/.mirror}
shift $(($# < 4 ? $# : 4))
bin=${SPPM_GPU:-target/release/sppm-gpu}
pbrt=${PBRT:-/tmp/pbrt-build/build/pbrt}
[ -x "$pbrt" ] || { echo "no pbrt-v4 at $pbrt: build it with scripts/measure/pbrt-v4/build.sh" >&2; exit 1; }
. scripts/measure/lib.sh
mkdir -p "$out"
out=$(cd "$out" && pwd)

# name | width | height | blocks' side for diff | our options beyond the file's. gonsolo/bitterli's scenes, then
# mmp/pbrt-v4-scenes' killeroo-simple and killeroo-moving (their geometry pbrt-v3's, which
# MIRRORS holds as mmp+pbrt-v3: scripts/measure/killeroo-simple.sh stages it) and killeroo-gold
# (its geometry/killeroo3.pbrt from $KILLEROO3, a copy of the collection's file: the collection
# is too big to fetch, and its text comes page by page through the search tool's read_file;
# textures/lines.png from MIRRORS' kennyalive+yar-test-scenes, whose copy of pbrt's is a
# stand-in; its spds/Au.eta.spd and Au.k.spd, which no mirror holds, stand in as pbrt-v4's
# named metal-Au-eta and metal-Au-k, and with GRAY=1 as every conductor's grey).
table=$(cat <<'T'
cornell-box|128|128|8|
veach-mis|256|144|8|
veach-bidir|128|128|8|
coffee|160|200|8|
water-caustic|128|128|8|--photons 50000
volumetric-caustic|128|128|8|
killeroo-simple|175|175|7|
killeroo-moving|175|175|7|
killeroo-gold|160|120|8|
T
)
# stage NAME: stages the scene and prints its file's path.
stage() {
    case $1 in
    killeroo-simple | killeroo-moving)
        local dir=$out/killeroos
        SPPM_GPU=$bin STAGE_ONLY=1 bash scripts/measure/killeroo-simple.sh "$dir" 1 "$mirrors" >&2
        # killeroo-moving.pbrt as the collection has it (comments left out): killeroo-simple's
        # camera, light, floor and first killeroo's transform and material (its size and
        # samples, which this script sets anyway), then each killeroo's start transform
        # translated (ActiveTransform).
        {
            sed '/^    Translate 100 200 -140$/q' "$dir/killeroo-simple.pbrt" | sed 's/killeroo-simple.exr/killeroo-moving.exr/'
            cat <<'PBRT'
    ActiveTransform StartTime
    Translate 35 35 35
    AttributeBegin
        Include "geometry/killeroo.pbrt"
    AttributeEnd
    Material "coateddiffuse"
        "float roughness" [ 0.15 ]
        "rgb reflectance" [ 0.4 0.5 0.4 ]
    AttributeBegin
        ActiveTransform StartTime
        Translate 30 0 0
        ActiveTransform All
        Translate -200 0 0
        Include "geometry/killeroo.pbrt"
    AttributeEnd
AttributeEnd
PBRT
        } >"$dir/killeroo-moving.pbrt"
        echo "$dir/$1.pbrt"
        ;;
    killeroo-gold)
        local dir=$out/killeroos k3=${KILLEROO3:-/tmp/kg/geometry/killeroo3.pbrt}
        [ -f "$k3" ] || { echo "killeroo-gold: no geometry/killeroo3.pbrt at \$KILLEROO3 ($k3)" >&2; return 1; }
        mkdir -p "$dir/geometry" "$dir/textures"
        cp "$k3" "$dir/geometry/killeroo3.pbrt"
        stage_one "$mirrors" "$out" yar kennyalive+yar-test-scenes "see the repository" textures/lines.png >&2
        cp "$out/yar/textures/lines.png" "$dir/textures/lines.png"
        # killeroo-gold.pbrt as the collection has it (comments left out), the gold's spectra
        # named (above).
        cat >"$dir/killeroo-gold.pbrt" <<'PBRT'
LookAt 200 250 70
    0 33 -50
    0 0 1
Camera "perspective"
    "float fov" [ 38 ]
Film "rgb"
    "string filename" [ "killeroo-gold.exr" ]
    "integer yresolution" [ 1026 ]
    "integer xresolution" [ 1368 ]
Sampler "halton"
    "integer pixelsamples" [ 512 ]
WorldBegin
AttributeBegin
    Material "diffuse"
        "rgb reflectance" [ 0 0 0 ]
    AreaLightSource "diffuse"
        "rgb L" [ 50 50 50 ]
    Translate 0 0 800
    ReverseOrientation
    Shape "disk"
        "float radius" [ 150 ]
AttributeEnd
AttributeBegin
    CoordSysTransform "camera"
    LightSource "distant"
        "rgb L" [ 0.2 0.2 0.2 ]
AttributeEnd
AttributeBegin
    Material "diffuse"
        "rgb reflectance" [ 0.5 0.5 0.5 ]
    Translate 0 0 -140
    Texture "grid" "spectrum" "imagemap"
        "string filename" [ "textures/lines.png" ]
    Texture "sgrid" "spectrum" "scale"
        "float scale" [ 0.5 ]
        "texture tex" [ "grid" ]
    Material "diffuse"
        "texture reflectance" [ "sgrid" ]
    Shape "trianglemesh"
        "point2 uv" [ 0 0 5 0 5 5 0 5 
            ]
        "integer indices" [ 0 1 2 2 3 0 ]
        "point3 P" [ -400 -400 0 400 -400 0 400 400 0 -400 400 0 ]
    Shape "trianglemesh"
        "point2 uv" [ 0 0 5 0 5 5 0 5 
            ]
        "integer indices" [ 0 1 2 2 3 0 ]
        "point3 P" [ -400 -400 0 400 -400 0 400 -400 1000 -400 -400 1000 ]
    Shape "trianglemesh"
        "point2 uv" [ 0 0 5 0 5 5 0 5 
            ]
        "integer indices" [ 0 1 2 2 3 0 ]
        "point3 P" [ -400 -400 0 -400 400 0 -400 400 1000 -400 -400 1000 ]
AttributeEnd
AttributeBegin
    Material "conductor"
        "spectrum k" [ "metal-Au-k" ]
        "spectrum eta" [ "metal-Au-eta" ]
        "float roughness" [ 0.002 ]
    Include "geometry/killeroo3.pbrt"
AttributeEnd
PBRT
        echo "$dir/$1.pbrt"
        ;;
    *)
        stage_one "$mirrors" "$out/bitterli" "$1" gonsolo+bitterli "see the scene's LICENSE.txt" "$1/pbrt" >&2
        echo "$out/bitterli/$1/$1/pbrt/scene-v4.pbrt"
        ;;
    esac
}
want=" $* "
while IFS='|' read -r name w h k opts; do
    [ $# -eq 0 ] || [[ $want == *" $name "* ]] || continue
    src=$(stage "$name")
    dir=$(dirname "$src")
    # The file at the small size, beside it so that its relative paths still resolve.
    tag=$name${GRAY:+-gray}
    python3 - "$src" "$dir/scene-$tag.pbrt" "$w" "$h" "${GRAY:-}" <<'PY'
import re, sys
src, dst, w, h, gray = sys.argv[1:]
def uncommented(line):
    # The line up to a '#' outside a string.
    quoted = False
    for i, c in enumerate(line):
        if c == '"':
            quoted = not quoted
        elif c == '#' and not quoted:
            return line[:i]
    return line
text = '\n'.join(uncommented(line) for line in open(src).read().split('\n'))
for key, value in (('xresolution', w), ('yresolution', h)):
    text, n = re.subn(r'("integer\s+%s"\s*\[?\s*)\d+' % key, r'\g<1>' + value, text)
    assert n == 1, (key, n)
text = re.sub(r'Sampler\s+"pmj02bn"', 'Sampler "zsobol"', text)
if gray:
    def mean(m):
        v = [float(x) for x in m.group(2).split()]
        assert len(v) == 3, m.group(0)
        return '%s[ %s ]' % (m.group(1), ' '.join(['%.6g' % (sum(v) / 3)] * 3))
    text = re.sub(r'("rgb\s+\w+"\s*)\[([^\]]*)\]', mean, text)
    # A conductor's named spectra: copper's RGB means (pbrt-v4's metal-Cu-eta and -k).
    text = re.sub(r'"spectrum\s+eta"\s*\[?\s*"[^"]*"\s*\]?', '"rgb eta" [ 0.6 0.6 0.6 ]', text)
    text = re.sub(r'"spectrum\s+k"\s*\[?\s*"[^"]*"\s*\]?', '"rgb k" [ 2.9 2.9 2.9 ]', text)
    assert not re.search(r'"(spectrum|blackbody)\s+\w+"', text), 'a spectrum left in ' + src
open(dst, 'w').write(text)
PY
    ref=$out/$tag-pbrt.exr
    if [ ! -f "$ref" ]; then
        start=$(date +%s)
        (cd "$dir" && "$pbrt" --quiet --spp "$spp" --outfile "$ref" "scene-$tag.pbrt")
        echo "$tag: pbrt-v4 at $spp spp in $(($(date +%s) - start)) s" >&2
    fi
    # shellcheck disable=SC2086
    "$bin" "$dir/scene-$tag.pbrt" --time-limit "$secs" --iterations 100000000 $opts -o "$out/$tag.exr" 2>&1 | tail -1
    echo "$tag ($w x $h${opts:+, $opts}) against pbrt-v4 ($spp spp): $("$bin" diff "$out/$tag.exr" "$ref" --downsample "$k")"
done <<< "$table"
