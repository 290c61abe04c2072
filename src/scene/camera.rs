//! The 2014 camera (CMR file, report section 5.2.3; SPEC 3.1).

use crate::math::{Vec3, cross};

/// Camera as the CMR file states it. Angles in degrees: `theta` is the polar angle from
/// +z (z is up), `phi` the azimuth from +x.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// World-space eye position: the centre of projection (an orthographic camera's
    /// ray plane passes through it).
    pub eye: Vec3,
    /// Polar angle of the view direction from +z, in degrees (90: in the xy plane).
    pub theta_deg: f32,
    /// Azimuth of the view direction from +x towards +y, in degrees.
    pub phi_deg: f32,
    /// Refractive index of the medium the camera sits in.
    pub medium_ior: f32,
    /// Distance from the eye to the screen.
    pub screen_distance: f32,
    /// Image width in pixels, before supersampling.
    pub width: u32,
    /// Image height in pixels, before supersampling.
    pub height: u32,
    /// Half the screen extent of one pixel: the screen spans `2 width s` by `2 height s`.
    pub retina_scale: f32,
    /// Distance from the screen to the focal plane.
    pub focal_length: f32,
    /// Radius of the lens.
    pub aperture: f32,
    /// Camera rays per pixel; more than one turns on depth of field.
    pub spp: u32,
    /// Supersampling factor per axis.
    pub aa: u32,
    /// `None`: the 2014 frame (SPEC 3.1), as the `.cmr` files mean it. `Some(up)`: a
    /// right-handed look-at frame with `up` as the image's vertical, as standard OBJ,
    /// PLY and Prism scene files mean it: seen from +z with +y up, +x is on the right.
    pub up: Option<Vec3>,
    /// How the screen maps to rays.
    pub projection: Projection,
    /// Lens shift: the screen window moved across the view, right and up, in units of
    /// the screen's width (the image stays square to the view direction, so verticals
    /// stay vertical; Blender's shift).
    pub shift: [f32; 2],
}

/// How a camera's screen maps to rays.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Projection {
    /// Rays leave the eye through each screen point (lens rays around it).
    #[default]
    Perspective,
    /// Rays leave each screen point, shifted back to the eye's plane, along the view
    /// direction: parallel rays, the screen's extent the same at every distance
    /// (`width * retina_scale` is the half width, glTF's `xmag`).
    Orthographic,
}

/// Orthonormal camera frame: `forward` (w), image right (r), image down (u).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Unit view direction, from the eye through the screen centre.
    pub forward: Vec3,
    /// Unit world direction in which pixel columns (x) increase.
    pub right: Vec3,
    /// Unit world direction in which pixel rows (y) increase.
    pub down: Vec3,
}

impl Camera {
    /// The 2014 frame. Its handedness (right = forward x down... rotated from local
    /// axes, not a look-at) is kept exactly: scenes were authored against it.
    pub fn frame(&self) -> Frame {
        let (st, ct) = self.theta_deg.to_radians().sin_cos();
        let (sp, cp) = self.phi_deg.to_radians().sin_cos();
        let forward = Vec3::new(st * cp, st * sp, ct);
        if let Some(up) = self.up {
            return look_at_frame(forward, up);
        }
        Frame {
            forward,
            right: Vec3::new(-sp, cp, 0.0),
            down: Vec3::new(ct * cp, ct * sp, -st),
        }
    }

    /// A right-handed pinhole camera at `from` looking at `at`, `up` the image's
    /// vertical, `fov_deg` the full horizontal field of view, `width x height` pixels.
    /// The screen sits at distance 1; `focal_length` and `aperture` are left at a
    /// pinhole's (set them for depth of field: the focal plane lies at `1 +
    /// focal_length`).
    pub fn look_at(
        from: Vec3,
        at: Vec3,
        up: Vec3,
        fov_deg: f32,
        width: u32,
        height: u32,
    ) -> Camera {
        let (theta_deg, phi_deg) = angles_of(at - from);
        let half = (fov_deg.clamp(1e-3, 179.0) * 0.5).to_radians().tan();
        Camera {
            eye: from,
            theta_deg,
            phi_deg,
            medium_ior: 1.0,
            screen_distance: 1.0,
            width,
            height,
            retina_scale: half / width.max(1) as f32,
            focal_length: 0.0,
            aperture: 0.0,
            spp: 1,
            aa: 1,
            up: Some(up),
            projection: Projection::Perspective,
            shift: [0.0, 0.0],
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

/// Polar angle from +z and azimuth from +x, in degrees, of direction `d`: how the 2014
/// camera states where it looks (`Camera::frame` turns them back).
pub fn angles_of(d: Vec3) -> (f32, f32) {
    let d = d.normalize_or(Vec3::X);
    // atan2, not acos of z: near the poles acos turns z's last bit into a large angle
    // (a view down -z came out 0.02 degrees off, a quarter pixel across 512).
    let theta = (d.x.hypot(d.y)).atan2(d.z).to_degrees();
    let phi = if d.x == 0.0 && d.y == 0.0 {
        0.0
    } else {
        d.y.atan2(d.x).to_degrees()
    };
    (theta, phi)
}

/// The right-handed frame looking along `forward` with `up` as the vertical: right =
/// forward x up. When the two are (nearly) parallel, another vertical is chosen so the
/// frame stays orthonormal.
pub fn look_at_frame(forward: Vec3, up: Vec3) -> Frame {
    let forward = forward.normalize_or(Vec3::X);
    let mut right = cross(forward, up).normalize_or_zero();
    if right.length_squared() < 0.5 {
        right = forward.any_orthonormal_vector();
    }
    Frame {
        forward,
        right,
        down: cross(forward, right),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_view_along_an_axis_keeps_its_angle_exactly() {
        for (d, theta) in [
            (-Vec3::Z, 180.0),
            (Vec3::Z * 3.9, 0.0),
            (Vec3::new(0.0, 0.0, -3.9), 180.0),
        ] {
            assert_eq!(angles_of(d).0, theta, "{d}");
        }
        let c = Camera::look_at(
            Vec3::new(0.0, 1.0, 3.9),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::Y,
            40.0,
            8,
            8,
        );
        assert!((c.frame().forward - -Vec3::Z).length() < 1e-6);
    }

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
            spp: 1,
            aa: 1,
            up: None,
            projection: Projection::Perspective,
            shift: [0.0, 0.0],
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
    fn look_at_is_right_handed_with_plus_x_on_the_right_seen_from_plus_z() {
        let c = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 90.0, 4, 2);
        let f = c.frame();
        assert!((f.forward + Vec3::Z).length() < 1e-6, "{f:?}");
        assert!((f.right - Vec3::X).length() < 1e-6, "{f:?}");
        assert!((f.down + Vec3::Y).length() < 1e-6, "{f:?}");
        // A 90 degree field: the screen at distance 1 spans [-1, 1] across.
        assert!((c.retina_scale * c.width as f32 - 1.0).abs() < 1e-6);
    }

    #[test]
    fn look_at_straight_along_up_still_gives_a_frame() {
        let c = Camera::look_at(Vec3::ZERO, Vec3::new(0.0, -3.0, 0.0), Vec3::Y, 60.0, 4, 4);
        let f = c.frame();
        for v in [f.forward, f.right, f.down] {
            assert!((v.length() - 1.0).abs() < 1e-5, "{f:?}");
        }
        assert!(f.forward.dot(f.right).abs() < 1e-5 && f.right.dot(f.down).abs() < 1e-5);
    }

    #[test]
    fn resolution_change_keeps_field_of_view() {
        let c = cam(90.0, 0.0).with_resolution(8, 4);
        assert_eq!(c.retina_scale * c.width as f32, 2.0);
    }
}
