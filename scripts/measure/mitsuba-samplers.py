#!/usr/bin/env python3
# Feeds BENCHMARKS.md "The Sobol sampler against Mitsuba's samplers (issue 26)" (docs/journal/session-13.md).
# Inputs: MITSUBA_TOOLS (mitsuba_timed.py) and the arguments.
"""Mitsuba 3's `path` with each of its samplers on a v1 scene at equal time (issue 26): the
anchor our Sobol sampler is to beat is Mitsuba's best sampler, not its default.

    .venv-mi/bin/python scripts/measure/mitsuba-samplers.py SCENE.toml OUTDIR [--seconds 30]
        [--chunk 64] [--samplers independent,stratified,multijitter,ldsampler]

Each sampler as `../shared/tools/mitsuba_timed.py` runs the independent one: an untimed
chunk first (Dr.Jit compiles its kernels then), then chunks of `--chunk` samples per pixel
with seeds 10^6, 10^6 + 1, ... until the clock passes `--seconds`, their mean written to
OUTDIR/SAMPLER.exr. (`mitsuba_reference.py` renders chunks of 64 with seeds 0, 1, 2, ...:
the same seeds and chunk would draw the very samples of the reference and make the
independent sampler's error look smaller than it is.) A chunk of a low-discrepancy sampler is one scrambled point set of
`--chunk` samples (64: a power of two for `ldsampler`, a square for `stratified`), and the
chunks are independent of one another, so the mean keeps each chunk's stratification: one
render call of all the samples would keep more, but does not fit in memory at thousands of
samples per pixel (`samples_per_pass`, which splits a call into passes, is deprecated in
Mitsuba 3.9 and rendered a single pass when tried). Prints each sampler's spp and time, and
its slowest and median chunk (a chunk far slower than the median would be a recompilation).
"""
import argparse, os, sys, time

TOOLS = os.environ.get("MITSUBA_TOOLS") or sys.exit("set MITSUBA_TOOLS to the folder holding mitsuba_timed.py (the study's shared tools)")
sys.path.insert(0, os.path.abspath(TOOLS))
import mitsuba as mi


def scene_with(ref, path, sampler, spp):
    """The reference tool's scene of `path` with `sampler` in place of `independent`."""
    load = mi.load_dict

    def patched(d):
        d["sensor"]["sampler"] = {"type": sampler, "sample_count": spp}
        return load(d)

    mi.load_dict = patched
    try:
        return ref.build(path, spp)
    finally:
        mi.load_dict = load


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("scene"); ap.add_argument("out")
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--chunk", type=int, default=64)
    ap.add_argument("--samplers", default="independent,stratified,multijitter,ldsampler")
    ap.add_argument("--variant", default="llvm_ad_rgb")
    a = ap.parse_args()
    mi.set_variant(a.variant)
    import numpy as np
    import mitsuba_reference as ref
    os.makedirs(a.out, exist_ok=True)
    for sampler in a.samplers.split(","):
        scene = scene_with(ref, a.scene, sampler, a.chunk)
        np.array(mi.render(scene, spp=a.chunk, seed=999999))  # warm-up: kernel compilation
        acc, k, times, t0 = None, 0, [], time.time()
        while time.time() - t0 < a.seconds:
            t = time.time()
            img = np.array(mi.render(scene, spp=a.chunk, seed=10**6 + k), dtype=np.float64)
            times.append(time.time() - t)
            acc = img if acc is None else acc + img
            k += 1
        dt = time.time() - t0
        out = os.path.join(a.out, f"{sampler}.exr")
        mi.Bitmap((acc / k).astype(np.float32), pixel_format=mi.Bitmap.PixelFormat.RGB).write(out)
        print(f"mitsuba path {sampler}: {k * a.chunk} spp in {dt:.1f} s (chunks: slowest {max(times):.2f} s, "
              f"median {sorted(times)[len(times) // 2]:.2f} s) -> {out}", flush=True)


if __name__ == "__main__":
    main()
