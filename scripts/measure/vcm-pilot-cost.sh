#!/usr/bin/env bash
# vcm's pilot cost model (src/integrators/shares.rs, CostModel): each candidate's pass time and
# counts of work at 256x256 (the pilot at the render's size, every candidate on every scene,
# through the SPPM_GPU_PILOT_LOG, SPPM_GPU_PILOT_SIDE and SPPM_GPU_PILOT_ALL hooks), on the
# canonical scenes and any scene files given. For each
# scene: each candidate's median pass time (its first two passes left out) and counts; then,
# for the scenes traced by code and for those traced through a BVH, the least-squares fit of a
# pass's time as s (camera vertices (1 + e where the pass merges) + a connections + b merge
# candidates + c light vertices + d pixels where light subpaths are traced), a scale s for
# each scene and a, b, e shared (the model's figures; c held at the model's, which a free fit
# drives below 0 as the light vertices and the candidates grow together; d, the splat pass's
# cost a pixel, is CostModel's, measured apart: the candidate without light subpaths with and
# without that pass), and each pass time's error under the fit. The canonical scenes and box.xml are traced by code (at most 256
# primitives, gpu::baked_bvh); scenes given are taken as traced through a BVH.
#
#   bash scripts/measure/vcm-pilot-cost.sh [BIN] [SCENE...]
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=${1:-target/release/sppm-gpu}
shift || true
scenes=(scenes/cornell-box.toml scenes/cornell-glossy.toml scenes/cornell-spheres.toml scenes/cornell-skylight.toml
    scenes/mitsuba/box.xml scenes/gallery/bunny-cube.toml "$@")
out=$(mktemp -d)
for scene in "${scenes[@]}"; do
    log="$out/$(printf '%02d' "$(ls "$out" | wc -l)").log"
    {
        echo "scene $scene"
        SPPM_GPU_PILOT_LOG=1 SPPM_GPU_PILOT_SIDE=256 SPPM_GPU_PILOT_ALL=1 "$bin" "$scene" --method vcm --width 256 --height 256 \
            --time-limit 0.1 -o "$out/image.exr" 2>&1 | grep -E "^pilot (pass|candidate)" || true
    } > "$log"
    rm -f "$out/image.exr"
done
python3 - "$out" <<'PY'
import glob, re, statistics, sys
import numpy as np
scenes = []
for log in sorted(glob.glob(sys.argv[1] + '/*.log')):
    lines = open(log).read().splitlines()
    name = lines[0].split(maxsplit=1)[1]
    times, counts, labels = {}, {}, []
    for line in lines[1:]:
        f = line.split(maxsplit=4)
        if line.startswith('pilot candidate'):
            labels.append(f[2])
        elif line.startswith('pilot pass'):
            k = int(f[2])
            times.setdefault(k, []).append(float(f[3]))
            counts.setdefault(k, []).append([int(x) for x in re.findall(r'\d+', f[4])])
    t = np.array([statistics.median(times[k][2:]) for k in sorted(times)])
    c = np.array([[statistics.mean(x) for x in zip(*counts[k])] for k in sorted(counts)])
    print(f"{name}:")
    for k, label in enumerate(labels):
        print(f"  {label:5s} {t[k] * 1e3:7.2f} ms  camera vertices {c[k][0]:8.0f} connections {c[k][1]:8.0f} "
              f"merge candidates {c[k][2]:9.0f} light vertices {c[k][3]:7.0f}")
    scenes.append((name, labels, t, c))
PIXELS = 256 * 256
def fit(group, title, splat_pixel, light_vertex, alone):
    if not group:
        return
    # Per candidate: the part of fixed figures (camera vertices, with the splat pass's cost a
    # pixel where light subpaths are traced and each light vertex's, or without light subpaths
    # the kernel's `alone` figure), then connections, merge candidates, and camera vertices
    # again where the pass merges (their lookups).
    def design(labels, c):
        rows = []
        for label, (cam, conn, cand, lv) in zip(labels, c):
            if label == 'none':
                rows.append([alone * cam, 0, 0, 0])
            else:
                rows.append([cam + splat_pixel * PIXELS * (lv > 0) + light_vertex * lv, conn, cand, cam * (cand > 0)])
        return np.array(rows)
    d = {n: design(labels, c) for n, labels, t, c in group}
    scale = {n: np.median(t / d[n][:, 0]) for n, labels, t, c in group}
    for _ in range(100):
        a = np.vstack([d[n][:, 1:] for n, *_ in group])
        b = np.concatenate([t / scale[n] - d[n][:, 0] for n, labels, t, c in group])
        w = np.concatenate([scale[n] / t for n, labels, t, c in group])
        r, *_ = np.linalg.lstsq(a * w[:, None], b * w, rcond=None)
        for n, labels, t, c in group:
            u = d[n][:, 0] + d[n][:, 1:] @ r
            scale[n] = np.sum(u / t) / np.sum(u * u / t ** 2)
    print(f"{title}: a connection {r[0]:.3f}, a merge candidate {r[1]:.3f}, a merging camera vertex {r[2]:.3f} "
          f"camera vertices besides (a light vertex held at {light_vertex})")
    for n, labels, t, c in group:
        u = scale[n] * (d[n][:, 0] + d[n][:, 1:] @ r)
        print(f"  {n}: {scale[n]:.2e} s a camera vertex; error " + " ".join(f"{l} {(p / q - 1) * 100:+.0f}%" for l, p, q in zip(labels, u, t)))
baked = [s for s in scenes if s[0].startswith('scenes/cornell') or s[0] == 'scenes/mitsuba/box.xml']
fit(baked, "traced by code", 0.14, 0.29, 0.89)
fit([s for s in scenes if s not in baked], "traced through a BVH", 0.04, 1.04, 0.91)
PY
rm -rf "$out"
