#!/usr/bin/env python3
"""Write scenes/mitsuba/textures/envmap-test.exr, the environment map of
scenes/mitsuba/envmap.xml: 64x32 linear RGB (float32 EXR, written by Mitsuba's Bitmap), four
coloured quadrants (warm and blue above the horizon, green and grey below), each brightening
from left to right, a bright 3x3 "sun" at texels x 39..41, y 9..11, and a pale top row. Every
feature is asymmetric, so a map turned or mirrored the wrong way shows.

    /work/.venv-mi/bin/python scripts/regen/mitsuba-test-envmap.py   # a venv with mitsuba and numpy
"""
import os

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")
here = os.path.dirname(os.path.abspath(__file__))
W, H = 64, 32
img = np.zeros((H, W, 3), np.float32)
for y in range(H):
    for x in range(W):
        u, v = (x + 0.5) / W, (y + 0.5) / H
        if v < 0.5:
            c = np.array([1.0, 0.45, 0.15]) if u < 0.5 else np.array([0.15, 0.35, 1.0])
        else:
            c = np.array([0.2, 0.7, 0.25]) if u < 0.5 else np.array([0.45, 0.45, 0.45])
        img[y, x] = c * (0.5 + 0.8 * u)
img[9:12, 39:42] = np.array([60.0, 55.0, 45.0])
img[0, :] = np.array([0.8, 0.8, 0.9])
mi.Bitmap(img).write(os.path.join(here, "..", "..", "scenes", "mitsuba", "textures", "envmap-test.exr"))
