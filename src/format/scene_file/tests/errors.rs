//! Every class of scene-file error, each naming its `file:line:column`.

use super::*;

#[test]
fn every_error_names_file_line_and_column() {
    let cases = [
        (
            "[[object]]\ntype = \"sphere\"\nradius = 1\ncolour = 3\n",
            "DIR/scene.toml:4:1: unknown field `colour`",
        ),
        (
            "[[object]]\ntype = \"sphere\"\nradius = \"big\"\n",
            "DIR/scene.toml:3:10: invalid type: string \"big\", expected f64",
        ),
        (
            "[[object]]\ntype = \"sphere\"\nradius = inf\n",
            "DIR/scene.toml:3:10: expected a finite number of magnitude at most 1e30, found inf",
        ),
        (
            "[[object]]\ntype = \"sphere\"\nradius = 1\nscale = [1, 2, 1]\n",
            "DIR/scene.toml:4:9: a sphere cannot be scaled differently along different axes",
        ),
        (
            "[[object]]\ntype = \"quad\"\nradius = 1\n",
            "DIR/scene.toml:3:10: `radius` does not apply to a quad, which takes `corner`, `edge1`, `edge2`",
        ),
        (
            "[[object]]\ntype = \"cone\"\n",
            "DIR/scene.toml:2:8: unknown object type \"cone\": expected mesh, sphere, plane",
        ),
        (
            "[[object]]\ntype = \"sphere\"\n",
            "DIR/scene.toml:2:8: a sphere needs `radius`",
        ),
        (
            "[[object]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"gold\"\n",
            "DIR/scene.toml:4:12: unknown material \"gold\": expected one of the [[material]] names (there are none)",
        ),
        (
            "[[material]]\nname = \"a\"\n[[material]]\nname = \"a\"\n",
            "DIR/scene.toml:4:8: material \"a\" is defined twice (first at DIR/scene.toml:2:8)",
        ),
        (
            "[[material]]\nname = \"a\"\ncolor = [1, -1, 0]\n",
            "DIR/scene.toml:3:9: expected colour channels >= 0, found [1, -1, 0]",
        ),
        (
            "[[material]]\nname = \"a\"\ncolor = \"#12345\"\n",
            "DIR/scene.toml:3:9: expected a colour \"#rrggbb\", found \"#12345\"",
        ),
        (
            "[[material]]\nname = \"a\"\ntexture = \"nowhere.png\"\n",
            "DIR/scene.toml:3:11: cannot open DIR/nowhere.png",
        ),
        (
            "[[object]]\nname = \"x\"\ntype = \"sphere\"\nradius = 1\n[[light]]\nname = \"x\"\ntype = \"point\"\nposition = [0, 0, 0]\n",
            "DIR/scene.toml:6:8: the name \"x\" is already taken",
        ),
        (
            "[[light]]\ntype = \"point\"\n",
            "DIR/scene.toml:2:8: a point light needs `position`",
        ),
        (
            "[[light]]\ntype = \"point\"\nposition = [0, 0, 0]\nfalloff = \"linear\"\n",
            "DIR/scene.toml:4:11: expected falloff \"none\" or \"inverse_square\", found \"linear\"",
        ),
        (
            "[render]\nwidth = 0\n",
            "DIR/scene.toml:2:9: expected width between 1 and 65536, found 0",
        ),
        (
            "[render]\ntonemap = \"filmic\"\n",
            "DIR/scene.toml:2:11: unknown tone map `filmic`: expected clamp, reinhard or aces",
        ),
        (
            "[render]\nfilter = \"box\"\n",
            "DIR/scene.toml:2:10: unknown filter `box`",
        ),
        (
            "[render]\nlight_sampling = \"some\"\n",
            "DIR/scene.toml:2:18: unknown light sampling `some`: expected auto, all, one or tree",
        ),
        (
            "[camera]\nfrom = [0, 0, 0]\nat = [0, 0, 0]\n",
            "DIR/scene.toml:3:6: expected `at` away from `from`",
        ),
        (
            "[camera]\ncmr = \"c.cmr\"\nfov = 40\n",
            "DIR/scene.toml:3:7: a camera given by `cmr` takes no other key",
        ),
        (
            "[[object]]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nscale = 0\n",
            "DIR/scene.toml:5:9: the transform flattens the object",
        ),
        (
            "[[object]]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nrotate = [0, 1, 0]\n",
            "DIR/scene.toml:5:10: expected rotate = [ax, ay, az, degrees], found 3 numbers",
        ),
        (
            "[[object]]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nmatrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]\n",
            "DIR/scene.toml:5:10: expected the last row of the matrix to be [0, 0, 0, 1]",
        ),
        (
            "[[track]]\ntarget = \"object:ghost\"\nmotion = \"translate\"\n",
            "DIR/scene.toml:2:10: unknown target \"object:ghost\": the scene has no named objects",
        ),
        (
            "[[track]]\ntarget = \"camera\"\nmotion = \"spin\"\n",
            "DIR/scene.toml:3:10: unknown motion \"spin\"",
        ),
        (
            "[[object]]\ntype = \"sphere\"\nradius = 1\n[[object]\n",
            "DIR/scene.toml:4:10: unclosed array table, expected `]`",
        ),
    ];
    let dir = Folder::new();
    for (text, expected) in cases {
        let e = dir.error(text);
        assert!(
            e.starts_with(expected),
            "for\n{text}\nexpected\n{expected}\nfound\n{e}"
        );
    }
}
