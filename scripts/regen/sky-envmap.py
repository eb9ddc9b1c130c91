#!/usr/bin/env python3
"""Write scenes/mitsuba/textures/sky.exr, the environment map of scenes/mitsuba/sky.xml
(issue 25): 256x128 equirectangular, linear RGB as half floats (Mitsuba's Bitmap writes the
EXR), Mitsuba's layout (u = atan2(d.x, -d.z) / 2 pi, v = acos(d.y) / pi, +y up). A smooth sky,
deep blue at the zenith paling to a hazy horizon, a dim brownish ground below it, and a sun:
a disk of 2.5 degrees radius at 35 degrees elevation (u = 0.06, just right of -z), radiance
600 (about 3/4 of the light on the ground comes from it, so that glass casts a sharp
caustic). Each texel is the mean of 4x4 samples across it, so the disk's edge is smooth.

    /work/.venv-mi/bin/python scripts/regen/sky-envmap.py   # a venv with mitsuba and numpy
"""
import os

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")
here = os.path.dirname(os.path.abspath(__file__))
W, H, S = 256, 128, 4
SUN_ELEVATION, SUN_U, SUN_RADIUS, SUN_L = np.radians(35.0), 0.06, np.radians(2.5), 600.0

# Sample positions: S x S per texel.
xs = (np.arange(W * S) + 0.5) / (W * S)
ys = (np.arange(H * S) + 0.5) / (H * S)
u, v = np.meshgrid(xs, ys)
theta, phi = v * np.pi, u * 2.0 * np.pi
d = np.stack([np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)], -1)

up = np.clip(d[..., 1], 0.0, 1.0)
zenith, horizon = np.array([0.06, 0.12, 0.3]), np.array([0.3, 0.32, 0.36])
t = up ** 0.45
sky = horizon * (1 - t)[..., None] + zenith * t[..., None]
ground = np.array([0.09, 0.07, 0.055]) * (1.0 - 0.5 * np.clip(-d[..., 1], 0.0, 1.0))[..., None]
img = np.where((d[..., 1] >= 0.0)[..., None], sky, ground)

st, sp = np.pi / 2 - SUN_ELEVATION, SUN_U * 2 * np.pi
sun = np.array([np.sin(st) * np.sin(sp), np.cos(st), -np.sin(st) * np.cos(sp)])
in_sun = (d @ sun) > np.cos(SUN_RADIUS)
img = np.where(in_sun[..., None], np.array([1.0, 0.95, 0.85]) * SUN_L, img)

img = img.reshape(H, S, W, S, 3).mean(axis=(1, 3)).astype(np.float16)
out = os.path.join(here, "..", "..", "scenes", "mitsuba", "textures", "sky.exr")
mi.Bitmap(img).write(out)
print(out, os.path.getsize(out), "bytes; sun direction", sun)
