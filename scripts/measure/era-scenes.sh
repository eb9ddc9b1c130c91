#!/usr/bin/env bash
# Feeds BENCHMARKS.md "Mitsuba 0.5/0.6 scenes of the field" (issue 33): public Mitsuba 0.5/0.6
# scene files from a path-guiding and a photon-mapping paper's repositories, read by our
# reader as their own version reads them (era parameters warned), rendered, and compared
# against references.
#
#   bash scripts/measure/era-scenes.sh stage MIRRORS DEST
#   bash scripts/measure/era-scenes.sh render DEST BINARY
#   bash scripts/measure/era-scenes.sh reference DEST BINARY MITSUBA_XML_PY
#   bash scripts/measure/era-scenes.sh compare DEST BINARY
#
# Inputs, all given as arguments (nothing else outside the repository is read):
# - MIRRORS: one clone per repository, OWNER+NAME/repo, bare or not (the layout the session's
#   `fetch` tool writes; scripts/measure/public-scenes.sh reads the same): Tom94/practical-path-guiding
#   and hchoi405/dppm-scenes.
# - DEST: receives one folder per scene (the scene's files at their paths in the source
#   repository, SOURCE.txt with repository, commit, paths and license), and in it the renders
#   (ours-*.exr, ref-*.exr, long-*.exr), their logs (*.log: the command, the load average, the
#   warnings our reader printed, the summary line) and the figures (figures.txt).
# - BINARY: target/release/sppm-gpu (or another build of it).
# - MITSUBA_XML_PY: ../shared/tools/mitsuba_xml.py, which renders any Mitsuba XML file with
#   Mitsuba 3 (python3 with `mitsuba` 3.9.1, llvm_ad_rgb; numpy and OpenEXR for the helpers).
#
# The scenes: ppg-cbox (Mueller et al.'s Cornell box lit only by a light facing the ceiling,
# 0.5.0, their `guided_path` integrator; their own render of it comes with it), dppm-cbox-
# caustics (a point light through a glass Suzanne, 0.6.0, the paper's SPPM fork) and dppm-box
# (two 8x4 mm area lights over glass and mirror boxes, 0.6.0, the same).
#
# Steps (renders one after another: two cores, never two at once):
# - stage: copies the scenes out of the mirrors.
# - render: ours at 256 pixels wide, SPPM and pt-nee for LIMIT seconds (default 60).
# - reference: the authors' render of ppg-cbox (their Mitsuba 0.6 fork's guided path tracer, 512
#   pixels square, 128 spp) halved, and as it would be with its light's spectrum read as written
#   (ref-authors-fixed: Mitsuba 0.5.0 and 0.6.0 as released interpolated a spectrum's values
#   backwards between its wavelengths, fixed upstream in 2020). Then a copy NAME-m3.xml of each
#   file that Mitsuba 3.9.1 loads with the meaning Mitsuba 0.5/0.6 gave the file (Mitsuba 3
#   upgrades camelCase names as it reads a 0.x file, but refuses 0.5's <lookAt>, <srgb>,
#   3-number <spectrum>, the `sobol` sampler, `highQualityEdges`, and reads a <spectrum> in its
#   own way: a flat one on an emitter as the colour of a flat spectrum, where 0.6 made it grey,
#   and one given by wavelengths on a reflectance under D65, where 0.6 took none): those are
#   written as <rgb> of 0.6's colours. Every sampler becomes `independent`: Mitsuba 3's
#   `ldsampler` (the dppm box's), rendered in mitsuba_xml.py's 16-spp chunks, left a structured
#   error in its ptracer image (8x8 blocks 0.8 to 1.3 times the independent sampler's, the
#   same at 1024 spp from seed 0 and at 3040 spp from seed 10^6). Then Mitsuba 3's `path` at SPP (default 4096; 8192 for ppg-cbox) with the file's max depth,
#   and for the dppm scenes `ptracer` too, which holds the caustics of the point light and the
#   tiny area lights that `path` cannot, but nothing the camera sees through glass or in a
#   mirror: a mask of those pixels (Mitsuba 3's first hits with a delta BSDF) splits the
#   image, and the composite reference takes ptracer in the 8x8 blocks that see none and path
#   in the others. For the dppm box, whose path render is fireflies, also long runs of our own
#   SPPM (LONG seconds, default 600) at the automatic radius and at half of it (RADIUS, default
#   0.0241: the automatic radius at 256x192, 3 pixel footprints at the look-at distance 2.446,
#   as src/integrators/sppm.rs auto_radius computes it): their difference bounds the bias.
#   A render whose image exists is not done again (delete it to render it anew).
# - compare: `sppm-gpu diff --downsample 8` of each render against its references, and the
#   same figures over the blocks that see glass or mirrors and over the rest.
set -euo pipefail
usage="usage: era-scenes.sh stage MIRRORS DEST | render DEST BINARY | reference DEST BINARY MITSUBA_XML_PY | compare DEST BINARY"
step=${1:?$usage}
limit=${LIMIT:-60}
spp=${SPP:-4096}
long=${LONG:-600}

PPG=Tom94+practical-path-guiding
DPPM=hchoi405+dppm-scenes
scenes=(ppg-cbox dppm-cbox-caustics dppm-box)
# file_of NAME: the scene file, at its path in the source repository.
file_of() {
    case $1 in
    ppg-cbox) echo scenes/cbox/cbox.xml ;;
    dppm-cbox-caustics) echo scenes/cbox-caustics/cbox-caustics_rand_scene0.xml ;;
    dppm-box) echo scenes/box/scene.xml ;;
    esac
}
# m3_of NAME: its copy for Mitsuba 3.
m3_of() { file_of "$1" | sed 's/\.xml$/-m3.xml/'; }
# size NAME: our --width and --height (256 wide, the file's aspect).
size() {
    case $1 in
    dppm-box) echo "--width 256 --height 192" ;;
    *) echo "--width 256 --height 256" ;;
    esac
}

# gitdir and stage_one: shared with public-scenes.sh.
. "$(dirname "$0")/lib.sh"

# helper COMMAND ARGS...: image and scene helpers in python3 (numpy, OpenEXR; `m3` and `mask`
# also import mitsuba).
helper() {
    python3 - "$@" <<'PY'
import os, re, sys, tempfile
import xml.etree.ElementTree as ET
import numpy as np
import OpenEXR

def read(path):
    with OpenEXR.File(path) as f:
        ch = f.parts[0].channels
        if "RGB" in ch:
            return np.asarray(ch["RGB"].pixels, dtype=np.float64)[..., :3]
        return np.stack([np.asarray(ch[c].pixels, dtype=np.float64) for c in "RGB"], -1)

def write(path, img):
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {"RGB": np.ascontiguousarray(img, dtype=np.float32)}) as f:
        f.write(path)

def blocks(img, b=8):
    h, w, _ = img.shape
    return img[: h // b * b, : w // b * b].reshape(h // b, b, w // b, b, 3).mean(axis=(1, 3))

def m3(src, dst):
    """SRC's copy DST that Mitsuba 3.9.1 loads, meaning what Mitsuba 0.5/0.6 read in SRC (the
    integrator is left for mitsuba_xml.py to replace)."""
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    tree = ET.parse(src)
    lin = lambda c: c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4
    nums = lambda text: [float(x) for x in re.split(r"[,\s]+", text.strip()) if x]
    def walk(el, in_emitter):
        for c in list(el):
            if c.get("name") in ("extEta", "attachLog", "highQualityEdges") and c.tag in ("string", "boolean"):
                el.remove(c)  # a mirror's outside medium (air); film options that change no pixel
                continue
            if c.tag == "lookAt":
                c.tag = "lookat"
            elif c.tag == "srgb":  # 0.6 decodes sRGB; Mitsuba 3 has no <srgb>
                c.tag, c.attrib["value"] = "rgb", " ".join("%.6g" % lin(x) for x in nums(c.get("value")))
            elif c.tag == "spectrum" and "value" in c.attrib:
                text = c.attrib.pop("value")
                c.attrib.pop("intent", None)
                if ":" in text:  # 0.6: the CIE integral without an illuminant, negatives clamped
                    pairs = [p.split(":") for p in text.split(",") if p.strip()]
                    rgb = mi.spectrum_list_to_srgb([float(a) for a, _ in pairs], [float(b) for _, b in pairs], False, False)
                    c.tag, text = "rgb", " ".join("%.6g" % max(0.0, float(rgb[i])) for i in range(3))
                elif len(nums(text)) == 3 or in_emitter:  # 0.6's RGB samples; a grey emitter
                    c.tag = "rgb"
                c.attrib["value"] = text
            elif c.tag == "sampler":  # the same expectation (see the header)
                c.set("type", "independent")
            walk(c, in_emitter or c.tag == "emitter")
    walk(tree.getroot(), False)
    tree.write(dst)

def halve(src, dst):
    """SRC box-downsampled 2x2."""
    write(dst, blocks(read(src), 2))

def release(scene, src, dst):
    """SRC (a render by Mitsuba 0.5.0 or 0.6.0 as released) as it would be with the emitter's
    spectrum read as written: those releases interpolated a spectrum's values backwards between
    the given wavelengths (InterpolatedSpectrum::eval, fixed upstream in 2020, cfeb7766), which
    changes the colour of the scene's one light given by wavelengths; light transport in their
    RGB build is linear in that colour (the reflectances' 4 nm samples change by <1%)."""
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    root = ET.parse(scene).getroot()
    spectra = [c.get("value") for e in root.iter("emitter") for c in e if c.tag == "spectrum" and ":" in c.get("value", "")]
    assert len(spectra) == 1, spectra
    pairs = [p.split(":") for p in spectra[0].split(",") if p.strip()]
    w, v = [float(a) for a, _ in pairs], [float(b) for _, b in pairs]
    fixed = np.array(mi.spectrum_list_to_srgb(w, v, False, False))
    # The releases: zero-extended by the mean spacing (zeroExtend), then lerp(t, f_b, f_a).
    step = (w[-1] - w[0]) / (len(w) - 1)
    if v[0] != 0:
        w, v = [w[0] - step] + w, [0.0] + v
    if v[-1] != 0:
        w, v = w + [w[-1] + step], v + [0.0]
    w, v = np.array(w), np.array(v)
    lam = np.arange(w[0], w[-1] + 1e-9, 0.05)
    i = np.clip(np.searchsorted(w, lam, side="right") - 1, 0, len(w) - 2)
    t = (lam - w[i]) / (w[i + 1] - w[i])
    released = np.array(mi.spectrum_list_to_srgb(list(lam), list(v[i + 1] + t * (v[i] - v[i + 1])), False, False))
    write(dst, read(src) * (fixed / released))
    print(f"{os.path.basename(dst)}: the light read as written {fixed.round(4)}, as 0.5.0/0.6.0 read it "
          f"{released.round(4)}: the render times {(fixed / released).round(4)}")

def mask(scene, w, h, dst):
    """The fraction of each pixel (4x4 samples) whose camera ray first meets a smooth glass or
    mirror (a delta BSDF), by Mitsuba 3 from the -m3 copy SCENE, its integrator left out."""
    import drjit as dr
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    w, h, n = int(w), int(h), 4
    tree = ET.parse(scene)
    root = tree.getroot()
    for i in root.findall("integrator"):
        root.remove(i)
    for film in root.iter("film"):  # Mitsuba 3 has no ldrfilm; the film's size is the file's
        film.set("type", "hdrfilm")
        for c in list(film):
            if c.get("name") in ("fileFormat", "pixelFormat", "gamma", "banner", "tonemapMethod", "exposure"):
                film.remove(c)
    fd, tmp = tempfile.mkstemp(suffix=".xml", prefix=".mask-", dir=os.path.dirname(os.path.abspath(scene)))
    os.close(fd)
    tree.write(tmp)
    try:
        sc = mi.load_file(tmp)
    finally:
        os.remove(tmp)
    idx = dr.arange(mi.UInt32, w * h * n * n)
    px, sub = idx // (n * n), idx % (n * n)
    x = (mi.Float(px % w) + (mi.Float(sub % n) + 0.5) / n) / w
    y = (mi.Float(px // w) + (mi.Float(sub // n) + 0.5) / n) / h
    ray, _ = sc.sensors()[0].sample_ray(0.0, 0.5, mi.Point2f(x, y), mi.Point2f(0.5, 0.5))
    si = sc.ray_intersect(ray)
    delta = si.is_valid() & mi.has_flag(si.bsdf(ray).flags(), mi.BSDFFlags.Delta)
    frac = np.array(mi.Float(delta)).reshape(h, w, n * n).mean(axis=2)
    write(dst, np.repeat(frac[..., None], 3, axis=2))
    print(f"mask {dst}: {frac.mean():.4f} of the pixels see glass or mirrors")

def seen(maskpath):
    m = read(maskpath)[..., 0]
    h, w = m.shape
    return m.reshape(h // 8, 8, w // 8, 8).max(axis=(1, 3)) > 0

def composite(rest, specular, maskpath, dst):
    """REST in the 8x8 blocks that see no glass or mirror, SPECULAR in the others."""
    a, b, sees = read(rest), read(specular), seen(maskpath)
    full = np.repeat(np.repeat(sees, 8, axis=0), 8, axis=1)
    write(dst, np.where(full[..., None], b, a))
    print(f"composite {dst}: {sees.mean():.3f} of the 8x8 blocks from {os.path.basename(specular)}")

def split(img, ref, maskpath, label):
    """8x8 relMSE and channel-mean ratios of IMG against REF over the blocks that see no glass
    or mirror ("rest") and over the others ("specular")."""
    x, r, sees = blocks(read(img)), blocks(read(ref)), seen(maskpath)
    for name, sel in (("rest", ~sees), ("specular", sees)):
        if not sel.any():
            continue
        xs, rs = x[sel], r[sel]
        rel = ((xs - rs) ** 2 / (rs ** 2 + 0.01)).mean()
        ratio = xs.mean(axis=0) / rs.mean(axis=0)
        print(f"{label}, {name} ({sel.mean():.3f} of the blocks): relMSE {rel:.3e}, mean / reference "
              + " ".join("%.4f" % v for v in ratio))

{"m3": m3, "halve": halve, "release": release, "mask": mask, "composite": composite, "split": split}[sys.argv[1]](*sys.argv[2:])
PY
}

# run LOG CMD...: CMD's output into LOG (with the command and the load average before and
# after); prints the last line it wrote (the summary).
run() {
    local log=$1
    shift
    {
        echo "+ $*"
        echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
    } > "$log"
    "$@" >> "$log" 2>&1
    local last
    last=$(tail -1 "$log")
    echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" >> "$log"
    echo "$last"
}

case $step in
stage)
    mirrors=${2:?$usage}
    dest=${3:?$usage}
    mkdir -p "$dest"
    stage_one "$mirrors" "$dest" ppg-cbox $PPG \
        "GPL-3.0 (the repository's LICENSE); the Cornell box from mitsuba-renderer.org, its light turned to the ceiling by Mueller et al." \
        "$(file_of ppg-cbox)" scenes/cbox/meshes scenes/cbox/cbox.exr
    stage_one "$mirrors" "$dest" dppm-cbox-caustics $DPPM "no license file in the repository" \
        "$(file_of dppm-cbox-caustics)" scenes/cbox-caustics/models/suzanne.obj
    stage_one "$mirrors" "$dest" dppm-box $DPPM "no license file in the repository" \
        "$(file_of dppm-box)" scenes/box/box.serialized
    ;;
render)
    dest=${2:?$usage}
    bin=$(realpath "${3:?$usage}")
    for s in "${scenes[@]}"; do
        d="$dest/$s"
        for m in sppm pt-nee; do
            echo "$s $m: $(run "$d/ours-$m.log" "$bin" "$d/$(file_of $s)" -o "$d/ours-$m.exr" $(size $s) \
                --method $m --time-limit "$limit" --iterations 1000000)"
        done
    done
    ;;
reference)
    dest=${2:?$usage}
    bin=$(realpath "${3:?$usage}")
    tool=$(realpath "${4:?$usage}")
    for s in "${scenes[@]}"; do
        helper m3 "$dest/$s/$(file_of $s)" "$dest/$s/$(m3_of $s)"
        grep -q '^m3:' "$dest/$s/SOURCE.txt" ||
            echo "m3:      $(m3_of $s), written by era-scenes.sh reference, is the file for Mitsuba 3.9.1 (its header says how); ours reads $(file_of $s)" >> "$dest/$s/SOURCE.txt"
    done
    # The path-guiding Cornell box: Mitsuba 3's path; its authors' own render (512 pixels
    # square, their Mitsuba 0.6 fork and guided path tracer, 128 spp), halved.
    d="$dest/ppg-cbox"
    [ -f "$d/ref-path.exr" ] || echo "ppg-cbox path: $(run "$d/ref-path.log" python3 "$tool" "$d/$(m3_of ppg-cbox)" \
        "$d/ref-path.exr" $(size ppg-cbox) --spp $((2 * spp)) --chunk 16)"
    helper halve "$d/scenes/cbox/cbox.exr" "$d/ref-authors.exr"
    helper release "$d/$(file_of ppg-cbox)" "$d/ref-authors.exr" "$d/ref-authors-fixed.exr"
    # The dppm scenes: Mitsuba 3's path and ptracer, the mask, the composite.
    for s in dppm-cbox-caustics dppm-box; do
        d="$dest/$s"
        n=$spp
        [ $s = dppm-box ] && n=$((spp / 4)) # its ptracer is 4x slower
        for i in path ptracer; do
            [ -f "$d/ref-$i.exr" ] || echo "$s $i: $(run "$d/ref-$i.log" python3 "$tool" "$d/$(m3_of $s)" \
                "$d/ref-$i.exr" $(size $s) --spp $n --chunk 16 --integrator $i)"
        done
        helper mask "$d/$(m3_of $s)" $(size $s | awk '{print $2, $4}') "$d/mask.exr"
        helper composite "$d/ref-ptracer.exr" "$d/ref-path.exr" "$d/mask.exr" "$d/ref-composite.exr"
    done
    # The dppm box: long runs of our own SPPM at the automatic radius and at half of it.
    d="$dest/dppm-box"
    radius=${RADIUS:-0.0241}
    [ -f "$d/long-sppm.exr" ] || echo "dppm-box long sppm: $(run "$d/long-sppm.log" "$bin" \
        "$d/$(file_of dppm-box)" -o "$d/long-sppm.exr" $(size dppm-box) --time-limit "$long" --iterations 1000000)"
    [ -f "$d/long-sppm-half.exr" ] || echo "dppm-box long sppm, half radius: $(run "$d/long-sppm-half.log" "$bin" \
        "$d/$(file_of dppm-box)" -o "$d/long-sppm-half.exr" $(size dppm-box) --time-limit "$long" \
        --iterations 1000000 --radius "$(python3 -c "print($radius / 2)")")"
    ;;
compare)
    dest=${2:?$usage}
    bin=$(realpath "${3:?$usage}")
    for s in "${scenes[@]}"; do
        d="$dest/$s"
        case $s in
        ppg-cbox) refs=(ref-path ref-authors ref-authors-fixed) ;;
        dppm-cbox-caustics) refs=(ref-composite ref-path ref-ptracer) ;;
        dppm-box) refs=(long-sppm ref-composite ref-ptracer) ;;
        esac
        {
            grep -h '^warning' "$d/ours-sppm.log" || true
            for r in "${refs[@]}"; do
                [ -f "$d/$r.exr" ] || continue
                for o in ours-sppm ours-pt-nee long-sppm long-sppm-half ref-authors-fixed; do
                    [ -f "$d/$o.exr" ] && [ "$o" != "$r" ] || continue
                    echo "$s $o vs $r: $("$bin" diff "$d/$o.exr" "$d/$r.exr" --downsample 8 2>&1 | tr '\n' ' ')"
                    if [ -f "$d/mask.exr" ]; then helper split "$d/$o.exr" "$d/$r.exr" "$d/mask.exr" "$s $o vs $r"; fi
                done
            done
        } | tee "$d/figures.txt"
    done
    ;;
*)
    echo "$usage" >&2
    exit 2
    ;;
esac
