"""prism.denoise: Intel Open Image Denoise through pyoidn, which is optional. Without it
the denoising tests skip, saying why, unless PRISM_TEST_OIDN=1 asks for them (then
`cargo test` installs pyoidn into its environment, and a missing pyoidn fails)."""

import os
import sys

import numpy as np
import pytest

import prism

WHITE = [0.75, 0.75, 0.75]


def quad(corner, edge1, edge2, color=WHITE):
    return dict(type="quad", corner=corner, edge1=edge1, edge2=edge2, material=dict(color=color))


def box_scene() -> prism.Scene:
    """A small Cornell-like box: diffuse walls, a ball and a block under a ceiling light,
    which path tracing at 4 samples leaves speckled."""
    return prism.scene_from_dict({
        "camera": {"from": [0, 1, 3.3], "at": [0, 1, 0], "fov": 40},
        "object": [
            quad([-1, 0, -1], [0, 0, 2], [2, 0, 0]),  # floor
            quad([-1, 2, -1], [2, 0, 0], [0, 0, 2]),  # ceiling
            quad([-1, 0, -1], [2, 0, 0], [0, 2, 0]),  # back
            quad([-1, 0, -1], [0, 2, 0], [0, 0, 2], [0.7, 0.1, 0.1]),
            quad([1, 0, -1], [0, 0, 2], [0, 2, 0], [0.1, 0.6, 0.1]),
            dict(type="sphere", center=[-0.4, 0.35, -0.3], radius=0.35),
            dict(type="box", min=[0.1, 0, -0.2], max=[0.7, 0.8, 0.4], rotate=[0, 1, 0, -20]),
        ],
        "light": [dict(type="quad", center=[0, 1.99, 0], edge1=[0.5, 0, 0],
                       edge2=[0, 0, 0.5], intensity=12)],
    })


def need_pyoidn():
    if os.environ.get("PRISM_TEST_OIDN") == "1":
        import pyoidn  # noqa: F401 -- asked for: missing is a failure, not a skip
    else:
        pytest.importorskip(
            "pyoidn",
            reason="prism.denoise needs pyoidn (pip install pyoidn; PRISM_TEST_OIDN=1 "
            "makes `cargo test` install it)",
        )


def shown_rmse(a: np.ndarray, b: np.ndarray) -> float:
    """RMSE of what a display shows, 0..1 (the light's radiance of 12 would otherwise
    outweigh every other pixel): float images clipped, 8-bit ones scaled."""
    def shown(x):
        return x / 255.0 if x.dtype == np.uint8 else np.clip(x.astype(np.float64), 0, 1)
    return float(np.sqrt(np.mean((shown(a) - shown(b)) ** 2)))


def test_a_noisy_path_render_comes_nearer_the_converged_one():
    need_pyoidn()
    scene = box_scene()
    options = dict(width=96, height=96, aa=1, integrator="path", seed=3)
    noisy = prism.render(scene, spp=4, **options)
    passes = prism.render_passes(scene, ("albedo", "normal"), spp=4, **options)
    converged = prism.render(scene, spp=256, **options)
    denoised = prism.denoise(noisy, passes["albedo"], passes["normal"])
    assert denoised.shape == noisy.shape and denoised.dtype == np.float32
    assert np.isfinite(denoised).all()
    # Measured: 0.039 before, 0.012 after (the converged image's own noise, about
    # 0.005, included).
    before, after = shown_rmse(noisy, converged), shown_rmse(denoised, converged)
    assert after < before / 2, (before, after)
    # Without the passes it denoises too; the image itself is left as it was.
    assert shown_rmse(prism.denoise(noisy), converged) < before / 2
    assert np.array_equal(noisy, prism.render(scene, spp=4, **options))
    # The 8-bit image render(srgb=True) gives comes back as 8 bits, nearer too.
    noisy8 = prism.render(scene, spp=4, srgb=True, **options)
    denoised8 = prism.denoise(noisy8, passes["albedo"], passes["normal"])
    assert denoised8.dtype == np.uint8 and denoised8.shape == noisy8.shape
    converged8 = prism._develop_srgb(converged)
    assert shown_rmse(denoised8, converged8) < shown_rmse(noisy8, converged8) / 2


def test_passes_of_another_shape_or_normals_alone_are_refused():
    image = np.zeros((4, 6, 3), np.float32)
    with pytest.raises(ValueError, match="the albedo pass is"):
        prism.denoise(image, np.zeros((4, 5, 3), np.float32))
    with pytest.raises(ValueError, match="only with an albedo pass"):
        prism.denoise(image, normal=image)
    with pytest.raises(ValueError, match="H x W x 3"):
        prism.denoise(np.zeros((4, 6), np.float32))


def test_without_pyoidn_the_error_says_how_to_get_it(monkeypatch):
    # A None entry in sys.modules makes `import pyoidn` raise ImportError.
    monkeypatch.setitem(sys.modules, "pyoidn", None)
    with pytest.raises(ImportError, match="pip install pyoidn"):
        prism.denoise(np.zeros((4, 6, 3), np.float32))


def test_render_with_denoise_is_refused_by_a_prism_without_oidn():
    """`denoise=True` asks the renderer itself (Intel Open Image Denoise linked in, the
    `oidn` feature), not pyoidn: the extension the tests build has no OIDN, so the job
    is refused as it resolves, before anything renders, saying how to get one."""
    with pytest.raises(prism.PrismError, match="oidn"):
        prism.render(box_scene(), width=32, height=32, integrator="path", denoise=True)
    # Asked not to, it renders as ever.
    image = prism.render(box_scene(), width=32, height=32, integrator="path", denoise=False)
    assert image.shape == (32, 32, 3)
