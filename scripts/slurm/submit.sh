#!/usr/bin/env bash
# Submit an sppm-gpu render split into BATCHES batches on Slurm: a job array that renders one
# batch per task (render-batch.sbatch), then a merge job (merge.sbatch) that runs once every task
# succeeded. Prints the two job ids (`render_job=ID`, `merge_job=ID`).
#
# Usage: submit.sh SCENE PASSES BATCHES OUT_DIR OUTPUT [extra render options...]
#   e.g. submit.sh scenes/cornell-box.toml 64 8 /shared/run1 /shared/run1/image.exr --width 1024 --height 1024
#
# It wraps the two commands a cluster user would type (paths on a filesystem every node sees):
#   jid=$(sbatch --parsable --array=0-7 \
#       --export=ALL,SCENE=/shared/scene.toml,PASSES=64,OUT_DIR=/shared/run1,EXTRA="--width 1024" \
#       render-batch.sbatch)
#   sbatch --parsable --dependency=afterok:$jid --kill-on-invalid-dep=yes \
#       --export=ALL,OUT_DIR=/shared/run1,OUTPUT=/shared/run1/image.exr,BATCHES=8,PASSES=64 merge.sbatch
# (This script puts the variables in sbatch's environment and passes --export=ALL, which is the
# same without --export's trouble with commas in values.)
#
# Environment:
#   SPPM_GPU            the sppm-gpu binary on the nodes (default: sppm-gpu on their PATH)
#   SPPM_ADAPTER        force one adapter for every task (see render-batch.sbatch)
#   RENDER_SBATCH_OPTS  extra sbatch options for the array, split at spaces,
#                       e.g. "--gres=gpu:1 --partition=gpu --time=02:00:00"
#   MERGE_SBATCH_OPTS   extra sbatch options for the merge job
#   ARRAY_LIMIT         run at most this many tasks at once (sbatch --array=0-7%ARRAY_LIMIT)
# Logs: OUT_DIR/logs/render-JOB_TASK.out and OUT_DIR/logs/merge-JOB.out.
set -euo pipefail

usage() {
    echo "usage: $0 SCENE PASSES BATCHES OUT_DIR OUTPUT [extra render options...]" >&2
    exit 2
}
die() {
    echo "submit: error: $*" >&2
    exit 1
}

(($# >= 5)) || usage
scene="$1" passes="$2" batches="$3" out_dir="$4" output="$5"
shift 5
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

[[ -f "$scene" ]] || die "no scene file $scene"
[[ "$passes" =~ ^[1-9][0-9]*$ ]] || die "PASSES must be a positive integer, not '$passes'"
[[ "$batches" =~ ^[1-9][0-9]*$ ]] || die "BATCHES must be a positive integer, not '$batches'"
((batches <= passes)) || die "more batches ($batches) than passes ($passes)"
for option in "$@"; do
    [[ "$option" != *[[:space:]]* ]] || die "render options can't contain spaces: '$option'"
    case "$option" in
    --passes | --passes=* | --partial | --partial=* | -o | --output | --output=* | --iterations | --iterations=*)
        die "$option is set by the batch scripts; give PASSES instead" ;;
    esac
done

# Absolute paths: the jobs may start in another folder (and on other nodes).
scene="$(realpath -e "$scene")"
out_dir="$(realpath -m "$out_dir")"
output="$(realpath -m "$output")"
if [[ "${SPPM_GPU:-}" == */* ]]; then
    SPPM_GPU="$(realpath -e "$SPPM_GPU")"
    export SPPM_GPU
fi
mkdir -p "$out_dir/logs" # sbatch doesn't create the folders of --output

array="0-$((batches - 1))${ARRAY_LIMIT:+%$ARRAY_LIMIT}"
read -r -a render_opts <<<"${RENDER_SBATCH_OPTS:-}"
read -r -a merge_opts <<<"${MERGE_SBATCH_OPTS:-}"

# --parsable prints "ID" or "ID;CLUSTER".
jid="$(SCENE="$scene" PASSES="$passes" BATCHES="$batches" OUT_DIR="$out_dir" EXTRA="$*" \
    sbatch --parsable --array="$array" --export=ALL \
    --output="$out_dir/logs/render-%A_%a.out" "${render_opts[@]}" "$here/render-batch.sbatch")"
jid="${jid%%;*}"
mid="$(OUT_DIR="$out_dir" OUTPUT="$output" BATCHES="$batches" PASSES="$passes" \
    sbatch --parsable --dependency="afterok:$jid" --kill-on-invalid-dep=yes --export=ALL \
    --output="$out_dir/logs/merge-%j.out" "${merge_opts[@]}" "$here/merge.sbatch")"
mid="${mid%%;*}"
echo "render_job=$jid"
echo "merge_job=$mid"
