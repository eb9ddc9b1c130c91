"""sppm_gpu: stochastic progressive photon mapping and path tracers on the GPU, from Python.

Load a scene (TOML, Mitsuba 3 XML or pbrt-v4), render it into a float32 numpy array of
linear RGB radiance, and write or read images as the ``sppm-gpu`` command line does::

    import sppm_gpu
    scene = sppm_gpu.load("scenes/cornell-box.toml")
    image = scene.render(passes=16)          # (height, width, 3) float32, linear
    sppm_gpu.write("cornell-box.png", image)

``Scene.render`` takes the command line's options as keywords (``method``, ``passes``,
``time_limit``, ``seed``, ``width``, ``height``, ``photons``, ``radius``, ...), and gives the
same image bit for bit as the command line for the same scene, method, seed and passes.
``Scene.progressive`` yields ``(passes, image)`` as a render refines; ``compare`` runs the
command line's equal-time comparison and returns its figures. Rendering releases the GIL,
and Ctrl-C raises ``KeyboardInterrupt`` without waiting for the pass on the device.

See docs/guide/python.md in the repository.
"""

import os
import tempfile

import numpy as np

from . import _native
from ._native import (
    Error,
    GpuError,
    ImageError,
    Progressive,
    Scene,
    SceneError,
    SettingError,
    adapters,
    load,
    read,
)

__all__ = [
    "Error",
    "GpuError",
    "ImageError",
    "Progressive",
    "Scene",
    "SceneError",
    "SettingError",
    "adapters",
    "compare",
    "load",
    "read",
    "write",
]

__version__ = "0.1.0"


def write(path, image):
    """Write an image, an array (height, width, 3) of linear RGB: OpenEXR (.exr, 32-bit
    float) or sRGB PNG (.png), as the command line writes them. Any float or integer array
    is converted to float32 first."""
    _native.write(path, np.ascontiguousarray(image, dtype=np.float32))


def compare(
    scene,
    reference,
    methods,
    time_limit,
    first_snapshot=0.5,
    downsample=1,
    max_passes=None,
    out=None,
    **settings,
):
    """Equal-time comparison of ``methods`` (names of ``sppm-gpu compare --methods``: sppm,
    sppm-photons, pt, pt-nee, lt, bpt, vcm, ...) on ``scene`` against ``reference`` (a path
    to an EXR or PNG, or an array (height, width, 3)), ``time_limit`` seconds of passes each.

    Returns the rows of the command line's compare.csv as dicts with the keys ``method``,
    ``seconds``, ``passes``, ``relMSE`` and ``RMSE``: one per method and snapshot, snapshots
    at ``first_snapshot`` seconds and doubling, and at ``time_limit``. With ``out`` (a
    folder), compare.csv, relmse-vs-time.png and equal-time.png are written there too.
    ``settings`` are ``Scene.render``'s (``help(sppm_gpu.Scene.render)``) but ``method``,
    ``passes`` and ``direct``, which the comparison sets itself, and ``adapter``. Like the command line, it prints its table on
    stdout and each snapshot on stderr. Ctrl-C raises ``KeyboardInterrupt`` at once; the
    comparison, which cannot stop part way, ends on its own thread."""
    if isinstance(reference, np.ndarray):
        with tempfile.TemporaryDirectory(prefix="sppm_gpu-") as folder:
            path = os.path.join(folder, "reference.exr")
            write(path, reference)
            return _native.compare(
                scene, path, list(methods), time_limit, first_snapshot, downsample, max_passes, out, **settings
            )
    return _native.compare(
        scene, reference, list(methods), time_limit, first_snapshot, downsample, max_passes, out, **settings
    )
