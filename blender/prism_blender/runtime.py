"""Finding the `prism` Python package this add-on renders with.

Blender runs its own Python, so the package must be importable there: bundled in the
add-on (``wheels/`` of a Blender 4.2+ extension, which Blender installs itself, or the
``vendor/`` folder of the 3.x add-on zip), installed into Blender's Python with pip, or
on ``PRISM_PYTHON_PATH``. Whatever goes wrong is kept as one sentence for the
interface to show: the add-on must load in any Blender, with or without Prism.
"""

import os
import sys

#: The oldest `prism` whose API the add-on uses (thread-safe `Passes.close`).
REQUIRED = (0, 1, 0)
#: What the add-on calls; a `prism` without them is too old.
API = ("scene_from_dict", "render_progressive", "render_passes", "Passes")

_state = {"module": None, "error": None, "tried": False}


def _candidates():
    here = os.path.dirname(os.path.abspath(__file__))
    paths = [os.path.join(here, "vendor")]
    extra = os.environ.get("PRISM_PYTHON_PATH")
    if extra:
        paths[:0] = [p for p in extra.split(os.pathsep) if p]
    return paths


def _version(text):
    parts = []
    for piece in str(text).split(".")[:3]:
        digits = "".join(c for c in piece if c.isdigit())
        parts.append(int(digits) if digits else 0)
    return tuple(parts + [0] * (3 - len(parts)))


def load():
    """The `prism` module, or None; `error()` then says why, in one sentence."""
    if _state["tried"]:
        return _state["module"]
    _state["tried"] = True
    for path in _candidates():
        if os.path.isdir(os.path.join(path, "prism")) and path not in sys.path:
            sys.path.insert(0, path)
    try:
        import prism
    except ImportError as err:
        _state["error"] = (
            "the Prism Python package is not installed in Blender's Python "
            f"{sys.version_info.major}.{sys.version_info.minor} ({err}); install the add-on "
            "zip that bundles it (docs/blender.md)"
        )
        return None
    except Exception as err:  # a broken build: a native module for another platform
        _state["error"] = f"the Prism Python package failed to load: {err}"
        return None
    missing = [name for name in API if not hasattr(prism, name)]
    version = getattr(prism, "__version__", "0")
    if missing or _version(version) < REQUIRED:
        _state["error"] = (
            f"the Prism package found ({version}, at {os.path.dirname(prism.__file__)}) is "
            f"older than this add-on needs ({'.'.join(map(str, REQUIRED))}"
            + (f"; it lacks {', '.join(missing)}" if missing else "")
            + ")"
        )
        return None
    _state["module"] = prism
    return prism


def error():
    """Why `load()` gave None (None when it did not)."""
    load()
    return _state["error"]


def reset():
    """Forget the last attempt (tests, and after the user installs the package)."""
    _state.update(module=None, error=None, tried=False)
