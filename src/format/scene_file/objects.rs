//! `[[object]]`: which keys each type takes, the shapes it makes in object space, and
//! those shapes placed by the object's transform.

use super::primitives::{self, Local, Piece};
use super::raw::RawObject;
use super::source::Source;
use super::transform::Transform;
use super::values::{Num, Vector};
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::scene::{MeshAttributes, Rectangle, Shape, Sphere, Triangle};
use glam::DVec3;
use toml::Spanned;

/// What an object is before it is placed.
pub enum Geometry {
    Local(Local),
    /// An unbounded plane, sized once the rest of the scene is known.
    Plane {
        point: DVec3,
        normal: DVec3,
    },
    /// A mesh file (`file`, relative to the scene file).
    Mesh(Spanned<String>),
    /// Placements of a mesh held once: the mesh object named `of`, or the mesh file
    /// `file`.
    Instance(InstanceOf),
}

/// What an instance places.
pub enum InstanceOf {
    /// The mesh of the mesh (or instance) object of this name.
    Object(Spanned<String>),
    /// A mesh file, read once.
    File(Spanned<String>),
}

/// The shape keys each object type takes.
fn keys_of(kind: &str) -> Option<&'static [&'static str]> {
    Some(match kind {
        "mesh" => &["file", "smooth", "up_axis"],
        "instance" => &["of", "file", "smooth", "up_axis", "transforms"],
        "sphere" => &["center", "radius"],
        "plane" => &["point", "normal"],
        "quad" => &["corner", "edge1", "edge2"],
        "triangle" => &["vertices"],
        "box" => &["min", "max"],
        "disk" => &["center", "normal", "radius"],
        "cylinder" => &["base", "top", "axis", "height", "radius", "capped"],
        _ => return None,
    })
}

pub fn geometry(source: &Source, raw: &RawObject) -> Result<Geometry> {
    let kind = raw.kind.get_ref().as_str();
    let allowed = keys_of(kind).ok_or_else(|| {
        source.error(
            &raw.kind,
            format!(
                "unknown object type \"{kind}\": expected mesh, sphere, plane, quad, triangle, \
                 box, disk, cylinder or instance"
            ),
        )
    })?;
    super::source::refuse_foreign_keys(source, raw.shape_keys(), allowed, kind)?;
    let article = if kind.starts_with(['a', 'e', 'i', 'o', 'u']) {
        "an"
    } else {
        "a"
    };
    let missing = |key: &str| source.error(&raw.kind, format!("{article} {kind} needs `{key}`"));
    let need = |v: &Option<Spanned<Vector>>, key: &str| -> Result<DVec3> {
        v.as_ref()
            .map(|v| v.get_ref().0)
            .ok_or_else(|| missing(key))
    };
    let or_origin = |v: &Option<Spanned<Vector>>| v.as_ref().map_or(DVec3::ZERO, |v| v.get_ref().0);
    let positive = |v: &Option<Spanned<Num>>, key: &str| -> Result<f64> {
        let n = v.as_ref().ok_or_else(|| missing(key))?;
        match n.get_ref().0 {
            x if x > 0.0 => Ok(x),
            x => Err(source.error(n, format!("expected {key} > 0, found {x}"))),
        }
    };
    let direction = |v: &Option<Spanned<Vector>>, key: &str, default: DVec3| -> Result<DVec3> {
        match v {
            None => Ok(default),
            Some(d) => unit(source, d, key),
        }
    };
    Ok(match kind {
        "mesh" => Geometry::Mesh(raw.file.clone().ok_or_else(|| missing("file"))?),
        "instance" => Geometry::Instance(match (&raw.of, &raw.file) {
            (Some(of), None) => InstanceOf::Object(of.clone()),
            (None, Some(file)) => InstanceOf::File(file.clone()),
            (Some(of), Some(_)) => {
                return Err(
                    source.error(of, "give `of` (a mesh object's name) or `file`, not both")
                );
            }
            (None, None) => return Err(missing("of` or `file")),
        }),
        "sphere" => Geometry::Local(primitives::sphere(
            or_origin(&raw.center),
            positive(&raw.radius, "radius")?,
        )),
        "plane" => Geometry::Plane {
            point: or_origin(&raw.point),
            normal: direction(&raw.normal, "normal", DVec3::Y)?,
        },
        "quad" => {
            let (e1, e2) = (need(&raw.edge1, "edge1")?, need(&raw.edge2, "edge2")?);
            if e1.cross(e2).length_squared() == 0.0 {
                return Err(source.error_at(
                    raw.edge2.as_ref().map_or(raw.kind.span(), Spanned::span),
                    "expected edges that span an area, found parallel or zero edges",
                ));
            }
            Geometry::Local(primitives::quad(or_origin(&raw.corner), e1, e2))
        }
        "triangle" => {
            let v = raw.vertices.as_ref().ok_or_else(|| missing("vertices"))?;
            let [a, b, c] = v.get_ref().map(|p| p.0);
            if (b - a).cross(c - a).length_squared() == 0.0 {
                return Err(source.error(
                    v,
                    "expected a triangle with area, found its vertices in a line",
                ));
            }
            Geometry::Local(primitives::triangle([a, b, c]))
        }
        "box" => {
            let (min, max) = (need(&raw.min, "min")?, need(&raw.max, "max")?);
            if !min.cmplt(max).all() {
                return Err(source.error_at(
                    raw.max.as_ref().map_or(raw.kind.span(), Spanned::span),
                    format!("expected max > min on every axis, found min {min} and max {max}"),
                ));
            }
            Geometry::Local(primitives::cuboid(min, max))
        }
        "disk" => Geometry::Local(primitives::disk(
            or_origin(&raw.center),
            direction(&raw.normal, "normal", DVec3::Y)?,
            positive(&raw.radius, "radius")?,
        )),
        "cylinder" => {
            let base = or_origin(&raw.base);
            let top = match (&raw.top, &raw.axis, &raw.height) {
                (Some(t), None, None) => t.get_ref().0,
                (None, axis, Some(_)) => {
                    base + direction(axis, "axis", DVec3::Y)? * positive(&raw.height, "height")?
                }
                (Some(t), _, _) => {
                    return Err(source.error(t, "give `top`, or `axis` and `height`, not both"));
                }
                (None, _, None) => return Err(missing("`top` or `height`")),
            };
            if (top - base).length() <= 0.0 {
                return Err(source.error(&raw.kind, "expected `top` away from `base`"));
            }
            let capped = raw.capped.as_ref().is_none_or(|c| *c.get_ref());
            Geometry::Local(primitives::cylinder(
                base,
                top,
                positive(&raw.radius, "radius")?,
                capped,
            ))
        }
        _ => unreachable!("keys_of knows every type"),
    })
}

/// A direction given by the file, made unit length; zero is an error.
pub fn unit(source: &Source, v: &Spanned<Vector>, key: &str) -> Result<DVec3> {
    let d = v.get_ref().0;
    let n = d.normalize_or_zero();
    if n == DVec3::ZERO {
        return Err(source.error(v, format!("expected a `{key}` that is not zero")));
    }
    Ok(n)
}

/// Shapes placed in the world, with their mesh attributes (`first_shape` 0).
pub struct Placed {
    pub shapes: Vec<Shape>,
    pub attributes: Option<MeshAttributes>,
}

/// Places `local` by `t`. `triangles_only` splits rectangles in two, for emitters
/// (an emissive mesh light samples triangles). Fails with a message when a sphere would
/// be scaled unevenly.
pub fn place(local: &Local, t: &Transform, triangles_only: bool) -> Result<Placed, String> {
    let mirrors = t.mirrors();
    let mut shapes = Vec::with_capacity(local.pieces.len() * 2);
    for piece in &local.pieces {
        match *piece {
            Piece::Sphere { center, radius } => {
                let s = t.uniform_scale().ok_or_else(|| {
                    "a sphere cannot be scaled differently along different axes (it would be \
                     an ellipsoid, which Prism has no shape for): give one number to `scale`, \
                     or use a mesh"
                        .to_string()
                })?;
                shapes.push(Shape::Sphere(Sphere {
                    center: t.point(center),
                    radius: (radius * s) as f32,
                }));
            }
            Piece::Triangle(v) => {
                let mut v = v.map(|p| t.point(p));
                if mirrors {
                    v.swap(1, 2);
                }
                shapes.push(Shape::Triangle(Triangle { v }));
            }
            Piece::Rectangle(v) => {
                let mut v = v.map(|p| t.point(p));
                if mirrors {
                    v.swap(1, 3);
                }
                if triangles_only {
                    shapes.push(Shape::Triangle(Triangle {
                        v: [v[0], v[1], v[2]],
                    }));
                    shapes.push(Shape::Triangle(Triangle {
                        v: [v[0], v[2], v[3]],
                    }));
                } else {
                    shapes.push(Shape::Rectangle(Rectangle { v }));
                }
            }
        }
    }
    let attributes =
        (!local.normal_indices.is_empty() || !local.texcoord_indices.is_empty()).then(|| {
            let rewind = |idx: &[[u32; 3]]| -> Vec<[u32; 3]> {
                idx.iter()
                    .map(|&[a, b, c]| if mirrors { [a, c, b] } else { [a, b, c] })
                    .collect()
            };
            MeshAttributes {
                first_shape: 0,
                len: shapes.len() as u32,
                normals: local
                    .normals
                    .iter()
                    .map(|n| t.normal(Vec3::new(n.x as f32, n.y as f32, n.z as f32)))
                    .collect(),
                normal_indices: rewind(&local.normal_indices),
                texcoords: local.texcoords.clone(),
                texcoord_indices: rewind(&local.texcoord_indices),
                colors: Vec::new(),
                color_indices: Vec::new(),
            }
        });
    Ok(Placed { shapes, attributes })
}

/// The object-level error for a transform that does not fit the shape.
pub fn placement_error(source: &Source, raw: &RawObject, message: String) -> Error {
    let span = raw
        .scale
        .as_ref()
        .map(Spanned::span)
        .or(raw.matrix.as_ref().map(Spanned::span))
        .unwrap_or(raw.kind.span());
    source.error_at(span, message)
}
