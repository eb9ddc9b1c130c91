#!/usr/bin/env python3
# Feeds BENCHMARKS.md "A profile of the JIT code, block by block" (docs/journal/session-07.md).
# Inputs: the arguments (a binary, a scene).
"""Where lavapipe's JIT code spends the time, kernel by kernel and block by block.

Lavapipe compiles each kernel with LLVM at run time, so `perf` sees only anonymous
addresses. With GALLIVM_DEBUG=asm Mesa prints the machine code of every kernel it compiles
(each `cs_co_variant:` section, offsets from the function's start); this script matches the
sampled addresses to that code by finding, for each kernel, the load address that puts the
most samples on instruction starts, and prints the share of samples per block of code with
the buffers (descriptor slots) and notable instructions in it.

    MESA_SHADER_CACHE_DISABLE=true GALLIVM_DEBUG=asm perf record -F 2000 -o /tmp/p.data \\
        target/release/sppm-gpu bench SCENE.toml ... 2> /tmp/asm.txt
    perf script -i /tmp/p.data -F ip,dso | grep -v '\\.so\\|kallsyms\\|sppm-gpu' \\
        | awk '{print $1}' > /tmp/ips.txt
    python3 scripts/measure/jit-profile.py /tmp/asm.txt /tmp/ips.txt [BLOCK_BYTES]

Each kernel's annotated listing (percent of its samples per instruction) is written to
/tmp/jit-profile-N.txt. Samples land on the instruction after a slow one (a cache miss shows
on the instruction after the load).
"""
import collections
import re
import sys


def sections(path):
    out, cur = [], None
    for line in open(path, errors="replace"):
        m = re.match(r"^([a-z_]+):$", line.rstrip("\n"))
        if m:
            cur = (m.group(1), [])
            out.append(cur)
            continue
        m = re.match(r"^\s+([0-9a-f]+):\t(.*)$", line.rstrip("\n"))
        if m and cur:
            cur[1].append((int(m.group(1), 16), m.group(2)))
    return out


def main():
    asm, ips_path = sys.argv[1], sys.argv[2]
    block = int(sys.argv[3]) if len(sys.argv) > 3 else 1024
    ips = collections.Counter(int(x, 16) for x in open(ips_path).read().split())
    total = sum(ips.values())
    remaining = dict(ips)
    kernels = [(i, code) for i, (name, code) in enumerate(sections(asm)) if name == "cs_co_variant"]
    # Largest first: a small kernel matches stray addresses of a large one by chance.
    for index, code in sorted(kernels, key=lambda k: -len(k[1])):
        offsets = {o for o, _ in code}
        size = max(offsets) + 16
        best = (0, 0)
        for ip in sorted(remaining, key=lambda k: -remaining[k])[:30]:
            for o in offsets:
                base = ip - o
                if base % 16:
                    continue
                inside = [(k, v) for k, v in remaining.items() if 0 <= k - base < size]
                hits = sum(v for k, v in inside if k - base in offsets)
                # Nearly every sample in the range must fall on an instruction start.
                if hits > best[0] and hits >= 0.97 * sum(v for _, v in inside):
                    best = (hits, base)
        hits, base = best
        if hits < 0.01 * total:
            continue
        hist = {k - base: v for k, v in remaining.items() if 0 <= k - base < size and k - base in offsets}
        for k in list(remaining):
            if k - base in hist:
                del remaining[k]
        print(f"kernel {index}: {len(code)} instructions, {100 * hits / total:.1f}% of the samples")
        with open(f"/tmp/jit-profile-{index}.txt", "w") as f:
            for o, text in code:
                f.write(f"{100 * hist.get(o, 0) / hits:6.2f} {o:5x} {text}\n")
        blocks = collections.defaultdict(lambda: [0.0, collections.Counter()])
        for o, text in code:
            b = blocks[o // block]
            b[0] += 100 * hist.get(o, 0) / hits
            # A storage buffer's base is reloaded from its descriptor slot (256 bytes each).
            m = re.search(r"movq\s+(\d+)\(%r\w+\), %r\w+", text)
            if m and int(m.group(1)) >= 256 and int(m.group(1)) % 256 == 0:
                b[1][f"slot{int(m.group(1)) // 256}"] += 1
            for k in ["lock", "vdivps", "vsqrtps", "vcvtdq2ps", "vpermd", "call"]:
                if k in text:
                    b[1][k] += 1
        for b in sorted(blocks):
            share, marks = blocks[b]
            if share >= 0.5:
                print(f"  {b * block:#7x} {share:5.1f}%  {dict(marks)}")
    print(f"not matched: {100 * sum(remaining.values()) / total:.1f}%")


if __name__ == "__main__":
    main()
