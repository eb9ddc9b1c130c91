#!/usr/bin/env bash
# Feeds BENCHMARKS.md "Throughput" (journal: "The 871k dragon on a quiet machine (issue 24)", docs/journal/session-13.md).
# Inputs: the 871k-triangle dragon's OBJ file, as the argument.
# Render the gallery's glass dragon with the 871k-triangle Stanford dragon in place of the
# 11k one, with --stats (GPU memory by buffer): the large-mesh check of BENCHMARKS.md.
# Usage: bash scripts/measure/big-dragon.sh [PATH/TO/dragon_871k.obj] [extra sppm-gpu options]
set -euo pipefail
cd "$(dirname "$0")/../.."
mesh="$(realpath "${1:?usage: big-dragon.sh DRAGON_871K_OBJ (dragon_871k.obj from the shared meshes of the study)}")"
shift || true
dir="$(mktemp -d)"
sed "s#file = \"meshes/dragon_11k.obj\"#file = \"$mesh\"#" scenes/gallery/glass-dragon.toml > "$dir/big-dragon.toml"
grep -q "$mesh" "$dir/big-dragon.toml"
mkdir -p out
cargo build --release --quiet
run=(target/release/sppm-gpu "$dir/big-dragon.toml" -o out/big-dragon.png --width 256 --height 256 --iterations 16 --stats "$@")
if [ -x /usr/bin/time ]; then
    /usr/bin/time -f "%e s wall, %M KB peak host memory" "${run[@]}"
else
    time "${run[@]}"
fi
