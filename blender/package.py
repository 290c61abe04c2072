#!/usr/bin/env python3
"""Packs the Blender add-on with the `prism` package inside, so installing it is one
step in Blender (Edit > Preferences > Add-ons > Install):

    python3 blender/package.py                # builds the wheel (maturin, release)
    python3 blender/package.py --wheel W.whl  # or packs a wheel built before
    python3 blender/package.py --package python/prism  # or a built package folder

It writes into --out (default dist/):

- prism_blender-VERSION.zip: the add-on folder with the package in
  prism_blender/vendor/ (Blender 3.x to 4.1, and 4.2+ as a legacy add-on);
- prism_blender-VERSION-extension.zip, when packing a wheel: a Blender 4.2+ extension
  whose manifest lists the wheel, which Blender installs itself.

The wheel is abi3 (CPython 3.9+), so one file serves the Pythons of every Blender
from 3.x on (3.10, 3.11, 3.13) on its platform.
"""

import argparse
import glob
import os
import re
import subprocess
import sys
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
ADDON = os.path.join(HERE, "prism_blender")


def addon_version():
    text = open(os.path.join(ADDON, "__init__.py"), encoding="utf-8").read()
    found = re.search(r'"version":\s*\((\d+),\s*(\d+),\s*(\d+)\)', text)
    return ".".join(found.groups())


def addon_files():
    """(path on disk, path inside the add-on folder) of every file the add-on ships."""
    for root, dirs, files in os.walk(ADDON):
        dirs[:] = [d for d in dirs if d not in ("__pycache__", "vendor")]
        for name in sorted(files):
            if name.endswith((".pyc", ".pyo")):
                continue
            path = os.path.join(root, name)
            yield path, os.path.relpath(path, ADDON)


def package_files_of_wheel(wheel):
    """(bytes, path) of the `prism` package inside a wheel."""
    with zipfile.ZipFile(wheel) as z:
        for name in z.namelist():
            if name.startswith("prism/") and not name.endswith("/"):
                yield z.read(name), name


def package_files_of_folder(folder):
    folder = os.path.abspath(folder)
    for root, dirs, files in os.walk(folder):
        dirs[:] = [d for d in dirs if d != "__pycache__"]
        for name in sorted(files):
            if name.endswith((".pyc", ".pyo")):
                continue
            path = os.path.join(root, name)
            with open(path, "rb") as f:
                yield f.read(), "prism/" + os.path.relpath(path, folder)


def write_legacy(out, version, package):
    path = os.path.join(out, f"prism_blender-{version}.zip")
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        for disk, inside in addon_files():
            if inside != "blender_manifest.toml":
                z.write(disk, f"prism_blender/{inside}")
        for data, inside in package:
            z.writestr(f"prism_blender/vendor/{inside}", data)
    return path


def write_extension(out, version, wheel):
    path = os.path.join(out, f"prism_blender-{version}-extension.zip")
    wheel_name = os.path.basename(wheel)
    manifest = open(os.path.join(ADDON, "blender_manifest.toml"), encoding="utf-8").read()
    manifest = manifest.replace("wheels = []", f'wheels = ["./wheels/{wheel_name}"]')
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        for disk, inside in addon_files():
            if inside == "blender_manifest.toml":
                z.writestr(inside, manifest)
            else:
                z.write(disk, inside)
        z.write(wheel, f"wheels/{wheel_name}")
    return path


def build_wheel(out):
    subprocess.run([sys.executable, "-m", "maturin", "build", "--release", "--manifest-path",
                    os.path.join(REPO, "python", "Cargo.toml"), "--out", out], check=True)
    wheels = sorted(glob.glob(os.path.join(out, "prism_raytracer-*.whl")), key=os.path.getmtime)
    if not wheels:
        raise SystemExit("maturin built no wheel")
    return wheels[-1]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    source = parser.add_mutually_exclusive_group()
    source.add_argument("--wheel", help="a prism_raytracer wheel built before")
    source.add_argument("--package", help="a built prism package folder (python/prism)")
    parser.add_argument("--out", default=os.path.join(REPO, "dist"))
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    version = addon_version()
    if args.package:
        if not glob.glob(os.path.join(args.package, "_prism*")):
            raise SystemExit(f"{args.package} holds no built extension (_prism*): build it "
                             "first (maturin develop)")
        written = [write_legacy(args.out, version, package_files_of_folder(args.package))]
    else:
        wheel = args.wheel or build_wheel(args.out)
        written = [write_legacy(args.out, version, package_files_of_wheel(wheel)),
                   write_extension(args.out, version, wheel)]
    for path in written:
        print(path)


if __name__ == "__main__":
    main()
