//! The 2014 camera (CMR file, report section 5.2.3; SPEC 3.1).

use crate::math::Vec3;

/// Camera as the CMR file states it. Angles in degrees: `theta` is the polar angle from
/// +z (z is up), `phi` the azimuth from +x.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub theta_deg: f32,
    pub phi_deg: f32,
    /// Refractive index of the medium the camera sits in.
    pub medium_ior: f32,
    /// Distance from the eye to the screen.
    pub screen_distance: f32,
    pub width: u32,
    pub height: u32,
    /// Half the screen extent of one pixel: the screen spans `2 width s` by `2 height s`.
    pub retina_scale: f32,
    /// Distance from the screen to the focal plane.
    pub focal_length: f32,
    /// Radius of the lens.
    pub aperture: f32,
    /// Camera rays per pixel; more than one turns on depth of field.
    pub rays_per_pixel: u32,
    /// Supersampling factor per axis.
    pub aa: u32,
}

/// Orthonormal camera frame: `forward` (w), image right (r), image down (u).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub forward: Vec3,
    pub right: Vec3,
    pub down: Vec3,
}

impl Camera {
    /// The 2014 frame. Its handedness (right = forward x down... rotated from local
    /// axes, not a look-at) is kept exactly: scenes were authored against it.
    pub fn frame(&self) -> Frame {
        let (st, ct) = self.theta_deg.to_radians().sin_cos();
        let (sp, cp) = self.phi_deg.to_radians().sin_cos();
        Frame {
            forward: Vec3::new(st * cp, st * sp, ct),
            right: Vec3::new(-sp, cp, 0.0),
            down: Vec3::new(ct * cp, ct * sp, -st),
        }
    }

    /// Same field of view at another resolution: the retina scale follows the width.
    pub fn with_resolution(&self, width: u32, height: u32) -> Camera {
        let mut c = self.clone();
        c.retina_scale = self.retina_scale * self.width as f32 / width as f32;
        c.width = width;
        c.height = height;
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam(theta: f32, phi: f32) -> Camera {
        Camera {
            eye: Vec3::ZERO,
            theta_deg: theta,
            phi_deg: phi,
            medium_ior: 1.0,
            screen_distance: 1.0,
            width: 4,
            height: 2,
            retina_scale: 0.5,
            focal_length: 1.0,
            aperture: 0.0,
            rays_per_pixel: 1,
            aa: 1,
        }
    }

    #[test]
    fn horizontal_camera_looking_along_x() {
        let f = cam(90.0, 0.0).frame();
        assert!((f.forward - Vec3::X).length() < 1e-6);
        assert!((f.right - Vec3::Y).length() < 1e-6);
        assert!((f.down + Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn frame_is_orthonormal_for_any_angles() {
        let f = cam(78.0614, 64.5).frame();
        for v in [f.forward, f.right, f.down] {
            assert!((v.length() - 1.0).abs() < 1e-6);
        }
        assert!(f.forward.dot(f.right).abs() < 1e-6);
        assert!(f.forward.dot(f.down).abs() < 1e-6);
        assert!(f.right.dot(f.down).abs() < 1e-6);
    }

    #[test]
    fn resolution_change_keeps_field_of_view() {
        let c = cam(90.0, 0.0).with_resolution(8, 4);
        assert_eq!(c.retina_scale * c.width as f32, 2.0);
    }
}
