//! Standard Wavefront OBJ (with its MTL libraries, see [`super::mtl`]) read into plain
//! data: [`ObjFile`]. Turning that into a [`Scene`] with materials and textures is the
//! scene builder's job; this module loads no image.
//!
//! What is read and every decision where the format is vague are in `docs/formats.md`
//! ("OBJ/MTL"). In short: polygons are triangulated (convex ones as the fan
//! `(1, k, k+1)` in file order, so triangle numbers match other renderers', Embree's
//! harness in `benches/` relies on it; concave ones by ear clipping), smoothing groups
//! get area-weighted normals, and everything Prism cannot use is counted and reported
//! in [`ObjFile::warnings`], never silently dropped.
//!
//! The older geometry-only entry points ([`load_mesh`], [`parse_mesh`], [`load`],
//! [`parse`]) read the same way but skip material libraries and normals.

mod lines;
mod reader;
mod smooth;
#[cfg(test)]
mod tests;
mod triangulate;

use std::collections::BTreeMap;
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

pub use super::mtl::{MtlMaterial, TextureMap};
pub use lines::MAX_FILE_BYTES;
pub(super) use lines::{
    Line, Lines, Token, Tokens, decode_name, parse_f64, parse_integer, read_file, shown,
    without_bom,
};
pub(super) use reader::number;
pub use triangulate::MAX_EAR_CLIPPED_CORNERS;

use crate::error::Result;
use crate::math::Vec3;
use crate::scene::{Material, Scene};

/// Everything an OBJ file and its material libraries say that Prism can render.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObjFile {
    /// `v x y z [w]`, 0-based in file order (`w` is read and ignored).
    pub positions: Vec<Vec3>,
    /// `v x y z r g b`: one colour per position as soon as any vertex has one (the
    /// others white); empty when none has.
    pub colors: Vec<Vec3>,
    /// `vt u [v [w]]` (`v` defaults to 0, `w` is ignored).
    pub texcoords: Vec<[f32; 2]>,
    /// `vn`, as written (not normalised), then the unit normals made for smoothing
    /// groups.
    pub normals: Vec<Vec3>,
    /// Every face, triangulated, in file order.
    pub triangles: Vec<ObjTriangle>,
    /// The `o` and `g` runs that own triangles, in file order. Triangles before the
    /// first `o`/`g` form a run named "" when there are any.
    pub groups: Vec<ObjGroup>,
    /// The materials of every `mtllib`, in order of appearance; names are unique.
    pub materials: Vec<MtlMaterial>,
    /// What was read but not used, or guessed: see [`Warning`].
    pub warnings: Vec<Warning>,
    /// Statements skipped, by kind (`l`, `p`, `curv`, `surf`, `t`, ..., `unknown`; MTL
    /// keys as `mtl:KEY`), with how many of each; each kind also gives one warning.
    pub skipped: BTreeMap<String, usize>,
}

/// One triangle: 0-based indices into [`ObjFile`]'s arrays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ObjTriangle {
    /// Indices into [`ObjFile::positions`], in the face's winding order.
    pub v: [u32; 3],
    /// Present when every corner of the face named a texture coordinate.
    pub vt: Option<[u32; 3]>,
    /// Present when every corner of the face named a normal, or the face is smoothed.
    pub vn: Option<[u32; 3]>,
    /// Index into [`ObjFile::materials`]; `None` before any `usemtl` or for an unknown
    /// name (the scene's default material).
    pub material: Option<u32>,
    /// The `s` group in force; 0 is flat.
    pub smoothing: u32,
}

/// A named run of triangles: an `o` object or a `g` group.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ObjGroup {
    /// The name; the names of `g a b` are joined by single spaces ("a b").
    pub name: String,
    /// Whether an `o` or a `g` started the run (the unnamed first run counts as `g`).
    pub kind: GroupKind,
    /// The run's triangles, as a range of indices into [`ObjFile::triangles`].
    pub triangles: Range<usize>,
}

/// The statement that names a run of triangles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GroupKind {
    /// `o NAME`.
    Object,
    /// `g NAME...`, or the unnamed run before the first `o`/`g`.
    Group,
}

/// Something read but not used, or read with a guess: the file keeps loading.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Warning {
    /// The file the warning concerns (the OBJ or one of its libraries).
    pub path: PathBuf,
    /// 1-based line of the statement.
    pub line: usize,
    /// What was skipped or guessed.
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{}:{}: {}", self.path.display(), self.line, self.message)
    }
}

/// Reads an OBJ file and the material libraries it names (relative to its folder).
pub fn load_obj(path: &Path) -> Result<ObjFile> {
    let bytes = lines::read_file(path, MAX_FILE_BYTES)?;
    parse_obj(&bytes, path)
}

/// Parses OBJ text; `path` names it in errors, and its folder is where `mtllib` files
/// are read from.
pub fn parse_obj(text: &[u8], path: &Path) -> Result<ObjFile> {
    parse_obj_with(text, path, &mut |library| {
        lines::read_file(library, MAX_FILE_BYTES)
    })
}

/// Parses OBJ text, getting each material library's bytes from `read_library` (given
/// the resolved path): for tests, and for callers that keep files elsewhere. An error
/// it returns becomes a warning.
pub fn parse_obj_with(
    text: &[u8],
    path: &Path,
    read_library: &mut dyn FnMut(&Path) -> Result<Vec<u8>>,
) -> Result<ObjFile> {
    reader::read(
        text,
        path,
        reader::Options {
            read_library: Some(read_library),
            smooth: true,
        },
    )
}

/// An indexed triangle mesh: the file's vertices (0-based) and its triangles in file
/// order, polygons fanned.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Positions, 0-based in file order.
    pub vertices: Vec<Vec3>,
    /// Index triples into `vertices`, every index checked in range.
    pub triangles: Vec<[u32; 3]>,
}

/// Reads a Wavefront OBJ file's triangles as a scene.
pub fn load(path: &Path) -> Result<Scene> {
    Ok(scene_of(&load_mesh(path)?))
}

/// Reads a Wavefront OBJ file's triangles as an indexed mesh.
pub fn load_mesh(path: &Path) -> Result<Mesh> {
    let bytes = lines::read_file(path, MAX_FILE_BYTES)?;
    mesh_of(&bytes, path)
}

/// Parses the text of an OBJ file into a scene; `path` names it in errors.
pub fn parse(text: &str, path: &Path) -> Result<Scene> {
    Ok(scene_of(&parse_mesh(text, path)?))
}

/// Parses the text of an OBJ file into an indexed mesh whose indices are all checked.
pub fn parse_mesh(text: &str, path: &Path) -> Result<Mesh> {
    mesh_of(text.as_bytes(), path)
}

/// The geometry alone: no material library is read and no normal is made.
fn mesh_of(text: &[u8], path: &Path) -> Result<Mesh> {
    let obj = reader::read(
        text,
        path,
        reader::Options {
            read_library: None,
            smooth: false,
        },
    )?;
    Ok(Mesh {
        triangles: obj.triangles.iter().map(|t| t.v).collect(),
        vertices: obj.positions,
    })
}

/// Every triangle of `mesh` as a shape wearing a matte white.
fn scene_of(mesh: &Mesh) -> Scene {
    let mut scene = crate::scene::SceneBuilder::new();
    let white = scene.add_classic_material(Material::default_white());
    scene.add_mesh(
        &mesh.vertices,
        &mesh.triangles,
        crate::scene::MeshMaterials::All(white),
        None,
    );
    scene.finish()
}
