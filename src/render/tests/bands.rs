//! The band loop's rows: progress counts each traced row once, streamed rows are the
//! image, and without anti-aliasing the image is the one-tap resample.

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
            let whitted = Whitted::new(&scene, &accel, &surfaces, plan.max_depth, plan.min_weight);
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
            let bits =
                |p: &[[f32; 3]]| -> Vec<u32> { p.iter().flatten().map(|v| v.to_bits()).collect() };
            assert_eq!(bits(&image.pixels), bits(&expected), "{integrator:?}");
            assert!(image.pixels.iter().flatten().any(|&v| v > 0.0));
        }
    }
}
