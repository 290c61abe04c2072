"""Prism's panels, and the generic panels of Blender that apply to Prism."""

import bpy

from . import runtime

#: Blender's own panels that show Prism's settings as well as Cycles' or Eevee's.
_GENERIC = (
    "RENDER_PT_format", "RENDER_PT_frame_range", "RENDER_PT_output", "RENDER_PT_color_management",
    "DATA_PT_lens", "DATA_PT_camera", "DATA_PT_camera_dof", "DATA_PT_camera_dof_focus",
    "DATA_PT_camera_dof_aperture", "DATA_PT_context_light", "DATA_PT_light",
    "DATA_PT_EEVEE_light", "DATA_PT_area", "DATA_PT_spot", "MATERIAL_PT_context_material",
    "MATERIAL_PT_preview", "EEVEE_MATERIAL_PT_surface", "WORLD_PT_context_world",
    "EEVEE_WORLD_PT_surface", "VIEWLAYER_PT_layer_passes", "VIEWLAYER_PT_layer_passes_data",
)


class _PrismPanel:
    """A Properties editor panel shown while Prism is the render engine."""

    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    COMPAT_ENGINES = {"PRISM"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


class PRISM_PT_render(_PrismPanel, bpy.types.Panel):
    bl_label = "Prism"
    bl_context = "render"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        error = runtime.error()
        if error:
            box = layout.box()
            box.label(text="Prism cannot render:", icon="ERROR")
            for line in _wrap(error, 60):
                box.label(text=line)
        settings = context.scene.prism
        layout.prop(settings, "integrator")
        col = layout.column(align=True)
        col.prop(settings, "samples", text="Render Samples")
        col.prop(settings, "preview_samples", text="Viewport Samples")
        layout.prop(settings, "max_bounces")
        if settings.integrator == "path":
            layout.prop(settings, "light_sampling")
        layout.prop(settings, "seed")
        layout.prop(settings, "denoise")
        layout.prop(context.scene.render, "film_transparent")


class PRISM_PT_object_visibility(_PrismPanel, bpy.types.Panel):
    """What Blender's Cycles-only visibility panel holds that Prism reads."""

    bl_label = "Prism Visibility"
    bl_context = "object"
    bl_options = {"DEFAULT_CLOSED"}

    @classmethod
    def poll(cls, context):
        return super().poll(context) and context.object is not None

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        obj = context.object
        layout.prop(obj, "hide_render", text="Hide in Renders", invert_checkbox=False)
        if obj.type == "LIGHT" and hasattr(obj, "visible_camera"):
            layout.prop(obj, "visible_camera", text="Seen by the Camera")


def _wrap(text, width):
    words, line, out = text.split(), "", []
    for word in words:
        if line and len(line) + 1 + len(word) > width:
            out.append(line)
            line = word
        else:
            line = f"{line} {word}".strip()
    return out + ([line] if line else [])


def _generic_panels():
    for name in _GENERIC:
        panel = getattr(bpy.types, name, None)
        if panel is not None and hasattr(panel, "COMPAT_ENGINES"):
            yield panel


def register():
    bpy.utils.register_class(PRISM_PT_render)
    bpy.utils.register_class(PRISM_PT_object_visibility)
    for panel in _generic_panels():
        panel.COMPAT_ENGINES.add("PRISM")


def unregister():
    for panel in _generic_panels():
        panel.COMPAT_ENGINES.discard("PRISM")
    bpy.utils.unregister_class(PRISM_PT_object_visibility)
    bpy.utils.unregister_class(PRISM_PT_render)
