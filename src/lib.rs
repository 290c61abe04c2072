//! Prism: a Whitted-style ray tracer for the 2014 scene formats and beyond.
//!
//! Data flows one way: [`format`] parses files into a [`scene::Scene`], [`accel`] builds
//! an intersector over its shapes, [`render`] traces camera rays into samples, and
//! [`film`] resamples them into the final image and writes it. [`anim`] poses a scene
//! and camera per frame of an animation and joins the frames into a video.

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
pub mod render;
pub mod scene;
pub mod util;

pub use error::{Error, Result};
