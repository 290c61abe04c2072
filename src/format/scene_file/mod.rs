//! Prism's scene file (TOML; SPEC 4.4, `docs/scene-format.md`): a camera, objects,
//! materials, lights, the ambient light, the background, render settings and animation
//! tracks, in one file and the files it includes.
//!
//! Every error names the file, line and column of the key at fault and says what was
//! expected. Nothing read is trusted: numbers must be finite, paths name regular files
//! (resolved against the folder of the file that names them), images are refused by
//! their header's size before they are decoded, and includes nest at most
//! [`MAX_INCLUDE_DEPTH`] deep without cycles.

mod build;
mod camera;
mod from_value;
mod images;
mod include;
pub(crate) mod lights;
mod materials;
mod objects;
mod openpbr;
mod primitives;
mod raw;
mod settings;
mod source;
mod tracks;
mod transform;
mod values;

#[cfg(test)]
mod tests;

pub use build::PLANE_SCALE;
pub use camera::{DEFAULT_FOV, DEFAULT_SIZE};
pub use from_value::{ArrayMesh, from_value};
pub use images::MAX_IMAGE_PIXELS;
pub use include::{MAX_FILE_BYTES, MAX_FILES, MAX_INCLUDE_DEPTH};
pub use lights::{DEFAULT_AREA_SAMPLES, MAX_AREA_SAMPLES};
pub use primitives::SEGMENTS;

use super::{SceneDialect, SceneFile};
use crate::error::{Error, Result};
use std::path::Path;

/// Reads the scene file at `path` and everything it names.
pub fn load(path: &Path) -> Result<SceneFile> {
    let text = include::read_text(path).map_err(|m| Error::file(path, m))?;
    parse(&text, path)
}

/// Parses `text` as the scene file at `path`: the files it includes and names (meshes,
/// images, a `.cmr`) are read from disk relative to `path`'s folder.
pub fn parse(text: &str, path: &Path) -> Result<SceneFile> {
    parse_with_meshes(text, path, InMemory::default())
}

/// What a scene given as data carries beside its text (Python's arrays), by the names
/// its objects use: meshes for a `file`, placements for an instance's `transforms`.
#[derive(Default)]
pub struct InMemory {
    /// Scenes built in memory, named as a mesh object's `file`.
    pub meshes: std::collections::HashMap<String, crate::scene::Scene>,
    /// Placements (row-major affine 4 x 4 matrices), named as an instance's
    /// `transforms`.
    pub transforms: std::collections::HashMap<String, Vec<[[f64; 4]; 4]>>,
}

/// [`parse`] where objects may name, as their `file` or `transforms`, what `given`
/// holds in memory instead of a file on disk or a list in the text.
pub fn parse_with_meshes(text: &str, path: &Path, given: InMemory) -> Result<SceneFile> {
    let documents = include::read_all(text.to_owned(), path)?;
    let (scene, camera, settings, warnings) = build::build(&documents, given)?;
    Ok(SceneFile {
        dialect: SceneDialect::PrismScene,
        scene,
        camera,
        cameras: Vec::new(),
        settings,
        warnings,
        counts: Default::default(),
    })
}
