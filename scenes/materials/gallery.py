#!/usr/bin/env python3
"""The OpenPBR material gallery in the README: every example material of the OpenPBR
specification (MaterialX documents) on one sphere (ball.toml) in Prism's default studio,
path traced, tiled into one picture with each material's name under it.

    python3 scenes/materials/gallery.py [--examples DIR] [--prism BIN] [--out FILE]
                                        [--size PX] [--spp N] [--columns K]

--examples defaults to ../shared/reference/openpbr-spec/examples (the specification's
repository, github.com/AcademySoftwareFoundation/OpenPBR, folder examples/); --prism to
target/release/prism (build it with `cargo build --release`); --out to
docs/images/materials.png. Needs Pillow to tile the renders. Prints each material's
render time and the total.
"""

import argparse
import pathlib
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--examples",
        type=pathlib.Path,
        default=ROOT.parent / "shared/reference/openpbr-spec/examples",
    )
    parser.add_argument("--prism", type=pathlib.Path, default=ROOT / "target/release/prism")
    parser.add_argument("--out", type=pathlib.Path, default=ROOT / "docs/images/materials.png")
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--spp", type=int, default=256)
    parser.add_argument("--columns", type=int, default=12)
    args = parser.parse_args()
    try:
        from PIL import Image, ImageDraw
    except ImportError:
        sys.exit("gallery.py needs Pillow to tile the renders: pip install pillow")
    examples = sorted(args.examples.glob("*.mtlx"))
    if not examples:
        sys.exit(
            f"no .mtlx files in {args.examples}: pass --examples with the examples/ "
            "folder of github.com/AcademySoftwareFoundation/OpenPBR"
        )
    if not args.prism.is_file():
        sys.exit(f"{args.prism} is missing: build it with `cargo build --release`")
    ball = ROOT / "scenes/materials/ball.toml"
    label = 14
    rows = (len(examples) + args.columns - 1) // args.columns
    sheet = Image.new(
        "RGB", (args.columns * args.size, rows * (args.size + label)), (24, 24, 24)
    )
    draw = ImageDraw.Draw(sheet)
    started = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        for i, mtlx in enumerate(examples):
            out = pathlib.Path(tmp) / f"{mtlx.stem}.png"
            t = time.perf_counter()
            subprocess.run(
                [
                    str(args.prism), "render", str(ball), str(out),
                    "--material", str(mtlx),
                    "--integrator", "path",
                    "--spp", str(args.spp),
                    "--width", str(args.size), "--height", str(args.size),
                    # The default view, closer in: the ball fills the tile.
                    "--fov", "26",
                    "--seed", "1", "--quiet",
                ],
                check=True,
            )
            name = mtlx.stem.removeprefix("open_pbr_")
            print(f"{name:24} {time.perf_counter() - t:6.2f} s")
            x, y = (i % args.columns) * args.size, (i // args.columns) * (args.size + label)
            with Image.open(out) as tile:
                sheet.paste(tile.convert("RGB"), (x, y))
            draw.text((x + 3, y + args.size + 1), name, fill=(220, 220, 220))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    sheet.save(args.out, optimize=True)
    print(f"{len(examples)} materials in {time.perf_counter() - started:.1f} s: {args.out}")


if __name__ == "__main__":
    main()
