//! Includes resolved against the including file; include cycles, depth and misplaced sections.

use super::*;

#[test]
fn includes_resolve_against_the_including_file() {
    let dir = Folder::new();
    dir.write(
        "lib/materials.toml",
        "include = [\"more/colours.toml\"]\n[[material]]\nname = \"red\"\ncolor = [1, 0, 0]\n",
    );
    dir.write(
        "lib/more/colours.toml",
        "[[material]]\nname = \"blue\"\ncolor = [0, 0, 1]\n",
    );
    let f = dir.load(
        "include = [\"lib/materials.toml\"]\n[[object]]\ntype = \"sphere\"\nradius = 1\n\
         material = \"blue\"\n",
    );
    let names: Vec<_> = f.scene.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["blue", "red"]);
    assert_eq!(f.scene.material_of, [0]);
}

#[test]
fn include_cycles_and_depth_are_errors_at_the_include_line() {
    let dir = Folder::new();
    dir.write("a.toml", "\ninclude = [\"b.toml\"]\n");
    dir.write("b.toml", "include = [\"a.toml\"]\n");
    assert_eq!(
        dir.error("include = [\"a.toml\"]\n"),
        "DIR/b.toml:1:12: include cycle: DIR/a.toml is already being read (it includes itself, \
         directly or not)"
    );
    let deep = Folder::new();
    for i in 0..20 {
        deep.write(
            &format!("f{i}.toml"),
            &format!("include = [\"f{}.toml\"]\n", i + 1),
        );
    }
    deep.write("f20.toml", "");
    assert_eq!(
        deep.error("include = [\"f0.toml\"]\n"),
        "DIR/f15.toml:1:12: includes nest more than 16 files deep"
    );
    assert_eq!(
        dir.error("include = [\"nowhere.toml\"]\n")
            .split(": No such")
            .next()
            .unwrap(),
        "DIR/scene.toml:1:12: cannot open DIR/nowhere.toml"
    );
    dir.write("cam.toml", "[camera]\nfrom = [0, 0, 1]\nat = [0, 0, 0]\n");
    assert_eq!(
        dir.error("include = [\"cam.toml\"]\n"),
        "DIR/cam.toml:1:1: [camera] belongs in the main scene file: an included file holds \
         materials, lights and objects"
    );
}
