"""Prism as a Blender render engine: F12 and the viewport, both through `export`."""

import queue
import threading

import bpy
import numpy as np

from . import export as exporter
from . import properties, runtime
from .camera import view_dict

#: How often F12 looks at Esc while a pass renders (seconds).
POLL = 0.05
#: The passes Prism adds for the compositor: name, channels, channel letters.
EXTRA_PASSES = (("Depth", 1, "Z"), ("Normal", 3, "XYZ"), ("Denoising Albedo", 3, "RGB"))


def rgba_rows(image, alpha=None):
    """An H x W x 3 image (top row first) as the W*H x 4 rows a render result takes
    (bottom row first), with alpha 1 where none is given."""
    h, w, _ = image.shape
    out = np.empty((h, w, 4), dtype=np.float32)
    out[..., :3] = image[::-1]
    out[..., 3] = 1.0 if alpha is None else alpha[::-1]
    return out.reshape(h * w, 4)


def set_rect(render_pass, rows):
    """Writes W*H x C rows into a render pass: `foreach_set` copies the buffer at
    once (5 ms for 1080p, where assigning `rect` converts float by float, 0.8 s).
    Blender 3.x takes the rows as they are, later versions flat as well."""
    rows = np.ascontiguousarray(rows, dtype=np.float32)
    for data in (rows, rows.reshape(-1)):
        try:
            render_pass.rect.foreach_set(data)
            return
        except (TypeError, ValueError, RuntimeError, AttributeError):
            continue
    render_pass.rect = rows


def resolution(scene):
    r = scene.render
    scale = r.resolution_percentage / 100.0
    return max(1, int(r.resolution_x * scale)), max(1, int(r.resolution_y * scale))


class _Pump:
    """Takes a render's passes on a thread of its own, so the caller can watch for a
    cancel while a pass renders; `stop()` cancels the pass in flight."""

    def __init__(self, passes):
        self.passes = passes
        self.queue = queue.Queue()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        try:
            for item in self.passes:
                self.queue.put(("pass", item))
        except BaseException as err:  # handed to the waiting thread
            self.queue.put(("error", err))
        self.queue.put(("end", None))

    def get(self, timeout):
        try:
            return self.queue.get(timeout=timeout)
        except queue.Empty:
            return None

    def stop(self):
        self.passes.close()
        self.thread.join()


def blender_depth(distance, camera):
    """Prism's depth (the distance along each pixel's ray; 0 where it escapes) as
    Blender's: the distance along the camera's view axis, 1e10 where nothing is met."""
    h, w = distance.shape
    z = distance.astype(np.float32)
    if camera.get("projection", "perspective") == "perspective":
        tan = np.tan(np.radians(camera["fov"]) / 2)
        if camera.get("fov_axis", "horizontal") == "horizontal":
            tx, ty = tan, tan * h / w
        else:
            tx, ty = tan * w / h, tan
        x = ((np.arange(w) + 0.5) / w * 2 - 1) * tx
        y = ((np.arange(h) + 0.5) / h * 2 - 1) * ty
        z = z / np.sqrt(1 + x[None, :] ** 2 + y[:, None] ** 2).astype(np.float32)
    return np.where(distance > 0, z, np.float32(1e10))


def _wanted_passes(layer, transparent):
    """Blender's pass name -> Prism's pass, for the passes this render writes."""
    cycles = getattr(layer, "cycles", None)
    wanted = {"Depth": ("depth", layer.use_pass_z), "Normal": ("normal", layer.use_pass_normal),
              "Denoising Albedo": ("albedo", bool(getattr(cycles, "denoising_store_passes",
                                                          False)))}
    out = {name: key for name, (key, on) in wanted.items() if on}
    if transparent:
        out.update(Alpha="alpha", Background="background")
    return out


def show_passes(passes, show, should_stop):
    """Hands each pass of `passes` (`prism.render_progressive`) to `show(samples,
    image)` as it comes, looking at `should_stop()` every POLL seconds meanwhile; a
    stop cancels the pass in flight. Returns whether it stopped early; raises what
    the render raised."""
    pump = _Pump(passes)
    while True:
        if should_stop():
            pump.stop()
            return True
        got = pump.get(POLL)
        if got is None:
            continue
        kind, item = got
        if kind == "end":
            return False
        if kind == "error":
            raise item
        show(*item)


class PrismRenderEngine(bpy.types.RenderEngine):
    bl_idname = "PRISM"
    bl_label = "Prism"
    bl_use_preview = False
    bl_use_eevee_viewport = False
    bl_use_shading_nodes_custom = False

    # Blender makes engines without calling __init__ on every version: the viewport's
    # session is found with getattr.
    _view = None
    _camera = None

    def __del__(self):
        view = getattr(self, "_view", None)
        if view is not None:
            view.stop()

    # ---- F12 ----------------------------------------------------------------

    def render(self, depsgraph):
        prism = runtime.load()
        if prism is None:
            self.report({"ERROR"}, f"Prism: {runtime.error()}")
            return
        scene = depsgraph.scene
        width, height = resolution(scene)
        camera = scene.camera.evaluated_get(depsgraph) if scene.camera else None
        if camera is None:
            self.report({"ERROR"}, "Prism: the scene has no camera")
            return
        self.update_stats("", "Prism: exporting the scene")
        made = exporter.export(depsgraph, width, height, camera_object=camera,
                               settings=properties.job_settings(scene))
        for warning in made.warnings:
            self.report({"WARNING"}, f"Prism: {warning}")
        self._camera = made.scene["camera"]
        try:
            prism_scene = prism.scene_from_dict(made.scene)
            options = {"threads": properties.threads(scene)}
            passes = None
            if scene.prism.denoise:
                try:
                    passes = prism.render_progressive(prism_scene, denoise=True, **options)
                    options["denoise"] = True
                except Exception as err:  # no denoiser in this Python: render without
                    self.report({"WARNING"}, f"Prism: not denoised: {err}")
            if passes is None:
                passes = prism.render_progressive(prism_scene, **options)
        except Exception as err:
            self.report({"ERROR"}, f"Prism: {err}")
            return
        self.render_passes_of(prism, prism_scene, passes, scene, width, height, options)

    def render_passes_of(self, prism, prism_scene, passes, scene, width, height, options):
        total = scene.prism.samples
        layer = bpy.context.view_layer or scene.view_layers[0]
        extras = _wanted_passes(layer, scene.render.film_transparent)
        for name, channels, letters in EXTRA_PASSES:
            if name in extras:
                self.add_pass(name, channels, letters)
        result = self.begin_result(0, 0, width, height)
        combined = result.layers[0].passes["Combined"]
        shown = []

        def show(samples, image):
            shown.append(image)
            set_rect(combined, rgba_rows(image))
            self.update_result(result)
            self.update_progress(min(1.0, samples / max(total, 1)))
            self.update_stats("", f"Prism: {samples} of {total} samples a pixel")

        try:
            cancelled = show_passes(passes, show, self.test_break)
        except Exception as err:
            self.report({"ERROR"}, f"Prism: {err}")
            cancelled = True
        if shown and not cancelled and extras:
            self._write_extra_passes(prism, prism_scene, result, shown[-1], extras, options)
        self.end_result(result, cancel=not shown)

    def _write_extra_passes(self, prism, prism_scene, result, image, extras, options):
        """The compositor's passes and film transparency, from Prism's passes rendered
        through the image's own samples (so they line up with it pixel for pixel)."""
        try:
            rendered = prism.render_passes(prism_scene, tuple(extras.values()),
                                           **{k: v for k, v in options.items() if k != "denoise"})
        except Exception as err:
            self.report({"WARNING"}, f"Prism: the compositor passes failed: {err}")
            return
        passes = result.layers[0].passes
        if "alpha" in rendered:
            # On a transparent film the background seen straight is taken out of the
            # image (premultiplied), and the share of samples meeting a surface is alpha.
            clear = np.maximum(image - rendered["background"], 0.0)
            set_rect(passes["Combined"], rgba_rows(clear, rendered["alpha"]))
        for name, key in extras.items():
            target = passes.find_by_name(name, "")
            if target is None or key not in ("depth", "normal", "albedo"):
                continue
            value = rendered[key]
            if key == "depth":
                value = blender_depth(value, self._camera)[..., None]
            set_rect(target, value[::-1].reshape(-1, value.shape[-1]))

    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        if renderlayer.use_pass_z:
            self.register_pass(scene, renderlayer, "Depth", 1, "Z", "VALUE")
        if renderlayer.use_pass_normal:
            self.register_pass(scene, renderlayer, "Normal", 3, "XYZ", "VECTOR")
        cycles = getattr(renderlayer, "cycles", None)
        if cycles is not None and getattr(cycles, "denoising_store_passes", False):
            self.register_pass(scene, renderlayer, "Denoising Albedo", 3, "RGB", "COLOR")

    # ---- viewport ---------------------------------------------------------------

    def view_update(self, context, depsgraph):
        if self._view is None:
            self._view = ViewportSession(self)
        self._view.update(context, depsgraph)

    def view_draw(self, context, depsgraph):
        if self._view is None:
            self._view = ViewportSession(self)
            self._view.update(context, depsgraph)
        self._view.draw(context, depsgraph)


class ViewportSession:
    """The viewport's render: the scene exported once and kept (meshes are read again
    only when an update changes them), a progressive render on a thread of its own
    that restarts (coarse first) when the scene or the view changes, and the latest
    pass drawn as a texture."""

    def __init__(self, engine):
        self.engine = engine
        self.cache = exporter.MeshCache()
        self.scene_dict = None
        self.camera = None
        self.size = None
        self.image = None
        self.texture = None  # (the image it shows, the GPU texture)
        self.lock = threading.Lock()
        self.passes = None
        self.thread = None
        self.generation = 0
        self.error = None
        self.done = False

    def update(self, context, depsgraph):
        """Re-export what changed: meshes whose geometry did are read again."""
        changed = set()
        for update in depsgraph.updates:
            if update.is_updated_geometry and isinstance(update.id, (bpy.types.Object,
                                                                     bpy.types.Mesh)):
                changed.add(update.id.original.name)
        if changed:
            self.cache.discard(changed)
        self.scene_dict = None  # exported again at the next draw, with the view's size
        self.stop()

    def _view_camera(self, context):
        region = context.region_data
        return view_dict(region.view_matrix, region.window_matrix, region.is_perspective)

    def draw(self, context, depsgraph):
        prism = runtime.load()
        if prism is None:
            self.engine.report({"ERROR"}, f"Prism: {runtime.error()}")
            return
        region = context.region
        size = (region.width, region.height)
        camera = self._view_camera(context)
        if self.scene_dict is None or size != self.size or camera != self.camera:
            self.size, self.camera = size, camera
            self.restart(prism, depsgraph)
        with self.lock:
            image = self.image
        if image is not None:
            self._draw_image(depsgraph.scene, image, size)
        if self.error:
            self.engine.update_stats("", f"Prism: {self.error}")
        if not self.done:
            self.engine.tag_redraw()

    def restart(self, prism, depsgraph):
        self.stop()
        width, height = self.size
        made = exporter.export(depsgraph, width, height, view=self.camera,
                               settings=properties.job_settings(depsgraph.scene, viewport=True),
                               cache=self.cache)
        self.scene_dict = made.scene
        self.generation += 1
        self.done = False
        generation = self.generation
        try:
            scene = prism.scene_from_dict(made.scene)
        except Exception as err:
            self.error = str(err)
            self.done = True
            return
        threads = properties.threads(depsgraph.scene)
        self.thread = threading.Thread(target=self._run, args=(prism, scene, generation,
                                                               threads), daemon=True)
        self.thread.start()

    def _run(self, prism, scene, generation, threads):
        width, height = self.size
        try:
            # Coarse first: a quarter of the pixels, one sample, shown at once.
            coarse = prism.render(scene, width=max(1, width // 4), height=max(1, height // 4),
                                  spp=1, threads=threads)
            self._show(coarse, generation)
            passes = prism.render_progressive(scene, threads=threads)
            self.passes = passes
            try:
                for _, image in passes:
                    if not self._show(image, generation):
                        break
            finally:
                passes.close()
        except Exception as err:
            self.error = str(err)
        if generation == self.generation:
            self.done = True

    def _show(self, image, generation):
        with self.lock:
            if generation != self.generation:
                return False
            self.image = image
        return True

    def stop(self):
        self.generation += 1
        passes, self.passes = self.passes, None
        if passes is not None:
            passes.close()
        if self.thread is not None:
            self.thread.join()
            self.thread = None

    def _draw_image(self, scene, image, size):
        import gpu
        from gpu_extras.presets import draw_texture_2d

        # A texture is made once a pass: Blender redraws far more often than passes land.
        if self.texture is None or self.texture[0] is not image:
            h, w, _ = image.shape
            rgba = rgba_rows(image)
            buffer = gpu.types.Buffer("FLOAT", w * h * 4, rgba.ravel())
            self.texture = (image, gpu.types.GPUTexture((w, h), format="RGBA16F", data=buffer))
        self.engine.bind_display_space_shader(scene)
        draw_texture_2d(self.texture[1], (0, 0), size[0], size[1])
        self.engine.unbind_display_space_shader()
