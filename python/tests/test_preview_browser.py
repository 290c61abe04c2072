"""`prism preview` in a real browser: headless Chromium (Debian's `chromium` and
`chromium-driver`, driven by selenium) loads the page from the binary, its image
converges to the pixels `prism render` writes, and a simulated drag changes the view.
Skips, saying why, where Chromium, its driver or selenium are missing."""

import io
import os
import shutil
import subprocess
import time

import numpy as np
import pytest

from conftest import SCENES

SHOWCASE = SCENES / "showcase" / "showcase.toml"


def _browser(scratch):
    """Headless Chromium, its temporary files (profile, singleton socket) kept in
    `scratch`, so that none outlive the test."""
    try:
        from selenium import webdriver
    except ImportError:
        pytest.skip("selenium is not installed: pip install selenium")
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    driver = shutil.which("chromedriver")
    if not chromium or not driver:
        pytest.skip("Chromium or its driver is not installed: apt-get install chromium "
                    "chromium-driver")
    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu",
                 "--disable-dev-shm-usage", "--force-color-profile=srgb",
                 "--window-size=1200,900", f"--user-data-dir={scratch / 'profile'}"):
        options.add_argument(flag)
    service = webdriver.ChromeService(executable_path=driver,
                                      env={**os.environ, "TMPDIR": str(scratch)})
    from selenium.common.exceptions import WebDriverException
    try:
        return webdriver.Chrome(options=options, service=service)
    except WebDriverException as err:
        # The machine's browser, not Prism: say so rather than fail.
        pytest.skip(f"Chromium did not start here: {str(err).splitlines()[0]}")


def _shown_pixels(browser):
    """The image the page shows, as the browser decoded it (RGB bytes)."""
    data = browser.execute_script("""
        const img = document.getElementById('frame');
        if (!img.complete || !img.naturalWidth) return null;
        const c = document.createElement('canvas');
        c.width = img.naturalWidth; c.height = img.naturalHeight;
        const g = c.getContext('2d');
        g.drawImage(img, 0, 0);
        return [c.width, c.height, Array.from(g.getImageData(0, 0, c.width, c.height).data)];
    """)
    if data is None:
        return None
    w, h, rgba = data
    return np.array(rgba, dtype=np.uint8).reshape(h, w, 4)[:, :, :3]


def _wait(test, seconds=60):
    end = time.time() + seconds
    while time.time() < end:
        got = test()
        if got is not None and got is not False:
            return got
        time.sleep(0.1)
    raise AssertionError("the page did not get there in time")


def test_the_page_converges_to_prism_renders_image_and_a_drag_moves_the_view(
        prism_bin, tmp_path):
    browser = _browser(tmp_path)
    server = subprocess.Popen([str(prism_bin), "preview", str(SHOWCASE), "--width", "160"],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        url = server.stdout.readline().strip()
        assert url.startswith("http://127.0.0.1:"), server.stderr.read()
        subprocess.run([str(prism_bin), "render", str(SHOWCASE), str(tmp_path / "cli.ppm"),
                        "--width", "160", "--quiet"], check=True)
        from conftest import read_ppm
        expected = read_ppm(tmp_path / "cli.ppm")
        browser.get(url)
        progress = lambda: "final" in browser.find_element("id", "progress").text  # noqa: E731

        def final_pixels():
            if not progress():
                return None
            shown = _shown_pixels(browser)
            return shown if shown is not None and shown.shape == expected.shape else None

        shown = _wait(final_pixels)
        assert np.array_equal(shown, expected)
        # A drag across the image orbits the camera: a new view, rendered to its end.
        from selenium.webdriver.common.action_chains import ActionChains
        image = browser.find_element("id", "frame")
        ActionChains(browser).move_to_element(image).click_and_hold().move_by_offset(
            60, 0).move_by_offset(40, 10).release().perform()

        def moved():
            shown = final_pixels()
            return shown if shown is not None and not np.array_equal(shown, expected) else None

        assert not np.array_equal(_wait(moved), expected)
        copied = browser.find_element("id", "copy")
        copied.click()
        text = browser.find_element("id", "copied").text
        assert text.startswith("[camera]") and "--look-from" in text
    finally:
        browser.quit()
        server.terminate()
        server.wait(timeout=10)
