#!/usr/bin/env bash
# vcm's pilot cost model (src/integrators/shares.rs, CostModel): each candidate pair of shares'
# pass time and counts of work at 256x256 (the pilot at the render's size through the
# SPPM_GPU_PILOT_LOG and SPPM_GPU_PILOT_SIDE hooks), on the canonical scenes and any scene
# files given. For each scene: each candidate's median pass time (its first two passes left
# out) and counts, the split of the time into a base, connections and merging (base = t(0,1)
# + t(1,0) - t(1,1)), the seconds per connection and per merge candidate, and the ratio of the
# candidates' times beside the model's.
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
    SPPM_GPU_PILOT_LOG=1 SPPM_GPU_PILOT_SIDE=256 "$bin" "$scene" --method vcm --width 256 --height 256 \
        --time-limit 0.1 -o "$out/image.exr" 2>&1 | grep -E "^pilot (pass|candidate)" > "$out/log.txt"
    python3 - "$scene" "$out/log.txt" <<'PY'
import re, statistics, sys
scene, log = sys.argv[1], sys.argv[2]
times, counts, model = {}, {}, {}
for line in open(log):
    f = line.split(maxsplit=4)
    if f[1] == 'candidate':
        model[len(model)] = float(line.split()[5])
    else:
        k = int(f[2])
        times.setdefault(k, []).append(float(f[3]))
        counts.setdefault(k, []).append([int(x) for x in re.findall(r'\d+', f[4])])
t = {k: statistics.median(v[2:]) for k, v in times.items()}
c = {k: [statistics.mean(x) for x in zip(*v)] for k, v in counts.items()}
base, connect, merge = t[1] + t[2] - t[0], t[0] - t[1], t[0] - t[2]
print(f"{scene}: pass s (1,1) {t[0]:.4f} (0,1) {t[1]:.4f} (1,0) {t[2]:.4f}; base {base:.4f}, connections {connect:.4f}, merging {merge:.4f}")
print(f"  camera vertices {c[0][0]:.0f}, connections {c[0][1]:.0f}, merge candidates {c[0][2]:.0f}; "
      f"s per camera vertex (base) {base / c[0][0]:.2e}, per connection {connect / c[0][1]:.2e}, per merge candidate {merge / c[0][2]:.2e}")
print("  time ratios " + " : ".join(f"{t[k] / t[1]:.2f}" for k in range(3)) + "; model " + " : ".join(f"{model[k] / model[1]:.2f}" for k in range(3)))
PY
done
rm -rf "$out"
