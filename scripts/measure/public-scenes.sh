#!/usr/bin/env bash
# Feeds BENCHMARKS.md "Ten public scenes: SPPM against Mitsuba 3, and equal time (60 s)" (docs/journal/session-11.md).
# Inputs: MIRRORS and DEST, as arguments.
# Stage public Mitsuba scenes (issue 23) outside the repository, from local git mirrors.
#
#   bash scripts/measure/public-scenes.sh [MIRRORS [DEST]]
#
# MIRRORS (default /work/.mirror) holds one bare or ordinary clone per repository, named
# OWNER+NAME/repo (the layout the session's `fetch` tool writes); DEST (default
# /work/public-scenes) receives one folder per scene, the scene's files at their paths in the
# source repository (so relative paths, <path> and <include> keep working), and a SOURCE.txt
# naming repository, commit, paths and license. Nothing is modified, except where a scene's
# notes say so: a derived copy (suffix -noenv) with its dim `constant` emitter removed, until
# environment emitters are read. Files whose blobs the mirror lacks (large files left out of
# public copies) are reported and skipped: such a scene is listed as incomplete.
# Scene files stay out of the repository; SURVEY.md in DEST has the table and the figures.
set -euo pipefail
MIRRORS=${1:-/work/.mirror}
DEST=${2:-/work/public-scenes}
mkdir -p "$DEST"

# gitdir and stage_one (lib.sh, shared with era-scenes.sh).
. "$(dirname "$0")/lib.sh"

# stage NAME MIRROR LICENSE SCENE PATH...: copy PATHs (files or folders) of MIRROR's HEAD; a
# mirror that is not there is reported and skipped.
stage() {
    gitdir "$MIRRORS" "$2" > /dev/null || return 0
    stage_one "$MIRRORS" "$DEST" "$@"
}

# copy_scene NAME FROM: FROM's scene tree and SOURCE.txt (not its results) into NAME.
copy_scene() {
    mkdir -p "$DEST/$1"
    for e in "$DEST/$2"/*; do
        [ -d "$e" ] || [ "$(basename "$e")" = SOURCE.txt ] || continue
        rm -rf "$DEST/$1/$(basename "$e")"; cp -r "$e" "$DEST/$1/"
    done
}

# derive NAME FROM SCENE: a copy of FROM's SCENE without its `constant` emitter.
noenv() {
    local name=$1 from=$2 scene=$3
    [ -f "$DEST/$from/$scene" ] || { echo "$name: skipped ($from is not staged)" >&2; return 0; }
    copy_scene "$name" "$from"
    python3 - "$DEST/$name/$scene" <<'EOF'
import re, sys
p = sys.argv[1]
s = open(p).read()
t = re.sub(r'\s*<emitter type="constant"\s*/>|\s*<emitter type="constant">.*?</emitter>', '', s, flags=re.S)
assert t != s, "no constant emitter"
open(p, "w").write(t)
EOF
    echo "modified: the <emitter type=\"constant\"> of $scene removed (until environment emitters are read)" >> "$DEST/$name/SOURCE.txt"
    echo "$name: $DEST/$name/$scene (derived from $from)"
}

# m3 NAME FROM SCENE: a copy of FROM's 0.6 SCENE in the form Mitsuba 3.9 reads, same meaning:
# <srgb> becomes <rgb> of the linear values (the sRGB transfer function, as Mitsuba 0.6 and our
# reader decode it) and a <spectrum> of three numbers (RGB in 0.6's RGB mode) becomes <rgb>.
m3() {
    local name=$1 from=$2 scene=$3
    [ -f "$DEST/$from/$scene" ] || { echo "$name: skipped ($from is not staged)" >&2; return 0; }
    copy_scene "$name" "$from"
    python3 - "$DEST/$name/$scene" <<'EOF'
import re, sys
p = sys.argv[1]
s = open(p).read()
lin = lambda c: c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4
def srgb(m):
    v = [lin(float(x)) for x in re.split(r"[,\s]+", m.group(2).strip())]
    return '<rgb name="%s" value="%s"/>' % (m.group(1), " ".join("%.6g" % x for x in v))
t = re.sub(r'<srgb\s+name="([^"]+)"\s+value="([^"]+)"\s*/>', srgb, s)
num = r'\s*[-0-9.eE+]+\s*'
t = re.sub(r'<spectrum(\s+name="[^"]+")\s+value="(%s,%s,%s)"\s*/>' % (num, num, num), r'<rgb\1 value="\2"/>', t)
# The integrator is a Mitsuba fork's SPPM (kNN, dualBuffer, stepSnapshot): keep its type and depth.
def integ(m):
    d = re.search(r'name="maxDepth"\s+value="([^"]+)"', m.group(0))
    return '<integrator type="sppm">%s</integrator>' % (
        '<integer name="maxDepth" value="%s"/>' % d.group(1) if d else '')
t = re.sub(r'<integrator\s+type="\$method">.*?</integrator>', integ, t, flags=re.S)
# Mitsuba 3 has no `sobol` sampler (the expectation is the same with `independent`), and its
# conductor no extEta (air; the scenes' conductors are material "none", perfect mirrors).
t = t.replace('<sampler type="sobol">', '<sampler type="independent">')
t = re.sub(r'\s*<string name="extEta" value="air"\s*/>', '', t)
# Film parameters Mitsuba 3.9 refuses and that change no pixel: 0.6's attachLog, 2's
# high_quality_edges.
t = re.sub(r'\s*<boolean name="(attachLog|high_quality_edges)" value="[^"]*"\s*/>', '', t)
assert t != s, "nothing to upgrade"
open(p, "w").write(t)
EOF
    echo "modified: <srgb> written as <rgb> of its linear values, 3-number <spectrum> as <rgb> (Mitsuba 3.9 reads neither); the fork's integrator (type \$method, kNN, dualBuffer, stepSnapshot) as sppm with its maxDepth; sampler sobol as independent; conductor extEta=air, film attachLog / high_quality_edges dropped (whichever the file has)" >> "$DEST/$name/SOURCE.txt"
    echo "$name: $DEST/$name/$scene (derived from $from)"
}

CC0="CC0 (Benedikt Bitterli, https://benedikt-bitterli.me/resources/; LICENSE.txt beside the scene)"
MD="no license file in mitsuba-data (Mitsuba 3 itself is BSD-3-Clause); Mitsuba documentation scenes"

# Bitterli's rendering resources in Mitsuba 3 form (takkasila/practical_path_guiding_lab).
P=takkasila+practical_path_guiding_lab
stage bitterli-cornell-box $P "$CC0" scenes/cornell-box/scene.xml scenes/cornell-box/LICENSE.txt
stage bitterli-veach-mis   $P "$CC0" scenes/veach-mis/scene.xml scenes/veach-mis/LICENSE.txt
stage bitterli-veach-bidir $P "$CC0" scenes/veach-bidir/scene.xml scenes/veach-bidir/LICENSE.txt scenes/veach-bidir/models
stage torus $P "repository GPL-3.0 (LICENSE at its root); the torus scene is from Mueller et al.'s practical path guiding" \
    scenes/torus/scene.xml scenes/torus/meshes.serialized

# Scenes of a photon-mapping paper's data set (hchoi405/dppm-scenes), Mitsuba 0.6.
D=hchoi405+dppm-scenes
stage dppm-box $D "no license file in the repository" scenes/box/scene.xml scenes/box/box.serialized
stage dppm-cbox-caustics $D "no license file in the repository" \
    scenes/cbox-caustics/cbox-caustics_rand_scene0.xml scenes/cbox-caustics/models/suzanne.obj
stage dppm-cbox-caustics-teapot $D "no license file in the repository" \
    scenes/cbox-caustics/cbox-caustics_rand_scene10.xml scenes/cbox-caustics/models/teapot.obj
m3 dppm-box-m3 dppm-box scenes/box/scene.xml
m3 dppm-cbox-caustics-m3 dppm-cbox-caustics scenes/cbox-caustics/cbox-caustics_rand_scene0.xml
m3 dppm-cbox-caustics-teapot-m3 dppm-cbox-caustics-teapot scenes/cbox-caustics/cbox-caustics_rand_scene10.xml

# Mitsuba's own documentation scenes (mitsuba-renderer/mitsuba-data).
M=mitsuba-renderer+mitsuba-data
stage mitsuba-spot $M "$MD" docs/scenes/emitter_spot_no_texture.xml \
    docs/scenes/include/emitter_scene.xml common/meshes/matpreview.serialized
noenv mitsuba-spot-noenv mitsuba-spot docs/scenes/emitter_spot_no_texture.xml
stage mitsuba-veach-mis $M "$MD" docs/scenes/integrator_direct_both.xml \
    docs/scenes/include/veach_mis.xml docs/scenes/meshes/veach common/meshes/rectangle.obj  # <path> needs common/
stage mitsuba-hello $M "$MD" scenes/hello.xml common/meshes/teapot.ply
stage mitsuba-twosided-cbox $M "$MD" docs/scenes/bsdf_twosided_cbox.xml common/meshes/cbox
stage mitsuba-ply-bunny $M "$MD" docs/scenes/shape_ply_bunny.xml \
    docs/scenes/include/shape_scene.xml common/meshes/bunny.ply common/textures/museum.exr common/meshes/matpreview.serialized
stage mitsuba-roughplastic $M "$MD" docs/scenes/bsdf_roughplastic_beckmann.xml \
    docs/scenes/include/matpreview.xml common/meshes/matpreview.serialized common/textures/museum.exr
# Mitsuba's material previews (issue 25): one BSDF each on the material-preview object under
# the museum environment map, those whose BSDFs we read; and scenes/matpreview.
for b in conductor_aluminium conductor_gold dielectric_diamond dielectric_glass diffuse_plain \
    diffuse_textured plastic_default plastic_diffuse plastic_nopreserve plastic_preserve plastic_shiny \
    roughconductor_copper roughdielectric_glass roughdielectric_rough roughplastic_beckmann \
    roughplastic_diffuse roughplastic_ggx roughplastic_nopreserve roughplastic_preserve thindielectric_glass; do
    stage "matpreview-$b" $M "$MD" "docs/scenes/bsdf_$b.xml" docs/scenes/include/matpreview.xml docs/scenes/include/matpreview_no_rr.xml \
        common/meshes/matpreview.serialized common/textures/museum.exr common/textures/wood.jpg common/textures/floor_tiles.jpg
done
stage mitsuba-matpreview $M "$MD" scenes/matpreview/matpreview.xml scenes/matpreview/envmap.exr \
    scenes/matpreview/matpreview.serialized

# Bitterli scenes in Mitsuba 0.5/2 form (jgarciapueyo/mitsuba2-transient-scenes).
J=jgarciapueyo+mitsuba2-transient-scenes
stage staircase2 $J "CC-BY (Bitterli's resources; LICENSE.txt beside the scene)" \
    staircase2/scene.xml staircase2/LICENSE.txt staircase2/models staircase2/textures
m3 staircase2-m3 staircase2 staircase2/scene.xml
stage m2-cbox-spheres $J "no license file (Mitsuba 2 Cornell box with spheres)" \
    cbox-spheres/scene.xml cbox-spheres/meshes
stage m2-veach-mi $J "no license file (Mitsuba 0.4 Veach MIS scene)" veach_mi/scene.xml veach_mi/floor.obj veach_mi/plate1.obj veach_mi/plate2.obj veach_mi/plate3.obj veach_mi/plate4.obj
