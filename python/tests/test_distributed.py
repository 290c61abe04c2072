"""prism.distributed on a local Ray cluster: frames and tiles equal local renders bit
for bit, a task whose worker dies is retried, a rerun renders only missing frames, and
failures name their frame. About a minute (Ray's start-up is most of it)."""

import os

import numpy as np
import pytest

import prism
from conftest import SCENES, same_bits

ray = pytest.importorskip("ray", reason="ray is not installed (pip install ray)")
from prism import distributed  # noqa: E402

pytestmark = pytest.mark.ray


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    """Two CPUs, and the crash hook armed by creating the file it names."""
    marker = tmp_path_factory.mktemp("crash") / "crash-once"
    ray.init(num_cpus=2, log_to_driver=False, include_dashboard=False,
             runtime_env={"env_vars": {distributed.CRASH_ENV: str(marker)}})
    yield marker
    ray.shutdown()


def frames_of(folder):
    return {p.name: p.read_bytes() for p in sorted(folder.glob("frame_*.png"))}


def test_an_animation_equals_the_local_render(cluster, small_animation, tmp_path):
    prism.animate(small_animation, tmp_path / "local")
    result = distributed.animate(str(small_animation), str(tmp_path / "ray"), progress=False)
    assert (result["rendered"], result["skipped"], result["missing"]) == (6, 0, 0)
    assert frames_of(tmp_path / "ray") == frames_of(tmp_path / "local")
    assert len(frames_of(tmp_path / "ray")) == 6
    assert not list((tmp_path / "ray").glob(".prism-*.part"))


def test_a_video_is_encoded_once_every_frame_exists(cluster, small_animation, tmp_path):
    prism.animate(small_animation, tmp_path / "local.gif")
    part = distributed.animate(str(small_animation), str(tmp_path / "ray.gif"), frames="0..3",
                               progress=False)
    assert part["video"] is None and part["missing"] == 3
    assert not (tmp_path / "ray.gif").exists()
    rest = distributed.animate(str(small_animation), str(tmp_path / "ray.gif"), progress=False)
    assert (rest["rendered"], rest["skipped"]) == (3, 3)
    assert (tmp_path / "ray.gif").read_bytes() == (tmp_path / "local.gif").read_bytes()


def test_a_tiled_still_equals_the_full_render(cluster, tmp_path):
    scene_path = SCENES / "example" / "example.objx"
    camera = SCENES / "example" / "example.cmr"
    options = dict(width=96, aa=2, filter="bicubic")
    tiled = distributed.render(str(scene_path), str(tmp_path / "tiled.png"), camera=str(camera),
                               tiles=5, progress=False, **options)
    scene = prism.load_scene(scene_path)
    local = prism.render(scene, prism.Camera.from_file(camera), **options)
    assert same_bits(tiled, local)
    prism.write_image(local, tmp_path / "local.png", transfer="classic")
    assert (tmp_path / "tiled.png").read_bytes() == (tmp_path / "local.png").read_bytes()


def test_a_task_whose_worker_dies_is_retried(cluster, small_animation, tmp_path):
    cluster.write_text("armed")
    prism.animate(small_animation, tmp_path / "local", frames="0..2")
    distributed.animate(str(small_animation), str(tmp_path / "ray"), frames="0..2",
                        progress=False)
    assert not cluster.exists() and cluster.with_name("crash-once.fired").exists()
    assert frames_of(tmp_path / "ray") == frames_of(tmp_path / "local")


def test_a_rerun_renders_only_the_missing_frames(cluster, small_animation, tmp_path):
    out = tmp_path / "ray"
    distributed.animate(str(small_animation), str(out), frames="0..4", progress=False)
    os.remove(out / "frame_0002.png")
    kept = (out / "frame_0000.png").stat().st_mtime_ns
    result = distributed.animate(str(small_animation), str(out), progress=False)
    assert (result["rendered"], result["skipped"]) == (3, 3)  # frames 2, 4, 5
    assert (out / "frame_0000.png").stat().st_mtime_ns == kept
    assert len(frames_of(out)) == 6


def test_a_failed_task_is_reported_with_its_key(cluster, tmp_path):
    good = str(SCENES / "example" / "example.objx")
    task = ray.remote(max_retries=0)(distributed._tile_task)
    refs = {k: task.remote(path, None, None, {"width": 16}, (0, 0, 16, 9))
            for k, path in [(0, good), (7, str(tmp_path / "missing.objx"))]}
    got = {}
    with pytest.raises(distributed.TaskFailed) as caught:
        distributed._gather(ray, refs, "frame", got.__setitem__, False, None)
    assert [k for k, _ in caught.value.failures] == [7]
    assert "frame 7:" in str(caught.value) and "missing.objx" in str(caught.value)
    assert list(got) == [0] and got[0].shape == (9, 16, 3)


def test_tiles_cover_the_frame():
    tiles = distributed.tiles_of(10, 4, 3)
    assert tiles == [(0, 0, 4, 3), (0, 3, 4, 4), (0, 7, 4, 3)]
    assert distributed.tiles_of(2, 4, 8) == [(0, 0, 4, 1), (0, 1, 4, 1)]


def test_the_command_line(cluster, tmp_path, small_animation):
    assert distributed.main(["animate", str(small_animation), str(tmp_path / "f"),
                             "--frames", "0..2", "-q"]) == 0
    assert len(frames_of(tmp_path / "f")) == 2
    scene = SCENES / "example" / "example.objx"
    assert distributed.main(["render", str(scene), str(SCENES / "example" / "example.cmr"),
                             str(tmp_path / "s.png"), "--width", "48", "--tiles", "3",
                             "-q"]) == 0
    assert (tmp_path / "s.png").stat().st_size > 0
    assert distributed.main(["render", str(tmp_path / "none.objx"), str(tmp_path / "x.png"),
                             "-q"]) == 2
