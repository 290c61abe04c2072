"""Prism's exceptions. Every error Prism reports is a :class:`PrismError`; those that a
bad input file causes are also the built-in exception a Python caller expects
(``ValueError`` for content, ``OSError`` for files), so ``except ValueError`` works.

Each carries where the problem is, as the command line prints it (``file:line:col``):
``file``, ``line`` and ``column`` (``None`` when not known).
"""

from typing import Optional


class PrismError(Exception):
    """Base of every error Prism raises."""

    file: Optional[str] = None
    line: Optional[int] = None
    column: Optional[int] = None


class SceneError(PrismError, ValueError):
    """A scene, material, camera or animation file that cannot be read as written:
    ``file`` and ``line`` (and ``column`` where the reader knows it) say where."""


class FileError(PrismError, OSError):
    """A file that cannot be opened, read or written (``file`` names it)."""


class SettingsError(PrismError, ValueError):
    """Options that cannot be rendered: a size, a region or a sample count."""
