"""The add-on zip that bundles `prism` installs in one step into a Blender that has
no other copy of the package, and renders."""

import os
import subprocess
import sys
import tempfile
import unittest
import zipfile

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))

INSTALL_AND_RENDER = """
import bpy, sys
bpy.ops.preferences.addon_install(filepath=sys.argv[-2])
bpy.ops.preferences.addon_enable(module="prism_blender")
import prism
print("PRISM FROM", prism.__file__)
scene = bpy.context.scene
scene.render.engine = "PRISM"
scene.render.resolution_x, scene.render.resolution_y = 32, 24
scene.prism.samples = 2
scene.render.filepath = sys.argv[-1]
bpy.ops.render.render(write_still=True)
"""


class Package(unittest.TestCase):
    def test_the_zip_bundles_prism_and_installs_in_one_step(self):
        if not bpy.app.binary_path:
            self.skipTest("Blender as a Python module (PyPI's bpy) has no program to run")
        package = os.path.join(os.environ.get("PRISM_PYTHON_PATH", ""), "prism")
        with tempfile.TemporaryDirectory() as folder:
            made = subprocess.run(
                [sys.executable if os.path.basename(sys.executable).startswith("python")
                 else "python3", os.path.join(REPO, "blender", "package.py"),
                 "--package", package, "--out", folder],
                capture_output=True, text=True)
            self.assertEqual(made.returncode, 0, made.stderr)
            (zip_path,) = made.stdout.split()
            names = zipfile.ZipFile(zip_path).namelist()
            self.assertIn("prism_blender/__init__.py", names)
            self.assertTrue(any(n.startswith("prism_blender/vendor/prism/_prism") for n in names))
            self.assertFalse(any("__pycache__" in n for n in names))
            env = {k: v for k, v in os.environ.items() if k not in ("PRISM_PYTHON_PATH",
                                                                     "PYTHONPATH")}
            env["BLENDER_USER_SCRIPTS"] = os.path.join(folder, "scripts")
            env["BLENDER_USER_CONFIG"] = os.path.join(folder, "config")
            frame = os.path.join(folder, "frame.png")
            run = subprocess.run(
                [bpy.app.binary_path, "-b", "--factory-startup", "--python-exit-code", "1",
                 "--python-expr", INSTALL_AND_RENDER, "--", zip_path, frame],
                env=env, capture_output=True, text=True, timeout=300)
            self.assertEqual(run.returncode, 0, run.stdout[-3000:] + run.stderr[-3000:])
            self.assertIn(os.path.join(folder, "scripts"), run.stdout)  # the vendored copy
            self.assertTrue(os.path.isfile(frame), run.stdout[-3000:])
