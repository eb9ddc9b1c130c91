#!/usr/bin/env bash
# A screenshot of `sppm-gpu view` for the docs: runs the view in Xvfb on a free display, waits
# for its title to say it has paused, captures its window with xwd and writes it as a PNG.
#
#   scripts/regen/view-screenshot.sh SCENE [VIEW OPTIONS] [-o OUT.png]
#   scripts/regen/view-screenshot.sh scenes/cornell-box.toml --passes-then-pause 8 -o docs/view.png
#
# Every option but -o (default docs/view.png) goes to `sppm-gpu view`; without
# --passes-then-pause it gets --passes-then-pause 8, so that the view pauses. Needs
# `cargo build --release` first, and Xvfb, xdotool and xwd (scripts/install-deps.sh).
# SPPM_VIEW_TIMEOUT: seconds to wait for the pause (default 300: kernels compile on first use);
# SPPM_XVFB_SCREEN: Xvfb's screen (default 2560x1600x24); SPPM_GPU: another binary.
set -euo pipefail
cd "$(dirname "$0")/../.."
binary="${SPPM_GPU:-target/release/sppm-gpu}"
timeout="${SPPM_VIEW_TIMEOUT:-300}"

# Take -o for ourselves; pass the rest on.
out=docs/view.png
args=()
while [ $# -gt 0 ]; do
    case "$1" in
        -o | --output)
            [ $# -ge 2 ] || { echo "view-screenshot: $1 needs a path" >&2; exit 2; }
            out="$2"
            shift 2
            ;;
        *)
            args+=("$1")
            shift
            ;;
    esac
done
if [ ${#args[@]} = 0 ]; then
    echo "usage: $0 SCENE [VIEW OPTIONS] [-o OUT.png]" >&2
    exit 2
fi
if [[ " ${args[*]} " != *" --passes-then-pause"* ]]; then args+=(--passes-then-pause 8); fi
[ -x "$binary" ] || { echo "view-screenshot: no $binary: run cargo build --release" >&2; exit 1; }
for tool in Xvfb xdotool xwd python3; do
    command -v "$tool" >/dev/null || { echo "view-screenshot: no $tool: run scripts/install-deps.sh" >&2; exit 1; }
done

work="$(mktemp -d)"
xvfb_pid=""
view_pid=""
# Stop the view and Xvfb (SIGTERM, so that Xvfb removes its lock and socket) however we exit.
cleanup() {
    if [ -n "$view_pid" ] && kill -0 "$view_pid" 2>/dev/null; then kill "$view_pid" 2>/dev/null || true; fi
    if [ -n "$xvfb_pid" ]; then
        kill "$xvfb_pid" 2>/dev/null || true
        wait "$xvfb_pid" 2>/dev/null || true
    fi
    rm -rf "$work"
}
trap cleanup EXIT
fail() {
    echo "view-screenshot: $*" >&2
    if [ -s "$work/view.log" ]; then sed 's/^/  view: /' "$work/view.log" >&2; fi
    exit 1
}

# Xvfb on the first free display from :91, large enough for the window.
display=""
for n in $(seq 91 199); do
    if [ -e "/tmp/.X11-unix/X$n" ] || [ -e "/tmp/.X$n-lock" ]; then continue; fi
    Xvfb ":$n" -screen 0 "${SPPM_XVFB_SCREEN:-2560x1600x24}" -nolisten tcp -noreset 2>"$work/xvfb.log" &
    xvfb_pid=$!
    for _ in $(seq 100); do
        if [ -e "/tmp/.X11-unix/X$n" ]; then display=":$n"; break 2; fi
        kill -0 "$xvfb_pid" 2>/dev/null || break
        sleep 0.1
    done
    # Another server took :n, or it did not start: try the next.
    kill "$xvfb_pid" 2>/dev/null || true
    wait "$xvfb_pid" 2>/dev/null || true
    xvfb_pid=""
done
[ -n "$display" ] || fail "could not start Xvfb on :91 to :199: $(cat "$work/xvfb.log")"
export DISPLAY="$display"
unset WAYLAND_DISPLAY

"$binary" view "${args[@]}" >"$work/view.log" 2>&1 &
view_pid=$!

# The window, then a title that says paused.
start=$SECONDS
wid=""
title=""
while :; do
    kill -0 "$view_pid" 2>/dev/null || fail "the view exited before pausing"
    [ $((SECONDS - start)) -lt "$timeout" ] || fail "not paused within $timeout s (title: ${title:-no window})"
    if [ -z "$wid" ]; then
        wid="$(xdotool search --onlyvisible --name '^sppm-gpu view: ' 2>/dev/null | head -n 1)" || wid=""
    fi
    if [ -n "$wid" ]; then
        title="$(xdotool getwindowname "$wid" 2>/dev/null)" || title=""
        if [[ "$title" =~ \|\ paused(\ \||$) ]]; then break; fi
    fi
    sleep 0.2
done
echo "view-screenshot: $title" >&2
# Let the last frame reach the window.
sleep 1
xwd -silent -nobdrs -id "$wid" -out "$work/view.xwd" || fail "xwd could not capture window $wid"

mkdir -p "$(dirname "$out")"
python3 - "$work/view.xwd" "$out" <<'EOF'
"""Converts an XWD file (24- or 32-bit ZPixmap, TrueColor) to an RGB PNG; standard library only."""
import struct
import sys
import zlib

source, target = sys.argv[1], sys.argv[2]
data = open(source, "rb").read()
# The header: 25 big-endian 32-bit fields, then the window's name.
(header_size, version, pixmap_format, depth, width, height, _xoffset, byte_order, _unit, _bit_order, _pad,
 bits_per_pixel, bytes_per_line, visual_class, red_mask, green_mask, blue_mask, _bits_per_rgb, _entries,
 ncolors, *_window) = struct.unpack(">25I", data[:100])
if version != 7 or pixmap_format != 2:
    sys.exit(f"{source}: not an XWD version 7 ZPixmap (version {version}, format {pixmap_format})")
if bits_per_pixel not in (24, 32) or visual_class not in (4, 5):
    sys.exit(f"{source}: {bits_per_pixel} bits a pixel, visual class {visual_class}: only 24/32-bit TrueColor")
pixel_bytes = bits_per_pixel // 8
# Pixels follow the name and the colour map (12 bytes an entry).
pixels = data[header_size + 12 * ncolors:]
if len(pixels) < bytes_per_line * height:
    sys.exit(f"{source}: {len(pixels)} bytes of pixels, expected {bytes_per_line * height}")


def byte_of(mask):
    """The byte of a pixel that holds a channel of mask `mask` (8 bits, byte-aligned)."""
    shift = (mask & -mask).bit_length() - 1
    if mask >> shift != 0xFF or shift % 8:
        sys.exit(f"{source}: channel mask {mask:#x} is not one byte")
    # byte_order 0 is least significant byte first.
    return shift // 8 if byte_order == 0 else pixel_bytes - 1 - shift // 8


channels = [byte_of(m) for m in (red_mask, green_mask, blue_mask)]
rows = []
for y in range(height):
    row = pixels[y * bytes_per_line:y * bytes_per_line + width * pixel_bytes]
    rgb = bytearray(3 * width)
    for i, at in enumerate(channels):
        rgb[i::3] = row[at::pixel_bytes]
    rows.append(b"\0" + bytes(rgb))  # filter type 0 (none)


def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)


png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
png += chunk(b"IDAT", zlib.compress(b"".join(rows), 9)) + chunk(b"IEND", b"")
open(target, "wb").write(png)
print(f"wrote {target} ({width}x{height}, from a {depth}-bit XWD)")
EOF

# Quit as a user would: focus the window (there is no window manager), then q.
timeout 10 xdotool windowfocus --sync "$wid" && xdotool key q || true
for _ in $(seq 200); do
    kill -0 "$view_pid" 2>/dev/null || break
    sleep 0.1
done
if kill -0 "$view_pid" 2>/dev/null; then
    echo "view-screenshot: the view did not exit within 20 s of q; killing it" >&2
else
    wait "$view_pid" || fail "the view exited with status $? after q"
    grep '^frames:' "$work/view.log" >&2 || true
fi
