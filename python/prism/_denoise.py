"""Denoising with Intel Open Image Denoise (OIDN) through the ``pyoidn`` package, which
ships the library: imported only when :func:`denoise` is called, so Prism never needs
it otherwise. The same filter as ``prism render --denoise`` (OIDN's ``RT`` filter,
guided by the albedo and normal passes, which are not taken as noise-free: at a few
samples a pixel they are as rough as the samples wherever a pixel holds more than one
surface or colour)."""

from typing import Any, Optional

import numpy as np


def denoise(image: Any, albedo: Optional[Any] = None, normal: Optional[Any] = None) -> np.ndarray:
    """``image`` denoised by Intel Open Image Denoise, guided by the ``albedo`` and
    ``normal`` passes of the same render when given (:func:`prism.render_passes` with
    the render's own options; normals only with the albedo). Nothing else in Prism
    denoises: an image changes only when this is called.

    ``image`` is what :func:`prism.render` returns: an H x W x 3 ``float32`` array of
    linear values (denoised as HDR radiance, returned as ``float32``), or with
    ``srgb=True`` the ``uint8`` display values (denoised as sRGB-encoded 0..1 values,
    returned as ``uint8``; denoising the linear image and developing it afterwards
    keeps more, as nothing is clipped yet).

    Needs ``pyoidn`` (``pip install pyoidn``): raises ``ImportError`` saying so when
    it is missing, ``ValueError`` for images of different shapes.
    """
    color = np.asarray(image)
    if color.ndim != 3 or color.shape[2] != 3:
        raise ValueError(f"expected an H x W x 3 image, found shape {color.shape}")
    display = color.dtype == np.uint8
    # OIDN wants finite, non-negative colours (a Lanczos filter rings below zero beside
    # a bright edge, and one NaN would spread), albedos in 0..1 and normals in -1..1.
    if display:
        color = _srgb_decode(color)
    else:
        color = np.maximum(_finite(color), 0.0)
    guides = {}
    for name, given, low in (("albedo", albedo, 0.0), ("normal", normal, -1.0)):
        if given is None:
            continue
        a = np.asarray(given)
        if a.shape != color.shape:
            raise ValueError(
                f"the {name} pass is {a.shape}, the image {color.shape}: give the passes "
                "of the same render (prism.render_passes with its options)"
            )
        guides[name] = np.clip(_finite(a), low, 1.0)
    if "normal" in guides and "albedo" not in guides:
        raise ValueError("a normal pass guides the denoiser only with an albedo pass")
    try:
        import pyoidn
    except ImportError as err:
        raise ImportError(
            "prism.denoise needs Intel Open Image Denoise's Python package, which ships "
            "the library: pip install pyoidn"
        ) from err
    out = pyoidn.denoise(
        color,
        guides.get("albedo"),
        guides.get("normal"),
        hdr=not display,
        clean_aux=False,
    )
    return _srgb_encode(out) if display else out


def _finite(a: np.ndarray) -> np.ndarray:
    """``a`` as contiguous ``float32`` with NaN and infinities made 0."""
    a = np.nan_to_num(np.asarray(a, dtype=np.float32), nan=0.0, posinf=0.0, neginf=0.0)
    return np.ascontiguousarray(a)


def _srgb_decode(a: np.ndarray) -> np.ndarray:
    """8-bit sRGB values to linear 0..1 ``float32``: what OIDN's LDR mode takes."""
    v = a.astype(np.float32) / 255.0
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4).astype(np.float32)


def _srgb_encode(a: np.ndarray) -> np.ndarray:
    """Linear 0..1 values back to 8-bit sRGB, rounded to nearest."""
    v = np.clip(np.nan_to_num(a.astype(np.float64), nan=0.0), 0.0, 1.0)
    v = np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)
    return np.round(v * 255.0).astype(np.uint8)
