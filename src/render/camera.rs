//! Camera rays of the 2014 camera (SPEC 3.1 and 3.4) over a supersampled frame.

use super::sampler::PixelSampler;
use crate::math::{Ray, Vec3};
use crate::scene::{Camera, Frame, Projection};

/// Generates the rays of every pixel of a `k*width x k*height` frame.
#[derive(Clone, Debug)]
pub struct CameraRays {
    eye: Vec3,
    frame: Frame,
    screen_center: Vec3,
    /// World step between neighbouring supersampled pixels along right and down.
    step: f32,
    /// Screen position of the centre of pixel (0, 0), relative to the screen centre.
    origin_x: f32,
    origin_y: f32,
    /// (d + f) / d: how much farther the focal plane is than the screen.
    focus_ratio: f32,
    aperture: f32,
    spp: u32,
    /// Parallel rays from the screen (shifted back to the eye's plane) along forward.
    orthographic: bool,
}

impl CameraRays {
    /// `aa` is the supersampling factor per axis; the field of view stays that of the
    /// camera: the screen spans `2 width s` by `2 height s` at any `aa`.
    pub fn new(camera: &Camera, aa: u32, spp: u32) -> CameraRays {
        let frame = camera.frame();
        let s = camera.retina_scale / aa as f32;
        let step = 2.0 * s;
        let mut origin_x = -(camera.width as f32) * camera.retina_scale + 0.5 * step;
        let mut origin_y = -(camera.height as f32) * camera.retina_scale + 0.5 * step;
        if camera.shift != [0.0, 0.0] {
            // The window slides across the screen's plane: right, and up (down is +y).
            let screen_width = 2.0 * camera.width as f32 * camera.retina_scale;
            origin_x += camera.shift[0] * screen_width;
            origin_y -= camera.shift[1] * screen_width;
        }
        CameraRays {
            eye: camera.eye,
            frame,
            screen_center: camera.eye + frame.forward * camera.screen_distance,
            step,
            origin_x,
            origin_y,
            focus_ratio: (camera.screen_distance + camera.focal_length) / camera.screen_distance,
            aperture: camera.aperture,
            spp: if camera.projection == Projection::Orthographic {
                1
            } else {
                spp.max(1)
            },
            orthographic: camera.projection == Projection::Orthographic,
        }
    }

    /// Rays per pixel: one pinhole ray plus `n - 1` lens rays.
    pub fn spp(&self) -> u32 {
        self.spp
    }

    /// The pinhole ray through the centre of supersampled pixel `(x, y)`.
    #[inline]
    pub fn pinhole(&self, x: u32, y: u32) -> Ray {
        if self.orthographic {
            return self.parallel(x, y);
        }
        Ray::new(self.eye, self.screen_point(x, y) - self.eye)
    }

    /// An orthographic camera's ray of pixel `(x, y)`: from the screen point moved back
    /// into the eye's plane, along the view direction.
    #[inline]
    fn parallel(&self, x: u32, y: u32) -> Ray {
        let sx = self.origin_x + x as f32 * self.step;
        let sy = self.origin_y + y as f32 * self.step;
        let origin = self.eye + self.frame.right * sx + self.frame.down * sy;
        Ray::new(origin, self.frame.forward)
    }

    #[inline]
    fn screen_point(&self, x: u32, y: u32) -> Vec3 {
        let sx = self.origin_x + x as f32 * self.step;
        let sy = self.origin_y + y as f32 * self.step;
        self.screen_center + self.frame.right * sx + self.frame.down * sy
    }

    /// A ray through point `(dx, dy)` of supersampled pixel `(x, y)` (each in [0, 1),
    /// from its top-left corner) from lens point `lens` (uniform in the unit square,
    /// mapped onto the aperture's disk): the path model's camera samples, spread over
    /// the pixel's area as a box filter weighs them. Without an aperture every ray
    /// starts at the eye; an orthographic ray starts on the screen's plane.
    #[inline]
    pub fn through(&self, x: u32, y: u32, (dx, dy): (f32, f32), lens: (f32, f32)) -> Ray {
        let sx = self.origin_x + (x as f32 + dx - 0.5) * self.step;
        let sy = self.origin_y + (y as f32 + dy - 0.5) * self.step;
        let offset = self.frame.right * sx + self.frame.down * sy;
        if self.orthographic {
            return Ray::new(self.eye + offset, self.frame.forward);
        }
        let to_screen = self.screen_center + offset - self.eye;
        if self.aperture <= 0.0 {
            return Ray::new(self.eye, to_screen);
        }
        let focus = self.eye + to_screen * self.focus_ratio;
        let (lx, ly) = crate::math::concentric_disk(lens);
        let origin = self.eye + (self.frame.right * lx + self.frame.down * ly) * self.aperture;
        Ray::new(origin, focus - origin)
    }

    /// Calls `emit` with each camera ray of pixel `(x, y)` and the pixel's random stream
    /// (for what the shading model samples): the pinhole ray, then the
    /// lens rays, aimed at the point where the pinhole ray meets the focal plane (which
    /// lies `d + f` from the eye along the view direction).
    #[inline]
    pub fn for_each_ray(
        &self,
        x: u32,
        y: u32,
        sampler: &mut PixelSampler,
        mut emit: impl FnMut(Ray, &mut PixelSampler),
    ) {
        if self.orthographic {
            // Parallel rays have no common focus: no lens rays, one ray a pixel.
            emit(self.parallel(x, y), sampler);
            return;
        }
        let to_screen = self.screen_point(x, y) - self.eye;
        emit(Ray::new(self.eye, to_screen), sampler);
        let lens_rays = self.spp - 1;
        if lens_rays == 0 {
            return;
        }
        let focus = self.eye + to_screen * self.focus_ratio;
        for i in 0..lens_rays {
            let (lx, ly) = sampler.disk_sample(i, lens_rays);
            let origin = self.eye + (self.frame.right * lx + self.frame.down * ly) * self.aperture;
            emit(Ray::new(origin, focus - origin), sampler);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{concentric_disk, normalize};

    /// Eye at the origin looking along +x; 4 x 2 pixels, s = 0.5, d = 1: the screen is
    /// the square [-2, 2] x [-1, 1] at x = 1, pixels one unit wide.
    fn camera() -> Camera {
        Camera {
            eye: Vec3::ZERO,
            theta_deg: 90.0,
            phi_deg: 0.0,
            medium_ior: 1.0,
            screen_distance: 1.0,
            width: 4,
            height: 2,
            retina_scale: 0.5,
            focal_length: 3.0,
            aperture: 0.5,
            spp: 1,
            aa: 1,
            up: None,
            projection: crate::scene::Projection::Perspective,
            shift: [0.0, 0.0],
        }
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-6
    }

    #[test]
    fn corner_and_centre_rays_of_a_known_camera() {
        let rays = CameraRays::new(&camera(), 1, 1);
        // Top-left pixel centre: right -1.5, down -0.5 (i.e. up, +z 0.5).
        let tl = rays.pinhole(0, 0);
        assert!(
            close(tl.dir, normalize(Vec3::new(1.0, -1.5, 0.5))),
            "{tl:?}"
        );
        let br = rays.pinhole(3, 1);
        assert!(
            close(br.dir, normalize(Vec3::new(1.0, 1.5, -0.5))),
            "{br:?}"
        );
        // Between the four central pixels lies the view axis.
        let a = rays.pinhole(1, 0).dir + rays.pinhole(2, 1).dir;
        assert!(close(normalize(a), Vec3::X));
    }

    #[test]
    fn a_lens_shift_slides_the_window_across_the_screen_plane() {
        // Shifted a quarter of the screen's width (4) right and half of it up: one
        // pixel right and two up, the view direction unchanged.
        let mut c = camera();
        c.shift = [0.25, 0.5];
        let rays = CameraRays::new(&c, 1, 1);
        let tl = rays.pinhole(0, 0);
        assert!(
            close(tl.dir, normalize(Vec3::new(1.0, -0.5, 2.5))),
            "{tl:?}"
        );
        assert!(close(
            rays.pinhole(2, 1).dir,
            normalize(Vec3::new(1.0, 1.5, 1.5))
        ));
    }

    #[test]
    fn orthographic_rays_are_parallel_and_span_the_screen() {
        let mut c = camera();
        c.projection = Projection::Orthographic;
        let rays = CameraRays::new(&c, 1, 9);
        // The screen spans [-2, 2] x [-1, 1]: pixel (0, 0) is at right -1.5, up 0.5.
        let tl = rays.pinhole(0, 0);
        assert!(close(tl.dir, Vec3::X) && close(tl.origin, Vec3::new(0.0, -1.5, 0.5)));
        let br = rays.pinhole(3, 1);
        assert!(close(br.dir, Vec3::X) && close(br.origin, Vec3::new(0.0, 1.5, -0.5)));
        let mut all = Vec::new();
        let mut sampler = PixelSampler::new(0, 2, 1);
        rays.for_each_ray(2, 1, &mut sampler, |r, _| all.push(r));
        assert_eq!(all.len(), 1);
        assert!(close(all[0].origin, Vec3::new(0.0, 0.5, -0.5)));
    }

    #[test]
    fn a_sample_at_the_pixel_centre_is_the_pinhole_ray_and_corners_bound_the_pixel() {
        let mut c = camera();
        c.aperture = 0.0;
        let rays = CameraRays::new(&c, 1, 1);
        let centre = rays.through(1, 0, (0.5, 0.5), (0.5, 0.5));
        assert!(close(centre.dir, rays.pinhole(1, 0).dir));
        // Pixel (1, 0) spans right [-1, 0] and up [0, 1] on the screen at x = 1.
        let corner = rays.through(1, 0, (0.0, 0.0), (0.5, 0.5));
        assert!(
            close(corner.dir, normalize(Vec3::new(1.0, -1.0, 1.0))),
            "{corner:?}"
        );
        // A lens ray meets the jittered pinhole ray on the focal plane (x = 4).
        let lensed = CameraRays::new(&camera(), 1, 1);
        let pin = rays.through(2, 1, (0.25, 0.75), (0.5, 0.5));
        let lens = lensed.through(2, 1, (0.25, 0.75), (0.9, 0.2));
        assert!(lens.origin.length() > 0.1 && lens.origin.length() <= 0.5 + 1e-6);
        let p = lens.at((4.0 - lens.origin.x) / lens.dir.x);
        let q = pin.at(4.0 / pin.dir.x);
        assert!((p - q).length() < 1e-5, "{p} vs {q}");
    }

    #[test]
    fn the_concentric_map_keeps_the_disk_and_its_area() {
        let n = 64;
        let mut inner = 0;
        for i in 0..n {
            for j in 0..n {
                let (x, y) =
                    concentric_disk(((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32));
                let r2 = x * x + y * y;
                assert!(r2 <= 1.0 + 1e-6);
                inner += (r2 < 0.25) as u32;
            }
        }
        // A quarter of the area lies within radius 1/2.
        assert!(
            (inner as f32 / (n * n) as f32 - 0.25).abs() < 0.01,
            "{inner}"
        );
    }

    #[test]
    fn supersampling_keeps_the_field_of_view() {
        let rays = CameraRays::new(&camera(), 2, 1);
        // 8 x 4 pixels of half size: the first centre is at right -1.75, down -0.75.
        assert!(close(
            rays.pinhole(0, 0).dir,
            normalize(Vec3::new(1.0, -1.75, 0.75))
        ));
    }

    #[test]
    fn lens_rays_meet_the_pinhole_ray_on_the_focal_plane() {
        let rays = CameraRays::new(&camera(), 1, 9);
        let mut sampler = PixelSampler::new(0, 2, 1);
        let mut all = Vec::new();
        rays.for_each_ray(2, 1, &mut sampler, |r, _| all.push(r));
        assert_eq!(all.len(), 9);
        // Focal plane at x = d + f = 4.
        let focus = all[0].at(4.0 / all[0].dir.x);
        for r in &all[1..] {
            assert!(r.origin.x.abs() < 1e-6 && r.origin.length() <= 0.5 + 1e-6);
            let p = r.at((4.0 - r.origin.x) / r.dir.x);
            assert!(
                close(p, focus) || (p - focus).length() < 1e-5,
                "{p} vs {focus}"
            );
        }
    }
}
