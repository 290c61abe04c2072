"""Runs the Blender add-on's tests in Blender's own Python:

    blender -b --factory-startup --python-exit-code 1 --python tests/blender/run.py

The add-on is loaded from blender/ and the `prism` package from python/ (built there by
`maturin develop`, as `cargo test` does) unless PRISM_PYTHON_PATH names another.
Arguments after `--` select tests by name, as unittest's -k does.
"""

import os
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "blender"))
sys.path.insert(0, HERE)
os.environ.setdefault("PRISM_PYTHON_PATH", os.path.join(REPO, "python"))


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    loader = unittest.TestLoader()
    if argv:
        loader.testNamePatterns = [f"*{p}*" for p in argv]
    suite = loader.discover(HERE, pattern="test_*.py", top_level_dir=HERE)
    result = unittest.TextTestRunner(verbosity=2, stream=sys.stdout).run(suite)
    if not result.wasSuccessful():
        raise SystemExit(1)


main()
