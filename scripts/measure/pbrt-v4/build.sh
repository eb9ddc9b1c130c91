#!/bin/bash
# Builds pbrt-v4 (CPU only) from nothing under $OUT (default /tmp/pbrt-build), for references
# of pbrt-v4 scene files (scripts/measure/pbrt-v4-references.sh; BENCHMARKS.md "pbrt-v4 scenes").
# pbrt-v4's pmj02tables.cpp and bluenoise.cpp (pure data, 16 MB) are not in its mirror:
# tools/gen_missing_tables.cpp writes stand-ins (scrambled Sobol points for the pmj02bn
# sampler, white noise for blue noise), so references avoid `Sampler "pmj02bn"`.
# Prerequisites (not doable from a shell script): the bare git mirrors below must
# exist; they were obtained with the session's `fetch` tool ("github:owner/name").
set -euo pipefail
# Usage: ./build.sh            (full: apt, extract, patch, build into /tmp/pbrt-build)
#        SKIP_APT=1 ./build.sh  (packages already installed)
#        OUT=/some/dir ./build.sh  (put src/ and build/ there; tools/ and
#                                   patches/ are always taken from this script's dir)
HERE=$(cd "$(dirname "$0")" && pwd)
B=${OUT:-/tmp/pbrt-build}
MIR=/work/.mirror
JOBS=${JOBS:-2}
mkdir -p "$B/tools"
cd "$B"
T0=$(date +%s)

# 0. the mirrors (from the fetch tool) must be there
for m in mmp+pbrt-v4 wdas+ptex google+double-conversion nothings+stb \
         AcademySoftwareFoundation+openexr wjakob+filesystem AcademySoftwareFoundation+openvdb \
         mmp+libdeflate lvandeve+lodepng JuliaStrings+utf8proc phoboslab+qoi glfw+glfw madler+zlib; do
  [ -d "$MIR/$m/repo" ] || { echo "missing mirror $MIR/$m/repo: fetch github:${m/+//} first" >&2; exit 1; }
done

# 1. Debian packages
if [ "${SKIP_APT:-0}" != 1 ]; then
  SUDO=; [ "$(id -u)" = 0 ] || SUDO=sudo
  $SUDO apt-get update -qq
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
    build-essential git cmake pkg-config zlib1g-dev libopenexr-dev libimath-dev \
    libgl-dev libx11-dev libxrandr-dev libxinerama-dev libxcursor-dev libxi-dev
fi

# extract REPO COMMIT DEST [PATH...]: write the tree of COMMIT into DEST.
# Uses git archive; if a blob is missing from the mirror, falls back to a
# per-file copy that skips (and reports) missing blobs.
extract() {
  local G=$1 C=$2 D=$3; shift 3
  mkdir -p "$D"
  if ! (git --git-dir="$G" archive "$C" -- "$@" | tar -x -C "$D") 2>/dev/null; then
    echo "git archive failed for $G $C; copying file by file" >&2
    git --git-dir="$G" ls-tree -r "$C" -- "$@" | while read -r m t h p; do
      if [ "$t" = blob ]; then
        mkdir -p "$D/$(dirname "$p")"
        if [ "$m" = 120000 ]; then ln -sf "$(git --git-dir="$G" cat-file blob "$h")" "$D/$p"
        elif git --git-dir="$G" cat-file blob "$h" > "$D/$p" 2>/dev/null; then
          if [ "$m" = 100755 ]; then chmod +x "$D/$p"; fi
        else echo "MISSING BLOB: $p" >&2; rm -f "$D/$p"; fi
      elif [ "$t" = commit ]; then mkdir -p "$D/$p"; fi
    done
    true
  fi
}

# 2. pbrt-v4 source
PG=$MIR/mmp+pbrt-v4/repo
PC=$(git --git-dir=$PG rev-parse HEAD)
rm -rf src && mkdir src
extract $PG $PC src

# 3. submodules at the commits pinned by pbrt-v4 (zlib: snapshot HEAD, unused —
#    the system zlib is found first; openexr: extracted only for the directory
#    check — the system OpenEXR 3.1.5 is found first and used)
pin() { git --git-dir=$PG ls-tree $PC src/ext/$1 | awk '{print $3}'; }
sub() { # name mirror [paths]
  local n=$1 m=$2; shift 2
  local c; c=$(pin $n)
  if ! git --git-dir=$MIR/$m/repo cat-file -e "$c^{commit}" 2>/dev/null; then
    echo "pinned commit $c of $n not in $m; using its HEAD" >&2; c=HEAD; fi
  extract $MIR/$m/repo $c src/src/ext/$n "$@"
}
sub ptex wdas+ptex
sub double-conversion google+double-conversion
sub stb nothings+stb
sub openexr AcademySoftwareFoundation+openexr
sub filesystem wjakob+filesystem
sub openvdb AcademySoftwareFoundation+openvdb nanovdb
sub libdeflate mmp+libdeflate
sub lodepng lvandeve+lodepng
sub utf8proc JuliaStrings+utf8proc
sub qoi phoboslab+qoi
sub glfw glfw+glfw
sub zlib madler+zlib

# 4. missing generated tables (blobs absent from the mirror) -> substitutes
nice -n 19 g++ -O2 -o tools/gen_missing_tables "$HERE/tools/gen_missing_tables.cpp"
tools/gen_missing_tables src/src/pbrt/util/pmj02tables.cpp src/src/pbrt/util/bluenoise.cpp

[ "${STOP_AFTER_SRC:-0}" = 1 ] && exit 0

# 5. patches
for p in "$HERE"/patches/*.diff; do patch -p1 -d src < "$p"; done

# 6. configure + build
rm -rf build && mkdir build && cd build
nice -n 19 cmake ../src -DCMAKE_BUILD_TYPE=Release -DGLFW_BUILD_WAYLAND=OFF -DGLFW_BUILD_X11=ON -DBUILD_TESTING=OFF
nice -n 19 make -j$JOBS pbrt_exe imgtool
ls -la pbrt imgtool
echo "build.sh finished in $(( $(date +%s) - T0 )) s; binary: $B/build/pbrt"
