//! Tests of the band loop: cancellation, packets of lens rays and tiles against rays
//! traced alone, progress, and the one-tap resample without anti-aliasing.

/// `scene` with a unit sphere at the origin wearing its first material.
pub(super) fn with_unit_ball(mut scene: crate::scene::Scene) -> crate::scene::Scene {
    let ball = crate::scene::Sphere {
        center: crate::math::Vec3::ZERO,
        radius: 1.0,
    };
    scene.push_shape(crate::scene::Shape::Sphere(ball), 0);
    scene
}

/// Adds a floor of material `material` one unit below the origin, 8 units square.
pub(super) fn add_floor(scene: &mut crate::scene::Scene, material: u32) {
    use crate::math::Vec3;
    let floor = crate::scene::Shape::Rectangle(crate::scene::Rectangle {
        v: [
            Vec3::new(-4.0, -1.0, 4.0),
            Vec3::new(4.0, -1.0, 4.0),
            Vec3::new(4.0, -1.0, -4.0),
            Vec3::new(-4.0, -1.0, -4.0),
        ],
    });
    scene.push_shape(floor, material);
}

/// A glass ball on a floor under a quad light, seen through a lens: every sample of
/// a pixel differs (position, lens point, light point, bounces).
pub(super) fn scene_and_camera(
    width: u32,
    height: u32,
) -> (crate::scene::Scene, crate::scene::Camera) {
    use crate::math::Vec3;
    use crate::scene::{Camera, Light, LightKind, Material, Scene, Surface};
    let glass = Surface {
        transmission: Vec3::splat(0.8),
        ior: 1.5,
        fresnel: true,
        ..Surface::default()
    };
    let mut scene = with_unit_ball(Scene {
        materials: vec![Material::default_white(), Material::default_white()],
        surfaces: vec![glass, Surface::default()],
        lights: vec![Light {
            kind: LightKind::Quad {
                u: Vec3::new(1.5, 0.0, 0.0),
                v: Vec3::new(0.0, 0.0, 1.5),
            },
            intensity: 8.0,
            ..Light::point(Vec3::new(-1.0, 3.0, 1.0), Vec3::ONE)
        }],
        ..Scene::default()
    });
    add_floor(&mut scene, 1);
    let mut camera = Camera::look_at(
        Vec3::new(0.5, 1.0, 4.0),
        Vec3::ZERO,
        Vec3::Y,
        50.0,
        width,
        height,
    );
    camera.aperture = 0.1;
    camera.focal_length = 3.0;
    (scene, camera)
}

/// Supersampled pixel `(x, y)` of `renderer`'s path render made the slow way: each of
/// its samples traced alone, a path at a time, from its own stream, added in order.
pub(super) fn traced_alone(
    renderer: &crate::render::Renderer,
    path: &crate::render::Path,
    rays: &crate::render::CameraRays,
    (x, y): (u32, u32),
    count: &mut crate::render::RayCount,
) -> crate::math::Vec3 {
    use crate::render::Integrator;
    let streams = crate::render::PixelStreams::new(renderer.plan.seed, x, y);
    let mut acc = crate::render::WeightedColor::default();
    for i in 0..renderer.plan.spp {
        let mut sampler = streams.sample(i);
        let jitter = sampler.next_2d();
        let lens = sampler.next_2d();
        let ray = rays.through(x, y, jitter, lens);
        path.trace_camera_ray(ray, &mut sampler, &mut acc, count);
    }
    acc.mean()
}

mod cancel_tests {
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
}

mod lens_packet_tests {
    use crate::render::*;
    use crate::scene::{Light, LightKind, Material, Surface};

    /// A pixel's lens rays traced as packets (where the model allows) give the pixel
    /// each ray gives traced alone, in order, from the pixel's stream.
    #[test]
    fn lens_rays_in_packets_shade_as_each_ray_traced_alone() {
        let glass = Surface {
            transmission: Vec3::splat(0.8),
            ior: 1.5,
            fresnel: true,
            ..Surface::default()
        };
        // The classic model's children too: a see-through ball, a mirroring floor.
        let ball = Material {
            color: Vec3::new(0.8, 0.3, 0.2),
            reflect: 0.3,
            refract: 0.6,
            ior: 1.5,
            transparent: true,
            ..Material::default_white()
        };
        let floor = Material {
            color: Vec3::new(0.2, 0.5, 0.9),
            reflect: 0.5,
            ..Material::default_white()
        };
        let mut scene = super::with_unit_ball(Scene {
            materials: vec![ball, floor],
            surfaces: vec![glass, Surface::default()],
            ..Scene::default()
        });
        super::add_floor(&mut scene, 1);
        let mut camera =
            Camera::look_at(Vec3::new(0.5, 1.0, 4.0), Vec3::ZERO, Vec3::Y, 50.0, 12, 10);
        camera.aperture = 0.2;
        camera.focal_length = 3.0;
        let point = Light::point(Vec3::new(2.0, 3.0, 4.0), Vec3::ONE);
        let quad = Light {
            kind: LightKind::Quad {
                u: Vec3::new(1.0, 0.0, 0.0),
                v: Vec3::new(0.0, 0.0, 1.0),
            },
            samples: 4,
            ..Light::point(Vec3::new(-1.0, 3.0, 1.0), Vec3::ONE)
        };
        for (lights, packets) in [(vec![point.clone()], true), (vec![point, quad], false)] {
            scene.lights = lights;
            let settings = RenderSettings {
                aa: Some(1),
                spp: Some(21),
                integrator: IntegratorKind::Whitted,
                ..RenderSettings::default()
            };
            let renderer = Renderer::new(&scene, &camera, settings).unwrap();
            let plan = &renderer.plan;
            let rays = CameraRays::new(&plan.camera, 1, plan.spp);
            let accel = Accel::build(plan.accel, &scene.shapes);
            let surfaces = scene.resolved_surfaces();
            let whitted = Whitted::new(&scene, &accel, &surfaces, plan.max_depth, plan.min_weight);
            assert_eq!(whitted.lens_packets(), packets);
            assert_same_pixels(&renderer, &whitted, &accel, &rays);
            // The classic model traces lens packets whatever the lights, and their
            // shadow rays toward each light as packets too.
            let classic = Classic::new(&scene, &accel, plan.camera.medium_ior);
            assert!(classic.lens_packets());
            assert_same_pixels(&renderer, &classic, &accel, &rays);
        }
    }

    fn assert_same_pixels<I: Integrator>(
        renderer: &Renderer,
        integrator: &I,
        accel: &Accel,
        rays: &CameraRays,
    ) {
        let mut count = RayCount::default();
        let mut lit = 0;
        let camera = renderer.camera();
        for y in 0..camera.height {
            for x in 0..camera.width {
                let pixel = renderer.pixel(integrator, accel, rays, x, y, &mut count);
                let mut sampler = PixelSampler::new(renderer.plan.seed, x, y);
                let mut acc = WeightedColor::default();
                rays.for_each_ray(x, y, &mut sampler, |ray, sampler| {
                    integrator.trace_camera_ray(ray, sampler, &mut acc, &mut count)
                });
                let alone = acc.mean();
                assert_eq!(
                    pixel.to_array().map(f32::to_bits),
                    alone.to_array().map(f32::to_bits),
                    "pixel ({x}, {y})"
                );
                lit += usize::from(pixel.max_element() > 0.0);
            }
        }
        assert!(lit > 60, "{lit} pixels lit");
    }
}

mod band_tests {
    use crate::render::*;
    use crate::scene::{Light, Material, Surface};

    #[test]
    fn progress_counts_every_traced_row_once() {
        let scene = super::with_unit_ball(Scene {
            materials: vec![Material::default_white()],
            lights: vec![Light::point(Vec3::new(2.0, 3.0, 4.0), Vec3::ONE)],
            ..Scene::default()
        });
        // Heights that leave a short last strip of rows, with and without anti-aliasing.
        let camera = Camera::look_at(Vec3::new(0.0, 0.5, 4.0), Vec3::ZERO, Vec3::Y, 50.0, 37, 23);
        for (aa, spp) in [(1, 1), (3, 1), (2, 3)] {
            let settings = RenderSettings {
                aa: Some(aa),
                spp: Some(spp),
                ..RenderSettings::default()
            };
            let renderer = Renderer::new(&scene, &camera, settings).unwrap();
            let rows = AtomicU64::new(0);
            renderer
                .render(&Progress(|n| {
                    rows.fetch_add(n, Ordering::Relaxed);
                }))
                .unwrap();
            assert_eq!(rows.into_inner(), renderer.rows_to_trace(), "aa {aa}");
            assert!(renderer.rows_to_trace() >= u64::from(23 * aa));
        }
    }

    #[test]
    fn streamed_rows_are_the_image_each_row_once() {
        let scene = super::with_unit_ball(Scene {
            materials: vec![Material::default_white()],
            lights: vec![Light::point(Vec3::new(2.0, 3.0, 4.0), Vec3::ONE)],
            ..Scene::default()
        });
        let camera = Camera::look_at(Vec3::new(0.0, 0.5, 4.0), Vec3::ZERO, Vec3::Y, 50.0, 37, 71);
        let region = Region {
            x: 3,
            y: 2,
            width: 30,
            height: 67,
        };
        for (aa, region) in [(1, None), (2, None), (1, Some(region)), (3, Some(region))] {
            let settings = RenderSettings {
                aa: Some(aa),
                region,
                threads: Some(2),
                ..RenderSettings::default()
            };
            let renderer = Renderer::new(&scene, &camera, settings).unwrap();
            let (w, h) = (renderer.region().width, renderer.region().height);
            let streamed = std::sync::Mutex::new(vec![[f32::NAN; 3]; (w * h) as usize]);
            let times = std::sync::Mutex::new(vec![0u32; h as usize]);
            let (image, _) = renderer
                .render(&Rows(|y, rows: &[[f32; 3]]| {
                    assert_eq!(rows.len() % w as usize, 0);
                    let start = y as usize * w as usize;
                    streamed.lock().unwrap()[start..start + rows.len()].copy_from_slice(rows);
                    for row in y..y + rows.len() as u32 / w {
                        times.lock().unwrap()[row as usize] += 1;
                    }
                }))
                .unwrap();
            assert!(
                times.into_inner().unwrap().iter().all(|&n| n == 1),
                "aa {aa}"
            );
            let bits =
                |p: &[[f32; 3]]| -> Vec<u32> { p.iter().flatten().map(|v| v.to_bits()).collect() };
            assert_eq!(bits(&streamed.into_inner().unwrap()), bits(&image.pixels));
            assert!(image.pixels.iter().flatten().any(|&v| v > 0.0));
        }
    }

    #[test]
    fn without_anti_aliasing_the_image_is_the_one_tap_resample_of_the_traced_pixels() {
        let scene = super::with_unit_ball(Scene {
            materials: vec![Material::default_white()],
            surfaces: vec![Surface {
                transmission: Vec3::splat(0.5),
                ior: 1.3,
                ..Surface::default()
            }],
            lights: vec![Light::point(Vec3::new(2.0, 3.0, 4.0), Vec3::ONE)],
            ..Scene::default()
        });
        let camera = Camera::look_at(Vec3::new(0.0, 0.5, 4.0), Vec3::ZERO, Vec3::Y, 50.0, 48, 40);
        for integrator in IntegratorKind::ALL {
            for region in [
                None,
                Some(Region {
                    x: 5,
                    y: 3,
                    width: 30,
                    height: 35,
                }),
            ] {
                let settings = RenderSettings {
                    aa: Some(1),
                    region,
                    integrator,
                    ..RenderSettings::default()
                };
                let renderer = Renderer::new(&scene, &camera, settings).unwrap();
                let (image, _) = renderer.render(&()).unwrap();
                // What the band loop gives: traced pixels through the resampler.
                let r = renderer.region();
                let plan = &renderer.plan;
                let rays = CameraRays::new(&plan.camera, 1, plan.spp);
                let accel = Accel::build(plan.accel, &scene.shapes);
                let surfaces = scene.resolved_surfaces();
                let whitted =
                    Whitted::new(&scene, &accel, &surfaces, plan.max_depth, plan.min_weight);
                let classic = Classic::new(&scene, &accel, plan.camera.medium_ior);
                let path = Path::new(&scene, &accel, &surfaces, plan.max_depth);
                let mut count = RayCount::default();
                let mut traced = Vec::new();
                for y in r.y..r.y + r.height {
                    for x in r.x..r.x + r.width {
                        let p = match integrator {
                            IntegratorKind::Classic => {
                                renderer.pixel(&classic, &accel, &rays, x, y, &mut count)
                            }
                            IntegratorKind::Whitted => {
                                renderer.pixel(&whitted, &accel, &rays, x, y, &mut count)
                            }
                            IntegratorKind::Path => {
                                super::traced_alone(&renderer, &path, &rays, (x, y), &mut count)
                            }
                        };
                        traced.push(p.to_array());
                    }
                }
                let (wx, wy) = renderer.weights();
                let expected = crate::film::resample::resample_window(
                    &traced, r.x, r.y, r.width, r.height, &wx, &wy, r.x, r.y, r.width, r.height,
                );
                let bits = |p: &[[f32; 3]]| -> Vec<u32> {
                    p.iter().flatten().map(|v| v.to_bits()).collect()
                };
                assert_eq!(bits(&image.pixels), bits(&expected), "{integrator:?}");
                assert!(image.pixels.iter().flatten().any(|&v| v > 0.0));
            }
        }
    }
}

mod sample_pass_tests {
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
                    let (image, stats) =
                        renderer.render_samples(&accel, &mut sums, to, &()).unwrap();
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
        let renderer =
            Renderer::new(&scene, &camera, path(4, 2, Filter::Lanczos, None, 2)).unwrap();
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
        let small =
            Renderer::new(&scene, &camera, path(8, 1, Filter::Area, Some(region), 2)).unwrap();
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
}

/// A scene of instances renders as its flattened twin, bit for bit, in every model.
mod instance_tests {
    use crate::math::Vec3;
    use crate::options::LightSampling;
    use crate::render::{IntegratorKind, RenderSettings, Renderer};
    use crate::scene::openpbr::Scalar;
    use crate::scene::{
        Camera, Instance, Light, LightKind, Material, MeshAttributes, Object, OpenPbr, Scene,
        ShapeId, Shapes, Surface,
    };
    use glam::{Affine3A, Quat};

    /// An octahedron with smooth normals, texture coordinates and colours, wearing
    /// `material`.
    fn gem(material: u32) -> Object {
        let positions = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
        let triangles = vec![
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ];
        let mut shapes = Shapes::new();
        shapes.push_mesh(&positions, &triangles);
        let normals = positions.iter().map(|p| *p * 0.8 + Vec3::Y * 0.2).collect();
        let uv = positions
            .iter()
            .map(|p| [p.x * 0.5 + 0.5, p.z * 0.5 + 0.5])
            .collect();
        let colors = positions.iter().map(|p| p.abs() * 0.5 + 0.5).collect();
        Object {
            name: "gem".into(),
            material_of: vec![material; triangles.len()],
            meshes: vec![MeshAttributes::per_vertex(&triangles, normals, uv, colors)],
            shapes,
        }
    }

    fn scene(metal: bool) -> Scene {
        let m = OpenPbr {
            base_metalness: Scalar::constant(1.0),
            specular_roughness: Scalar::constant(0.3),
            ..OpenPbr::default()
        };
        let mut scene = Scene {
            materials: vec![Material::default_white(); 2],
            surfaces: vec![
                Surface::from_classic(&Material::default_white()),
                if metal {
                    Surface {
                        openpbr: Some(Box::new(m)),
                        ..Surface::default()
                    }
                } else {
                    Surface::from_classic(&Material::default_white())
                },
            ],
            lights: vec![Light::point(Vec3::new(1.0, 5.0, 3.0), Vec3::splat(30.0))],
            objects: vec![gem(1)],
            ..Scene::default()
        };
        super::add_floor(&mut scene, 0);
        scene.instances = (0..7)
            .map(|k| {
                let f = k as f32;
                let mirror = if k % 3 == 1 { -1.0 } else { 1.0 };
                Instance::new(
                    0,
                    Affine3A::from_scale_rotation_translation(
                        glam::Vec3::new(mirror * 0.5, 0.4 + 0.1 * f, 0.45),
                        Quat::from_rotation_y(f * 0.9) * Quat::from_rotation_x(0.3),
                        glam::Vec3::new(f - 3.0, -0.5 + 0.1 * f, (f * 1.7).sin()),
                    ),
                )
            })
            .collect();
        scene
    }

    fn render(scene: &Scene, integrator: IntegratorKind) -> Vec<[f32; 3]> {
        render_with(scene, integrator, LightSampling::default())
    }

    fn render_with(
        scene: &Scene,
        integrator: IntegratorKind,
        light_sampling: LightSampling,
    ) -> Vec<[f32; 3]> {
        let camera = Camera::look_at(Vec3::new(0.0, 2.0, 7.0), Vec3::ZERO, Vec3::Y, 45.0, 48, 32);
        let settings = RenderSettings {
            spp: Some(4),
            integrator,
            light_sampling,
            ..RenderSettings::default()
        };
        let renderer = Renderer::new(scene, &camera, settings).unwrap();
        renderer.render(&()).unwrap().0.pixels
    }

    fn same_bits(a: &[[f32; 3]], b: &[[f32; 3]]) -> bool {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(a, b)| a.map(f32::to_bits) == b.map(f32::to_bits))
    }

    /// The gems with their upper halves glowing (material 2), lit by nothing else:
    /// the glow of the first four is one light (as glTF lights a material), each of the
    /// other three's its own (as the scene file lights an instance).
    fn glowing_scene() -> Scene {
        let mut scene = scene(false);
        scene.materials.push(Material::default_white());
        scene.surfaces.push(Surface {
            emission: Vec3::new(4.0, 3.0, 2.0),
            ..Surface::from_classic(&Material::default_white())
        });
        for m in &mut scene.objects[0].material_of[..4] {
            *m = 2;
        }
        let glowing = |i: u32| (0..4).map(move |shape| ShapeId { instance: i, shape });
        let shared = Light::mesh(&scene, (0..4).flat_map(glowing)).unwrap();
        let own: Vec<Light> = (4..7)
            .map(|i| Light::mesh(&scene, glowing(i)).unwrap())
            .collect();
        scene.lights = std::iter::once(shared).chain(own).collect();
        scene
    }

    #[test]
    fn glowing_instances_light_as_their_flattened_twin_bit_for_bit() {
        let scene = glowing_scene();
        let flat = scene.flattened();
        let LightKind::Mesh { shapes, .. } = &flat.lights[0].kind else {
            panic!()
        };
        // The copies' indices: the floor is shape 0, each gem 8 shapes.
        assert_eq!(shapes[..5], [1, 2, 3, 4, 9].map(ShapeId::world));
        let dark = Scene {
            lights: Vec::new(),
            ..scene.clone()
        };
        for (integrator, sampling) in [
            (IntegratorKind::Path, LightSampling::All),
            (IntegratorKind::Path, LightSampling::One),
            (IntegratorKind::Path, LightSampling::Tree),
            (IntegratorKind::Whitted, LightSampling::All),
        ] {
            let placed = render_with(&scene, integrator, sampling);
            let twin = render_with(&flat, integrator, sampling);
            assert!(same_bits(&placed, &twin), "{integrator:?}, {sampling:?}");
            // The lights are sampled: the whitted model sees the floor lit only
            // through them; the path model finds the same light either way, but
            // with other numbers.
            let unlit = render_with(&dark, integrator, sampling);
            let sum = |p: &[[f32; 3]]| p.iter().map(|c| c[0] + c[1] + c[2]).sum::<f32>();
            match integrator {
                IntegratorKind::Whitted => assert!(sum(&placed) > 1.5 * sum(&unlit)),
                _ => assert!(!same_bits(&placed, &unlit), "{sampling:?}"),
            }
        }
    }

    /// Smooth instances in a scene whose own meshes are flat, traced in the path
    /// model's lanes: the placed normals are interpolated there too.
    #[test]
    fn lanes_shade_placed_vertex_normals_as_the_flattened_twin() {
        let scene = glowing_scene();
        assert!(scene.meshes.is_empty());
        let flat = scene.flattened();
        let placed = render_with(&scene, IntegratorKind::Path, LightSampling::All);
        let twin = render_with(&flat, IntegratorKind::Path, LightSampling::All);
        assert!(same_bits(&placed, &twin));
    }

    #[test]
    fn instances_render_as_their_flattened_twin_bit_for_bit() {
        for metal in [false, true] {
            let scene = scene(metal);
            let flat = scene.flattened();
            assert_eq!(flat.shapes.len(), 1 + 7 * 8);
            for integrator in [
                IntegratorKind::Path,
                IntegratorKind::Whitted,
                IntegratorKind::Classic,
            ] {
                let placed = render(&scene, integrator);
                let twin = render(&flat, integrator);
                assert!(same_bits(&placed, &twin), "{integrator:?}, metal {metal}");
                // The gems are seen: pixels differ from the floor-only render.
                let bare = Scene {
                    instances: Vec::new(),
                    ..scene.clone()
                };
                assert_ne!(render(&bare, integrator), placed, "{integrator:?}");
            }
        }
    }
}
