"""The add-on registers in a new Blender: its engine, its settings and the panels that
show them."""

import unittest

import bpy

import support


class Registration(unittest.TestCase):
    def test_the_engine_and_its_settings_are_registered(self):
        support.empty_scene()
        engines = {getattr(e, "bl_idname", None) for e in bpy.types.RenderEngine.__subclasses__()}
        self.assertIn("PRISM", engines)
        scene = bpy.context.scene
        scene.render.engine = "PRISM"
        self.assertEqual(scene.render.engine, "PRISM")
        settings = scene.prism
        self.assertEqual((settings.integrator, settings.samples, settings.max_bounces),
                         ("path", 64, 12))

    def test_light_sampling_reaches_the_job_where_it_is_not_left_to_prism(self):
        from prism_blender import properties
        support.empty_scene()
        scene = bpy.context.scene
        scene.render.engine = "PRISM"
        settings = scene.prism
        self.assertEqual(settings.light_sampling, "auto")
        self.assertNotIn("light_sampling", properties.job_settings(scene))
        settings.light_sampling = "one"
        self.assertEqual(properties.job_settings(scene)["light_sampling"], "one")
        settings.light_sampling = "tree"
        self.assertEqual(properties.job_settings(scene)["light_sampling"], "tree")
        settings.integrator = "whitted"
        self.assertNotIn("light_sampling", properties.job_settings(scene))

    def test_blender_panels_for_cameras_lights_materials_and_the_world_show_for_prism(self):
        support.addon()
        for name in ("DATA_PT_lens", "DATA_PT_camera_dof", "DATA_PT_EEVEE_light",
                     "EEVEE_MATERIAL_PT_surface", "EEVEE_WORLD_PT_surface", "RENDER_PT_format",
                     "RENDER_PT_color_management"):
            panel = getattr(bpy.types, name)
            self.assertIn("PRISM", panel.COMPAT_ENGINES, name)
        self.assertTrue(hasattr(bpy.types, "PRISM_PT_render"))
        self.assertTrue(hasattr(bpy.types, "PRISM_PT_object_visibility"))
