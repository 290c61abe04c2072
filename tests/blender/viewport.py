"""The viewport test, in Blender with its interface (under Xvfb, Mesa's software
OpenGL): the 3D view in Rendered shading with Prism runs view_update and view_draw,
a screenshot shows the render, and moving the light renders again.

    xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup \\
        --python tests/blender/viewport.py [-- OUT_FOLDER]

Blender's interface runs after this script returns, so the test is a sequence of
steps on a timer; it ends Blender with exit code 0 when every check passed, else 1,
and leaves viewport-before.png and viewport-after.png in OUT_FOLDER (default: a
temporary folder).
"""

import os
import sys
import tempfile
import traceback

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "blender"))
os.environ.setdefault("PRISM_PYTHON_PATH", os.path.join(REPO, "python"))

import prism_blender  # noqa: E402
from prism_blender import engine  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
OUT = argv[0] if argv else tempfile.mkdtemp(prefix="prism-viewport-")
os.makedirs(OUT, exist_ok=True)
calls = {"view_update": 0, "view_draw": 0, "restarts": 0}


def _count(name):
    method = getattr(engine.PrismRenderEngine, name)

    # Blender calls an engine's methods by their signature: it is kept.
    def counted(self, context, depsgraph):
        calls[name] += 1
        return method(self, context, depsgraph)

    setattr(engine.PrismRenderEngine, name, counted)


def _count_restarts():
    restart = engine.ViewportSession.restart

    def counted(self, *args):
        calls["restarts"] += 1
        return restart(self, *args)

    engine.ViewportSession.restart = counted


def _view3d():
    window = bpy.context.window_manager.windows[0]
    for area in window.screen.areas:
        if area.type == "VIEW_3D":
            region = next(r for r in area.regions if r.type == "WINDOW")
            return window, area, region
    raise RuntimeError("no 3D view")


def _screenshot(name):
    window, area, region = _view3d()
    path = os.path.join(OUT, name)
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.screen.screenshot_area(filepath=path)
    image = bpy.data.images.load(path)
    w, h = image.size
    pixels = np.empty(w * h * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    bpy.data.images.remove(image)
    return pixels.reshape(h, w, 4)[..., :3]


def _finish(ok, message=""):
    print(("viewport test passed" if ok else "viewport test FAILED") + (f": {message}" if message else ""))
    print(f"viewport screenshots in {OUT}; calls {calls}; errors "
          f"{[s.error for s in _sessions() if s is not None]}")
    sys.stdout.flush()
    os._exit(0 if ok else 1)


state = {"step": 0, "ticks": 0, "before": None}


def _settled():
    """Whether the viewport's render has finished its passes."""
    sessions = [s for s in _sessions() if s is not None]
    return bool(sessions) and all(s.done for s in sessions)


def _sessions():
    import gc

    return [getattr(o, "_view", None) for o in gc.get_objects()
            if isinstance(o, engine.PrismRenderEngine)]


def _redraw():
    # Tagged only: Blender's own loop redraws it. Forcing a draw from the timer with
    # `wm.redraw_timer` crashed Blender 3.4 in about one run in ten: a segfault in
    # CPython's `_PyErr_Fetch`, called from inside the operator on the main thread.
    _, area, _ = _view3d()
    area.tag_redraw()


def tick():
    try:
        state["ticks"] += 1
        if state["ticks"] > 600:
            _finish(False, f"timed out at step {state['step']}")
        _redraw()
        if state["step"] == 0:
            scene = bpy.context.scene
            scene.render.engine = "PRISM"
            scene.prism.preview_samples = 4
            # In the factory scene, a floor all round: the first-run splash hides the
            # middle of the view, not the floor's light (a file given has no splash).
            if not bpy.data.filepath:
                bpy.ops.mesh.primitive_plane_add(size=60, location=(0, 0, -1))
            _, area, _ = _view3d()
            area.spaces[0].shading.type = "RENDERED"
            state["step"] = 1
        elif state["step"] == 1 and _settled():
            state["before"] = _screenshot("viewport-before.png")
            light = next(o for o in bpy.data.objects if o.type == "LIGHT")
            light.data.energy *= 8
            state["restarts"] = calls["restarts"]
            state["step"] = 2
        elif state["step"] == 2 and calls["restarts"] > state["restarts"] and _settled():
            after = _screenshot("viewport-after.png")
            before = state["before"]
            checks = [
                (calls["view_update"] >= 2, "view_update ran for the first view and the edit"),
                (calls["view_draw"] >= 2, "view_draw ran"),
                (float(before.std()) > 0.02, "the viewport shows an image, not a flat colour"),
                (float(after.mean()) > float(before.mean()) + 0.01,
                 "a brighter light renders a brighter view"),
            ]
            failed = [text for ok, text in checks if not ok]
            print(f"viewport mean before {before.mean():.4f}, after {after.mean():.4f}")
            _finish(not failed, "; ".join(failed))
        return 0.1
    except Exception:
        traceback.print_exc()
        _finish(False, "an exception")


prism_blender.register()
_count("view_update")
_count("view_draw")
_count_restarts()
bpy.app.timers.register(tick, first_interval=1.0)
