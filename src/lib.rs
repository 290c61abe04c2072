//! Prism: a ray tracer for the 2014 course report's scenes and for the scenes today's
//! tools export (Wavefront OBJ/MTL, PLY, glTF 2.0, Prism scene files), with the
//! report's weighted-mean model (*classic*) and a physically based Whitted model
//! (*whitted*).
//!
//! A render in a few lines: read a scene file, resolve it with options into a [`Job`]
//! (scene, camera, render settings and how the image is developed), render it, write
//! it.
//!
//! ```
//! use prism::{JobOptions, RenderOptions};
//! # fn main() -> prism::Result<()> {
//! let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/showcase/showcase.toml");
//! let options = JobOptions {
//!     render: RenderOptions { width: Some(64), ..Default::default() },
//!     ..Default::default()
//! };
//! let job = prism::prepare(scene.as_ref(), &options)?;
//! let (image, stats) = job.render()?;
//! assert_eq!((image.width, image.height), (64, 36)); // the file's 16:9 is kept
//! # let dir = tempfile::tempdir().unwrap();
//! # let path = dir.path().join("showcase.png");
//! job.write(&image, &path)?; // sRGB-encoded, as `prism render` writes it
//! assert!(stats.rays > 0);
//! # Ok(()) }
//! ```
//!
//! Scenes can be built in code as well ([`SceneBuilder`]) and given as data
//! ([`format::scene_file::from_value`]).
//!
//! Data flows one way, and every module imports only from those below it: [`format`](mod@format)
//! reads files into a [`Scene`] ([`scene`]), [`accel`] builds an intersector over its
//! shapes, [`render`] traces camera rays through an integrator into samples, and
//! [`film`] resamples, develops and writes the image. [`job`] resolves what a front end
//! was told into one [`Job`]; [`anim`] poses a job's scene and camera per frame. At the
//! bottom, [`options`] names the settings every stage reads, and [`util`] holds the
//! limits, the file opener, text helpers and the linear image codecs.

#![warn(missing_docs)]

pub mod accel;
pub mod anim;
pub mod bench;
pub mod compare;
pub mod error;
pub mod film;
pub mod format;
pub mod info;
pub mod job;
pub mod math;
pub mod options;
pub mod preview;
pub mod render;
pub mod scene;
pub mod util;

pub use error::{Error, Result};
pub use film::{Image, OutputOptions, write_image};
pub use format::{SceneDialect, SceneFile, load};
pub use job::{Job, JobOptions, LookAt, prepare, resolve};
pub use options::{Filter, IntegratorKind, RenderOptions, ToneMap};
pub use render::{RenderSettings, RenderStats, Renderer};
pub use scene::{Camera, Scene, SceneBuilder};
