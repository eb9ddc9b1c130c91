#!/usr/bin/env bash
# The photon-mapping terms of vcm's pilot cost model (src/integrators/shares.rs, CostModel:
# visible_point_path, photon_hit, photon): the pilot's own passes at its own size (128 pixels on
# the longer side), every candidate on every scene (the SPPM_GPU_PILOT_LOG and
# SPPM_GPU_PILOT_ALL hooks), each scene at three settings so that camera paths, photons and
# their hits vary apart (as set; --direct-samples 1; --photons 100000 --direct-samples 4).
# For each run: the time of a camera vertex on that scene (the median over the other
# candidates of a pass's time over its cost under the model), and photon mapping's median pass
# time (its first two passes left out) in those units; then, for the scenes traced by code and
# for those traced through a BVH, the least-squares fit of it as a camera path's, a hit's and a
# photon's cost, weighted by 1 / time, and each run's error under the fit.
#
#   bash scripts/measure/photon-mapping-cost.sh [BIN]
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=${1:-target/release/sppm-gpu}
baked=(scenes/cornell-box.toml scenes/cornell-glossy.toml scenes/cornell-spheres.toml scenes/cornell-skylight.toml
    scenes/mitsuba/box.xml)
traversed=(scenes/gallery/bunny-cube.toml scenes/gallery/glass-dragon.toml scenes/gallery/flower-pot.toml)
out=$(mktemp -d)
for scene in "${baked[@]}" "${traversed[@]}"; do
    for settings in "" "--direct-samples 1" "--photons 100000 --direct-samples 4"; do
        log="$out/$(printf '%02d' "$(ls "$out" | wc -l)").log"
        group=baked
        [[ " ${traversed[*]} " == *" $scene "* ]] && group=traversed
        {
            echo "$group $scene $settings"
            # shellcheck disable=SC2086
            SPPM_GPU_PILOT_LOG=1 SPPM_GPU_PILOT_ALL=1 "$bin" "$scene" --method vcm --width 256 --height 256 $settings \
                --time-limit 0.1 -o "$out/image.exr" 2>&1 | grep -E "^pilot (pass|candidate|sppm)" || true
        } > "$log"
        rm -f "$out/image.exr"
    done
done
python3 - "$out" <<'PY'
import glob, re, statistics, sys
import numpy as np
runs = []
for log in sorted(glob.glob(sys.argv[1] + '/*.log')):
    lines = open(log).read().splitlines()
    group, name = lines[0].split(maxsplit=2)[:2]
    settings = lines[0].split(maxsplit=2)[2] if len(lines[0].split(maxsplit=2)) > 2 else ''
    times, labels, costs, mapping, work = {}, [], {}, [], None
    for line in lines[1:]:
        f = line.split()
        if line.startswith('pilot candidate'):
            labels.append(f[2])
            costs[f[2]] = float(f[4])
        elif line.startswith('pilot sppm pass'):
            mapping.append(float(f[3]))
            work = [float(x) for x in re.findall(r'[\d.]+', line.split('[', 1)[1])]
        elif line.startswith('pilot pass'):
            times.setdefault(int(f[2]), []).append(float(f[3]))
    others = [l for l in labels if l != 'sppm']
    vertex = statistics.median(statistics.median(times[k][2:]) / costs[l] for k, l in enumerate(others))
    t = statistics.median(mapping[2:])
    runs.append((group, f'{name} {settings}'.strip(), t / vertex, work, t, vertex))
for group in ('baked', 'traversed'):
    rows = [r for r in runs if r[0] == group]
    a = np.array([r[3] for r in rows])
    y = np.array([r[2] for r in rows])
    x, *_ = np.linalg.lstsq(a / y[:, None], np.ones(len(y)), rcond=None)
    print(f"{group}: a camera path {x[0]:.2f}, a photon hit {x[1]:.2f}, a photon {x[2]:.2f} camera vertices")
    for r, p in zip(rows, a @ x):
        print(f"  {r[1]}: pass {r[4] * 1e3:.0f} ms, a camera vertex {r[5] * 1e9:.0f} ns; "
              f"camera paths {r[3][0]:.0f}, hits {r[3][1]:.0f}, photons {r[3][2]:.0f}; error {(p / r[2] - 1) * 100:+.0f}%")
PY
rm -rf "$out"
