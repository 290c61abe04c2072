"""Prism across a cluster, on Ray: the frames of an animation and the tiles of a still
are independent and bit-exact whatever the machine or thread count, so each becomes a
Ray task; the driver (this process) writes or assembles the results.

- Animations: one task per frame still to render. The task returns the frame's file
  (PNG bytes); the driver writes it atomically into the frame folder as soon as it
  arrives (a temporary file in the folder, then a rename), so a frame file that exists
  is complete and a rerun renders only the missing frames. A video is encoded once,
  by the driver, when every frame exists.
- Stills: ``--tiles N`` bands of rows, each rendered as a region (a bit-exact crop of
  the full render), returned as float32 arrays and assembled; the image is written as
  ``prism render`` writes it.

A task whose worker dies (a lost machine, a crash) is retried by Ray up to
``max_retries`` times; a task that fails (an error in the scene) is reported with its
frame number or tile. Inputs reach the workers either through Ray's ``runtime_env``
(``working_dir``: the folder is uploaded and the tasks read paths relative to it) or
from storage every machine mounts at the same path. See docs/distributed.md.

Command line::

    python -m prism.distributed render SCENE [CAMERA] OUTPUT [--tiles N] [--address ADDR]
    python -m prism.distributed animate ANIM OUTPUT [--frames A..B] [--address ADDR]
"""

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

import prism

# Fault injection for tests: when this variable names a file that exists, the first
# task to claim it (by renaming it) kills its worker, as a lost machine would.
CRASH_ENV = "PRISM_DISTRIBUTED_CRASH_ONCE"


class TaskFailed(prism.PrismError):
    """Some tasks failed after their retries: ``failures`` lists (frame or tile, error)."""

    def __init__(self, what: str, failures: List[Tuple[Any, BaseException]]):
        self.failures = failures
        lines = [f"{what} {key}: {err}" for key, err in failures]
        super().__init__(f"{len(failures)} task(s) failed:\n  " + "\n  ".join(lines))


# ---------------------------------------------------------------------------------------
# Worker side. Ray reuses worker processes, so a scene or animation is read once per
# process and kept for the tasks after it.

_cache: Dict[Tuple[Any, ...], Any] = {}


def _cached(key: Tuple[Any, ...], load):
    if key not in _cache:
        if len(_cache) >= 4:
            _cache.clear()
        _cache[key] = load()
    return _cache[key]


def _maybe_crash() -> None:
    marker = os.environ.get(CRASH_ENV)
    if marker:
        try:
            os.rename(marker, marker + ".fired")
        except OSError:
            return
        os._exit(1)


def _frame_task(anim_path: str, fingerprint: str, suffix: str, k: int, threads: int):
    """Renders frame ``k``; returns the frame file's bytes and the task's timings."""
    t0 = time.time()
    _maybe_crash()
    anim = _cached(("anim", anim_path, threads), lambda: prism.Animation(anim_path, threads))
    if anim.fingerprint != fingerprint:
        raise prism.SettingsError(
            f"{anim_path}: the worker's copy of the animation or its scene differs from "
            "the driver's (stale shared storage?)"
        )
    t1 = time.time()
    data = anim.render_frame_bytes(f"frame_%04d{suffix}", k)
    t2 = time.time()
    return data, {"start": t0, "load": t1 - t0, "render": t2 - t1, "end": t2}


def _tile_task(scene_path: str, dialect: Optional[str], camera_path: Optional[str],
               options: Dict[str, Any], region: Tuple[int, int, int, int]):
    """Renders one region of the still; returns its float32 pixels and timings."""
    t0 = time.time()
    _maybe_crash()
    scene = _cached(("scene", scene_path, dialect), lambda: prism.load_scene(scene_path, dialect))
    camera = prism.Camera.from_file(camera_path) if camera_path else None
    t1 = time.time()
    pixels = prism.render(scene, camera, region=region, **options)
    t2 = time.time()
    return pixels, {"start": t0, "load": t1 - t0, "render": t2 - t1, "end": t2}


# ---------------------------------------------------------------------------------------
# Driver side.


def _init_ray(address: Optional[str], working_dir: Optional[str], **init: Any):
    import ray

    if not ray.is_initialized():
        runtime_env = {"working_dir": working_dir} if working_dir else None
        ray.init(address=address, runtime_env=runtime_env, log_to_driver=False, **init)
    return ray


def _task_path(path: Optional[str], working_dir: Optional[str]) -> Optional[str]:
    """A path as the workers see it: relative to the uploaded working_dir, else
    absolute (on storage every machine mounts at the same place)."""
    if path is None:
        return None
    p = Path(path).resolve()
    if working_dir:
        root = Path(working_dir).resolve()
        try:
            return str(p.relative_to(root))
        except ValueError:
            raise prism.SettingsError(
                f"{path} is outside the working_dir {working_dir} that is shipped to the workers"
            ) from None
    return str(p)


def _write_atomically(path: Path, data: bytes) -> None:
    """A temporary file in the target's folder, renamed over it once complete (the
    library's convention: `.prism-*.part`, which a later run cleans up)."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".prism-", suffix=".part")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def _gather(ray, refs: Dict[Any, Any], what: str, on_result, progress: bool,
            stats: Optional[List[Dict[str, float]]]) -> None:
    """Waits for every task, handing each result to ``on_result(key, value)`` as it
    arrives; failures are collected and raised together once the rest are done."""
    bar = None
    if progress:
        try:
            from tqdm.auto import tqdm

            bar = tqdm(total=len(refs), unit=what + "s")
        except ImportError:
            pass
    key_of = {ref: key for key, ref in refs.items()}
    pending = list(refs.values())
    failures = []
    try:
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            for ref in done:
                key = key_of[ref]
                try:
                    value, timing = ray.get(ref)
                except Exception as err:  # a task's error, after Ray's retries
                    failures.append((key, getattr(err, "cause", None) or err))
                    continue
                timing["received"] = time.time()
                on_result(key, value)
                if stats is not None:
                    stats.append(timing)
                if bar is not None:
                    bar.update(1)
    except BaseException:
        for ref in pending:
            ray.cancel(ref, force=True)
        raise
    finally:
        if bar is not None:
            bar.close()
    if failures:
        raise TaskFailed(what, sorted(failures, key=lambda f: f[0]))


def animate(anim_path: str, output: str, frames: Optional[str] = None,
            address: Optional[str] = None, working_dir: Optional[str] = None,
            cpus_per_task: int = 1, max_retries: int = 3, keep_frames: bool = False,
            progress: bool = True, stats: Optional[List[Dict[str, float]]] = None,
            **ray_init: Any) -> Dict[str, Any]:
    """Renders an animation on Ray; the same files as ``prism animate ANIM OUTPUT
    [--frames A..B]``. Returns what :func:`prism.animate` returns."""
    anim = prism.Animation(anim_path)
    start, end = anim.frame_range(frames)
    todo = anim.prepare(output, start, end)
    suffix = Path(anim.frame_path(output, 0)).suffix
    if todo:
        ray = _init_ray(address, working_dir, **ray_init)
        task = ray.remote(num_cpus=cpus_per_task, max_retries=max_retries)(_frame_task)
        path = _task_path(anim_path, working_dir)
        refs = {k: task.remote(path, anim.fingerprint, suffix, k, cpus_per_task) for k in todo}

        def write(k: int, data: bytes) -> None:
            _write_atomically(Path(anim.frame_path(output, k)), data)

        _gather(ray, refs, "frame", write, progress, stats)
    result = dict(anim.finish(output, keep_frames))
    result.update(rendered=len(todo), skipped=(end - start) - len(todo))
    return result


def tiles_of(height: int, width: int, count: int) -> List[Tuple[int, int, int, int]]:
    """``count`` bands of whole rows covering the frame (fewer when it has fewer rows)."""
    count = max(1, min(count, height))
    edges = [round(i * height / count) for i in range(count + 1)]
    return [(0, y0, width, y1 - y0) for y0, y1 in zip(edges, edges[1:])]


def render(scene_path: str, output: Optional[str] = None, camera: Optional[str] = None,
           tiles: int = 8, dialect: Optional[str] = None, address: Optional[str] = None,
           working_dir: Optional[str] = None, cpus_per_task: int = 1, max_retries: int = 3,
           exposure: Optional[float] = None, tonemap: Optional[str] = None,
           progress: bool = True, stats: Optional[List[Dict[str, float]]] = None,
           ray_init: Optional[Dict[str, Any]] = None, **options: Any) -> np.ndarray:
    """Renders a still as ``tiles`` Ray tasks and returns the assembled H x W x 3
    float32 image (equal to :func:`prism.render` with the same options); with
    ``output``, also writes it as ``prism render SCENE [CAMERA] OUTPUT`` would."""
    scene = prism.load_scene(scene_path, dialect)
    cam = prism.Camera.from_file(camera) if camera else None
    options = {k: v for k, v in options.items() if v is not None}
    # The development is resolved with the rest of the job, as prism render does.
    develop = {k: v for k, v in (("exposure", exposure), ("tonemap", tonemap)) if v is not None}
    plan = prism.plan(scene, cam, **options, **develop)
    width, height = plan["width"], plan["height"]
    image = np.empty((height, width, 3), dtype=np.float32)
    ray = _init_ray(address, working_dir, **(ray_init or {}))
    task = ray.remote(num_cpus=cpus_per_task, max_retries=max_retries)(_tile_task)
    opts = dict(options, threads=cpus_per_task)
    paths = (_task_path(scene_path, working_dir), _task_path(camera, working_dir))
    refs = {r: task.remote(paths[0], dialect, paths[1], opts, r)
            for r in tiles_of(height, width, tiles)}

    def place(region: Tuple[int, int, int, int], pixels: np.ndarray) -> None:
        x, y, w, h = region
        image[y:y + h, x:x + w] = pixels

    _gather(ray, refs, "tile", place, progress, stats)
    if output is not None:
        prism.write_image(image, output, exposure=plan["exposure"], tonemap=plan["tonemap"],
                          transfer=plan["transfer"])
    return image


# ---------------------------------------------------------------------------------------
# Command line.


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m prism.distributed",
                                description="Render Prism stills and animations on Ray.")
    sub = p.add_subparsers(dest="command", required=True)

    def cluster(s: argparse.ArgumentParser) -> None:
        s.add_argument("--address", help="Ray cluster to join (e.g. auto, ray://HOST:10001); "
                                         "default: a local cluster")
        s.add_argument("--working-dir", help="ship this folder to the workers (Ray "
                                             "runtime_env); input paths must be inside it")
        s.add_argument("--cpus-per-task", type=int, default=1,
                       help="cores each task reserves and renders with")
        s.add_argument("--retries", type=int, default=3,
                       help="times a task whose worker died is run again")
        s.add_argument("--quiet", "-q", action="store_true", help="no progress bar")
        s.add_argument("--stats", action="store_true",
                       help="print the tasks' mean start, load, render and transfer times")

    r = sub.add_parser("render", help="a still, as tiles")
    r.add_argument("scene")
    r.add_argument("paths", nargs="+", metavar="[CAMERA] OUTPUT")
    r.add_argument("--tiles", type=int, default=8)
    r.add_argument("--dialect", choices=["objx", "obj", "toml"])
    for name in ("width", "height", "aa", "seed", "max_depth"):
        r.add_argument("--" + name.replace("_", "-"), type=int)
    # --dof-rays and --aa-filter are the older names of --spp and --filter.
    r.add_argument("--spp", "--dof-rays", dest="spp", type=int)
    r.add_argument("--filter", "--aa-filter", dest="filter",
                   choices=["nearest", "bilinear", "area", "bicubic", "lanczos"])
    r.add_argument("--integrator", choices=["classic", "whitted"])
    r.add_argument("--accel", choices=["bvh", "bvh-copied", "octree", "list"])
    r.add_argument("--min-weight", type=float)
    r.add_argument("--exposure", type=float)
    r.add_argument("--tonemap", choices=["clamp", "reinhard", "aces"])
    cluster(r)

    a = sub.add_parser("animate", help="the frames of an animation, and its video")
    a.add_argument("animation")
    a.add_argument("output")
    a.add_argument("--frames", metavar="A..B")
    a.add_argument("--keep-frames", action="store_true")
    cluster(a)
    return p


def _print_stats(stats: List[Dict[str, float]], submitted: float) -> None:
    if not stats:
        return
    n = len(stats)
    mean = lambda xs: sum(xs) / n  # noqa: E731
    print(f"tasks {n}  start {mean([s['start'] - submitted for s in stats]):.3f}s (from "
          f"submission, queueing included)  load {mean([s['load'] for s in stats]):.3f}s  "
          f"render {mean([s['render'] for s in stats]):.3f}s  transfer "
          f"{mean([s['received'] - s['end'] for s in stats]):.3f}s")


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = _parser().parse_args(argv)
    stats: Optional[List[Dict[str, float]]] = [] if args.stats else None
    common = dict(address=args.address, working_dir=args.working_dir,
                  cpus_per_task=args.cpus_per_task, max_retries=args.retries,
                  progress=not args.quiet and sys.stderr.isatty(), stats=stats)
    submitted = time.time()
    try:
        if args.command == "render":
            if len(args.paths) > 2:
                raise prism.SettingsError("expected [CAMERA] OUTPUT after the scene")
            camera, output = (None, args.paths[0]) if len(args.paths) == 1 else args.paths
            options = {k: getattr(args, k) for k in (
                "width", "height", "aa", "spp", "seed", "max_depth", "filter",
                "integrator", "accel", "min_weight")}
            render(args.scene, output, camera=camera, tiles=args.tiles, dialect=args.dialect,
                   exposure=args.exposure, tonemap=args.tonemap, **common, **options)
        else:
            result = animate(args.animation, args.output, frames=args.frames,
                             keep_frames=args.keep_frames, **common)
            if result["missing"] and Path(args.output).suffix:
                print(f"note: {result['missing']} frames of the animation are not rendered "
                      f"yet: {args.output} is made by the run that completes them",
                      file=sys.stderr)
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except (prism.PrismError, ValueError, OSError) as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    if stats is not None:
        _print_stats(stats, submitted)
    return 0


if __name__ == "__main__":
    sys.exit(main())
