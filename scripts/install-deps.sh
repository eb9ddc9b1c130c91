#!/usr/bin/env bash
# Install what sppm-gpu needs on Debian or Ubuntu: Mesa's software Vulkan driver (lavapipe),
# which also serves machines without a GPU, when no Vulkan driver is present; and for
# `sppm-gpu view`, its test (tests/suite/view.rs) and scripts/regen/view-screenshot.sh, the X libraries
# winit loads at run time, Xvfb, xdotool and xwd (x11-apps); for the Python package, python3
# and python3-venv. Installs only what is missing,
# with one `apt-get update`; does nothing when all of it is present.
#
# On Debian 12 (bookworm) lavapipe comes from bookworm-backports (Mesa 25) rather than from
# bookworm itself (Mesa 22.3): Mesa 25 loads storage buffers at per-invocation addresses with
# vector gathers where 22.3 loads them one lane at a time, and runs the SPPM kernels 2.6x
# faster (BENCHMARKS.md). It upgrades a dozen Mesa and libdrm packages. Set
# SPPM_DEBIAN_MESA=1 to install Debian's own instead; the renderer works with both, and the
# script falls back to Debian's own when backports cannot be reached.
set -euo pipefail

# Whether the Debian package $1 is installed.
installed() { [ "$(dpkg-query -W -f='${Status}' "$1" 2>/dev/null)" = "install ok installed" ]; }

need_vulkan=1
if ls /usr/share/vulkan/icd.d/*.json >/dev/null 2>&1 && ldconfig -p | grep libvulkan.so.1 >/dev/null; then
    need_vulkan=0
fi
# The view: the X libraries winit opens (dlopen) at run time, then the test's tools.
view=()
for package in libx11-6 libx11-xcb1 libxcursor1 libxi6 libxrandr2 libxkbcommon-x11-0; do
    installed "$package" || view+=("$package")
done
command -v Xvfb >/dev/null || view+=(xvfb)
command -v xdotool >/dev/null || view+=(xdotool)
command -v xwd >/dev/null || view+=(x11-apps)
# The Python package (scripts/python-package.sh): python3 with venv and pip (Debian's python3
# has neither without python3-venv).
python3 -c 'import venv, ensurepip' >/dev/null 2>&1 || view+=(python3 python3-venv)
if [ "$need_vulkan" = 0 ] && [ ${#view[@]} = 0 ]; then
    exit 0
fi

SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
install=(env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends)
codename="$(. /etc/os-release 2>/dev/null; echo "${VERSION_CODENAME:-}")" || codename=""
has_backports() { grep -rqs "bookworm-backports" /etc/apt/sources.list /etc/apt/sources.list.d/; }
echo "install-deps: installing$([ "$need_vulkan" = 1 ] && echo " mesa-vulkan-drivers") ${view[*]}" >&2

if [ "$need_vulkan" = 1 ]; then
    # The view's packages go in the same transaction, so that the Mesa GL packages Xvfb pulls
    # in come from the same release as the Vulkan driver.
    if [ "$codename" = bookworm ] && [ "${SPPM_DEBIAN_MESA:-0}" != 1 ]; then
        list=/etc/apt/sources.list.d/bookworm-backports.list
        added=0
        if ! has_backports; then
            echo "deb http://deb.debian.org/debian bookworm-backports main" | $SUDO tee "$list" >/dev/null
            added=1
        fi
        if $SUDO apt-get update -qq && $SUDO "${install[@]}" -t bookworm-backports mesa-vulkan-drivers "${view[@]}"; then
            exit 0
        fi
        echo "install-deps: bookworm-backports failed; installing Debian's own mesa-vulkan-drivers" >&2
        if [ "$added" = 1 ]; then $SUDO rm -f "$list"; fi
    fi
    $SUDO apt-get update -qq
    $SUDO "${install[@]}" mesa-vulkan-drivers "${view[@]}"
    exit 0
fi

# A Vulkan driver is there. When it is Mesa from bookworm-backports, take Xvfb's Mesa GL
# packages from there too, to match it.
target=()
mesa="$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null)" || mesa=""
if [ "$codename" = bookworm ] && [[ "$mesa" == *bpo* ]] && has_backports; then
    target=(-t bookworm-backports)
fi
$SUDO apt-get update -qq
$SUDO "${install[@]}" "${target[@]}" "${view[@]}"
