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
        CameraRays {
            eye: camera.eye,
            frame,
            screen_center: camera.eye + frame.forward * camera.screen_distance,
            step,
            origin_x: -(camera.width as f32) * camera.retina_scale + 0.5 * step,
            origin_y: -(camera.height as f32) * camera.retina_scale + 0.5 * step,
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
    use crate::math::normalize;

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
