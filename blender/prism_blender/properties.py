"""The Prism settings a scene carries (its Render Properties panel)."""

import bpy


class PrismRenderSettings(bpy.types.PropertyGroup):
    integrator: bpy.props.EnumProperty(
        name="Integrator",
        items=[
            ("path", "Path", "Path tracing: every bounce of light, as Cycles"),
            ("whitted", "Whitted", "Direct light through the same BSDFs, plus perfect mirrors "
             "and glass: fast, no indirect light"),
        ],
        default="path",
    )
    samples: bpy.props.IntProperty(
        name="Samples", description="Samples a pixel of the final render", default=64,
        min=1, soft_max=4096, max=65536)
    preview_samples: bpy.props.IntProperty(
        name="Viewport Samples", description="Samples a pixel in the viewport", default=32,
        min=1, soft_max=1024, max=65536)
    max_bounces: bpy.props.IntProperty(
        name="Max Bounces", description="Bounces of a path at most", default=12, min=0,
        max=1024)
    light_sampling: bpy.props.EnumProperty(
        name="Light Sampling",
        description="Shadow rays a path traces at each bounce",
        items=[
            ("auto", "Auto", "A shadow ray toward every light up to 16 lights; above, one "
             "light drawn from the light tree"),
            ("all", "All Lights", "A shadow ray toward every light: the least noise a sample"),
            ("one", "One Light", "One shadow ray, toward a light chosen by its contribution: "
             "as many shadow rays with many lights as with one"),
            ("tree", "Light Tree", "One light drawn from a tree over the lights by how much "
             "each part may light the point: fastest with many lights"),
        ],
        default="auto",
    )
    seed: bpy.props.IntProperty(
        name="Seed", description="Seed of the samples: the same seed gives the same image",
        default=0, min=0)
    denoise: bpy.props.BoolProperty(
        name="Denoise", description="Denoise the render with Intel Open Image Denoise "
        "(needs pyoidn in Blender's Python)", default=False)


def job_settings(scene, viewport=False):
    """The `[render]` keys of this scene's Prism settings (and Blender's threads)."""
    s = scene.prism
    out = {"integrator": s.integrator, "spp": s.preview_samples if viewport else s.samples,
           "max_depth": s.max_bounces, "seed": s.seed}
    if s.integrator == "whitted":
        out["max_depth"] = min(s.max_bounces, 64)
    elif s.light_sampling != "auto":
        out["light_sampling"] = s.light_sampling
    return out


def threads(scene):
    """Blender's thread count when fixed by the user, else None (every core)."""
    render = scene.render
    return render.threads if render.threads_mode == "FIXED" else None


def register():
    bpy.utils.register_class(PrismRenderSettings)
    bpy.types.Scene.prism = bpy.props.PointerProperty(type=PrismRenderSettings)


def unregister():
    del bpy.types.Scene.prism
    bpy.utils.unregister_class(PrismRenderSettings)
