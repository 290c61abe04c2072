"""Prism, a physically based ray tracer, as a Blender render engine.

Rendering goes through the `prism` Python package (found by `runtime`); the add-on
itself is pure Python and loads in any Blender 3.x or 4.x, saying in its panel why
it cannot render when the package is missing or too old.
"""

bl_info = {
    "name": "Prism",
    "author": "Prism developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Render Properties > Render Engine > Prism",
    "description": "Prism, a physically based ray tracer (path tracing, OpenPBR materials)",
    "doc_url": "https://github.com/prism-renderer/prism/blob/main/docs/blender.md",
    "category": "Render",
}

if "bpy" in locals():  # F8 / script reload: pick up edited modules
    import importlib

    for _name in ("runtime", "meshes", "lights", "camera", "materials", "world", "export",
                  "properties", "engine", "ui"):
        if _name in locals():
            importlib.reload(locals()[_name])

import bpy  # noqa: E402

from . import engine, properties, runtime, ui  # noqa: E402


def register():
    properties.register()
    bpy.utils.register_class(engine.PrismRenderEngine)
    ui.register()
    runtime.load()  # found now, so the panel can say at once if it is missing


def unregister():
    ui.unregister()
    bpy.utils.unregister_class(engine.PrismRenderEngine)
    properties.unregister()
