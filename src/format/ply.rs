//! Stanford PLY meshes (`ascii`, `binary_little_endian` and `binary_big_endian` 1.0).
//!
//! The `vertex` element gives positions (`x y z`) and, when all of a set is present,
//! normals (`nx ny nz`), colours (`red green blue`: integers scaled to 0..1 by their
//! type's maximum, floats as stored; alpha is ignored) and texture coordinates (`u v`,
//! `s t`, `texture_u texture_v` or `texture_s texture_t`). The `face` element's
//! `vertex_indices` (or `vertex_index`) lists are fanned into triangles `(1, k, k+1)`
//! like [`super::obj`]'s polygons. Every other element and property is read past.
//!
//! Header errors name the line and column; body errors name the line and column in
//! ASCII and the byte offset in binary. Before anything is reserved, every element's
//! row count is checked against the bytes left in the file, at the fewest bytes a row
//! can take, so a short file cannot make the reader allocate for rows it does not have.

mod body;
mod header;
#[cfg(test)]
mod tests;

use std::path::Path;

use body::{Field, Values};
use header::{Element, Encoding, Header, PropertyKind, Scalar};

use super::text::shown;
use crate::error::{Error, Result};
use crate::math::Vec3;

/// Larger files are refused before they are read: the biggest public scans are a few
/// hundred megabytes, and this keeps a stray multi-gigabyte file from filling memory.
pub const MAX_FILE_BYTES: u64 = 2 << 30;

/// A PLY file's mesh as plain data: vertex attributes in parallel arrays (an absent
/// attribute is an empty array) and triangles whose indices are all checked.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlyMesh {
    /// Vertex positions (`x y z`), in the file's own frame and units.
    pub positions: Vec<Vec3>,
    /// Per-vertex normals (`nx ny nz`) as stored, not normalised.
    pub normals: Vec<Vec3>,
    /// Red, green, blue in 0..1 for integer types; float colours as stored.
    pub colors: Vec<Vec3>,
    /// Per-vertex texture coordinates (`u v` or a synonym) as stored.
    pub texcoords: Vec<[f32; 2]>,
    /// Indices into `positions`, each polygon fanned into `(1, k, k+1)` in file order.
    pub triangles: Vec<[u32; 3]>,
    /// What was read past or dropped, for the user: one line each.
    pub warnings: Vec<String>,
}

/// Reads a PLY file. Only regular files of at most [`MAX_FILE_BYTES`] are read.
pub fn load(path: &Path) -> Result<PlyMesh> {
    parse(&read_bytes(path)?, path)
}

/// A directory, a FIFO or a device such as `/dev/zero` would fail late, block or never
/// end, so only regular files are read, and never more than the bound (a file may
/// grow between the check and the read).
fn read_bytes(path: &Path) -> Result<Vec<u8>> {
    crate::util::file::read_regular(path, MAX_FILE_BYTES)
        .map_err(|e| Error::file(path, format!("cannot read: {e}")))
}

/// Parses a PLY file held in memory; `path` names it in errors.
pub fn parse(bytes: &[u8], path: &Path) -> Result<PlyMesh> {
    let header = header::parse(bytes, path)?;
    check_rows_fit(&header, bytes.len(), path)?;
    let vertex_count = header
        .elements
        .iter()
        .find(|e| e.name == "vertex")
        .map_or(0, |e| e.rows);
    let mut values = Values::new(header.encoding, bytes, header.body_start, path);
    let mut mesh = PlyMesh::default();
    for element in &header.elements {
        match element.name.as_str() {
            "vertex" => read_vertices(element, &mut values, &mut mesh, path)?,
            "face" => read_faces(element, vertex_count, &mut values, &mut mesh, path)?,
            _ => {
                skip_rows(element, &mut values)?;
                if element.rows > 0 {
                    mesh.warnings.push(format!(
                        "element {} ({} rows) is not read",
                        shown(&element.name),
                        element.rows
                    ));
                }
            }
        }
    }
    mesh.warnings.extend(values.trailing());
    Ok(mesh)
}

/// Refuses a header whose rows cannot all fit in the bytes after it.
fn check_rows_fit(header: &Header, file_bytes: usize, path: &Path) -> Result<()> {
    let body_bytes = (file_bytes - header.body_start) as u64;
    // The file's last ASCII value needs no separator after it.
    let slack = u64::from(header.encoding == Encoding::Ascii);
    let mut needed = 0u64;
    for element in &header.elements {
        let row_bytes = element.min_row_bytes(header.encoding);
        needed += u64::from(element.rows) * row_bytes;
        if needed > body_bytes + slack {
            return Err(Error::parse_at(
                path,
                element.line,
                element.count_column,
                format!(
                    "expected a row count that fits in the file: {} rows of element {} \
                     take at least {} bytes, found {} bytes after the header for all \
                     elements",
                    element.rows,
                    shown(&element.name),
                    u64::from(element.rows) * row_bytes,
                    body_bytes
                ),
            ));
        }
    }
    Ok(())
}

/// Reads past every row of an element that is not kept.
fn skip_rows(element: &Element, values: &mut Values) -> Result<()> {
    if element.properties.is_empty() {
        return Ok(());
    }
    for row in 0..element.rows {
        for p in &element.properties {
            let field = Field {
                element: &element.name,
                row,
                property: &p.name,
            };
            skip_property(p.kind, values, field)?;
        }
    }
    Ok(())
}

fn skip_property(kind: PropertyKind, values: &mut Values, field: Field) -> Result<()> {
    match kind {
        PropertyKind::Scalar(ty) => values.skip(ty, field),
        PropertyKind::List { length, item } => {
            let n = values.list_length(length, item, field)?;
            values.skip_items(item, n, field)
        }
    }
}

/// Where a vertex property's value goes.
#[derive(Clone, Copy, PartialEq)]
enum Slot {
    Position(usize),
    Normal(usize),
    /// A colour channel and what the stored value is divided by to bring it to 0..1.
    Color(usize, f64),
    Texcoord(usize),
    Skip,
}

const TEXCOORD_NAMES: [[&str; 2]; 4] = [
    ["u", "v"],
    ["s", "t"],
    ["texture_u", "texture_v"],
    ["texture_s", "texture_t"],
];

/// Where each vertex property goes, and which optional attributes are present.
struct VertexLayout {
    slots: Vec<Slot>,
    normals: bool,
    colors: bool,
    texcoords: bool,
}

fn vertex_layout(
    element: &Element,
    path: &Path,
    warnings: &mut Vec<String>,
) -> Result<VertexLayout> {
    let mut slots = vec![Slot::Skip; element.properties.len()];
    for (axis, name) in ["x", "y", "z"].into_iter().enumerate() {
        let index = element.property(name).ok_or_else(|| {
            Error::parse_at(
                path,
                element.line,
                1,
                format!(
                    "expected properties x, y and z in element `vertex`, found no {}",
                    shown(name)
                ),
            )
        })?;
        slots[index] = Slot::Position(axis);
        scalar_type(element, index, path)?;
    }
    let mut set = |names: &[&str], slot: fn(usize, Scalar) -> Slot| -> Result<bool> {
        let Some(indices) = property_set(element, names, warnings) else {
            return Ok(false);
        };
        for (axis, index) in indices.into_iter().enumerate() {
            slots[index] = slot(axis, scalar_type(element, index, path)?);
        }
        Ok(true)
    };
    let normals = set(&["nx", "ny", "nz"], |axis, _| Slot::Normal(axis))?;
    let color = |axis, ty: Scalar| Slot::Color(axis, color_divisor(ty));
    let colors = set(&["red", "green", "blue"], color)?
        || set(&["diffuse_red", "diffuse_green", "diffuse_blue"], color)?;
    let mut texcoords = false;
    for names in TEXCOORD_NAMES {
        if set(&names, |axis, _| Slot::Texcoord(axis))? {
            texcoords = true;
            break;
        }
    }
    Ok(VertexLayout {
        slots,
        normals,
        colors,
        texcoords,
    })
}

/// The indices of the properties named `names` if all are there; a partial set is
/// left out with a warning (a lone `nx` is not a normal).
fn property_set(
    element: &Element,
    names: &[&str],
    warnings: &mut Vec<String>,
) -> Option<Vec<usize>> {
    let found: Vec<Option<usize>> = names.iter().map(|n| element.property(n)).collect();
    if found.iter().all(Option::is_none) {
        return None;
    }
    if let Some((missing, _)) = names.iter().zip(&found).find(|(_, f)| f.is_none()) {
        warnings.push(format!(
            "vertex properties {} are ignored: {} is missing",
            names.join(" "),
            shown(missing)
        ));
        return None;
    }
    Some(found.into_iter().flatten().collect())
}

/// The type of a vertex property that must be a single number.
fn scalar_type(element: &Element, index: usize, path: &Path) -> Result<Scalar> {
    let property = &element.properties[index];
    match property.kind {
        PropertyKind::Scalar(ty) => Ok(ty),
        PropertyKind::List { .. } => Err(Error::parse_at(
            path,
            property.line,
            1,
            format!(
                "expected a scalar type for vertex property {}, found a list",
                shown(&property.name)
            ),
        )),
    }
}

/// Integer colours span their type's range (255 is full for `uchar`); floats are
/// already in 0..1.
fn color_divisor(ty: Scalar) -> f64 {
    match ty.integer_range() {
        Some((_, max)) => max as f64,
        None => 1.0,
    }
}

fn read_vertices(
    element: &Element,
    values: &mut Values,
    mesh: &mut PlyMesh,
    path: &Path,
) -> Result<()> {
    let layout = vertex_layout(element, path, &mut mesh.warnings)?;
    let rows = element.rows as usize;
    mesh.positions.reserve_exact(rows);
    if layout.normals {
        mesh.normals.reserve_exact(rows);
    }
    if layout.colors {
        mesh.colors.reserve_exact(rows);
    }
    if layout.texcoords {
        mesh.texcoords.reserve_exact(rows);
    }
    for row in 0..element.rows {
        let (mut position, mut normal, mut color, mut uv) =
            ([0.0f32; 3], [0.0f32; 3], [0.0f32; 3], [0.0f32; 2]);
        for (property, &slot) in element.properties.iter().zip(&layout.slots) {
            let field = Field {
                element: &element.name,
                row,
                property: &property.name,
            };
            let (target, divisor) = match slot {
                Slot::Position(axis) => (&mut position[axis], 1.0),
                Slot::Normal(axis) => (&mut normal[axis], 1.0),
                Slot::Color(axis, divisor) => (&mut color[axis], divisor),
                Slot::Texcoord(axis) => (&mut uv[axis], 1.0),
                Slot::Skip => {
                    skip_property(property.kind, values, field)?;
                    continue;
                }
            };
            let PropertyKind::Scalar(ty) = property.kind else {
                unreachable!("vertex_layout gives slots to scalars only")
            };
            let place = values.place();
            let value = (values.scalar(ty, field)? / divisor) as f32;
            if !value.is_finite() {
                return Err(values.error_at(
                    place,
                    format!("expected a finite number (in f32) for {field}, found {value}"),
                ));
            }
            *target = value;
        }
        mesh.positions.push(Vec3::from_array(position));
        if layout.normals {
            mesh.normals.push(Vec3::from_array(normal));
        }
        if layout.colors {
            mesh.colors.push(Vec3::from_array(color));
        }
        if layout.texcoords {
            mesh.texcoords.push(uv);
        }
    }
    Ok(())
}

/// Reads the faces' index lists, fanning each polygon as it is read, and passes over
/// every other face property.
fn read_faces(
    element: &Element,
    vertex_count: u32,
    values: &mut Values,
    mesh: &mut PlyMesh,
    path: &Path,
) -> Result<()> {
    let indices = element
        .property("vertex_indices")
        .or_else(|| element.property("vertex_index"))
        .ok_or_else(|| {
            Error::parse_at(
                path,
                element.line,
                1,
                "expected a list property vertex_indices (or vertex_index) in element `face`",
            )
        })?;
    let index_property = &element.properties[indices];
    let PropertyKind::List { length, item } = index_property.kind else {
        return Err(Error::parse_at(
            path,
            index_property.line,
            1,
            format!(
                "expected a list for {}, found a scalar",
                shown(&index_property.name)
            ),
        ));
    };
    if !item.is_integer() {
        return Err(Error::parse_at(
            path,
            index_property.line,
            1,
            format!(
                "expected an integer type for the items of {}, found {}",
                shown(&index_property.name),
                item.name()
            ),
        ));
    }
    mesh.triangles.reserve(element.rows as usize);
    let mut short_faces = 0u64;
    for row in 0..element.rows {
        for (p, property) in element.properties.iter().enumerate() {
            let field = Field {
                element: &element.name,
                row,
                property: &property.name,
            };
            if p != indices {
                skip_property(property.kind, values, field)?;
                continue;
            }
            let n = values.list_length(length, item, field)?;
            if n < 3 {
                short_faces += 1;
            }
            let (mut first, mut previous) = (0, 0);
            for k in 0..n {
                let place = values.place();
                let value = values.scalar(item, field)?;
                if value < 0.0 || value >= f64::from(vertex_count) {
                    return Err(values.error_at(
                        place,
                        format!(
                            "expected a vertex index from 0 to {} for {field}, found {value}",
                            i64::from(vertex_count) - 1
                        ),
                    ));
                }
                let index = value as u32;
                match k {
                    0 => first = index,
                    1 => {}
                    _ => mesh.triangles.push([first, previous, index]),
                }
                previous = index;
            }
            if mesh.triangles.len() > crate::util::limits::MAX_SHAPES {
                let place = values.place();
                return Err(values.error_at(
                    place,
                    format!(
                        "expected at most {} triangles, found more by {field}",
                        crate::util::limits::MAX_SHAPES
                    ),
                ));
            }
        }
    }
    if short_faces > 0 {
        mesh.warnings.push(format!(
            "dropped {short_faces} face(s) of fewer than 3 vertices"
        ));
    }
    Ok(())
}
