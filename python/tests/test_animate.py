"""prism.animate: the frames and videos of `prism animate`, resuming, and errors."""

import pytest

import prism
from conftest import run_cli


def test_frames_equal_the_command_line(prism_bin, small_animation, tmp_path):
    run_cli(prism_bin, "animate", small_animation, tmp_path / "cli", "--frames", "1..4")
    result = prism.animate(small_animation, tmp_path / "py", frames="1..4")
    assert (result["rendered"], result["skipped"], result["video"]) == (3, 0, None)
    assert result["missing"] == 3
    for k in (1, 2, 3):
        name = f"frame_{k:04d}.png"
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    assert not (tmp_path / "py" / "frame_0000.png").exists()


def test_a_rerun_renders_only_missing_frames(small_animation, tmp_path):
    out = tmp_path / "frames"
    prism.animate(small_animation, out, frames="0..2")
    before = (out / "frame_0000.png").stat().st_mtime_ns
    calls = []
    result = prism.animate(small_animation, out, progress=lambda d, t: calls.append((d, t)))
    assert (result["rendered"], result["skipped"], result["missing"]) == (4, 2, 0)
    assert (out / "frame_0000.png").stat().st_mtime_ns == before
    assert calls[-1] == (4, 4)


def test_a_video_equals_the_command_line(prism_bin, small_animation, tmp_path):
    run_cli(prism_bin, "animate", small_animation, tmp_path / "cli.gif")
    result = prism.animate(small_animation, tmp_path / "py.gif")
    assert result["video"]["frames"] == 6
    assert (tmp_path / "py.gif").read_bytes() == (tmp_path / "cli.gif").read_bytes()
    assert not (tmp_path / "py.gif.frames").exists()  # frames removed once encoded


def test_animation_properties(small_animation):
    anim = prism.Animation(small_animation)
    assert (anim.frames, anim.fps, anim.size) == (6, 24.0, (64, 36))
    assert anim.frame_range("2..=3") == (2, 4) and anim.frame_range() == (0, 6)
    assert len(anim.fingerprint) == 16
    with pytest.raises(prism.SettingsError, match="--frames"):
        anim.frame_range("4..9")


def test_an_error_in_the_animation_file_names_its_line(small_animation):
    text = small_animation.read_text().replace("fps = 24", "fps = 24\nspeed = 2")
    small_animation.write_text(text)
    with pytest.raises(prism.SceneError) as caught:
        prism.animate(small_animation, small_animation.parent / "out")
    assert caught.value.file == str(small_animation) and caught.value.line == 9


WHITTED_ANIMATION = """[camera]
from = [0, 0, 4]
at = [0, 0, 0]
[render]
width = 32
height = 18
exposure = 0.5
tonemap = "reinhard"
[animation]
frames = 2
[[object]]
name = "ball"
type = "sphere"
radius = 1
material = { color = [0.9, 0.4, 0.2] }
[[light]]
type = "point"
position = [2, 2, 4]
intensity = 4
[[track]]
target = "object:ball"
motion = "translate"
keys = [[0, [0, 0, 0]], [0.04, [0.5, 0, 0]]]
"""


def test_a_whitted_animations_frames_and_video_equal_the_command_lines(prism_bin, tmp_path):
    scene = tmp_path / "ball.toml"
    scene.write_text(WHITTED_ANIMATION)
    run_cli(prism_bin, "animate", scene, tmp_path / "cli")
    prism.animate(scene, tmp_path / "py")
    for k in (0, 1):
        name = f"frame_{k:04d}.png"
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    # The film leaves the stamp `prism animate` leaves: a rerun there does no work.
    prism.animate(scene, tmp_path / "film.gif")
    assert (tmp_path / ".film.gif.prism").is_file()
    import subprocess
    out = subprocess.run([str(prism_bin), "animate", str(scene), str(tmp_path / "film.gif")],
                         check=True, capture_output=True, text=True)
    assert "nothing to do" in out.stderr
