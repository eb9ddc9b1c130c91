#!/usr/bin/env bash
# Install what sppm-gpu needs on Debian or Ubuntu: Mesa's software Vulkan driver (lavapipe),
# which also serves machines without a GPU. Does nothing when a Vulkan driver is present.
#
# On Debian 12 (bookworm) lavapipe comes from bookworm-backports (Mesa 25) rather than from
# bookworm itself (Mesa 22.3): Mesa 25 loads storage buffers at per-invocation addresses with
# vector gathers where 22.3 loads them one lane at a time, and runs the SPPM kernels 2.6x
# faster (BENCHMARKS.md). It upgrades a dozen Mesa and libdrm packages. Set
# SPPM_DEBIAN_MESA=1 to install Debian's own instead; the renderer works with both, and the
# script falls back to Debian's own when backports cannot be reached.
set -euo pipefail
if ls /usr/share/vulkan/icd.d/*.json >/dev/null 2>&1 && ldconfig -p | grep -q libvulkan.so.1; then
    exit 0
fi
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
install=(env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends)
codename="$(. /etc/os-release 2>/dev/null; echo "${VERSION_CODENAME:-}")" || codename=""
if [ "$codename" = bookworm ] && [ "${SPPM_DEBIAN_MESA:-0}" != 1 ]; then
    list=/etc/apt/sources.list.d/bookworm-backports.list
    added=0
    if ! grep -rqs "bookworm-backports" /etc/apt/sources.list /etc/apt/sources.list.d/; then
        echo "deb http://deb.debian.org/debian bookworm-backports main" | $SUDO tee "$list" >/dev/null
        added=1
    fi
    if $SUDO apt-get update -qq && $SUDO "${install[@]}" -t bookworm-backports mesa-vulkan-drivers; then
        exit 0
    fi
    echo "install-deps: bookworm-backports failed; installing Debian's own mesa-vulkan-drivers" >&2
    if [ "$added" = 1 ]; then $SUDO rm -f "$list"; fi
fi
$SUDO apt-get update -qq
$SUDO "${install[@]}" mesa-vulkan-drivers
