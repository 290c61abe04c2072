//! The 2014 scene file (`.objx`), a small cousin of Wavefront OBJ.
//!
//! | line | meaning |
//! |---|---|
//! | `v x y z` | adds a vertex; vertices are numbered **from 0** |
//! | `f i` | a point light at vertex `i` (invisible; colour of the material in force, white if none) |
//! | `f i r` | a sphere with centre vertex `i` and radius `r > 0` |
//! | `f i j k` | a triangle; its normal follows the right-hand rule |
//! | `f i j k l` | a rectangle; opposite sides equal and adjacent sides perpendicular, within 1e-5 of the longest side |
//! | `mtllib FILE` | reads a material file (see [`super::mtlx`]), relative to this file's folder |
//! | `usemtl NAME` | the material of the faces that follow |
//! | `g NAME...` | Prism's extension: the faces and lights that follow belong to these groups (`g` alone: to none) |
//! | `o NAME` | Prism's extension: the faces and lights that follow belong to object `NAME` |
//!
//! Groups and objects share one namespace ([`crate::scene::Group`]); rendering ignores
//! them, animation moves them. A face refers only to vertices defined above it. Faces before any `usemtl` wear
//! [`Material::default_white`]. Comment lines start with `#`; any other keyword is an error.

use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

use glam::DVec3;

use super::mtlx::{self, MaterialLibrary};
use super::obj::Mesh;
use super::text::{At, data_lines, read_text, shown};
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::scene::{
    Group, Light, Material, Rectangle, Scene, SceneBuilder, Shape, Sphere, Triangle,
};

/// Reads a scene file and the material files and textures it names.
pub fn load(path: &Path) -> Result<Scene> {
    parse(&read_text(path)?, path, read_text)
}

/// Parses the text of a scene file at `path`. `path` names the file in errors, and its
/// folder is where `mtllib` paths are resolved; `read_material_file` is handed each
/// resolved path and returns that file's text (tests serve it from memory). Textures
/// named by a material file are read from disk, relative to that file's folder.
pub fn parse(
    text: &str,
    path: &Path,
    read_material_file: impl FnMut(&Path) -> Result<String>,
) -> Result<Scene> {
    let mut builder = Builder {
        folder: path.parent().unwrap_or(Path::new("")),
        read_material_file,
        vertices: Vec::new(),
        library: MaterialLibrary::new(),
        current: None,
        default_white: None,
        groups: Vec::new(),
        group_ids: HashMap::new(),
        object: None,
        scene: SceneBuilder::new(),
        named: Vec::new(),
    };
    for line in data_lines(text) {
        let at = At {
            path,
            line: line.number,
        };
        builder.line(at, &line.tokens)?;
    }
    let (materials, textures) = builder.library.into_parts();
    let mut scene = builder.scene;
    for m in materials {
        scene.add_classic_material(m);
    }
    for t in textures {
        scene.add_texture(t);
    }
    for g in builder.named {
        scene.add_group(g);
    }
    Ok(scene.finish())
}

/// The scene as it is read, line by line.
struct Builder<'p, R> {
    folder: &'p Path,
    read_material_file: R,
    /// Kept in f64 so the rectangle test sees the file's values, not their f32 roundings.
    vertices: Vec<DVec3>,
    library: MaterialLibrary,
    /// Material in force (`usemtl`), as an index into the library.
    current: Option<u32>,
    /// Index of the default white once a face has needed it.
    default_white: Option<u32>,
    /// Groups in force (`g`), as indices into `scene.groups`.
    groups: Vec<u32>,
    /// Index into `scene.groups` of each group name seen so far.
    group_ids: HashMap<String, u32>,
    /// Object in force (`o`), as an index into `scene.groups`.
    object: Option<u32>,
    scene: SceneBuilder,
    /// Every group named so far (`g`, `o`), in order of first use.
    named: Vec<Group>,
}

impl<R: FnMut(&Path) -> Result<String>> Builder<'_, R> {
    fn line(&mut self, at: At, tokens: &[&str]) -> Result<()> {
        let (keyword, args) = (tokens[0], &tokens[1..]);
        match keyword {
            "v" => self.vertex(at, args),
            "f" => self.face(at, args),
            "mtllib" => {
                let file = one_argument(at, keyword, "file name", args)?;
                self.material_file(at, file)
            }
            "usemtl" => {
                let name = one_argument(at, keyword, "material name", args)?;
                let index = self.library.find(name).ok_or_else(|| {
                    at.error(format!(
                        "unknown material {}: no mtllib read so far defines it",
                        shown(name)
                    ))
                })?;
                self.current = Some(index);
                Ok(())
            }
            "g" => {
                self.groups = args.iter().map(|name| self.group_index(name)).collect();
                Ok(())
            }
            "o" => {
                let name = one_argument(at, keyword, "object name", args)?;
                self.object = Some(self.group_index(name));
                Ok(())
            }
            _ => Err(at.error(format!(
                "unknown keyword {}: expected v, f, mtllib, usemtl, g or o",
                shown(keyword)
            ))),
        }
    }

    fn vertex(&mut self, at: At, args: &[&str]) -> Result<()> {
        if args.len() != 3 {
            return Err(at.error(format!(
                "expected 3 coordinates after v (v x y z), found {}",
                args.len()
            )));
        }
        let x = at.number(args[0], "the x coordinate")?;
        let y = at.number(args[1], "the y coordinate")?;
        let z = at.number(args[2], "the z coordinate")?;
        self.vertices.push(DVec3::new(x, y, z));
        Ok(())
    }

    fn face(&mut self, at: At, args: &[&str]) -> Result<()> {
        if args.is_empty() || args.len() > 4 {
            return Err(at.error(format!(
                "expected 1 to 4 values after f (f i: light, f i r: sphere, f i j k: triangle, \
                 f i j k l: rectangle), found {}",
                args.len()
            )));
        }
        if args.len() == 1 {
            let position = to_f32(self.vertex_at(at, args[0])?.1);
            let color = match self.current {
                Some(m) => self.library.materials()[m as usize].color,
                None => Vec3::ONE,
            };
            let light = self.scene.add_light(Light::point(position, color));
            for g in self.named_groups() {
                self.named[g].lights.push(light);
            }
            return Ok(());
        }
        let shape = if args.len() == 2 {
            let center = to_f32(self.vertex_at(at, args[0])?.1);
            let radius = at.number_above(args[1], "the radius", 0.0, true)? as f32;
            Shape::Sphere(Sphere { center, radius })
        } else {
            let mut corners = Vec::with_capacity(args.len());
            for token in args {
                corners.push(self.vertex_at(at, token)?);
            }
            let points = |i: usize| to_f32(corners[i].1);
            if corners.len() == 3 {
                Shape::Triangle(Triangle {
                    v: [points(0), points(1), points(2)],
                })
            } else {
                check_rectangle(&corners).map_err(|why| {
                    let [i, j, k, l] = [0, 1, 2, 3].map(|n| corners[n].0);
                    at.error(format!(
                        "vertices {i} {j} {k} {l} do not form a rectangle: {why}"
                    ))
                })?;
                Shape::Rectangle(Rectangle {
                    v: [points(0), points(1), points(2), points(3)],
                })
            }
        };
        let material = self.material_in_force(at)?;
        let index = self.scene.add_shape(shape, material);
        for g in self.named_groups() {
            self.named[g].shapes.push(index);
        }
        Ok(())
    }

    /// Index of the group called `name`, created on first use.
    fn group_index(&mut self, name: &str) -> u32 {
        if let Some(&i) = self.group_ids.get(name) {
            return i;
        }
        let groups = &mut self.named;
        groups.push(Group {
            name: name.to_string(),
            ..Group::default()
        });
        let i = (groups.len() - 1) as u32;
        self.group_ids.insert(name.to_string(), i);
        i
    }

    /// The groups the next face or light joins: those of `g` and the `o` object, once each.
    fn named_groups(&self) -> Vec<usize> {
        let mut all: Vec<usize> = self.groups.iter().map(|&g| g as usize).collect();
        all.extend(self.object.map(|o| o as usize));
        all.sort_unstable();
        all.dedup();
        all
    }

    /// The vertex a face token names, with its index.
    fn vertex_at(&self, at: At, token: &str) -> Result<(usize, DVec3)> {
        if token.is_empty() || !token.bytes().all(|b| b.is_ascii_digit()) {
            return Err(at.error(format!(
                "expected a vertex index (an integer from 0), found {}",
                shown(token)
            )));
        }
        let defined = self.vertices.len();
        let index = token.parse::<usize>().ok();
        match index {
            Some(i) if i < defined => Ok((i, self.vertices[i])),
            _ => Err(at.error(format!(
                "vertex index {} out of range: {defined} {} defined so far",
                // Digits only, but possibly too many for a usize.
                index.map_or_else(|| shown(token), |i| i.to_string()),
                if defined == 1 { "vertex" } else { "vertices" }
            ))),
        }
    }

    fn material_in_force(&mut self, at: At) -> Result<u32> {
        if let Some(m) = self.current.or(self.default_white) {
            return Ok(m);
        }
        let index = self.library.push_unnamed(at, Material::default_white())?;
        self.default_white = Some(index);
        Ok(index)
    }

    fn material_file(&mut self, at: At, file: &str) -> Result<()> {
        let resolved = self.folder.join(file);
        let text = (self.read_material_file)(&resolved).map_err(|e| match e {
            // A file that cannot be read is blamed on the line that names it.
            Error::File { path, message } => at.error(format!(
                "cannot read material file {}: {}",
                path.display(),
                message.strip_prefix("cannot read: ").unwrap_or(&message)
            )),
            other => other,
        })?;
        mtlx::parse(&text, &resolved, &mut self.library)
    }
}

/// Writes an indexed triangle mesh in the 2014 form: vertices numbered from 0, one
/// `f i j k` per triangle, no materials (every shape gets the matte white default).
/// Coordinates are written in the shortest form that reads back to the same `f32`.
pub fn write_mesh(mesh: &Mesh, source: &str, w: &mut impl Write) -> std::io::Result<()> {
    writeln!(
        w,
        "# {source}: {} vertices, {} triangles",
        mesh.vertices.len(),
        mesh.triangles.len()
    )?;
    writeln!(w, "# 2014 scene format; vertices are numbered from 0.")?;
    for v in &mesh.vertices {
        writeln!(w, "v {} {} {}", v.x, v.y, v.z)?;
    }
    for [a, b, c] in &mesh.triangles {
        writeln!(w, "f {a} {b} {c}")?;
    }
    Ok(())
}

fn one_argument<'t>(at: At, keyword: &str, what: &str, args: &[&'t str]) -> Result<&'t str> {
    match args {
        [one] => Ok(one),
        _ => Err(at.error(format!(
            "expected 1 {what} after {keyword}, found {} values",
            args.len()
        ))),
    }
}

fn to_f32(p: DVec3) -> Vec3 {
    p.as_vec3().into()
}

/// Why four corners (index, position) in order are not a rectangle, checked in f64 with
/// a tolerance relative to the longest side so that big rooms and small boxes are judged
/// alike. Side ij must equal side lk as vectors (a parallelogram) and ij must be
/// perpendicular to il.
fn check_rectangle(corners: &[(usize, DVec3)]) -> std::result::Result<(), String> {
    let [a, b, c, d] = [0, 1, 2, 3].map(|n| corners[n].1);
    let name = |m: usize, n: usize| format!("{}-{}", corners[m].0, corners[n].0);
    let sides = [
        (b - a, name(0, 1)),
        (c - b, name(1, 2)),
        (d - c, name(2, 3)),
        (a - d, name(3, 0)),
    ];
    let longest = sides.iter().map(|s| s.0.length()).fold(0.0, f64::max);
    let tolerance = 1e-5 * longest;
    if let Some((_, side)) = sides.iter().find(|s| s.0.length() <= tolerance) {
        return Err(format!("side {side} has zero length"));
    }
    let mismatch = ((b - a) - (c - d)).length();
    if mismatch > tolerance {
        return Err(format!(
            "sides {} and {} are not equal and parallel (they differ by {}, more than {})",
            name(0, 1),
            name(3, 2),
            short(mismatch),
            short(tolerance)
        ));
    }
    // Distance by which side ij leans along side il.
    let lean = (b - a).dot(d - a).abs() / (d - a).length();
    if lean > tolerance {
        let angle = (b - a).angle_between(d - a).to_degrees();
        return Err(format!(
            "sides {} and {} are not perpendicular (angle {angle:.4} degrees)",
            name(0, 1),
            name(0, 3)
        ));
    }
    Ok(())
}

/// A length for a message: four decimals, or scientific notation when that shows nothing.
fn short(x: f64) -> String {
    if x != 0.0 && x.abs() < 1e-3 {
        format!("{x:.3e}")
    } else {
        format!("{x:.4}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const MTL: &str = "newmtl red 255 0 0 1 1 0 1 1 0 0 0\nnewmtl blue 0 0 51 1 1 0 1 1 0 0 0\n";

    /// Parses `text` as `dir/s.objx`; `dir/m.mtlx` and `dir/n.mtlx` are served from memory.
    fn parse_str(text: &str) -> Result<Scene> {
        parse(text, Path::new("dir/s.objx"), |p: &Path| match p.to_str() {
            Some("dir/m.mtlx") => Ok(MTL.to_string()),
            Some("dir/n.mtlx") => Ok("newmtl green 0 255 0 1 1 0 1 1 0 0 0\n".to_string()),
            Some("dir/dup.mtlx") => Ok("\nnewmtl red 1 1 1 1 1 0 1 1 0 0 0\n".to_string()),
            _ => Err(Error::file(p, "cannot read: not found")),
        })
    }

    fn err(text: &str) -> String {
        parse_str(text).unwrap_err().to_string()
    }

    const SQUARE: &str = "v 0 0 0\nv 2 0 0\nv 2 3 0\nv 0 3 0\n";

    #[test]
    fn shapes_and_lights_get_exact_values() {
        let text = format!("{SQUARE}v 1 1 5.5\nf 0 1 2\nf 0 1 2 3\nf 4 0.75\nf 4\n");
        let scene = parse_str(&text).unwrap();
        let v = |x, y, z| Vec3::new(x, y, z);
        assert_eq!(
            scene.shapes,
            vec![
                Shape::Triangle(Triangle {
                    v: [v(0., 0., 0.), v(2., 0., 0.), v(2., 3., 0.)]
                }),
                Shape::Rectangle(Rectangle {
                    v: [v(0., 0., 0.), v(2., 0., 0.), v(2., 3., 0.), v(0., 3., 0.)]
                }),
                Shape::Sphere(Sphere {
                    center: v(1., 1., 5.5),
                    radius: 0.75
                }),
            ]
        );
        assert_eq!(scene.lights, vec![Light::point(v(1., 1., 5.5), Vec3::ONE)]);
        // The default white is added once, for the faces that had no usemtl.
        assert_eq!(scene.materials, vec![Material::default_white()]);
        assert_eq!(scene.material_of, vec![0, 0, 0]);
    }

    #[test]
    fn materials_apply_until_the_next_usemtl() {
        let text = format!(
            "mtllib m.mtlx\n{SQUARE}f 0 1 2\nusemtl blue\nf 0 1\nf 2\nusemtl red\nf 1 2 3\n\
             mtllib n.mtlx\nusemtl green\nf 3 1\n"
        );
        let scene = parse_str(&text).unwrap();
        let names: Vec<_> = scene.materials.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["red", "blue", "default", "green"]);
        assert_eq!(scene.material_of, vec![2, 1, 0, 3]);
        assert_eq!(scene.lights[0].color, Vec3::new(0.0, 0.0, 0.2));
        // No default white when every face has a material.
        let scene = parse_str("mtllib m.mtlx\nusemtl red\nv 0 0 0\nf 0 1\nf 0\n").unwrap();
        assert_eq!(scene.materials.len(), 2);
        assert_eq!(scene.lights[0].color, Vec3::X);
    }

    #[test]
    fn whitespace_comments_and_crlf_are_tolerated() {
        let text = "# c\r\n\r\nv  1\t2 3 \r\n   # indented\r\nf  0   4\r\n";
        let scene = parse_str(text).unwrap();
        assert_eq!(
            scene.shapes,
            vec![Shape::Sphere(Sphere {
                center: Vec3::new(1.0, 2.0, 3.0),
                radius: 4.0
            })]
        );
    }

    #[test]
    fn exact_messages() {
        assert_eq!(
            err("v 0 0 0\nvt 0 0\n"),
            "dir/s.objx:2: unknown keyword `vt`: expected v, f, mtllib, usemtl, g or o"
        );
        let ten = "v 0 0 0\n".repeat(10);
        assert_eq!(
            err(&format!("{ten}f 0 1 12\n")),
            "dir/s.objx:11: vertex index 12 out of range: 10 vertices defined so far"
        );
        assert_eq!(
            err("v 0 0 0\n\nf 0 abc\n"),
            "dir/s.objx:3: expected a number for the radius, found `abc`"
        );
        assert_eq!(
            err(&format!("{SQUARE}f 0 1 3 2\n")),
            "dir/s.objx:5: vertices 0 1 3 2 do not form a rectangle: sides 0-1 and 2-3 are not \
             equal and parallel (they differ by 4.0000, more than 3.606e-5)"
        );
    }

    #[test]
    fn errors_name_the_line_and_what_was_expected() {
        let cases: &[(&str, usize, &str)] = &[
            (
                "v 1 2\n",
                1,
                "expected 3 coordinates after v (v x y z), found 2",
            ),
            ("v 1 2 3 4\n", 1, "found 4"),
            (
                "v 1 nan 3\n",
                1,
                "expected a finite number for the y coordinate, found `nan`",
            ),
            ("v 1 2 1e39\n", 1, "the z coordinate"),
            ("v 0 0 0\nf\n", 2, "expected 1 to 4 values after f"),
            ("v 0 0 0\nf 0 0 0 0 0\n", 2, "found 5"),
            ("v 0 0 0\nf 0 0\n", 2, "expected the radius > 0, found `0`"),
            ("v 0 0 0\nf 0 -1\n", 2, "the radius > 0"),
            (
                "v 0 0 0\nf 0 inf\n",
                2,
                "expected a finite number for the radius",
            ),
            (
                "v 0 0 0\nf -1 2\n",
                2,
                "expected a vertex index (an integer from 0), found `-1`",
            ),
            ("v 0 0 0\nf 1.0\n", 2, "found `1.0`"),
            (
                "f 0\n",
                1,
                "vertex index 0 out of range: 0 vertices defined so far",
            ),
            ("v 0 0 0\nf 1\n", 2, "1 vertex defined so far"),
            (
                "v 0 0 0\nf 99999999999999999999999 1\n",
                2,
                "`99999999999999999999999` out of range",
            ),
            ("usemtl red\n", 1, "unknown material `red`"),
            ("mtllib m.mtlx\nusemtl nope\n", 2, "unknown material `nope`"),
            (
                "usemtl\n",
                1,
                "expected 1 material name after usemtl, found 0 values",
            ),
            (
                "mtllib a b\n",
                1,
                "expected 1 file name after mtllib, found 2 values",
            ),
            (
                "\nmtllib gone.mtlx\n",
                2,
                "cannot read material file dir/gone.mtlx: not found",
            ),
            ("o\n", 1, "expected 1 object name after o, found 0 values"),
            (
                "o a b\n",
                1,
                "expected 1 object name after o, found 2 values",
            ),
            ("v 0 0 0 # trailing comment\n", 1, "found 6"),
        ];
        for &(text, line, words) in cases {
            let e = err(text);
            let prefix = format!("dir/s.objx:{line}: ");
            assert!(
                e.starts_with(&prefix) && e.contains(words),
                "{text:?} gave {e}"
            );
        }
    }

    #[test]
    fn groups_and_objects_record_their_shapes_and_lights() {
        let text = format!(
            "{SQUARE}f 0 1 2\ng wall left\nf 0 1 2 3\nf 3\no ball\nf 0 1\ng\nf 1 2\n\
             g left\nf 2 3\n"
        );
        let scene = parse_str(&text).unwrap();
        let group = |name: &str| {
            let g = scene.group(name).unwrap();
            (g.shapes.clone(), g.lights.clone())
        };
        assert_eq!(group("wall"), (vec![1, 2], vec![0]));
        assert_eq!(group("left"), (vec![1, 2, 4], vec![0]));
        // An object stays in force across `g` lines.
        assert_eq!(group("ball"), (vec![2, 3, 4], vec![]));
        let names: Vec<_> = scene.groups.iter().map(|g| g.name.as_str()).collect();
        assert_eq!(names, ["wall", "left", "ball"]);
        assert!(scene.group("nothing").is_none());
    }

    #[test]
    fn sixty_thousand_groups_each_hold_their_shape() {
        // Names are looked up in a map: a linear search per name took seconds here.
        let mut text = String::from(SQUARE);
        for i in 0..60_000 {
            text.push_str(&format!("g part{i}\nf 0 1 2\n"));
        }
        let scene = parse_str(&text).unwrap();
        assert_eq!(scene.groups.len(), 60_000);
        assert_eq!(scene.group("part59999").unwrap().shapes, vec![59_999]);
        assert_eq!(scene.group("part0").unwrap().shapes, vec![0]);
    }

    #[test]
    fn material_file_errors_point_into_the_material_file() {
        assert_eq!(
            err("mtllib m.mtlx\nmtllib dup.mtlx\n"),
            "dir/dup.mtlx:2: material `red` is already defined at dir/m.mtlx:1"
        );
        assert!(err("mtllib m.mtlx\nmtllib m.mtlx\n").contains("already defined"));
    }

    #[test]
    fn rectangles_are_checked_with_a_relative_tolerance() {
        let rect = |corners: &str| parse_str(&format!("{corners}f 0 1 2 3\n"));
        // A big room is judged like a small box: 1e-6 relative error passes.
        assert!(rect("v 0 0 0\nv 4000 0 0\nv 4000 600 0.004\nv 0 600 0\n").is_ok());
        assert!(rect("v 0 0 0\nv 4000 0 0\nv 4000 600 0.1\nv 0 600 0.1\n").is_ok());
        assert!(rect("v 0 0 0\nv 4e-3 0 0\nv 4e-3 6e-4 0\nv 0 6e-4 0\n").is_ok());
        // A parallelogram: equal opposite sides, not perpendicular.
        let e = rect("v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 1 0\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("sides 0-1 and 0-3 are not perpendicular (angle 45.0000"),
            "{e}"
        );
        let e = rect("v 0 0 0\nv 0 0 0\nv 0 1 0\nv 0 1 0\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("side 0-1 has zero length"), "{e}");
        let e = rect("v 1 1 1\nv 1 1 1\nv 1 1 1\nv 1 1 1\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("do not form a rectangle: side 0-1 has zero length"),
            "{e}"
        );
        // A skewed quad that is not even planar.
        assert!(rect("v 0 0 0\nv 1 0 0\nv 1 1 1\nv 0 1 0\n").is_err());
    }

    /// A line from the scene vocabulary with random arguments.
    fn keyword_line() -> impl Strategy<Value = String> {
        let keyword = prop_oneof![4 => "v|f|mtllib|usemtl|g|o|#", 1 => "\\PC{0,3}"];
        let token = prop_oneof![
            "[0-9]{1,2}",
            "-?[0-9]{1,4}(\\.[0-9]{0,3})?",
            "nan|inf|1e39|1e-50|99999999999999999999|m.mtlx|n.mtlx|red|blue",
            "\\PC{0,4}",
        ];
        (keyword, prop::collection::vec(token, 0..6))
            .prop_map(|(k, t)| format!("{k} {}", t.join(" ")))
    }

    proptest! {
        #[test]
        fn arbitrary_text_never_panics(text in "\\PC{0,300}") {
            let _ = parse_str(&text);
        }

        #[test]
        fn arbitrary_keyword_lines_never_panic(
            lines in prop::collection::vec(keyword_line(), 0..40),
        ) {
            let text = format!("{SQUARE}{}", lines.join("\n"));
            let _ = parse_str(&text);
        }
    }

    #[test]
    fn a_written_mesh_reads_back_as_the_same_triangles() {
        let text = "v 0.1 0.2 0.3\nv 1e-7 123456.79 -7\nv 1 0 0\nv 0 1 0.333333343\nf 1 2 3 4\n";
        let obj_path = Path::new("m.obj");
        let mesh = crate::format::obj::parse_mesh(text, obj_path).unwrap();
        let mut out = Vec::new();
        write_mesh(&mesh, "m.obj", &mut out).unwrap();
        let written = std::str::from_utf8(&out).unwrap();
        assert!(written.contains("\nf 0 1 2\nf 0 2 3\n"), "{written}");
        let back = parse(written, Path::new("m.objx"), |_| unreachable!()).unwrap();
        let direct = crate::format::obj::parse(text, obj_path).unwrap();
        assert_eq!(back.shapes, direct.shapes);
        assert_eq!(back.shapes.len(), 2);
    }
}
