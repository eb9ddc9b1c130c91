"""Type stubs of sppm_gpu (the native module sppm_gpu._native and its Python wrappers)."""

import os
from typing import Any, Dict, Iterator, List, Mapping, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np
import numpy.typing as npt

# Unpack (PEP 692, **kwargs typed by a TypedDict) is in typing from Python 3.11 only; the
# package supports 3.9. A stub is read by type checkers, never imported: they all carry
# typing_extensions' stub (typeshed's stdlib), so it needs no runtime dependency.
from typing_extensions import Unpack

__version__: str

_Path = Union[str, "os.PathLike[str]"]
_Image = npt.NDArray[np.float32]
_Adapter = Union[int, str, None]

class _CompareParams(TypedDict, total=False):
    """The render settings compare() takes: _RenderParams' but method, passes and direct."""

    seed: Optional[int]
    width: Optional[int]
    height: Optional[int]
    photons: Optional[int]
    radius: Optional[float]
    alpha: Optional[float]
    spp: Optional[int]
    max_depth: Optional[int]
    direct_samples: Optional[int]
    light_paths: Optional[int]
    connect_share: Optional[float]
    merge_share: Optional[float]
    radius_schedule: Optional[str]
    radius_rule: Optional[str]
    sampler: Optional[str]

class _RenderParams(_CompareParams, total=False):
    """The render settings, keywords of Scene.render() and Scene.progressive(): each
    overrides the scene's setting as the command line's option of the same name does
    (passes is --iterations); None keeps the scene's. What each means:
    help(sppm_gpu.Scene.render)."""

    method: Optional[str]
    passes: Optional[int]
    time_limit: Optional[float]
    direct: Optional[str]

class Error(Exception):
    """Anything sppm_gpu refuses or fails at: the base of the errors below."""

class SceneError(Error):
    """A scene file, or a mesh or texture it names, is malformed or missing."""

    file: str
    line: Optional[int]
    key: Optional[str]
    message: str

class GpuError(Error):
    """No adapter, a device the renderer cannot use, or a failed device."""

class ImageError(Error):
    """An image could not be read or written."""

    file: str

class SettingError(Error):
    """A setting out of range or unknown."""

class Progressive(Iterator[Tuple[int, _Image]]):
    """The iterator of Scene.progressive(): (passes, image) pairs."""

    @property
    def seconds(self) -> float:
        """Seconds of passes when the last image was taken."""
    def __iter__(self) -> "Progressive": ...
    def __next__(self) -> Tuple[int, _Image]: ...
    def close(self) -> None:
        """Stop the render after the passes on the device; the iterator then ends."""

class Scene:
    """A loaded scene; render() overrides its settings by keyword, never changing it."""

    @property
    def path(self) -> str: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def method(self) -> str: ...
    @property
    def passes(self) -> int: ...
    @property
    def seed(self) -> int: ...
    @property
    def time_limit(self) -> Optional[float]: ...
    def render(self, *, adapter: _Adapter = None, **params: Unpack[_RenderParams]) -> _Image:
        """Render; linear RGB radiance, float32 (height, width, 3). Each setting overrides the
        scene's; None keeps it."""
    def progressive(
        self, *, every: Optional[int] = None, adapter: _Adapter = None, **params: Unpack[_RenderParams]
    ) -> Progressive:
        """(passes, image) after every `every` passes (or at 1, 2, 4, ... passes) and at the
        end."""

def load(path: _Path, **params: Any) -> Scene:
    """Load a TOML, Mitsuba XML or pbrt-v4 scene; params set a Mitsuba scene's $names."""

def write(path: _Path, image: npt.ArrayLike) -> None:
    """Write (height, width, 3) linear RGB as OpenEXR (.exr) or sRGB PNG (.png)."""

def read(path: _Path) -> _Image:
    """Read an .exr or .png as linear RGB, float32 (height, width, 3)."""

def adapters() -> List[Dict[str, Any]]:
    """The machine's adapters: index, name, backend, device_type, driver."""

def compare(
    scene: Scene,
    reference: Union[_Path, npt.ArrayLike],
    methods: Sequence[str],
    time_limit: float,
    first_snapshot: float = 0.5,
    downsample: int = 1,
    max_passes: Optional[int] = None,
    out: Optional[_Path] = None,
    *,
    adapter: _Adapter = None,
    **params: Unpack[_CompareParams],
) -> List[Mapping[str, Union[str, float, int]]]:
    """Equal-time comparison; the rows of compare.csv (method, seconds, passes, relMSE, RMSE)."""
