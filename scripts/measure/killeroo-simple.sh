#!/usr/bin/env bash
# Feeds BENCHMARKS.md "pbrt-v4 scenes" (issue 44): mmp/pbrt-v4-scenes' killeroos/killeroo-simple.pbrt
# read by the pbrt-v4 reader, against Mitsuba 3's render of the same scene as read.
#
#   bash scripts/measure/killeroo-simple.sh OUT_DIR [SECONDS] [MIRRORS] [MITSUBA_PYTHON] [SPP]
#
# The collection is too big to fetch; its killeroo-simple.pbrt (1.6 KB; its directives are written
# below as the collection has them, comments left out) includes geometry/killeroo.pbrt, a 287 KB
# `loopsubdiv` that is pbrt-v3's scenes/geometry/killeroo.pbrt (mmp/pbrt-v3, fetchable: MIRRORS
# holds mmp+pbrt-v3/repo) in pbrt-v4's syntax (`levels`, `point3`: every position and index the same). The scene is
# converted to our TOML (the subdivided meshes as PLY), then rendered at 175x175 with a box
# filter by Mitsuba 3 (`path`, SPP samples a pixel; the killeroos' coateddiffuse as
# `roughplastic`, nonlinear) and by us (pt-nee, SECONDS). Mitsuba's plastics have no absorbing
# layer under the coating, so both renders leave pbrt-v4's out (`thickness`, `scatterings`
# removed: they are checked against pbrt's walk by chi_square::coated_diffuse_matches_pbrt_walk);
# a third render keeps it. MITSUBA_PYTHON (default python3) has `mitsuba` and `OpenEXR`.
# With STAGE_ONLY=1 it writes OUT_DIR/killeroo-simple.pbrt and its geometry and stops.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:?usage: killeroo-simple.sh OUT_DIR [SECONDS] [MIRRORS] [MITSUBA_PYTHON] [SPP]}
secs=${2:-60}
mirrors=${3:-/work/.mirror}
python=${4:-python3}
spp=${5:-16384}
bin=$(realpath "${SPPM_GPU:-target/release/sppm-gpu}")
tools=$(realpath ../shared/tools)
mkdir -p "$out/geometry"
out=$(cd "$out" && pwd)
git -C "$mirrors/mmp+pbrt-v3/repo" show HEAD:scenes/geometry/killeroo.pbrt |
    sed 's/"integer nlevels"/"integer levels"/; s/"point P"/"point3 P"/' >"$out/geometry/killeroo.pbrt"
cat >"$out/killeroo-simple.pbrt" <<'PBRT'
LookAt 400 20 30
    0 63 -110
    0 0 1
Rotate -5 0 0 1
Camera "perspective"
    "float fov" [ 39 ]
Film "rgb"
    "string filename" [ "killeroo-simple.exr" ]
    "integer yresolution" [ 700 ]
    "integer xresolution" [ 700 ]
Sampler "halton"
    "integer pixelsamples" [ 256 ]
WorldBegin
AttributeBegin
    Material "diffuse"
        "rgb reflectance" [ 0 0 0 ]
    Translate 150 0 20
    Translate 0 120 0
    AreaLightSource "diffuse"
        "rgb L" [ 2000 2000 2000 ]
    Shape "sphere"
        "float radius" [ 3 ]
AttributeEnd
AttributeBegin
    Material "diffuse"
        "rgb reflectance" [ 0.5 0.5 0.8 ]
    Translate 0 0 -140
    Shape "trianglemesh"
        "point2 uv" [ 0 0 5 0 5 5 0 5 ]
        "integer indices" [ 0 1 2 2 3 0 ]
        "point3 P" [ -1000 -1000 0 1000 -1000 0 1000 1000 0 -1000 1000 0 ]
    Shape "trianglemesh"
        "point2 uv" [ 0 0 5 0 5 5 0 5 ]
        "integer indices" [ 0 1 2 2 3 0 ]
        "point3 P" [ -400 -1000 -1000 -400 1000 -1000 -400 1000 1000 -400 -1000 1000 ]
AttributeEnd
AttributeBegin
    Scale 0.5 0.5 0.5
    Rotate -60 0 0 1
    Material "coateddiffuse"
        "float roughness" [ 0.025 ]
        "rgb reflectance" [ 0.4 0.2 0.2 ]
    Translate 100 200 -140
    Include "geometry/killeroo.pbrt"
    Material "coateddiffuse"
        "float roughness" [ 0.15 ]
        "rgb reflectance" [ 0.4 0.5 0.4 ]
    Translate -200 0 0
    Include "geometry/killeroo.pbrt"
AttributeEnd
PBRT
# STAGE_ONLY=1: the scene files alone (scripts/measure/pbrt-v4-references.sh renders them).
[ -z "${STAGE_ONLY:-}" ] || exit 0
cd "$out"
rm -rf k.toml k.meshes
"$bin" convert killeroo-simple.pbrt -o k.toml 2>/dev/null
# 175x175, a box filter (Mitsuba's reference script's); without and with pbrt-v4's layer.
python3 - <<'PY'
s = open("k.toml").read()
s = s.replace('filter = "gaussian"\nfilter_stddev = 0.5\n', 'filter = "box"\n')
s = s.replace("height = 700", "height = 175").replace("width = 700", "width = 175")
open("layer.toml", "w").write(s)
open("plain.toml", "w").write(s.replace("scatterings = 5\n", "").replace("thickness = 0.01\n", ""))
PY
# Mitsuba's reference script, its plastic added (Mitsuba's own plugin) and PLY meshes read as PLY.
"$python" - "$tools" plain.toml mitsuba.exr "$spp" <<'PY'
import importlib.util, sys
tools, scene, out, spp = sys.argv[1:]
spec = importlib.util.spec_from_file_location("reference", f"{tools}/mitsuba_reference.py")
ref = importlib.util.module_from_spec(spec)
spec.loader.exec_module(ref)
material = ref.material
def plastic(m, base):
    if m["type"] != "plastic":
        return material(m, base)
    bsdf = {"type": "roughplastic", "distribution": m["distribution"], "alpha": float(m["roughness"]),
            "int_ior": float(m["ior"]), "ext_ior": 1.0, "nonlinear": bool(m["nonlinear"]),
            "diffuse_reflectance": ref.rgb(m["albedo"])}
    return {"type": "twosided", "bsdf": bsdf}
ref.material = plastic
load_dict = ref.mi.load_dict
def ply(d):
    for v in d.values():
        if isinstance(v, dict) and v.get("type") == "obj" and v["filename"].endswith(".ply"):
            v["type"] = "ply"
    return load_dict(d)
ref.mi.load_dict = ply
sys.argv = [sys.argv[0], scene, out, "--spp", spp, "--seed", "23"]
ref.main()
PY
"$bin" plain.toml --time-limit "$secs" -o plain.exr 2>&1 | tail -1
"$bin" layer.toml --time-limit "$secs" -o layer.exr 2>&1 | tail -1
# Blocks of 7x7 (175 = 25 x 7); the light's own pixels (2,000) left out of the means.
"$python" - <<'PY'
import OpenEXR, Imath, numpy as np
def load(p):
    f = OpenEXR.InputFile(p)
    dw = f.header()["dataWindow"]
    w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
    pt = Imath.PixelType(Imath.PixelType.FLOAT)
    return np.stack([np.frombuffer(f.channel(c, pt), dtype=np.float32).reshape(h, w) for c in "RGB"], -1).astype(np.float64)
ref = load("mitsuba.exr")
blocks = lambda a: a.reshape(25, 7, 25, 7, 3).mean(axis=(1, 3))
unlit = ref.max(-1) < 50
for name in ("plain", "layer"):
    ours = load(f"{name}.exr")
    keep = unlit & (ours.max(-1) < 50)
    means = ours[keep].mean(0) / ref[keep].mean(0)
    a, b = blocks(ours), blocks(ref)
    dark = b.max(-1) < 50
    ratio = a[dark] / b[dark]
    rel = np.mean((a[dark] - b[dark]) ** 2 / (b[dark] ** 2 + 1e-2))
    print(f"{name}: 7x7 relMSE {rel:.3e}, means {np.round(means, 4)}, median block ratio "
          f"{np.round(np.median(ratio, 0), 4)}, 5th-95th percentile (G) {np.round(np.percentile(ratio[:, 1], [5, 95]), 4)}")
PY
