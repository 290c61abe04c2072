"""Stubs of the Rust extension `prism._prism` (the public API is `prism`)."""

from os import PathLike
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

_Path = Union[str, PathLike[str]]
_Vec3 = Tuple[float, float, float]
_Callback = Optional[Callable[[int, int], Any]]

__version__: str
# "release", or "debug" for `maturin develop`'s build.
BUILD: str

class Scene:
    """A scene read from a file: .objx (2014), .obj (Wavefront) or .toml (Prism)."""
    @property
    def path(self) -> str: ...
    @property
    def dialect(self) -> str: ...
    @property
    def warnings(self) -> List[str]: ...
    def info(self) -> Dict[str, Any]:
        """What `prism info --json` prints, as a dict."""
    def _repr_html_(self) -> str: ...

class Camera:
    """A camera for `prism.render`."""
    @staticmethod
    def from_file(path: _Path) -> Camera:
        """A 2014 camera file (.cmr), read now so that a bad file fails here."""
    @staticmethod
    def look_at(
        from_: _Vec3,
        at: _Vec3,
        up: _Vec3 = (0.0, 1.0, 0.0),
        fov: float = 40.0,
        width: Optional[int] = None,
        height: Optional[int] = None,
    ) -> Camera:
        """A right-handed look-at camera; `fov` is the horizontal field of view in
        degrees; `width` and `height` default to the scene's."""

class Animation:
    """A loaded animation file and the scene and camera files it names."""
    def __init__(
        self, path: _Path, threads: Optional[int] = None, accel: Optional[str] = None
    ) -> None: ...
    @property
    def path(self) -> str: ...
    @property
    def frames(self) -> int: ...
    @property
    def fps(self) -> float: ...
    @property
    def size(self) -> Tuple[int, int]: ...
    @property
    def fingerprint(self) -> str: ...
    def frame_range(self, text: Optional[str] = None) -> Tuple[int, int]: ...
    def prepare(self, output: _Path, start: int, end: int) -> List[int]: ...
    def frame_path(self, output: _Path, k: int) -> str: ...
    def render_frames(
        self, output: _Path, frames: List[int], progress: _Callback = None
    ) -> int: ...
    def render_frame_bytes(self, output: _Path, k: int) -> bytes: ...
    def finish(self, output: _Path, keep_frames: bool = False) -> Dict[str, Any]: ...

def load_scene(path: _Path, dialect: Optional[str] = None) -> Scene: ...
def scene_from_json(
    json: str,
    meshes: List[Tuple[str, bytes, bytes, Optional[bytes], Optional[bytes], Optional[bytes]]],
    folder: _Path,
    transforms: List[Tuple[str, bytes]] = ...,
) -> Scene: ...
def render(
    scene: Scene,
    camera: Optional[Camera] = None,
    options: Optional[Dict[str, Any]] = None,
    progress: _Callback = None,
    srgb: bool = False,
    preview: Optional[Callable[[bytes, int, int], None]] = None,
) -> Tuple[bytearray, int, int, str]: ...
def plan(
    scene: Scene, camera: Optional[Camera] = None, options: Optional[Dict[str, Any]] = None
) -> Dict[str, Any]: ...
def write_image(
    data: bytes,
    width: int,
    height: int,
    dtype: str,
    path: _Path,
    exposure: float = 0.0,
    tonemap: str = "clamp",
    transfer: str = "srgb",
    png_bits: int = 8,
    exr_precision: str = "half",
) -> None: ...
def encode_png(data: bytes, width: int, height: int) -> bytes: ...
def restrict_paths(folder: Union[str, "PathLike[str]"]) -> None: ...
