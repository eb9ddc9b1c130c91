#!/usr/bin/env bash
# The check a person runs on a machine with a Vulkan GPU, in one command, from the project's
# root. It prints a table (also written to OUT/table.txt) of:
#   1. the canonical scenes at their own settings against tests/references (8x8 relMSE);
#   2. pacing: pt-nee at 1024x1024 and SPPM with 1,000,000 photons a pass under
#      --time-limit 5 (the process's wall time; the check asks for the render's own time
#      within 5% of the limit), and SIGINT during a render (exit within 0.5 s, image written);
#   3. `bench` and pass throughput (sppm, pt-nee, lt, bpt and vcm) at 256x256 and 1024x1024;
#   4. where Python's `mitsuba` imports with its `cuda_ad_rgb` variant and --mitsuba-tools DIR
#      names the folder of mitsuba_reference.py and mitsuba_timed.py: equal time against
#      Mitsuba 3's CUDA path tracer on the canonical scenes (sppm, pt-nee, lt, bpt, vcm), each against a
#      reference Mitsuba renders on the same GPU (REF_SPP samples, default 16384), relMSE of
#      both at SECONDS_EACH (default 10) seconds of wall time;
#   5. equal-time error against SPPM's photons and camera samples a pass
#      (scripts/measure/pass-work.sh, WORK_SECONDS each, default 3): the device's defaults;
#      and against bpt's and vcm's light subpaths a pass (the same script's --light-paths);
#   6. last, the test suite with CI=true on that GPU (tests pick their adapter from
#      SPPM_GPU_ADAPTER, as the command line's --adapter): `cargo test --release` where cargo
#      is installed, else every prebuilt test binary in --tests DIR (a GPU machine may have no
#      Rust toolchain), each cut at TEST_S seconds (default 300).
#
#   bash scripts/gpu-check.sh [--bin SPPM_GPU] [--tests DIR] [--mitsuba-tools DIR] [--out DIR]
#                             [--adapter SELECTOR] [--skip scenes,pacing,bench,mitsuba,work,lightpaths,tests]
#
# --bin defaults to target/release/sppm-gpu (built with cargo if missing and cargo is there);
# --adapter to the first adapter that is not a CPU device (an index or a part of its name, as
# --list-adapters shows them). Feeds BENCHMARKS.md "Pacing: time limit, Ctrl-C and
# throughput". With --tests DIR the test binaries read scenes and references through the
# checkout path they were built in: ../shared/tools/gpu-kit/run.sh recreates it. The
# integration tests are one binary, `suite` (tests/suite/main.rs; pack it with
# TESTS="suite mitsuba_xml sppm_gpu"), whose modules run alone as `suite sppm::`.
set -u
cd "$(dirname "$0")/.."
bin=target/release/sppm-gpu tests= tools= out=gpu-check-out adapter= skip=
while [ $# -gt 0 ]; do
    case $1 in
        --bin) bin=$2; shift 2 ;;
        --tests) tests=$2; shift 2 ;;
        --mitsuba-tools) tools=$2; shift 2 ;;
        --out) out=$2; shift 2 ;;
        --adapter) adapter=$2; shift 2 ;;
        --skip) skip=$2; shift 2 ;;
        -h|--help) sed -n '2,28p' "$0"; exit 0 ;;
        *) echo "gpu-check.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
    esac
done
skipped() { [[ ",$skip," == *",$1,"* ]]; }
mkdir -p "$out"
table=$out/table.txt
: > "$table"
row() { printf '%-34s | %s\n' "$1" "$2" | tee -a "$table"; }
now() { date +%s.%N; }
seconds() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", b - a }'; }

if [ ! -x "$bin" ]; then
    if command -v cargo >/dev/null; then
        cargo build --release -q || exit 1
    else
        echo "gpu-check.sh: no binary at $bin and no cargo to build one (--bin PATH)" >&2
        exit 1
    fi
fi
"$bin" --list-adapters | tee "$out/adapters.txt"
# A container whose NVIDIA Vulkan manifest names libGLX_nvidia.so.0 finds no driver without an
# X server ("Could not get 'vkCreateInstance'", seen on an H200 2026-11-28); the EGL library
# of the same driver serves Vulkan headless.
egl=/usr/local/nvidia/lib64/libEGL_nvidia.so.0
if ! grep -qv '(Cpu,' "$out/adapters.txt" && [ -f "$egl" ]; then
    printf '{"file_format_version":"1.0.1","ICD":{"library_path":"%s","api_version":"1.3.0"}}\n' "$egl" >"$out/nvidia_egl_icd.json"
    export VK_DRIVER_FILES=$PWD/$out/nvidia_egl_icd.json
    [ "${out#/}" != "$out" ] && export VK_DRIVER_FILES=$out/nvidia_egl_icd.json
    echo "gpu-check.sh: no GPU adapter; trying NVIDIA's driver through $egl" >&2
    "$bin" --list-adapters | tee "$out/adapters.txt"
fi
if [ -z "$adapter" ]; then
    adapter=$(grep -v '(Cpu,' "$out/adapters.txt" | head -1 | cut -d: -f1)
fi
if [ -z "$adapter" ]; then
    echo "gpu-check.sh: no adapter but CPU devices; name one with --adapter to check it anyway" >&2
    exit 1
fi
export SPPM_GPU_ADAPTER=$adapter
row "adapter" "$(grep "^$adapter:" "$out/adapters.txt" || echo "$adapter")"
run() { "$bin" "$1" --adapter "$adapter" "${@:2}"; }
# The render's own summary line (not --stats' "kernels compiled in ..." line after it).
summary() { grep -E " in [0-9.]+ s" | grep -v "^kernels compiled" | tail -1; }

# 1. The canonical scenes against their references.
if ! skipped scenes; then
    for s in furnace cornell-box cornell-spheres cornell-glossy point-light textured depth-of-field; do
        ds=8
        [ $s = furnace ] && ds=1
        line=$(run "scenes/$s.toml" -o "$out/$s.exr" 2>&1 | summary)
        row "scene $s" "$(echo "$line" | sed 's/ ->.*//'); $("$bin" diff "$out/$s.exr" "tests/references/$s.exr" --downsample $ds 2>&1 | tail -1)"
    done
fi

# 2. Pacing: the time limit and Ctrl-C on completed work.
if ! skipped pacing; then
    for case in "pt-nee 1024" "sppm 256"; do
        set -- $case
        extra=(--width "$2" --height "$2" --method "$1" --iterations 100000000 --time-limit 5)
        [ "$1" = sppm ] && extra+=(--photons 1000000)
        t0=$(now)
        line=$(run scenes/cornell-box.toml -o "$out/limit.exr" "${extra[@]}" --stats 2>&1 | tee "$out/limit-$1.log" | summary)
        t1=$(now)
        took=$(echo "$line" | grep -oE 'in [0-9.]+ s' | grep -oE '[0-9.]+')
        verdict=$(awk -v t="$took" 'BEGIN { print (t >= 4.75 && t <= 5.25) ? "ok" : "OFF" }')
        row "time limit 5 s: $1 $2x$2" "$verdict: render $took s, process $(seconds "$t0" "$t1") s; $(grep -E '^in flight' "$out/limit-$1.log")"
    done
    rm -f "$out/interrupted.exr"
    # The binary itself in the background (not through a function, whose subshell would take
    # the signal).
    "$bin" scenes/cornell-box.toml --adapter "$adapter" -o "$out/interrupted.exr" --width 1024 --height 1024 \
        --method pt-nee --iterations 100000000 >"$out/interrupt.log" 2>&1 &
    pid=$!
    sleep 4
    t0=$(now)
    kill -INT $pid
    code=0
    wait $pid || code=$?
    t1=$(now)
    took=$(seconds "$t0" "$t1")
    written=no
    [ -s "$out/interrupted.exr" ] && written=yes
    verdict=$(awk -v t="$took" -v w=$written -v c=$code 'BEGIN { print (t <= 0.5 && w == "yes" && c == 130) ? "ok" : "OFF" }')
    row "SIGINT after 4 s (pt-nee 1024)" "$verdict: exit $code after $took s, image written: $written"
fi

# 3. bench and throughput.
if ! skipped bench; then
    for size in 256 1024; do
        run_bench=$("$bin" bench scenes/cornell-box.toml --width $size --height $size --iterations 32 2>&1 | tee "$out/bench-$size.log" | grep -E 'total' | head -1)
        row "bench cornell-box ${size}x$size" "$run_bench"
        for m in sppm pt-nee lt bpt vcm; do
            line=$(run scenes/cornell-box.toml -o "$out/t.exr" --width $size --height $size --method $m --iterations 256 2>&1 | summary)
            row "throughput $m ${size}x$size" "$(echo "$line" | sed 's/ ->.*//')"
        done
    done
fi

# 4. Equal time against Mitsuba 3's CUDA variant, where it is there.
if ! skipped mitsuba; then
    if [ -n "$tools" ] && python3 -c 'import mitsuba as mi; mi.set_variant("cuda_ad_rgb")' 2>/dev/null; then
        secs=${SECONDS_EACH:-10}
        for s in cornell-box cornell-spheres cornell-glossy; do
            ref=$out/$s-mitsuba-ref.exr
            [ -f "$ref" ] || python3 "$tools/mitsuba_reference.py" "scenes/$s.toml" "$ref" --variant cuda_ad_rgb \
                --spp "${REF_SPP:-16384}" --chunk 256 >"$out/$s-ref.log" 2>&1
            python3 "$tools/mitsuba_timed.py" "scenes/$s.toml" "$out/$s-mitsuba.exr" --variant cuda_ad_rgb --seconds "$secs" \
                --chunk 64 >"$out/$s-mitsuba.log" 2>&1
            mi=$("$bin" diff "$out/$s-mitsuba.exr" "$ref" --downsample 8 2>&1 | tail -1 | awk '{print $2}')
            methods="sppm pt-nee lt bpt vcm"
            [ $s = cornell-spheres ] && methods="sppm pt-nee bpt vcm" # light tracing cannot see the glass
            for m in $methods; do
                run "scenes/$s.toml" -o "$out/$s-$m.exr" --method $m --iterations 100000000 --time-limit "$secs" >/dev/null 2>&1
                ours=$("$bin" diff "$out/$s-$m.exr" "$ref" --downsample 8 2>&1 | tail -1 | awk '{print $2}')
                row "equal time $secs s: $s $m" "relMSE $ours; Mitsuba cuda path $mi ($(tail -1 "$out/$s-mitsuba.log"))"
            done
        done
    else
        row "equal time against Mitsuba" "skipped: needs --mitsuba-tools DIR and Python's mitsuba with cuda_ad_rgb"
    fi
fi
# 5. Equal-time error against the work of an SPPM pass (photons x camera samples), the
#    measurement behind the device's defaults (GpuContext::pass_work).
if ! skipped work; then
    bash scripts/measure/pass-work.sh --bin "$bin" --out "$out" --adapter "$adapter" --seconds "${WORK_SECONDS:-3}" \
        >"$out/pass-work.log" 2>&1
    while read -r l; do row "pass work" "$l"; done <"$out/pass-work.txt"
fi

# 5b. Equal-time error against bpt's and vcm's light subpaths a pass (light_paths), the
#     measurement behind their default (integrators::light::PIXELS_PER_LIGHT_PATH).
if ! skipped lightpaths; then
    bash scripts/measure/pass-work.sh --bin "$bin" --out "$out" --adapter "$adapter" --seconds "${WORK_SECONDS:-3}" \
        --light-paths "${LIGHT_PATHS:-1024 4096 16384 65536}" >"$out/light-paths.log" 2>&1
    while read -r l; do row "light paths" "$l"; done <"$out/light-paths.txt"
fi

# 6. The tests on this GPU, last: the longest part, cut by TEST_S where time is short.
if ! skipped tests; then
    if [ -n "$tests" ]; then
        for t in "$tests"/*; do
            [ -x "$t" ] && [ -f "$t" ] && [ "${t%.xz}" = "$t" ] || continue
            n=$(basename "$t")
            r=$(CI=true timeout "${TEST_S:-300}" "$t" 2>&1 | tee "$out/test-$n.log" | grep -E '^test result' | tail -1)
            row "test $n" "${r:-no result (timeout or crash: $out/test-$n.log)}"
        done
    elif command -v cargo >/dev/null; then
        CI=true cargo test --release --workspace >"$out/tests.log" 2>&1
        code=$?
        passed=$(grep -E '^test result' "$out/tests.log" | awk '{p += $4; f += $6} END {print p " passed, " f " failed"}')
        row "cargo test (CI=true)" "exit $code: $passed ($out/tests.log)"
    else
        row "tests" "skipped: no cargo and no --tests DIR"
    fi
fi

echo "table: $table"
