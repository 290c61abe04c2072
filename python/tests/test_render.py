"""Rendering to arrays: shapes, dtypes, options, the command line's pixels bit for bit,
progress, the GIL, and Ctrl-C."""

import _thread
import signal
import threading
import time

import numpy as np
import pytest

import prism
from conftest import SCENES, read_ppm, run_cli, same_bits

EXAMPLE = SCENES / "example" / "example.objx"
EXAMPLE_CMR = SCENES / "example" / "example.cmr"
SHOWCASE = SCENES / "showcase" / "showcase.toml"


@pytest.fixture(scope="module")
def example():
    return prism.load_scene(EXAMPLE), prism.Camera.from_file(EXAMPLE_CMR)


def test_shapes_and_dtypes(example):
    scene, camera = example
    linear = prism.render(scene, camera, width=64)
    assert linear.shape == (36, 64, 3) and linear.dtype == np.float32  # 16:9 kept
    assert 0.0 <= linear.min() and linear.max() <= 1.0 and linear.max() > 0.1
    display = prism.render(scene, camera, width=64, height=20, srgb=True)
    assert display.shape == (20, 64, 3) and display.dtype == np.uint8
    assert prism.plan(scene, camera, width=64)["height"] == 36


@pytest.mark.parametrize("scene_path,camera,options", [
    (EXAMPLE, EXAMPLE_CMR, dict(width=120, aa=2)),
    (SHOWCASE, None, dict(width=96, height=54, seed=3)),
    (SHOWCASE, None, dict(width=64, spp=2, exposure=1.5, tonemap="aces")),
    (SHOWCASE, None, dict(width=64, height=36, spp=2, integrator="path", light_sampling="one")),
])
def test_pixels_equal_the_command_line(prism_bin, tmp_path, scene_path, camera, options):
    cli_args = [scene_path] + ([camera] if camera else [])
    flags = [x for k, v in options.items() for x in (f"--{k.replace('_', '-')}", v)]
    run_cli(prism_bin, "render", *cli_args, tmp_path / "cli.ppm", *flags)
    run_cli(prism_bin, "render", *cli_args, tmp_path / "cli.png", *flags)
    scene = prism.load_scene(scene_path)
    cam = prism.Camera.from_file(camera) if camera else None
    pixels = prism.render(scene, cam, srgb=True, **options)
    assert same_bits(pixels, read_ppm(tmp_path / "cli.ppm"))
    # Linear pixels written with the plan's development: the CLI's PNG, byte for byte.
    plan = prism.plan(scene, cam, **options)
    prism.write_image(prism.render(scene, cam, **options), tmp_path / "py.png",
                      exposure=plan["exposure"], tonemap=plan["tonemap"],
                      transfer=plan["transfer"])
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()


def test_one_shadow_ray_a_bounce_renders_the_same_light_with_other_noise():
    scene = prism.load_scene(SHOWCASE)
    options = dict(width=48, height=27, spp=16, integrator="path")
    every = prism.render(scene, **options, light_sampling="all")
    for way in ("one", "tree"):
        one = prism.render(scene, **options, light_sampling=way)
        assert not same_bits(every, one)
        assert abs(one.mean() / every.mean() - 1) < 0.05, way
    assert same_bits(every, prism.render(scene, **options))  # two lights: auto is all
    with pytest.raises(ValueError, match="unknown light sampling"):
        prism.render(scene, **options, light_sampling="some")


def test_look_at_camera_equals_the_command_line(prism_bin, tmp_path):
    run_cli(prism_bin, "render", SHOWCASE, tmp_path / "cli.ppm", "--look-from", "0,3,9",
            "--look-at", "0,1,0", "--fov", "50", "--width", "80", "--height", "40")
    camera = prism.Camera.look_at((0, 3, 9), (0, 1, 0), fov=50, width=80, height=40)
    pixels = prism.render(prism.load_scene(SHOWCASE), camera, srgb=True)
    assert same_bits(pixels, read_ppm(tmp_path / "cli.ppm"))
    assert "look_at" in repr(camera)
    with pytest.raises(ValueError):
        prism.Camera.look_at((1, 1, 1), (1, 1, 1))


def test_a_region_is_a_crop_of_the_full_frame(example):
    scene, camera = example
    full = prism.render(scene, camera, width=96, aa=2, filter="lanczos")
    part = prism.render(scene, camera, width=96, aa=2, filter="lanczos", region=(10, 7, 30, 20))
    assert same_bits(part, np.ascontiguousarray(full[7:27, 10:40]))


def test_every_intersector_gives_the_same_pixels():
    scene = prism.load_scene(SHOWCASE)
    renders = {accel: prism.render(scene, width=64, height=36, accel=accel)
               for accel in ("bvh", "bvh-copied", "octree", "list")}
    for accel, pixels in renders.items():
        assert same_bits(pixels, renders["bvh"]), accel
    with pytest.raises(ValueError, match="expected bvh, bvh-copied, octree or list"):
        prism.render(scene, width=64, height=36, accel="kd-tree")


def test_bad_options_raise(example):
    scene, camera = example
    with pytest.raises(prism.SettingsError):
        prism.render(scene, camera, width=64, region=(60, 0, 10, 10))
    with pytest.raises(ValueError, match="unknown filter"):
        prism.render(scene, camera, width=64, filter="gauss")
    with pytest.raises(TypeError, match="unknown render option"):
        prism.render(scene, camera, colour=3)


def test_a_render_over_its_memory_budget_raises(example):
    scene, camera = example
    with pytest.raises(prism.SettingsError, match="memory budget of 64 KiB"):
        prism.render(scene, camera, width=64, max_memory="64K")
    with pytest.raises(prism.SettingsError, match="memory budget of 64 KiB"):
        prism.render(scene, camera, width=64, max_memory=65536)
    with pytest.raises(ValueError, match="expected a size"):
        prism.render(scene, camera, width=64, max_memory="lots")
    assert prism.render(scene, camera, width=64, max_memory="256M").shape == (36, 64, 3)


def test_progress_is_reported_up_to_the_total(example):
    scene, camera = example
    calls = []
    prism.render(scene, camera, width=64, progress=lambda done, total: calls.append((done, total)))
    assert calls and calls[-1][0] == calls[-1][1] > 0
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)
    prism.render(scene, camera, width=32, progress=True)  # a tqdm bar
    with pytest.raises(TypeError):
        prism.render(scene, camera, width=32, progress=3)


def test_an_exception_in_the_progress_callback_stops_the_render(example):
    scene, camera = example

    def fail(done, total):
        raise RuntimeError("stop")

    with pytest.raises(RuntimeError, match="stop"):
        prism.render(scene, camera, width=2000, aa=4, progress=fail)


def big_render():
    return prism.load_scene(SHOWCASE), dict(width=3840, height=2160, aa=4)


@pytest.fixture
def ctrl_c():
    """Presses Ctrl-C after a delay: `fired = ctrl_c(0.3)` gets the time it was pressed.

    Python's own SIGINT handler is installed for the test: a process that inherited
    SIGINT ignored (a background job of a non-interactive shell) would not see the
    press, and the render waiting for it would run to its end."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timers = []

    def press(after):
        fired = []

        def interrupt():
            fired.append(time.monotonic())
            _thread.interrupt_main()

        timer = threading.Timer(after, interrupt)
        timers.append(timer)
        timer.start()
        return fired

    yield press
    for timer in timers:
        timer.cancel()
    signal.signal(signal.SIGINT, previous)


def test_the_gil_is_released_while_rendering(ctrl_c):
    scene, options = big_render()
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.01)

    counter = threading.Thread(target=count)
    counter.start()
    ctrl_c(0.5)
    try:
        with pytest.raises(KeyboardInterrupt):
            prism.render(scene, **options)
    finally:
        stop.set()
        counter.join()
    assert len(ticks) >= 20  # the other thread ran all along


def test_ctrl_c_stops_a_render_promptly(ctrl_c):
    scene, options = big_render()
    fired = ctrl_c(0.3)
    with pytest.raises(KeyboardInterrupt):
        prism.render(scene, **options)
    assert time.monotonic() - fired[0] < 2.0


def test_width_alone_keeps_the_scene_files_aspect():
    image = prism.render(prism.load_scene(SHOWCASE), width=96, aa=1)
    assert image.shape == (54, 96, 3)


def test_the_namespace_is_what_the_package_offers():
    names = dir(prism)
    assert "render" in names and "scene_from_dict" in names and "load_scene" in names
    for stray in ("np", "Any", "Dict", "Optional", "Tuple", "Union"):
        assert stray not in names


def test_a_tqdm_bar_starts_with_its_total(example, capsys):
    pytest.importorskip("tqdm")
    scene, camera = example
    prism.render(scene, camera, width=32, progress=True)
    err = capsys.readouterr().err
    assert "0rows [" not in err
    assert "rows" in err


def test_old_option_names_are_aliases(example):
    scene, camera = example
    new = prism.render(scene, camera, width=48, aa=2, spp=3)
    old = prism.render(scene, camera, width=48, aa=2, dof_rays=3)
    assert same_bits(new, old)
    assert not same_bits(new, prism.render(scene, camera, width=48, aa=2, spp=3, seed=4))


def test_the_plan_carries_the_development_given(example):
    scene, camera = example
    plan = prism.plan(scene, None, exposure=2.0, tonemap="reinhard", png_bits=16)
    assert (plan["exposure"], plan["tonemap"], plan["transfer"]) == (2.0, "reinhard", "classic")
    assert plan["png_bits"] == "16"
    with pytest.raises(ValueError, match="tone map"):
        prism.plan(scene, None, tonemap="filmic")


def test_a_preview_sees_the_image_form_and_ends_on_the_final_one(example):
    scene, camera = example
    frames = []
    options = dict(width=160, aa=2, spp=8)
    data, w, h, dtype = prism._prism.render(
        scene, camera, options, None, True,
        lambda rgb8, width, height: frames.append((bytes(rgb8), width, height)))
    assert dtype == "u1" and frames
    assert all((fw, fh) == (w, h) and len(f) == w * h * 3 for f, fw, fh in frames)
    # The last frame shown is the image returned, which is what srgb=True gives.
    assert frames[-1][0] == bytes(data)
    final = prism.render(scene, camera, srgb=True, **options)
    assert frames[-1][0] == final.tobytes()
    # A frame shown before the end is part of the way there (rows still black), or the
    # whole image if the last rows landed just before it.
    for f, _, _ in frames[:-1]:
        rows = np.frombuffer(f, np.uint8).reshape(h, w * 3)
        assert f == frames[-1][0] or (rows.max(axis=1) == 0).any()


def test_show_updates_one_image_in_the_notebook_cell(example, monkeypatch):
    import sys
    import types

    shown = []

    class Handle:
        def update(self, image):
            shown.append(image)

    display_module = types.ModuleType("IPython.display")
    display_module.Image = lambda data, format: (format, data)
    display_module.display = lambda image, display_id: shown.append(image) or Handle()
    monkeypatch.setitem(sys.modules, "IPython", types.ModuleType("IPython"))
    monkeypatch.setitem(sys.modules, "IPython.display", display_module)
    scene, camera = example
    pixels = prism.render(scene, camera, width=64, show=True)
    assert pixels.dtype == np.float32
    assert shown and all(fmt == "png" and png[:8] == b"\x89PNG\r\n\x1a\n" for fmt, png in shown)
    # Sample passes: one image per pass, the first displayed and the rest updating it.
    shown.clear()
    passes = prism.render_progressive(scene, camera, width=32, integrator="path", spp=4, show=True)
    assert [spp for spp, image in passes] == [1, 2, 4]
    assert len(shown) == 3 and all(fmt == "png" for fmt, _ in shown)
    final = prism.render(scene, camera, width=32, integrator="path", spp=4, srgb=True)
    h, w, _ = final.shape
    assert shown[-1][1] == prism._prism.encode_png(final.tobytes(), w, h)
    monkeypatch.delitem(sys.modules, "IPython.display")
    monkeypatch.setitem(sys.modules, "IPython", None)
    with pytest.raises(ImportError, match="IPython"):
        prism.render(scene, camera, width=16, show=True)


def test_the_path_model_renders_the_same_on_any_thread_count():
    scene = prism.load_scene(SHOWCASE)
    one = prism.render(scene, width=48, aa=1, integrator="path", spp=4, threads=1)
    two = prism.render(scene, width=48, aa=1, integrator="path", spp=4, threads=2)
    assert one.shape == (27, 48, 3)
    assert np.isfinite(one).all() and (one >= 0).all()
    assert np.array_equal(one, two)
    whitted = prism.render(scene, width=48, aa=1, integrator="whitted")
    assert not np.array_equal(one, whitted)


def test_passes_line_up_with_the_image_and_say_what_each_pixel_sees():
    scene = prism.load_scene(SHOWCASE)
    options = dict(width=64, aa=1, integrator="path", spp=2)
    image = prism.render(scene, **options)
    passes = prism.render_passes(scene, ("albedo", "normal", "depth"), **options)
    assert passes["albedo"].shape == image.shape
    assert passes["depth"].shape == image.shape[:2]
    # Normals are unit vectors where a surface is seen (depth > 0), zero elsewhere;
    # only pixels on an edge average two of them.
    seen = passes["depth"] > 0
    lengths = np.linalg.norm(passes["normal"], axis=-1)
    assert seen.any() and (~seen).any()  # the floor, and the sky above it
    assert np.mean(np.abs(lengths[seen] - 1.0) < 0.05) > 0.8
    assert (passes["albedo"][~seen] == 0).all() and (lengths[~seen] == 0).all()
    with pytest.raises(ValueError, match="albedo, normal, depth, alpha or background"):
        prism.render_passes(scene, ("shadows",), **options)


def test_alpha_and_background_passes_make_a_transparent_film():
    scene = prism.load_scene(SHOWCASE)
    options = dict(width=64, aa=2, integrator="path", spp=2)
    image = prism.render(scene, **options)
    passes = prism.render_passes(scene, ("alpha", "background", "depth"), **options)
    alpha, background = passes["alpha"], passes["background"]
    assert alpha.shape == image.shape[:2] and background.shape == image.shape
    assert ((alpha >= 0) & (alpha <= 1)).all()
    # Where no sample meets a surface the image is the background, exactly what the
    # pass holds (the same camera samples); where every sample does, the pass is black.
    sky, solid = alpha == 0, alpha == 1
    assert sky.any() and solid.any() and ((alpha > 0) & (alpha < 1)).any()  # edges
    np.testing.assert_allclose(image[sky], background[sky], rtol=1e-6, atol=1e-7)
    assert (background[solid] == 0).all()
    assert ((passes["depth"] > 0) == (alpha > 0)).all()


def test_progressive_passes_refine_to_the_rendered_image():
    scene = prism.load_scene(SHOWCASE)
    options = dict(width=48, aa=1, integrator="path", spp=6, seed=3)
    passes = list(prism.render_progressive(scene, **options))
    assert [spp for spp, _ in passes] == [1, 2, 4, 6]
    assert all(image.shape == (27, 48, 3) for _, image in passes)
    # Each pass is the mean of the samples so far: the first is a render of one
    # sample, the last the render of all, bit for bit.
    assert np.array_equal(passes[0][1], prism.render(scene, **dict(options, spp=1)))
    assert np.array_equal(passes[-1][1], prism.render(scene, **options))
    assert not np.array_equal(passes[0][1], passes[-1][1])
    # Developed as render(srgb=True) develops.
    developed = list(prism.render_progressive(scene, srgb=True, **options))
    assert developed[-1][1].dtype == np.uint8
    assert np.array_equal(developed[-1][1], prism.render(scene, srgb=True, **options))
    # A model that does not spread its samples gives one pass: the whole render.
    whitted = list(prism.render_progressive(scene, width=48, aa=1, integrator="whitted"))
    assert len(whitted) == 1
    assert np.array_equal(whitted[0][1], prism.render(scene, width=48, aa=1, integrator="whitted"))


def test_progressive_bad_options_raise_at_the_call_and_leaving_early_stops():
    scene = prism.load_scene(SHOWCASE)
    with pytest.raises(prism.SettingsError):
        prism.render_progressive(scene, integrator="path", spp=0)
    big = dict(width=1920, aa=2, integrator="path", spp=4096)
    # Closing (as leaving a loop does) stops the pass being rendered behind the one
    # given and waits for its thread: promptly, not after the 4096 samples.
    for passes in (prism.render_progressive(scene, **big), prism._prism.render_progressive(scene, None, big)):
        spp = next(passes)[0]
        assert spp == 1
        started = time.monotonic()
        passes.close()
        assert time.monotonic() - started < 2.0
        with pytest.raises(StopIteration):
            next(passes)


def test_close_from_another_thread_stops_the_pass_in_flight():
    # A host application (Blender's Esc) cancels from its own thread while another
    # waits on the pass being rendered: the waiting thread's loop ends promptly.
    import threading

    scene, options = big_render()
    passes = prism.render_progressive(scene, integrator="path", spp=4096, **options)
    got, raised = [], []

    def wait():
        try:
            got.extend(spp for spp, _ in passes)
        except BaseException as err:  # the loop must simply end
            raised.append(err)

    waiter = threading.Thread(target=wait)
    waiter.start()
    time.sleep(0.3)
    started = time.monotonic()
    passes.close()
    waiter.join(5.0)
    assert not waiter.is_alive() and time.monotonic() - started < 2.0
    assert not raised and all(spp < 4096 for spp in got)


def test_ctrl_c_stops_a_progressive_render_promptly(ctrl_c):
    scene, options = big_render()
    passes = prism.render_progressive(scene, integrator="path", spp=64, **options)
    fired = ctrl_c(0.3)
    with pytest.raises(KeyboardInterrupt):
        for _ in passes:
            pass
    assert time.monotonic() - fired[0] < 2.0


def test_the_extension_names_its_build():
    # The Blender benchmarks refuse to time anything but a release build.
    assert prism._prism.BUILD in ("debug", "release")
