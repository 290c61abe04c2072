//! Sample passes: they add up to one render bit for bit, report their rows, refuse
//! torn sums and passes out of order, and make progressive renders.

use crate::film::Image;
use crate::options::Filter;
use crate::render::*;
use std::sync::atomic::AtomicBool;

fn path(
    spp: u32,
    aa: u32,
    filter: Filter,
    region: Option<Region>,
    threads: usize,
) -> RenderSettings {
    RenderSettings {
        spp: Some(spp),
        aa: Some(aa),
        filter,
        region,
        threads: Some(threads),
        integrator: IntegratorKind::Path,
        ..RenderSettings::default()
    }
}

fn bits(image: &Image) -> Vec<u32> {
    image.pixels.iter().flatten().map(|v| v.to_bits()).collect()
}

/// Passes of 1, 3 and 4 samples end on the image one render of 8 makes, bit for bit,
/// and the pass that ends at 4 is a render of 4: without anti-aliasing (the image
/// filled straight), with it (bands resampled), with filters wider than a pixel
/// (bands that share supersampled rows) and a region, on two threads and on one.
#[test]
fn sample_passes_add_up_to_one_render_bit_for_bit() {
    let (scene, camera) = super::scene_and_camera(24, 18);
    let region = Region {
        x: 3,
        y: 2,
        width: 17,
        height: 13,
    };
    let cases = [
        (1, Filter::Area, None),
        (2, Filter::Area, None),
        (2, Filter::Lanczos, Some(region)),
        (3, Filter::Bicubic, None),
    ];
    for threads in [2, 1] {
        for (aa, filter, region) in cases {
            let case = format!("aa {aa}, {filter:?}, {region:?}, {threads} threads");
            let whole = |spp| {
                let settings = path(spp, aa, filter, region, threads);
                Renderer::new(&scene, &camera, settings)
                    .unwrap()
                    .render(&())
                    .unwrap()
                    .0
            };
            let renderer =
                Renderer::new(&scene, &camera, path(8, aa, filter, region, threads)).unwrap();
            let accel = renderer.build_accel().unwrap();
            let mut sums = renderer.sample_sums().unwrap();
            let mut images = Vec::new();
            for to in [1, 4, 8] {
                let (image, stats) = renderer.render_samples(&accel, &mut sums, to, &()).unwrap();
                assert_eq!(sums.samples(), to, "{case}");
                assert!(stats.rays > 0, "{case}");
                images.push(image);
            }
            assert_eq!(bits(&images[2]), bits(&whole(8)), "{case}");
            assert_eq!(bits(&images[1]), bits(&whole(4)), "{case}");
            assert_ne!(bits(&images[1]), bits(&images[2]), "{case}");
            assert!(
                images[2].pixels.iter().flatten().any(|&v| v > 0.0),
                "{case}"
            );
        }
    }
}

/// A pass reports to its observer as a render does: where it starts, each traced
/// row once (a row shared by two bands is traced once), every output row once.
#[test]
fn a_sample_pass_reports_its_rows_to_the_observer() {
    // Taller than a band of output rows, so that two bands share supersampled rows.
    let (scene, camera) = super::scene_and_camera(24, 40);
    let renderer = Renderer::new(&scene, &camera, path(4, 2, Filter::Lanczos, None, 2)).unwrap();
    let accel = renderer.build_accel().unwrap();
    let mut sums = renderer.sample_sums().unwrap();
    struct Log {
        units: AtomicU64,
        progressed: AtomicU64,
        rows: AtomicU64,
    }
    impl Observer for Log {
        fn begin(&self, _: Region, units: u64) {
            self.units.store(units, Ordering::Relaxed);
        }
        fn progress(&self, units: u64) {
            self.progressed.fetch_add(units, Ordering::Relaxed);
        }
        fn rows(&self, _: u32, pixels: &[[f32; 3]]) {
            self.rows
                .fetch_add(pixels.len() as u64 / 24, Ordering::Relaxed);
        }
    }
    for to in [2, 4] {
        let log = Log {
            units: AtomicU64::new(0),
            progressed: AtomicU64::new(0),
            rows: AtomicU64::new(0),
        };
        renderer
            .render_samples(&accel, &mut sums, to, &log)
            .unwrap();
        let units = log.units.into_inner();
        // The frame's 80 supersampled rows, each once; the two bands' rows overlap
        // by Lanczos-3's reach.
        assert_eq!(units, 80);
        assert!(renderer.rows_to_trace() > units);
        assert_eq!(log.progressed.into_inner(), units);
        assert_eq!(log.rows.into_inner(), 40);
    }
}

/// A cancelled pass leaves its sums torn, and later passes refuse them; so do a
/// pass that goes back or past the image's samples, and models that do not spread
/// their samples.
#[test]
fn torn_sums_and_passes_out_of_order_are_refused() {
    let (scene, camera) = super::scene_and_camera(24, 18);
    let renderer = Renderer::new(&scene, &camera, path(8, 1, Filter::Area, None, 2)).unwrap();
    let accel = renderer.build_accel().unwrap();
    let mut sums = renderer.sample_sums().unwrap();
    renderer.render_samples(&accel, &mut sums, 2, &()).unwrap();
    for to in [1, 9] {
        let e = renderer
            .render_samples(&accel, &mut sums, to, &())
            .unwrap_err();
        assert!(e.to_string().contains("must end between"), "{e}");
    }
    assert_eq!(sums.samples(), 2);
    let flag = AtomicBool::new(false);
    let stop_at_once = (
        CancelOn(&flag),
        Progress(|_| flag.store(true, Ordering::Relaxed)),
    );
    let e = renderer
        .render_samples(&accel, &mut sums, 8, &stop_at_once)
        .unwrap_err();
    assert!(matches!(e, crate::error::Error::Interrupted));
    let e = renderer
        .render_samples(&accel, &mut sums, 8, &())
        .unwrap_err();
    assert!(e.to_string().contains("cancelled pass"), "{e}");
    // A fresh start renders.
    let mut sums = renderer.sample_sums().unwrap();
    assert!(renderer.render_samples(&accel, &mut sums, 8, &()).is_ok());
    // Sums of another window are not this render's.
    let region = Region {
        x: 1,
        y: 1,
        width: 4,
        height: 4,
    };
    let small = Renderer::new(&scene, &camera, path(8, 1, Filter::Area, Some(region), 2)).unwrap();
    let e = small.render_samples(&accel, &mut sums, 8, &()).unwrap_err();
    assert!(e.to_string().contains("not this render's"), "{e}");
    let whitted = RenderSettings {
        integrator: IntegratorKind::Whitted,
        ..path(8, 1, Filter::Area, None, 2)
    };
    let whitted = Renderer::new(&scene, &camera, whitted).unwrap();
    assert!(!whitted.spreads_samples());
    let e = whitted.sample_sums().err().unwrap();
    assert!(
        e.to_string().contains("does not render in sample passes"),
        "{e}"
    );
}

/// A progressive render: sample passes doubling to the image's samples, the last
/// the whole render's image bit for bit; one pass, the whole render, for a model
/// that does not spread its samples or sums over the memory budget. The totals a
/// front end is told before the first pass are those the passes then take.
#[test]
fn a_progressive_render_doubles_its_samples_or_renders_once() {
    let (scene, camera) = super::scene_and_camera(24, 18);
    let whole = |settings: &RenderSettings| {
        let r = Renderer::new(&scene, &camera, settings.clone()).unwrap();
        r.render(&()).unwrap().0
    };
    let roomy = Renderer::new(&scene, &camera, path(6, 1, Filter::Area, None, 2)).unwrap();
    let tight = RenderSettings {
        // Room for the render, not for 16 bytes of sums a pixel more.
        max_memory: Some(crate::render::memory_estimate(&scene, &roomy.plan).total() + 16),
        ..path(6, 1, Filter::Area, None, 2)
    };
    let whitted = RenderSettings {
        integrator: IntegratorKind::Whitted,
        ..path(6, 1, Filter::Area, None, 2)
    };
    for (settings, want) in [
        (path(6, 1, Filter::Area, None, 2), vec![1, 2, 4, 6]),
        (tight, vec![6]),
        (whitted, vec![6]),
    ] {
        let Ok(renderer) = Renderer::new(&scene, &camera, settings.clone()) else {
            panic!("{settings:?}");
        };
        let accel = renderer.build_accel().unwrap();
        assert_eq!(renderer.pass_totals(), want, "{settings:?}");
        let mut progressive = renderer.progressive();
        assert_eq!(progressive.totals(), want);
        let mut last = None;
        while let Some((to, rendered)) = progressive.next_pass(&renderer, &accel, &()) {
            last = Some((to, rendered.unwrap().0));
        }
        let (to, image) = last.unwrap();
        assert_eq!(to, *want.last().unwrap());
        assert_eq!(image.pixels, whole(&settings).pixels, "{settings:?}");
    }
}

/// Passes rendered with an intersector built earlier are those `render_aovs`
/// makes; a cancelled observer stops them with `Interrupted`.
#[test]
fn passes_with_a_given_intersector_match_and_stop_when_cancelled() {
    let (scene, camera) = super::scene_and_camera(24, 18);
    let renderer = Renderer::new(&scene, &camera, path(2, 1, Filter::Area, None, 2)).unwrap();
    let accel = renderer.build_accel().unwrap();
    let aovs = [Aov::Albedo, Aov::Normal];
    let own = renderer.render_aovs(&aovs).unwrap();
    let given = renderer.render_aovs_with(&accel, &aovs, &()).unwrap();
    assert_eq!(own.len(), 2);
    for (a, b) in own.iter().zip(&given) {
        assert_eq!(a.pixels, b.pixels);
    }
    let stop = AtomicBool::new(true);
    let e = renderer
        .render_aovs_with(&accel, &aovs, &CancelOn(&stop))
        .unwrap_err();
    assert!(matches!(e, crate::error::Error::Interrupted), "{e}");
}
