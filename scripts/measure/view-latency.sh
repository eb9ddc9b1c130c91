#!/usr/bin/env bash
# Feeds BENCHMARKS.md "Session 6: the preview window (issue 14)" (docs/journal/session-06.md).
# Inputs: the repository's scenes; Xvfb and xdotool (scripts/install-deps.sh).
# Frame rate and input latency of `sppm-gpu view` while it renders (BENCHMARKS.md): runs the
# view in Xvfb, lets it render, sends a camera move every 2 seconds and a method switch with
# xdotool, quits, and prints the view's own `frames:` line.
#
#   bash scripts/measure/view-latency.sh [SCENE] [VIEW OPTIONS]     (default scenes/cornell-box.toml)
#
# Needs `cargo build --release`, Xvfb and xdotool (scripts/install-deps.sh).
set -euo pipefail
cd "$(dirname "$0")/../.."
scene="${1:-scenes/cornell-box.toml}"
shift || true
for tool in Xvfb xdotool; do
    command -v "$tool" >/dev/null || { echo "view-latency: no $tool: run scripts/install-deps.sh" >&2; exit 1; }
done
display=90
while [ -e "/tmp/.X11-unix/X$display" ] || [ -e "/tmp/.X$display-lock" ]; do display=$((display + 1)); done
out="$(mktemp)"
Xvfb ":$display" -screen 0 1024x768x24 -nolisten tcp -noreset >/dev/null 2>&1 &
xvfb=$!
view=""
trap 'kill $view $xvfb 2>/dev/null || true; rm -f "$out"' EXIT
export DISPLAY=":$display"
sleep 1
target/release/sppm-gpu view "$scene" "$@" >"$out" &
view=$!
window="$(timeout 120 xdotool search --sync --name "sppm-gpu view" | head -1)"
# No window manager under Xvfb: focus the window, then type.
xdotool windowfocus "$window" 2>/dev/null || true
sleep 5
for key in Left Left Up Right Right Down Left 2 Right 1 Left; do
    xdotool key "$key" 2>/dev/null
    sleep 2
done
xdotool getwindowname "$window"
xdotool key q
wait "$view"
view=""
grep '^frames:' "$out"
