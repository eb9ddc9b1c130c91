#!/usr/bin/env bash
# Feeds BENCHMARKS.md "The material previews converge to Mitsuba's references (issue 25)" (docs/journal/session-14.md).
# Inputs: BINARY and DEST (previews staged by public-scenes.sh, their ref.exr).
# Convergence on Mitsuba's material previews (issue 25): relMSE against each preview's
# reference (DEST/NAME/ref.exr, Mitsuba `path`) after growing numbers of sppm passes and
# pt-nee samples, in 6x6 blocks (the previews are 240x180, which 8 does not divide; 6x6 gives
# 40x30 = 1,200 blocks, about the canonical scenes' 32x32 in 8x8 blocks, and a smaller block
# keeps more noise, so the figure is the stricter one). Noise falls as 1/N and bias does not:
# a figure that stops falling before the reference's own noise floor is a bias.
#
#   bash scripts/measure/matpreview-convergence.sh BINARY [DEST [NAME ...]]
#
# SNAPS_SPPM and SNAPS_PT (comma-separated pass counts) replace the default snapshots.
# Writes DEST/NAME/conv-{sppm,ptnee}/ (`sppm-gpu passes`: passes.csv and the snapshots).
set -euo pipefail
bin=$(realpath "${1:?usage: matpreview-convergence.sh BINARY [DEST [NAME ...]]}")
dest=${2:-/work/public-scenes}
shift $(($# < 2 ? $# : 2))
names=("$@")
[ ${#names[@]} -gt 0 ] || names=(matpreview-diffuse_plain matpreview-roughconductor_copper matpreview-dielectric_glass)
cd "$dest"
for n in "${names[@]}"; do
    # The previews at their references' size; Mitsuba's scenes/matpreview (256x192) in 8x8
    # blocks, as the canonical scenes.
    case $n in
        mitsuba-matpreview) s=$n/scenes/matpreview/matpreview.xml size=(256 192) blocks=8 ;;
        mitsuba-ply-bunny) s=$n/docs/scenes/shape_ply_bunny.xml size=(240 180) blocks=6 ;;
        *) s=$n/docs/scenes/bsdf_${n#matpreview-}.xml size=(240 180) blocks=6 ;;
    esac
    for m in sppm pt-nee; do
        snaps=${SNAPS_SPPM:-16,32,64,128,256}
        [ "$m" = pt-nee ] && snaps=${SNAPS_PT:-64,128,256,512}
        echo "== $n $m, load $(cut -d' ' -f1-3 /proc/loadavg), $(date +%T)"
        "$bin" passes "$s" --method "$m" --width "${size[0]}" --height "${size[1]}" --snapshots "$snaps" \
            --reference "$n/ref.exr" --downsample "$blocks" --out "$n/conv-${m/-/}" 2>&1 | grep -vE 'clip|gamma|warning' | tail -8
    done
done
