//! Scene, material and camera files in, plain [`Scene`] and [`Camera`] data out.
//!
//! The 2014 formats: [`objx`] (scene), [`mtlx`] (materials, named by the scene's
//! `mtllib`) and [`cmr`] (camera). Each has a `load(path)` that reads files and a
//! `parse(text, path, ...)` that works on text in memory, for tests and fuzzing.
//!
//! Every error is a [`crate::error::Error`] naming the file and the 1-based line, and saying
//! what was expected and what was found (`scene.objx:12: expected a number for the
//! radius, found `abc``). A file that cannot be read is an [`crate::error::Error::File`].
//! No input makes a parser panic, overflow or hang.
//!
//! Relative paths inside a file (`mtllib`, textures) are resolved against the folder of
//! the file that names them, never the working directory.
//!
//! Dialects, by extension: `.obj` is standard Wavefront OBJ with its MTL libraries
//! ([`wavefront`]), `.ply` a PLY mesh ([`ply`]), `.toml` a Prism scene file
//! ([`scene_file`]), `.gltf` and `.glb` glTF 2.0 ([`gltf`]), `.objx` the 2014 dialect;
//! any other extension is an error naming these and `--dialect`. [`SceneDialect`] is
//! where more slot in.

pub mod cmr;
pub mod gltf;
pub mod image_file;
pub mod materialx;
pub mod mtl;
pub mod mtlx;
pub mod obj;
pub mod objx;
pub mod ply;
mod ply_scene;
pub mod scene_file;
pub(crate) mod text;
pub mod wavefront;

use std::path::Path;

use crate::error::Result;
use crate::options::{IntegratorKind, RenderOptions};
use crate::scene::{Camera, Scene};

/// What a scene file says: the scene, and for the dialects that can say them (Prism
/// scene files), a camera and render settings. Front ends merge their own options over
/// `settings` and fall back to a default camera when there is none.
#[derive(Clone, Debug)]
pub struct SceneFile {
    /// The dialect the file was read as: by its extension, or as `--dialect` said.
    pub dialect: SceneDialect,
    /// The scene the file describes, its materials, lights and background included.
    pub scene: Scene,
    /// The file's own camera (Prism scene files, glTF); `None` when it has none, and
    /// front ends frame the scene from a default three-quarter view.
    pub camera: Option<Camera>,
    /// Every camera the file holds, in its order (`camera` is the first): glTF's
    /// camera nodes, which `--camera-name` and `--camera-index` choose from.
    pub cameras: Vec<NamedCamera>,
    /// The render options the file states (a Prism scene file's `[render]`, glTF's
    /// exposure for Blender's light units); all `None` where it states none.
    pub settings: RenderOptions,
    /// What was read but not understood or not found (`file:line: message`): the peers
    /// are lenient with these, and so is Prism, but it says so.
    pub warnings: Vec<String>,
    /// What the file itself held, where the reader knows (`prism info`).
    pub counts: SourceCounts,
}

/// A camera of a scene file, with the name the file gave it.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedCamera {
    /// The name the file gives it (glTF: the node's, else the camera's); `None` when
    /// it has none.
    pub name: Option<String>,
    /// The camera, placed in world space (a glTF node's world transform applied).
    pub camera: Camera,
}

/// Counts of the file's own records, before Prism builds its scene from them: `v`,
/// `vn` and `vt` lines of an OBJ, vertex properties of a PLY. Zero where the format
/// has none or the reader does not count them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SourceCounts {
    /// Vertex positions: an OBJ's `v` lines, a PLY's or glTF mesh's vertices.
    pub vertices: usize,
    /// Normals: `vn` lines, or the PLY or glTF vertices that carry one.
    pub normals: usize,
    /// Texture coordinates: `vt` lines, or the PLY or glTF vertices that carry them
    /// (glTF's first set).
    pub texcoords: usize,
}

impl SceneDialect {
    /// Every dialect, in the order messages list them.
    pub const ALL: [SceneDialect; 5] = [
        SceneDialect::WavefrontObj,
        SceneDialect::Gltf,
        SceneDialect::Ply,
        SceneDialect::PrismScene,
        SceneDialect::Objx2014,
    ];

    /// The shading model a file of this dialect is rendered with unless told otherwise.
    pub fn default_integrator(self) -> IntegratorKind {
        match self {
            SceneDialect::Objx2014 => IntegratorKind::Classic,
            _ => IntegratorKind::Whitted,
        }
    }

    /// The name `prism info` and `--dialect` use.
    pub fn name(self) -> &'static str {
        match self {
            SceneDialect::Objx2014 => "objx",
            SceneDialect::WavefrontObj => "obj",
            SceneDialect::PrismScene => "toml",
            SceneDialect::Ply => "ply",
            SceneDialect::Gltf => "gltf",
        }
    }

    /// The extensions (lower case, without the dot) that name the dialect.
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            SceneDialect::Objx2014 => &["objx"],
            SceneDialect::WavefrontObj => &["obj"],
            SceneDialect::PrismScene => &["toml"],
            SceneDialect::Ply => &["ply"],
            SceneDialect::Gltf => &["gltf", "glb"],
        }
    }

    /// The dialect `--dialect NAME` names.
    pub fn named(name: &str) -> Option<SceneDialect> {
        Self::ALL.into_iter().find(|d| d.name() == name)
    }

    /// Every dialect's name, for `--dialect`'s list.
    pub fn names() -> [&'static str; 5] {
        Self::ALL.map(SceneDialect::name)
    }

    /// The dialect a scene file's extension names (case-insensitive), or an error
    /// listing the extensions Prism reads and `--dialect`.
    pub fn for_path(path: &Path) -> Result<SceneDialect> {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        Self::ALL
            .into_iter()
            .find(|d| d.extensions().iter().any(|x| ext.eq_ignore_ascii_case(x)))
            .ok_or_else(|| {
                let known: Vec<String> = Self::ALL
                    .iter()
                    .flat_map(|d| d.extensions())
                    .map(|x| format!(".{x}"))
                    .collect();
                crate::error::Error::file(
                    path,
                    format!(
                        "cannot tell the scene format from the extension {}: Prism reads {}; \
                         name another with --dialect {}",
                        if ext.is_empty() {
                            "(none)".to_string()
                        } else {
                            text::shown(&format!(".{ext}"))
                        },
                        known.join(", "),
                        Self::names().join("|")
                    ),
                )
            })
    }
}

/// Reads any scene file, with the dialect its extension names.
pub fn load(path: &Path) -> Result<SceneFile> {
    load_as(path, SceneDialect::for_path(path)?)
}

/// Reads any scene file in the given dialect.
pub fn load_as(path: &Path, dialect: SceneDialect) -> Result<SceneFile> {
    let mut file = match dialect {
        SceneDialect::WavefrontObj => wavefront::load(path)?,
        SceneDialect::PrismScene => scene_file::load(path)?,
        SceneDialect::Ply => ply_scene::load(path)?,
        SceneDialect::Gltf => gltf::load(path)?,
        SceneDialect::Objx2014 => load_objx_file(path)?,
    };
    // Warnings quote the files too: the same bound as errors.
    for w in &mut file.warnings {
        *w = crate::error::bounded(std::mem::take(w));
    }
    // A large file's parse (a PLY's text, a scene file's document of ten thousand
    // transforms) freed millions of small allocations the allocator would keep: they
    // go back before the render allocates its own.
    crate::util::give_back_freed_memory();
    Ok(file)
}

fn load_objx_file(path: &Path) -> Result<SceneFile> {
    let scene = load_scene_as(path, SceneDialect::Objx2014)?;
    Ok(SceneFile {
        dialect: SceneDialect::Objx2014,
        scene,
        camera: None,
        cameras: Vec::new(),
        settings: RenderOptions::default(),
        warnings: Vec::new(),
        counts: SourceCounts::default(),
    })
}

/// The dialects a scene file can be written in.
///
/// [`SceneDialect::for_path`] picks one by extension; [`load_as`] lets a caller
/// override the choice.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SceneDialect {
    /// The course report's `.objx` + `.mtlx` (see [`objx`]).
    Objx2014,
    /// Standard Wavefront OBJ: its triangles (see [`obj`]).
    WavefrontObj,
    /// Prism's own scene file, TOML (see [`scene_file`]).
    PrismScene,
    /// A PLY mesh (see [`ply`]).
    Ply,
    /// glTF 2.0, `.gltf` or `.glb` (see [`gltf`]).
    Gltf,
}

/// Reads a scene file with the dialect [`SceneDialect::for_path`] picks, with its
/// material files and textures.
pub fn load_scene(path: &Path) -> Result<Scene> {
    load_scene_as(path, SceneDialect::for_path(path)?)
}

/// Reads a scene file in the given dialect, whatever its name.
pub fn load_scene_as(path: &Path, dialect: SceneDialect) -> Result<Scene> {
    match dialect {
        SceneDialect::Objx2014 => objx::load(path),
        SceneDialect::WavefrontObj => Ok(wavefront::load(path)?.scene),
        SceneDialect::PrismScene => scene_file::load(path).map(|f| f.scene),
        SceneDialect::Ply => ply_scene::load(path).map(|f| f.scene),
        SceneDialect::Gltf => gltf::load(path).map(|f| f.scene),
    }
}

/// Reads a 2014 camera file (`.cmr`).
pub fn load_camera(path: &Path) -> Result<Camera> {
    cmr::load(path)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{FillMode, Shape};
    use std::path::PathBuf;

    /// `to` written relative to the working directory, so a test can load a file by a
    /// relative path without changing the (process-wide) working directory.
    fn relative_to_cwd(to: &Path) -> PathBuf {
        let cwd = std::env::current_dir().unwrap();
        let mut rel = PathBuf::new();
        for _ in cwd.components().skip(1) {
            rel.push("..");
        }
        rel.join(to.strip_prefix("/").unwrap())
    }

    #[test]
    fn paths_resolve_against_the_folder_of_the_file_that_names_them() {
        let root = tempfile::tempdir().unwrap();
        let scenes = root.path().join("scenes");
        std::fs::create_dir_all(scenes.join("mats/tex")).unwrap();
        // A 2x1 image: red then blue.
        let mut png = image::RgbImage::new(2, 1);
        png.put_pixel(0, 0, image::Rgb([255, 0, 0]));
        png.put_pixel(1, 0, image::Rgb([0, 0, 255]));
        png.save(scenes.join("mats/tex/checker.png")).unwrap();
        std::fs::write(
            scenes.join("mats/room.mtlx"),
            "# header\nnewmtl tiled 1 2 3 1 1 0 1 1 0 0 0 tex/checker.png 0.5\n\
             newmtl same 1 2 3 1 1 0 1 1 0 0 0 ./tex/checker.png 0.5\n\
             newmtl fitted 1 2 3 1 1 0 1 1 0 0 0 tex/../tex/checker.png fit\n",
        )
        .unwrap();
        std::fs::write(
            scenes.join("room.objx"),
            "mtllib mats/room.mtlx\nv 0 0 0\nusemtl tiled\nf 0 1\nusemtl fitted\nf 0 2\n",
        )
        .unwrap();

        let path = relative_to_cwd(&scenes.join("room.objx"));
        assert!(path.is_relative() && std::env::current_dir().unwrap() != scenes);
        let scene = load_scene(&path).unwrap();
        assert_eq!(scene.shapes.len(), 2);
        let names: Vec<_> = scene.materials.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["tiled", "same", "fitted"]);
        // One texture per (image, fill mode): `same` shares the first one.
        assert_eq!(scene.textures.len(), 2);
        let textures: Vec<_> = scene.materials.iter().map(|m| m.texture).collect();
        assert_eq!(textures, [Some(0), Some(0), Some(1)]);
        let t = &scene.textures[0];
        assert_eq!((t.width, t.height), (2, 1));
        assert_eq!(t.texels, vec![[255, 0, 0], [0, 0, 255]]);
        assert_eq!(t.fill, FillMode::Tile { scale: 0.5 });
        assert_eq!(scene.textures[1].fill, FillMode::Fit);
        assert_eq!(scene.textures[1].texels, t.texels);
    }

    #[test]
    fn texture_errors_name_the_material_file_line_and_image() {
        let root = tempfile::tempdir().unwrap();
        std::fs::write(root.path().join("bad.png"), b"not a png").unwrap();
        for (image, line) in [("missing.jpg", 1), ("bad.png", 2)] {
            let mtl = root.path().join(format!("{image}.mtlx"));
            let text = format!(
                "{}newmtl a 0 0 0 1 1 1 1 1 0 0 0 {image}\n",
                "\n".repeat(line - 1)
            );
            std::fs::write(&mtl, text).unwrap();
            let e = mtlx::load(&mtl, &mut mtlx::MaterialLibrary::new()).unwrap_err();
            let expected = format!(
                "{}:{line}: cannot load texture {}: ",
                mtl.display(),
                root.path().join(image).display()
            );
            assert!(e.to_string().starts_with(&expected), "{e}");
        }
    }

    #[test]
    fn a_2014_texture_claiming_a_huge_image_is_refused_from_its_header() {
        // A binary PPM header promising 60000 x 60000 pixels and holding none.
        let root = tempfile::tempdir().unwrap();
        std::fs::write(root.path().join("huge.ppm"), b"P6\n60000 60000\n255\n").unwrap();
        let mtl = root.path().join("m.mtlx");
        std::fs::write(&mtl, "newmtl a 0 0 0 1 1 1 1 1 0 0 0 huge.ppm\n").unwrap();
        let e = mtlx::load(&mtl, &mut mtlx::MaterialLibrary::new()).unwrap_err();
        assert!(e.to_string().contains("60000x60000"), "{e}");
    }

    #[test]
    fn unreadable_files_are_file_errors() {
        let e = load_scene(Path::new("/nonexistent/prism/s.objx")).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("/nonexistent/prism/s.objx: cannot read: "),
            "{e}"
        );
        assert!(load_camera(Path::new("/nonexistent/prism/c.cmr")).is_err());
        let root = tempfile::tempdir().unwrap();
        let scene = root.path().join("s.objx");
        std::fs::write(&scene, "v 0 0 0\n\nmtllib nowhere.mtlx\n").unwrap();
        let e = load_scene(&scene).unwrap_err().to_string();
        let expected = format!(
            "{}:3: cannot read material file {}: ",
            scene.display(),
            root.path().join("nowhere.mtlx").display()
        );
        assert!(e.starts_with(&expected), "{e}");
        std::fs::write(&scene, b"v 0 0 0\nv \xc3\x28 0 0\n").unwrap();
        let e = load_scene(&scene).unwrap_err().to_string();
        assert!(e.contains(":2: expected UTF-8 text"), "{e}");
    }

    #[test]
    fn seed_scenes_load_with_the_expected_contents() {
        let root = Path::new("/work/shared/seed-scenes/Ray-Tracing");
        if !root.join("scene0/scene.objx").exists() {
            println!("skipped: the seed scenes are not at {}", root.display());
            return;
        }
        let scene0 = load_scene(&root.join("scene0/scene.objx")).unwrap();
        assert_eq!(scene0.shapes.len(), 9);
        assert_eq!(scene0.lights.len(), 1);
        let spheres = scene0
            .shapes
            .iter()
            .filter(|s| matches!(s, Shape::Sphere(_)));
        assert_eq!(spheres.count(), 2);
        assert_eq!(scene0.materials.len(), 7);
        // wall, water, ceiling and floor each name a different image.
        assert_eq!(scene0.textures.len(), 4);
        let water = scene0.material(6);
        assert_eq!(water.name, "water");
        assert_eq!(
            scene0.textures[water.texture.unwrap() as usize].fill,
            FillMode::Tile { scale: 0.25 }
        );
        let camera0 = load_camera(&root.join("scene0/scene.cmr")).unwrap();
        assert_eq!((camera0.width, camera0.height), (3840, 2160));

        let scene1 = load_scene(&root.join("scene1/scene.objx")).unwrap();
        // 6 walls, floor, ceiling, water, 5 table faces, big sphere, 12 footstep faces, 5 marbles.
        assert_eq!(scene1.shapes.len(), 32);
        assert_eq!(scene1.lights.len(), 1);
        let camera1 = load_camera(&root.join("scene1/scene.cmr")).unwrap();
        assert_eq!((camera1.width, camera1.height), (3840, 2160));
        assert_eq!((camera1.aa, camera1.spp), (4, 128));
        assert_eq!(camera1.theta_deg, 78.0614);
    }
}
