#!/usr/bin/env bash
# Run every `sppm-gpu` command of the README's "Five things to try" as written, with short
# limits so that the whole takes a minute or two: --time-limit N becomes 1, renders without
# one get --iterations 2, and renders that name no reference are made 32x32 (compare keeps the
# reference's size). `view` is skipped without a display. Prints each command and its exit
# code; exits 1 if any failed.
#   bash scripts/check/readme-commands.sh [BINARY]
set -uo pipefail
cd "$(dirname "$0")/../.."
bin=$(realpath "${1:-${CARGO_TARGET_DIR:-target}/release/sppm-gpu}")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The fenced block after "## Five things to try", continuation lines joined, comments dropped.
commands=$(awk '/^## Five things to try/{f=1} f && /^```sh/{b=1; next} b && /^```/{exit} b' README.md |
    sed -e 's/#.*//' | sed -e ':a' -e '/\\$/N; s/\\\n//; ta' | grep '^sppm-gpu ')
failed=0
while IFS= read -r line; do
    args=${line#sppm-gpu }
    case "$args" in
    view*) [ -n "${DISPLAY:-}" ] || { echo "skipped (no display): $line"; continue; } ;;
    esac
    if [[ $args == *--time-limit* ]]; then
        args=$(sed -E 's/--time-limit [0-9.]+/--time-limit 1/' <<<"$args")
    elif [[ $args != info* && $args != merge* && $args != view* ]]; then
        args="$args --iterations 2"
    fi
    if [[ $args != compare* && $args != info* && $args != merge* ]]; then
        args="$args --width 32 --height 32"
    fi
    # Relative scene paths are the repository's; outputs go to the work folder.
    (cd "$work" && ln -sfn "$OLDPWD/scenes" scenes && ln -sfn "$OLDPWD/tests" tests && eval "\"$bin\" $args" >"$work/log" 2>&1)
    code=$?
    echo "rc $code: sppm-gpu $args"
    if [ $code -ne 0 ]; then
        failed=1
        tail -3 "$work/log"
    fi
done <<<"$commands"
exit $failed
