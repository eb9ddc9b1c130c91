#!/usr/bin/env python3
"""Write the texture files of scenes/mitsuba/textures.xml, from this script alone so that they
can be remade: a 6x4 8-bit sRGB PNG whose every texel differs (red across, green down, blue in
a checker, the top-left texel white) and a 4x4 linear Radiance HDR (flat RGBE scanlines) of
warm and cool stripes, in scenes/mitsuba/textures/; and a quad with OBJ texture coordinates
(`vt`) in scenes/mitsuba/meshes/ceiling.obj.

    python3 scripts/regen/mitsuba-test-textures.py
"""
import math, os, struct, zlib

here = os.path.dirname(os.path.abspath(__file__))
textures = os.path.join(here, "..", "..", "scenes", "mitsuba", "textures")
meshes = os.path.join(here, "..", "..", "scenes", "mitsuba", "meshes")
os.makedirs(textures, exist_ok=True)


def write_png(path, width, height, rgb):
    """rgb(x, y) -> (r, g, b) bytes; row 0 is the top."""
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    raw = b"".join(b"\0" + bytes(c for x in range(width) for c in rgb(x, y)) for y in range(height))
    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return bytes(4)
    mantissa, exponent = math.frexp(m)
    scale = mantissa * 256.0 / m
    return bytes([int(r * scale), int(g * scale), int(b * scale), exponent + 128])


def write_hdr(path, width, height, rgb):
    """rgb(x, y) -> linear (r, g, b); row 0 is the top. Flat (not run-length) scanlines."""
    with open(path, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
        f.write(f"-Y {height} +X {width}\n".encode())
        for y in range(height):
            f.write(b"".join(rgbe(*rgb(x, y)) for x in range(width)))


def grid(x, y):
    if (x, y) == (0, 0):
        return (255, 255, 255)
    return (40 + 40 * x, 30 + 60 * y, 200 if (x + y) % 2 else 60)


write_png(os.path.join(textures, "grid.png"), 6, 4, grid)
# Values exactly representable in RGBE (an 8-bit mantissa of a power-of-two scale).
stripes = [(0.875, 0.5, 0.25), (0.25, 0.5, 0.875), (0.75, 0.75, 0.75), (0.5, 0.25, 0.125)]
write_hdr(os.path.join(textures, "stripes.hdr"), 4, 4, lambda x, y: stripes[(x + 3 * y) % 4])

# The ceiling y = 1 of the box, facing down, its vt twice over the quad (repeating).
with open(os.path.join(meshes, "ceiling.obj"), "w") as f:
    f.write("# A quad with texture coordinates, for textures.xml (scripts/regen/mitsuba-test-textures.py)\n")
    for x, z in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
        f.write(f"v {x} 1 {z}\n")
    for u, v in [(0, 2), (2, 2), (2, 0), (0, 0)]:
        f.write(f"vt {u} {v}\n")
    f.write("f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n")
