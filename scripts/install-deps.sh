#!/usr/bin/env bash
# Install what sppm-gpu needs on Debian or Ubuntu: Mesa's software Vulkan driver (lavapipe),
# which also serves machines without a GPU. Does nothing when a Vulkan driver is present.
set -euo pipefail
if ls /usr/share/vulkan/icd.d/*.json >/dev/null 2>&1 && ldconfig -p | grep -q libvulkan.so.1; then
    exit 0
fi
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends mesa-vulkan-drivers
