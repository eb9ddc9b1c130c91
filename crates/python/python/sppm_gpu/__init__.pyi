"""Type stubs of sppm_gpu (the native module sppm_gpu._native and its Python wrappers)."""

import os
from typing import Any, Dict, Iterator, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Path = Union[str, "os.PathLike[str]"]
_Image = npt.NDArray[np.float32]
_Adapter = Union[int, str, None]

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
    def render(
        self,
        method: Optional[str] = None,
        passes: Optional[int] = None,
        time_limit: Optional[float] = None,
        seed: Optional[int] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        photons: Optional[int] = None,
        radius: Optional[float] = None,
        alpha: Optional[float] = None,
        spp: Optional[int] = None,
        max_depth: Optional[int] = None,
        direct: Optional[str] = None,
        direct_samples: Optional[int] = None,
        light_paths: Optional[int] = None,
        radius_schedule: Optional[str] = None,
        radius_rule: Optional[str] = None,
        sampler: Optional[str] = None,
        adapter: _Adapter = None,
    ) -> _Image:
        """Render; linear RGB radiance, float32 (height, width, 3). None keeps the scene's
        setting; method is sppm, pt, pt-nee, lt, bpt or vcm."""
    def progressive(
        self,
        method: Optional[str] = None,
        passes: Optional[int] = None,
        time_limit: Optional[float] = None,
        every: Optional[int] = None,
        seed: Optional[int] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        photons: Optional[int] = None,
        radius: Optional[float] = None,
        alpha: Optional[float] = None,
        spp: Optional[int] = None,
        max_depth: Optional[int] = None,
        direct: Optional[str] = None,
        direct_samples: Optional[int] = None,
        light_paths: Optional[int] = None,
        radius_schedule: Optional[str] = None,
        radius_rule: Optional[str] = None,
        sampler: Optional[str] = None,
        adapter: _Adapter = None,
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
    width: Optional[int] = None,
    height: Optional[int] = None,
    seed: Optional[int] = None,
    photons: Optional[int] = None,
    radius: Optional[float] = None,
    adapter: _Adapter = None,
) -> List[Mapping[str, Union[str, float, int]]]:
    """Equal-time comparison; the rows of compare.csv (method, seconds, passes, relMSE, RMSE)."""
