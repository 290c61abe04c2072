//! Cancellation and the observer: a cancelled render stops at its next tile or pixel
//! and says so; the observer sees begin, progress and finish.

use crate::render::*;
use crate::scene::Material;
use std::sync::atomic::AtomicBool;

#[test]
fn a_cancelled_render_stops_and_says_so() {
    let scene = super::with_unit_ball(Scene {
        materials: vec![Material::default_white()],
        ..Scene::default()
    });
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 40.0, 64, 64);
    let flag = AtomicBool::new(false);
    let rows = AtomicU64::new(0);
    let renderer = Renderer::new(&scene, &camera, RenderSettings::default()).unwrap();
    // Cancelled after the first row: the rest are skipped.
    let result = renderer.render(&(
        CancelOn(&flag),
        Progress(|n| {
            rows.fetch_add(n, Ordering::Relaxed);
            flag.store(true, Ordering::Relaxed);
        }),
    ));
    assert!(matches!(result, Err(crate::error::Error::Interrupted)));
    // Strips of rows already running when the flag went up finish; no new one
    // starts.
    let threads = rayon::current_num_threads() as u64;
    let rows = rows.into_inner();
    assert!(rows <= (2 * threads + 2) * TILE_ROWS as u64, "{rows} rows");
    // Not cancelled: the same renderer's output.
    flag.store(false, Ordering::Relaxed);
    assert!(renderer.render(&()).is_ok());
}

/// The driver tells its observer where it starts (the window and the units of
/// work), counts every unit, and says it finished once, with the stats it returns;
/// a cancelled render is never said to have finished.
#[test]
fn the_observer_sees_begin_progress_and_finish() {
    struct Log {
        begun: std::sync::Mutex<Option<(Region, u64)>>,
        units: AtomicU64,
        finished: std::sync::Mutex<Vec<u64>>,
        stop_after: Option<u64>,
    }
    impl Observer for Log {
        fn begin(&self, region: Region, units: u64) {
            *self.begun.lock().unwrap() = Some((region, units));
        }
        fn progress(&self, units: u64) {
            self.units.fetch_add(units, Ordering::Relaxed);
        }
        fn cancelled(&self) -> bool {
            self.stop_after
                .is_some_and(|n| self.units.load(Ordering::Relaxed) >= n)
        }
        fn finished(&self, stats: &RenderStats) {
            self.finished.lock().unwrap().push(stats.rays);
        }
    }
    let scene = super::with_unit_ball(Scene {
        materials: vec![Material::default_white()],
        ..Scene::default()
    });
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 40.0, 40, 30);
    let settings = RenderSettings {
        aa: Some(2),
        ..RenderSettings::default()
    };
    let renderer = Renderer::new(&scene, &camera, settings).unwrap();
    let log = |stop_after| Log {
        begun: Default::default(),
        units: AtomicU64::new(0),
        finished: Default::default(),
        stop_after,
    };
    let whole = log(None);
    let (_, stats) = renderer.render(&whole).unwrap();
    let (region, units) = whole.begun.into_inner().unwrap().unwrap();
    assert_eq!((region.width, region.height), (40, 30));
    assert_eq!(units, renderer.rows_to_trace());
    assert_eq!(whole.units.into_inner(), units);
    assert_eq!(whole.finished.into_inner().unwrap(), vec![stats.rays]);
    let stopped = log(Some(1));
    let e = renderer.render(&stopped).unwrap_err();
    assert!(matches!(e, crate::error::Error::Interrupted));
    assert!(stopped.finished.into_inner().unwrap().is_empty());
}

/// A shading model that raises the cancel flag on its first call and counts its
/// calls (each a tile of camera rays, or one ray).
struct Cancelling<'a> {
    flag: &'a AtomicBool,
    calls: AtomicU64,
}

impl Cancelling<'_> {
    fn called(&self) {
        self.calls.fetch_add(1, Ordering::Relaxed);
        self.flag.store(true, Ordering::Relaxed);
    }
}

impl Integrator for Cancelling<'_> {
    fn lens_packets(&self) -> bool {
        false
    }

    fn trace_camera_ray(
        &self,
        _: Ray,
        _: &mut PixelSampler,
        _: &mut WeightedColor,
        _: &mut RayCount,
    ) {
        self.called();
    }

    fn trace_camera_packet(
        &self,
        _: &[Ray],
        _: &[Option<Hit>],
        _: &mut [PixelSampler],
        _: &mut [WeightedColor],
        _: &mut RayCount,
    ) {
        self.called();
    }
}

/// Cancelling stops a strip at its next tile (one ray a pixel) or its next pixel
/// (many rays a pixel), not at its end: on a frame 2048 pixels wide, a strip is 128
/// tiles, or 8192 pixels of 8 lens rays. With anti-aliasing no band is resampled or
/// written after it.
#[test]
fn a_cancelled_strip_stops_at_its_next_tile_or_pixel() {
    let scene = super::with_unit_ball(Scene {
        materials: vec![Material::default_white()],
        ..Scene::default()
    });
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 40.0, 2048, 8);
    let accel = Accel::build(crate::accel::AccelKind::Bvh, &scene.shapes);
    let threads = rayon::current_num_threads() as u64;
    for (spp, aa, per_call) in [(None, 1, 1), (Some(8), 1, 8), (None, 2, 1)] {
        let flag = AtomicBool::new(false);
        let settings = RenderSettings {
            spp,
            aa: Some(aa),
            ..RenderSettings::default()
        };
        let renderer = Renderer::new(&scene, &camera, settings).unwrap();
        let cancelling = Cancelling {
            flag: &flag,
            calls: AtomicU64::new(0),
        };
        let (progressed, written) = (AtomicU64::new(0), AtomicU64::new(0));
        let watch = (
            CancelOn(&flag),
            (
                Progress(|n| {
                    progressed.fetch_add(n, Ordering::Relaxed);
                }),
                Rows(|_, _: &[[f32; 3]]| {
                    written.fetch_add(1, Ordering::Relaxed);
                }),
            ),
        );
        renderer.render_frame(&cancelling, &accel, Instant::now(), &watch, None);
        assert!(watch.cancelled());
        // Each thread finishes the tile or pixel it is in.
        let calls = cancelling.calls.into_inner();
        let case = format!("{spp:?} lens rays, AA {aa}");
        assert!(calls <= threads * per_call, "{calls} calls, {case}");
        assert_eq!(progressed.into_inner(), 0, "progress reported, {case}");
        // No band is resampled or handed on once the render is cancelled.
        assert_eq!(written.into_inner(), 0, "rows written, {case}");
    }
}
