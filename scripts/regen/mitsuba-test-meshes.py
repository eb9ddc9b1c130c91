#!/usr/bin/env python3
"""Write the mesh files of scenes/mitsuba/ (the Mitsuba XML test scenes): the Stanford bunny
(an OBJ given as the argument: the study's shared meshes/bunny.obj) as binary little-endian PLY, a square pyramid as ASCII PLY, and
two shapes in Mitsuba's .serialized format (version 4: a zlib stream per shape, then the
shapes' offsets and count), all from this script alone so that the files can be remade.

    python3 scripts/regen/mitsuba-test-meshes.py BUNNY_OBJ
"""
import math, os, struct, sys, zlib

here = os.path.dirname(os.path.abspath(__file__))
out = os.path.join(here, "..", "..", "scenes", "mitsuba", "meshes")
os.makedirs(out, exist_ok=True)


def read_obj(path):
    v, f = [], []
    for line in open(path):
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            v.append(tuple(float(x) for x in w[1:4]))
        elif w[0] == "f":
            idx = [int(x.split("/")[0]) - 1 for x in w[1:]]
            for i in range(1, len(idx) - 1):
                f.append((idx[0], idx[i], idx[i + 1]))
    return v, f


# The bunny, binary little-endian PLY, positions only (Mitsuba computes its normals).
v, f = read_obj(sys.argv[1] if len(sys.argv) > 1 else sys.exit("usage: mitsuba-test-meshes.py BUNNY_OBJ"))
with open(os.path.join(out, "bunny.ply"), "wb") as o:
    o.write(("ply\nformat binary_little_endian 1.0\ncomment Stanford bunny (Stanford 3D Scanning Repository)\n"
             f"element vertex {len(v)}\nproperty float x\nproperty float y\nproperty float z\n"
             f"element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n").encode())
    for p in v:
        o.write(struct.pack("<3f", *p))
    for t in f:
        o.write(struct.pack("<B3i", 3, *t))

# A square pyramid, ASCII PLY (Mitsuba 3 reads triangles only: the base is two).
with open(os.path.join(out, "pyramid.ply"), "w") as o:
    o.write("ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 6\nproperty list uchar int vertex_indices\nend_header\n")
    for p in [(-1, 0, -1), (1, 0, -1), (1, 0, 1), (-1, 0, 1), (0, 1.5, 0)]:
        o.write("%g %g %g\n" % p)
    o.write("3 0 1 2\n3 0 2 3\n3 0 4 1\n3 1 4 2\n3 2 4 3\n3 3 4 0\n")


def serialized_shape(name, positions, normals, faces, double=False):
    flags = (0x0001 if normals else 0) | (0x2000 if double else 0x1000)
    fmt = "<d" if double else "<f"
    body = struct.pack("<I", flags) + name.encode() + b"\0" + struct.pack("<QQ", len(positions), len(faces))
    for p in positions:
        body += b"".join(struct.pack(fmt, x) for x in p)
    for n in normals or []:
        body += b"".join(struct.pack(fmt, x) for x in n)
    for t in faces:
        body += struct.pack("<3I", *t)
    return struct.pack("<HH", 0x041C, 4) + zlib.compress(body)


# Shape 0: an octahedron (no normals, single precision); shape 1: a smooth-shaded UV sphere
# of radius 1 with its normals (double precision), 16 x 8.
octa_v = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
octa_f = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
sv, sn, sf = [], [], []
rings, segs = 8, 16
for i in range(rings + 1):
    th = math.pi * i / rings
    for j in range(segs):
        ph = 2 * math.pi * j / segs
        p = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
        sv.append(p)
        sn.append(p)
for i in range(rings):
    for j in range(segs):
        a, b = i * segs + j, i * segs + (j + 1) % segs
        c, d = a + segs, b + segs
        if i > 0:
            sf.append((a, b, c))
        if i < rings - 1:
            sf.append((b, d, c))
shapes = [serialized_shape("octahedron", octa_v, None, octa_f), serialized_shape("sphere", sv, sn, sf, double=True)]
with open(os.path.join(out, "shapes.serialized"), "wb") as o:
    offsets = []
    for s in shapes:
        offsets.append(o.tell())
        o.write(s)
    for off in offsets:
        o.write(struct.pack("<Q", off))
    o.write(struct.pack("<I", len(shapes)))
print("wrote", os.listdir(out))
