#!/usr/bin/env bash
# Feeds BENCHMARKS.md "Thin shells: the gather's normal test" (issue 33, item 1). A photon
# that lands inside a thin shell must not light the visible points on its outside: the gather
# skips photons on the other side of a point's surface (same_side, shaders/shared/grid.wgsl;
# each photon hit keeps its surface's normal). An old binary (without the test) against a new
# one (with it), one render at a time:
#   0. tests/scenes/thin-shells.toml (a box and a globe lit from inside, seen from outside):
#      the image's mean, the pixels not black, the brightest;
#   1. the canonical scenes (cornell-box, cornell-spheres, cornell-glossy, point-light,
#      textured) at their own settings, seeds SEEDS (default "0 1 2"; the scenes' own is 0):
#      `sppm-gpu diff` against tests/references at --downsample 8 (relMSE, mean ratio);
#   2. corners: the same renders' 8x8 blocks that the room's creases cross (the five scenes
#      share the room and the camera), each block's mean over the reference's: the mean of
#      |ratio - 1| and the mean ratio over the crease blocks, old and new, and new over old at
#      the same seed (the same photons and camera paths: only the skipped photons differ);
#   3. Bitterli's veach-bidir (Mitsuba 3 form) at 256x256 for LIMIT seconds (default 60),
#      against REF (Mitsuba 3's render of the same file, e.g. 4,096 spp of
#      ../shared/tools/mitsuba_xml.py SCENE REF --spp 4096 --chunk 16 --width 256 --height 256):
#      32x32 blocks, each block's mean over REF's: the small lamp's block (the block holding
#      pixel LAMP, default 207,103: the lamp at (-2.69, 5.10, -3.77) through the file's
#      camera), the three other blocks furthest from 1, and the channel means' ratios; then
#      PASSES passes (default 100) of each, same seed: the same figures, and new over old block
#      by block (the same camera paths and photons: only the skipped photons differ);
#   4. equal time: cornell-box for 20 s, old and new alternating, ROUNDS rounds (default 2):
#      the passes done and the diff against the reference;
#   5. the test: cargo test --release --test suite sppm::thin_shell (in this checkout; set
#      CARGO_TARGET_DIR as for any build).
#
#   bash scripts/measure/thin-shell.sh OUT OLD_BINARY NEW_BINARY SCENE_XML REF_EXR
#
# OUT receives the renders (old/, new/) and the figures (thin-shell.txt). Needs python3 with
# numpy and OpenEXR (pip install numpy OpenEXR).
set -euo pipefail
usage="usage: thin-shell.sh OUT OLD_BINARY NEW_BINARY SCENE_XML REF_EXR"
out=${1:?$usage}
old=${2:?$usage}
new=${3:?$usage}
xml=${4:?$usage}
ref=${5:?$usage}
seeds=${SEEDS:-0 1 2}
limit=${LIMIT:-60}
passes=${PASSES:-100}
rounds=${ROUNDS:-2}
lamp=${LAMP:-207,103}
old=$(realpath "$old"); new=$(realpath "$new"); xml=$(realpath "$xml"); ref=$(realpath "$ref")
mkdir -p "$out/old" "$out/new"
out=$(realpath "$out")
cd "$(dirname "$0")/../.."
report="$out/thin-shell.txt"
: > "$report"
say() { echo "$*" | tee -a "$report"; }

# Block statistics (python: numpy and OpenEXR).
blocks() {
    python3 - "$@" <<'EOF'
import sys, math
import numpy as np
import OpenEXR

def read(path):
    with OpenEXR.File(path) as f:
        ch = f.parts[0].channels
        if "RGB" in ch:
            return np.asarray(ch["RGB"].pixels, dtype=np.float64)[..., :3]
        return np.stack([np.asarray(ch[c].pixels, dtype=np.float64) for c in "RGB"], -1)

def block_means(img, b):
    h, w, _ = img.shape
    return img[: h // b * b, : w // b * b].reshape(h // b, b, w // b, b, 3).mean(axis=(1, 3))

def lum(x):
    return x.mean(axis=-1)

def crease_blocks(size=256, b=8):
    # The room of the canonical scenes, [-1, 1] x [0, 2] x [-1, 1], from (0, 1, 3.9) looking
    # along -z with 39.3 degrees of vertical field of view: the back wall's four edges and the
    # four edges from its corners to the open front.
    t = math.tan(math.radians(39.3) / 2)
    def px(p):
        x, y, z = p[0], p[1] - 1.0, p[2] - 3.9
        return (size / 2 * (1 + x / (-z) / t), size / 2 * (1 - y / (-z) / t))
    back = [(-1, 0, -1), (1, 0, -1), (1, 2, -1), (-1, 2, -1)]
    segs = [(back[i], back[(i + 1) % 4]) for i in range(4)] + [(c, (c[0], c[1], 1)) for c in back]
    keep = set()
    for a, c in segs:
        for k in range(2001):
            s = k / 2000
            p = [a[i] + s * (c[i] - a[i]) for i in range(3)]
            u, v = px(p)
            if 0 <= u < size and 0 <= v < size:
                keep.add((int(v) // b, int(u) // b))
    return sorted(keep)

cmd = sys.argv[1]
if cmd == "corners":
    # corners REF OLD NEW: crease blocks (8x8) of OLD and NEW over REF, and NEW over OLD.
    ref, old, new = (block_means(read(p), 8) for p in sys.argv[2:5])
    cb = crease_blocks()
    r = np.array([lum(ref[i, j]) for i, j in cb])
    o = np.array([lum(old[i, j]) for i, j in cb]) / r
    n = np.array([lum(new[i, j]) for i, j in cb]) / r
    print(f"{len(cb)} crease blocks: mean |ratio - 1| old {np.abs(o - 1).mean():.4f} new {np.abs(n - 1).mean():.4f};"
          f" mean ratio old {o.mean():.4f} new {n.mean():.4f}; new/old {np.mean(n / o):.4f}"
          f" (min {np.min(n / o):.4f}, max {np.max(n / o):.4f})")
elif cmd == "veach":
    # veach REF OLD NEW LAMP_X,LAMP_Y: 32x32 blocks over REF.
    ref_img = read(sys.argv[2])
    lx, ly = (int(v) for v in sys.argv[5].split(","))
    lamp = (ly // 32, lx // 32)
    rb = lum(block_means(ref_img, 32))
    for name, path in (("old", sys.argv[3]), ("new", sys.argv[4])):
        img = read(path)
        ratio = lum(block_means(img, 32)) / rb
        other = [(abs(ratio[i, j] - 1), i, j) for i in range(ratio.shape[0]) for j in range(ratio.shape[1]) if (i, j) != lamp]
        other.sort(reverse=True)
        worst = ", ".join(f"({j},{i}) {ratio[i, j]:.3f}" for _, i, j in other[:3])
        means = img.reshape(-1, 3).mean(0) / ref_img.reshape(-1, 3).mean(0)
        print(f"{name}: lamp block ({lamp[1]},{lamp[0]}) {ratio[lamp]:.3f}; furthest other blocks (x,y) {worst};"
              f" channel means {means[0]:.4f} {means[1]:.4f} {means[2]:.4f}")
        np.savetxt(path + ".blocks32.txt", ratio, fmt="%.3f")
    if len(sys.argv) > 6:
        # Same seed and pass count: new over old, block by block (only the skipped photons differ).
        ro = lum(block_means(read(sys.argv[3]), 32))
        rn = lum(block_means(read(sys.argv[4]), 32))
        q = rn / ro
        other = max((abs(q[i, j] - 1), i, j) for i in range(q.shape[0]) for j in range(q.shape[1]) if (i, j) != lamp)
        print(f"new/old: lamp block {q[lamp]:.3f}; furthest other block ({other[2]},{other[1]}) {q[other[1], other[2]]:.3f}")
elif cmd == "shells":
    # shells IMAGE...: mean, pixels not black, brightest.
    for path in sys.argv[2:]:
        img = read(path)
        print(f"{path}: mean {img.mean():.3g}, {int((img.max(-1) > 0).sum())} of {img.shape[0] * img.shape[1]} pixels lit, brightest {img.max():.3g}")
EOF
}

say "# 0. tests/scenes/thin-shells.toml: a box and a globe lit from inside, seen from outside"
for b in old new; do
    bin=$old
    [ $b = new ] && bin=$new
    say "$b: $("$bin" tests/scenes/thin-shells.toml -o "$out/$b/thin-shells.exr" 2>&1 | grep -E " in [0-9.]+ s" | tail -1)"
done
blocks shells "$out/old/thin-shells.exr" "$out/new/thin-shells.exr" | tee -a "$report"

say "# 1. canonical scenes against tests/references (diff --downsample 8)"
canon="cornell-box cornell-spheres cornell-glossy point-light textured"
for s in $canon; do
    for seed in $seeds; do
        for b in old new; do
            bin=$old
            [ $b = new ] && bin=$new
            line=$("$bin" "scenes/$s.toml" -o "$out/$b/$s-$seed.exr" --seed "$seed" 2>&1 | grep -E " in [0-9.]+ s" | tail -1)
            d=$("$new" diff "$out/$b/$s-$seed.exr" "tests/references/$s.exr" --downsample 8)
            say "$s seed $seed $b: $d   [$line]"
        done
    done
done

say "# 2. corners: 8x8 blocks crossed by the room's creases, over the reference"
for s in $canon; do
    for seed in $seeds; do
        say "$s seed $seed: $(blocks corners "tests/references/$s.exr" "$out/old/$s-$seed.exr" "$out/new/$s-$seed.exr")"
    done
done

say "# 3. veach-bidir, 256x256, $limit s"
for b in old new; do
    bin=$old
    [ $b = new ] && bin=$new
    line=$("$bin" "$xml" -o "$out/$b/veach-bidir.exr" --width 256 --height 256 --time-limit "$limit" --iterations 100000 2>&1 \
        | grep -E " in [0-9.]+ s" | tail -1)
    say "$b: $line"
done
blocks veach "$ref" "$out/old/veach-bidir.exr" "$out/new/veach-bidir.exr" "$lamp" | tee -a "$report"
say "# 3b. veach-bidir, 256x256, $passes passes each (same seed: the same camera paths and photons)"
for b in old new; do
    bin=$old
    [ $b = new ] && bin=$new
    line=$("$bin" "$xml" -o "$out/$b/veach-bidir-$passes.exr" --width 256 --height 256 --iterations "$passes" 2>&1 \
        | grep -E " in [0-9.]+ s" | tail -1)
    say "$b: $line"
done
blocks veach "$ref" "$out/old/veach-bidir-$passes.exr" "$out/new/veach-bidir-$passes.exr" "$lamp" paired | tee -a "$report"

say "# 4. equal time: cornell-box at --time-limit 20, old and new alternating, $rounds rounds"
for round in $(seq "$rounds"); do
    for b in old new; do
        bin=$old
        [ $b = new ] && bin=$new
        line=$("$bin" scenes/cornell-box.toml -o "$out/$b/cornell-box-20s.exr" --time-limit 20 --iterations 100000 2>&1 \
            | grep -E " in [0-9.]+ s" | tail -1 | cut -d'(' -f1)
        say "round $round $b: $line; $("$new" diff "$out/$b/cornell-box-20s.exr" tests/references/cornell-box.exr --downsample 8)"
    done
done

say "# 5. cargo test --release --test suite sppm::thin_shell"
cargo test --release --test suite sppm::thin_shell 2>&1 | grep -E "^test |test result" | tee -a "$report"
