"""Prism, a Whitted-style ray tracer, from Python.

Load a scene file of any dialect Prism reads, render it to a NumPy array (or a region
of it), write images in every format ``prism render`` writes, and render animations::

    import prism
    scene = prism.load_scene("scenes/example/example.objx")
    camera = prism.Camera.from_file("scenes/example/example.cmr")
    image = prism.render(scene, camera, width=480, aa=2)     # H x W x 3 float32
    prism.write_image(image, "example.png", transfer="classic")

The renderer is the library the command line uses, through the same option handling,
so the same inputs give the same pixels as ``prism render``, bit for bit. Rendering
releases the GIL, and Ctrl-C stops a render within a fraction of a second.
``prism.denoise`` denoises a render with Intel Open Image Denoise (``pip install
pyoidn``).
``prism.distributed`` spreads frames and tiles over a Ray cluster.
"""

from os import PathLike
from typing import Any, Callable, Dict, Optional, Tuple, Union

import numpy as np

from . import _prism
from ._denoise import denoise
from ._prism import Animation, Camera, Scene
from .errors import FileError, PrismError, SceneError, SettingsError

__all__ = [
    "Animation",
    "Camera",
    "FileError",
    "Passes",
    "PrismError",
    "Scene",
    "SceneError",
    "SettingsError",
    "animate",
    "denoise",
    "load_scene",
    "render",
    "render_passes",
    "render_progressive",
    "scene_from_dict",
    "restrict_paths",
    "show",
    "write_image",
]
__version__ = _prism.__version__


def __dir__() -> list:
    # What the package offers, not the names it imports (np, Any, ...).
    return sorted(__all__ + ["__version__", "distributed"])

Path = Union[str, "PathLike[str]"]
Progress = Union[None, bool, Callable[[int, int], Any]]


def load_scene(path: Path, dialect: Optional[str] = None) -> Scene:
    """Reads a scene file: ``.objx`` (the 2014 dialect, with its ``.mtlx`` and
    textures), ``.obj`` (Wavefront), ``.ply``, ``.gltf`` / ``.glb`` (glTF 2.0, with
    its cameras and lights) or ``.toml`` (Prism's scene file). ``dialect``
    (``"objx"``, ``"obj"``, ``"ply"``, ``"gltf"``, ``"toml"``) overrides the one the
    extension names.

    Raises :class:`SceneError` (a ``ValueError``) with ``file``, ``line`` and
    ``column`` for malformed content, :class:`FileError` for a missing file.
    """
    return _prism.load_scene(path, dialect)


def scene_from_dict(scene: Dict[str, Any], folder: Optional[Path] = None) -> Scene:
    """A scene from a dict in the scene file's own schema (docs/scene-format.md), as
    ``tomllib.load`` would give for a ``.toml`` file: ``camera``, ``object``,
    ``material``, ``light``, ``render`` and the rest. An object of ``"type": "mesh"``
    may carry arrays instead of a ``file``: ``vertices`` (N x 3), ``faces`` (M x 3
    vertex indices), and optionally ``normals`` (N x 3), ``uvs`` (N x 2) and
    ``colors`` (N x 3 or N x 4 linear RGB(A), alpha dropped: multiplied into the
    albedo), so NumPy and trimesh meshes render without files. An object of ``"type": "instance"``
    places a named mesh object once more per 4 x 4 matrix of ``transforms`` (an
    N x 4 x 4 array), holding the mesh once. Relative paths (``file``, ``texture``)
    resolve against ``folder`` (default: the working directory).

    Raises :class:`SceneError` naming the entry at fault, as for a file.
    """
    import copy
    import json
    import os

    scene = copy.copy(scene)
    meshes = []
    placements = []
    objects = []
    for i, obj in enumerate(scene.get("object", []) or []):
        if isinstance(obj, dict) and isinstance(obj.get("transforms"), np.ndarray):
            # N x 4 x 4 placements go over as bytes, not numbers in text.
            matrices = obj["transforms"]
            if matrices.ndim != 3 or matrices.shape[1:] != (4, 4):
                raise ValueError(f"object {i}: transforms must be N x 4 x 4, found {matrices.shape}")
            name = f"<transforms of object {i}>"
            placements.append((name, np.ascontiguousarray(matrices, dtype="<f8").tobytes()))
            obj = dict(obj, transforms=name)
        if isinstance(obj, dict) and "vertices" in obj:
            obj = dict(obj)
            name = f"<arrays of object {i}>"
            if "faces" not in obj:
                raise ValueError(f"object {i}: a mesh with vertices needs faces (M x 3 vertex indices)")
            vertices = np.ascontiguousarray(obj.pop("vertices"), dtype="<f4")
            faces = np.asarray(obj.pop("faces"))
            if faces.size and faces.min() < 0:
                raise ValueError(f"object {i}: faces hold a negative vertex index ({faces.min()})")
            faces = np.ascontiguousarray(faces, dtype="<u4")
            normals = obj.pop("normals", None)
            uvs = obj.pop("uvs", None)
            colors = obj.pop("colors", None)
            if vertices.ndim != 2 or vertices.shape[1] != 3:
                raise ValueError(f"object {i}: vertices must be N x 3, found {vertices.shape}")
            if faces.ndim != 2 or faces.shape[1] != 3:
                raise ValueError(f"object {i}: faces must be M x 3, found {faces.shape}")
            if normals is not None:
                normals = np.ascontiguousarray(normals, dtype="<f4")
                if normals.shape != vertices.shape:
                    raise ValueError(f"object {i}: normals must be N x 3 like vertices, found {normals.shape}")
                normals = normals.tobytes()
            if uvs is not None:
                uvs = np.ascontiguousarray(uvs, dtype="<f4")
                if uvs.shape != (vertices.shape[0], 2):
                    raise ValueError(f"object {i}: uvs must be N x 2, found {uvs.shape}")
                uvs = uvs.tobytes()
            if colors is not None:
                colors = np.asarray(colors)
                if colors.ndim != 2 or colors.shape[0] != vertices.shape[0] or colors.shape[1] not in (3, 4):
                    raise ValueError(f"object {i}: colors must be N x 3 or N x 4 like vertices, found {colors.shape}")
                colors = np.ascontiguousarray(colors[:, :3], dtype="<f4").tobytes()
            obj["file"] = name
            meshes.append((name, vertices.tobytes(), faces.tobytes(), normals, uvs, colors))
        objects.append(obj)
    if objects:
        scene["object"] = objects

    def plain(o: Any) -> Any:
        if isinstance(o, np.ndarray):
            return o.tolist()
        if isinstance(o, np.generic):
            return o.item()
        raise TypeError(f"{type(o).__name__} is not a scene value")

    text = json.dumps(scene, default=plain)
    return _prism.scene_from_json(
        text, meshes, os.fspath(folder) if folder is not None else os.getcwd(), placements
    )


def restrict_paths(folder: Path) -> None:
    """Confines every later read of this process (scenes, meshes, materials, textures,
    includes, animations) to ``folder``: a path leading outside it, after ``..`` and
    symbolic links are resolved, raises :class:`FileError` or :class:`SceneError`.
    For services rendering scene files from others, as ``prism --restrict-paths``.
    It cannot be lifted: run each job in a process of its own (Ray workers are).

    Raises :class:`SettingsError` if ``folder`` is not a folder or reads are already
    restricted to another one.
    """
    _prism.restrict_paths(folder)


def _progress_callback(progress: Progress, unit: str) -> Tuple[Optional[Callable], Callable]:
    """The callable for the Rust side and a function that closes what it opened:
    ``True`` means a tqdm bar (when tqdm is installed)."""
    if progress is True:
        try:
            from tqdm.auto import tqdm
        except ImportError:
            return None, lambda: None
        # Made at the first report, when its total is known: a bar made empty prints
        # a stray "0rows" line first.
        bars: list = []

        def update(done: int, total: int) -> None:
            if not bars:
                bars.append(tqdm(total=total, unit=unit))
            bar = bars[0]
            bar.total = total
            bar.n = done
            bar.refresh()

        def close() -> None:
            for bar in bars:
                bar.close()

        return update, close
    if progress is None or progress is False:
        return None, lambda: None
    if not callable(progress):
        raise TypeError("progress must be a callable(done, total), True or None")
    return progress, lambda: None


def render(
    scene: Scene,
    camera: Optional[Camera] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    aa: Optional[int] = None,
    filter: Optional[str] = None,
    region: Optional[Tuple[int, int, int, int]] = None,
    seed: Optional[int] = None,
    threads: Optional[int] = None,
    integrator: Optional[str] = None,
    progress: Progress = None,
    srgb: bool = False,
    show: bool = False,
    **options: Any,
) -> np.ndarray:
    """Renders ``scene`` and returns the image as a NumPy array.

    Each option overrides the scene file and the camera, as in ``prism render``:
    ``width`` and ``height`` (the field of view is kept; ``width`` alone keeps the
    aspect ratio), ``aa`` (K x K samples per pixel), ``filter`` (``nearest``,
    ``bilinear``, ``area``, ``bicubic``, ``lanczos``), ``region=(x, y, w, h)`` (that
    window of the full frame, identical to the same crop of a full render), ``seed``,
    ``threads`` (the image does not depend on it), ``integrator`` (``classic``,
    ``whitted`` or ``path``), and the keywords ``spp`` (samples per pixel; ``dof_rays`` is its
    older name), ``max_depth``, ``min_weight``, ``light_sampling`` (path model:
    ``"all"`` traces a shadow ray toward every light at a vertex, ``"one"`` toward one
    chosen by its contribution, ``"tree"`` toward one light drawn from a tree over the
    lights, ``"auto"`` all up to 16 lights and tree above), ``exposure`` and ``tonemap`` (the
    development of ``srgb=True``), ``accel`` and ``max_memory`` (bytes, or a size such
    as ``"4G"``: a render whose estimate is larger is refused; default half the
    machine's memory), ``environment`` (an equirectangular ``.hdr``, ``.exr`` or 8-bit
    image lighting the scene, with ``environment_rotate`` in degrees about the vertical
    and ``environment_strength``), ``material`` (a MaterialX ``.mtlx`` document whose
    OpenPBR material every shape wears). ``camera`` (:class:`Camera`) replaces the
    scene's own.

    Returns an H x W x 3 ``float32`` array of linear values (0..1 for the classic
    model, radiance for whitted), or with ``srgb=True`` the H x W x 3 ``uint8`` values
    ``prism render`` writes to a PNG (the scene file's exposure and tone map; the sRGB
    curve for whitted, the 2014 program's values for classic).

    ``show=True`` in a notebook (IPython) shows the image in the cell as it forms,
    refreshed a few times a second until the render ends (rows not rendered yet are
    black; developed as ``srgb=True`` would be).

    ``progress`` is a callable ``(done, total)`` (called from this thread) or ``True``
    for a tqdm bar. The GIL is released while rendering; Ctrl-C raises
    ``KeyboardInterrupt`` promptly.
    """
    opts: Dict[str, Any] = dict(
        width=width,
        height=height,
        aa=aa,
        filter=filter,
        region=region,
        seed=seed,
        threads=threads,
        integrator=integrator,
        **options,
    )
    callback, close = _progress_callback(progress, "rows")
    try:
        preview = _cell_preview() if show else None
        data, w, h, dtype = _prism.render(scene, camera, opts, callback, srgb, preview)
    finally:
        close()
    return np.frombuffer(data, dtype=np.dtype(dtype)).reshape(h, w, 3)


def render_progressive(
    scene: Scene,
    camera: Optional[Camera] = None,
    srgb: bool = False,
    show: bool = False,
    **options: Any,
) -> "Passes":
    """The image :func:`render` makes with the same options, in sample passes: yields
    ``(samples, image)`` after 1, 2, 4, 8 … samples a pixel and last after the job's
    ``spp``, each ``image`` (H x W x 3 ``float32``, linear) the mean of all samples so
    far, so the noise falls pass by pass and the last is :func:`render`'s image bit
    for bit. The path model renders this way; the others (and a path render whose sums
    would not fit ``max_memory``) yield one image, the whole render. With
    ``denoise=True`` every image is denoised. ``srgb=True`` yields the ``uint8``
    images :func:`render` gives with it; ``show=True`` in a notebook shows each pass in
    the cell, one image refined in place.

    The next pass renders while the caller looks at the last; stop early by leaving
    the loop (or ``close()`` on the iterator, from any thread). Bad options raise here, not at the first
    pass. Waiting releases the GIL; Ctrl-C raises ``KeyboardInterrupt`` promptly::

        for spp, image in prism.render_progressive(scene, integrator="path", spp=256):
            prism.write_image(image, f"pass-{spp}.exr")
    """
    preview = _cell_preview() if show else None
    passes = _prism.render_progressive(scene, camera, options, srgb or show)
    return Passes(passes, srgb, preview)


class Passes:
    """The passes :func:`render_progressive` yields, as an iterator of ``(samples,
    image)``. ``close()`` stops the render, the pass in flight too (within a fraction
    of a second), and may be called from any thread: a host application's user
    interface can cancel a render another thread is waiting on."""

    def __init__(self, passes: Any, srgb: bool, preview: Optional[Callable]) -> None:
        self._passes = passes
        self._srgb = srgb
        self._preview = preview

    def __iter__(self) -> "Passes":
        return self

    def __next__(self) -> Tuple[int, np.ndarray]:
        try:
            samples, data, rgb8, w, h = next(self._passes)
        except BaseException:
            self._passes.close()
            raise
        if self._preview is not None:
            self._preview(rgb8, w, h)
        if self._srgb:
            return samples, np.frombuffer(rgb8, dtype=np.uint8).reshape(h, w, 3)
        return samples, np.frombuffer(data, dtype=np.float32).reshape(h, w, 3)

    @property
    def totals(self) -> list:
        """Samples a pixel after each pass, in order."""
        return list(self._passes.totals)

    def close(self) -> None:
        """Stops the render; the iterator then ends."""
        self._passes.close()

    def __enter__(self) -> "Passes":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def __del__(self) -> None:
        passes = getattr(self, "_passes", None)
        if passes is not None:
            passes.close()


def render_passes(
    scene: Scene,
    passes: Tuple[str, ...] = ("albedo", "normal"),
    camera: Optional[Camera] = None,
    **options: Any,
) -> Dict[str, np.ndarray]:
    """Passes for compositing and denoising of the image :func:`render` makes with the
    same options, through its own camera samples and filter, so they line up with it
    pixel for pixel: ``albedo`` (H x W x 3), ``normal`` (H x W x 3, world space, facing
    the camera), ``depth`` (H x W, the distance along the ray; 0 where it escapes),
    ``alpha`` (H x W, the share of the pixel's samples that meet a surface) and
    ``background`` (H x W x 3, the background where rays escape: the image less it is
    the image on a transparent film, premultiplied by ``alpha``).
    They are the auxiliary images Intel Open Image Denoise takes: see
    :func:`denoise`."""
    rendered = _prism.render_passes(scene, list(passes), camera, options)
    out: Dict[str, np.ndarray] = {}
    for name, (data, w, h) in zip(passes, rendered):
        a = np.frombuffer(data, dtype=np.float32).reshape(h, w, 3)
        out[name] = a[..., 0].copy() if name in ("depth", "alpha") else a
    return out


def _cell_preview() -> Callable[[bytes, int, int], None]:
    """A callable showing 8-bit frames in the notebook cell: one image, updated."""
    try:
        from IPython.display import Image, display
    except ImportError as err:
        raise ImportError("show=True shows the image in a notebook: it needs IPython") from err
    handle: list = []

    def preview(rgb8: bytes, width: int, height: int) -> None:
        image = Image(data=_prism.encode_png(rgb8, width, height), format="png")
        if handle:
            handle[0].update(image)
        else:
            handle.append(display(image, display_id=True))

    return preview


def plan(scene: Scene, camera: Optional[Camera] = None, **options: Any) -> Dict[str, Any]:
    """What :func:`render` with these options would make, without rendering: the full
    frame's ``width`` and ``height`` (before any region), the ``integrator``, and the
    ``exposure``, ``tonemap`` and ``transfer`` ``prism render`` would develop it with
    (and the ``png_bits`` and ``exr_precision`` it would write)."""
    return _prism.plan(scene, camera, options)


def _samples(array: Any) -> Tuple[bytes, int, int, str]:
    a = np.asarray(array)
    if a.ndim != 3 or a.shape[2] != 3:
        raise ValueError(f"expected an H x W x 3 array, found shape {a.shape}")
    if a.dtype == np.uint8:
        dtype = "u1"
    else:
        a = a.astype("<f4", copy=False)
        dtype = "<f4"
    h, w = a.shape[:2]
    return np.ascontiguousarray(a).tobytes(), w, h, dtype


def write_image(
    array: Any,
    path: Path,
    exposure: float = 0.0,
    tonemap: str = "clamp",
    transfer: str = "srgb",
    png_bits: int = 8,
    exr_precision: str = "half",
) -> None:
    """Writes an H x W x 3 array to ``path`` in the format its extension names:
    png, bmp, jpg/jpeg, ppm, tga, exr, hdr. The file is written atomically.

    Float arrays are linear values: EXR and HDR store them as they are; the 8- and
    16-bit formats develop them with ``exposure`` (stops), ``tonemap`` (``clamp``,
    ``reinhard``, ``aces``) and ``transfer`` (``srgb``, or ``classic``: no curve, as
    ``prism render`` stores a 2014 scene's render). ``uint8`` arrays are written as
    they are (divided by 255 in EXR and HDR).
    """
    data, w, h, dtype = _samples(array)
    _prism.write_image(
        data, w, h, dtype, path, exposure, tonemap, transfer, png_bits, exr_precision
    )


def animate(
    path: Path,
    output: Path,
    frames: Optional[str] = None,
    threads: Optional[int] = None,
    keep_frames: bool = False,
    progress: Progress = None,
) -> Dict[str, Any]:
    """Renders an animation file as ``prism animate ANIM OUTPUT [--frames A..B]``: to a
    folder of numbered PNG frames, a ``%04d`` pattern, or a video (``.mp4``, ``.gif``,
    ``.apng``) encoded once every frame exists. Each frame is written atomically; a
    rerun skips the frames already written. ``progress`` counts frames.

    Returns ``rendered`` (frames rendered now), ``skipped``, ``missing`` (frames of the
    animation not rendered yet) and ``video`` (``frames``, ``bytes``, ``fps`` when a
    video was written, else ``None``).
    """
    anim = Animation(path, threads)
    start, end = anim.frame_range(frames)
    todo = anim.prepare(output, start, end)
    callback, close = _progress_callback(progress, "frames")
    try:
        rendered = anim.render_frames(output, todo, callback)
    finally:
        close()
    result = dict(anim.finish(output, keep_frames))
    result.update(rendered=rendered, skipped=(end - start) - len(todo))
    return result


def show(array: Any) -> Optional[bytes]:
    """Displays an image in a notebook (IPython) as a PNG; float arrays are developed
    with the sRGB curve. Returns the PNG file's bytes when IPython is not there (so a
    script can save them), else ``None`` (so a cell ending with it shows one image)."""
    a = np.asarray(array)
    if a.dtype != np.uint8:
        a = _develop_srgb(a)
    data, w, h, _ = _samples(a)
    png = _prism.encode_png(data, w, h)
    try:
        from IPython.display import Image, display
    except ImportError:
        return png
    display(Image(data=png, format="png"))
    return None


def _develop_srgb(a: np.ndarray) -> np.ndarray:
    """Linear values to 8-bit sRGB, for previews (files go through write_image)."""
    v = np.clip(np.nan_to_num(a.astype(np.float64), nan=0.0, posinf=1.0), 0.0, 1.0)
    v = np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)
    return np.round(v * 255.0).astype(np.uint8)
