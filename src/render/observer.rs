//! What a front end watches of a render, and how it stops one: the one render driver
//! ([`super::Renderer::render`]) reports to an [`Observer`] as it goes. A progress bar,
//! a PNG encoded while the render runs, Python's progress callback and a server that
//! cancels a render when its view changes are all observers.

use super::{Region, RenderStats};
use std::sync::atomic::{AtomicBool, Ordering};

/// Called from the render's threads, in no set order between threads: each method must
/// be cheap and thread-safe. Every method has a default that does nothing.
pub trait Observer: Sync {
    /// The render starts: the window of the frame it renders, and its units of work
    /// (supersampled rows, the unit [`Observer::progress`] counts).
    fn begin(&self, _region: Region, _units: u64) {}
    /// `units` more supersampled rows are traced.
    fn progress(&self, _units: u64) {}
    /// Output rows are final: the first row's place in the window and its pixels
    /// (whole rows, linear values). Each row is handed over once.
    fn rows(&self, _first_row: u32, _pixels: &[[f32; 3]]) {}
    /// Asked between tiles: `true` stops the render, which then returns
    /// [`crate::error::Error::Interrupted`] within a tile's time.
    fn cancelled(&self) -> bool {
        false
    }
    /// The render finished whole (not called for a cancelled render).
    fn finished(&self, _stats: &RenderStats) {}
}

/// Watches nothing.
impl Observer for () {}

/// Counts progress with a closure (`Progress(|rows| bar.inc(rows))`).
pub struct Progress<F>(pub F);

impl<F: Fn(u64) + Sync> Observer for Progress<F> {
    fn progress(&self, units: u64) {
        (self.0)(units)
    }
}

/// Stops the render once the flag is set (by a signal handler, Python's Ctrl-C, a
/// newer request).
pub struct CancelOn<'a>(pub &'a AtomicBool);

impl Observer for CancelOn<'_> {
    fn cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// Two observers as one: both see every event; the render stops when either asks.
impl<A: Observer, B: Observer> Observer for (A, B) {
    fn begin(&self, region: Region, units: u64) {
        self.0.begin(region, units);
        self.1.begin(region, units);
    }
    fn progress(&self, units: u64) {
        self.0.progress(units);
        self.1.progress(units);
    }
    fn rows(&self, first_row: u32, pixels: &[[f32; 3]]) {
        self.0.rows(first_row, pixels);
        self.1.rows(first_row, pixels);
    }
    fn cancelled(&self) -> bool {
        self.0.cancelled() || self.1.cancelled()
    }
    fn finished(&self, stats: &RenderStats) {
        self.0.finished(stats);
        self.1.finished(stats);
    }
}

impl<T: Observer + ?Sized> Observer for &T {
    fn begin(&self, region: Region, units: u64) {
        (**self).begin(region, units)
    }
    fn progress(&self, units: u64) {
        (**self).progress(units)
    }
    fn rows(&self, first_row: u32, pixels: &[[f32; 3]]) {
        (**self).rows(first_row, pixels)
    }
    fn cancelled(&self) -> bool {
        (**self).cancelled()
    }
    fn finished(&self, stats: &RenderStats) {
        (**self).finished(stats)
    }
}

/// Takes finished rows with a closure (`Rows(|first_row, pixels| ...)`).
pub struct Rows<F>(pub F);

impl<F: Fn(u32, &[[f32; 3]]) + Sync> Observer for Rows<F> {
    fn rows(&self, first_row: u32, pixels: &[[f32; 3]]) {
        (self.0)(first_row, pixels)
    }
}
