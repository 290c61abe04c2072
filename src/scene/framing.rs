//! A view for a model that brings no camera or lights: a three-quarter view framing
//! its bounds, a key and a fill light, the neutral studio around it. What `prism render
//! model.obj out.png` shows.

use super::{Background, Camera, Light, LightKind, Scene};
use crate::math::{Aabb, Vec3, cross, normalize};

/// Horizontal field of view of the default camera, in degrees: a normal lens.
pub const DEFAULT_FOV: f32 = 40.0;
/// Width and height of the default view (16:9).
pub const DEFAULT_SIZE: (u32, u32) = (960, 540);

/// A camera looking at the centre of `bounds` from the front-left and above (with
/// `up` the vertical), far enough that the bounding sphere fits the frame with a margin.
pub fn three_quarter_view(bounds: Aabb, up: Vec3, width: u32, height: u32) -> Camera {
    let up = up.normalize_or(Vec3::Y);
    let (front, right) = horizontal_axes(up);
    let (center, radius) = if bounds.is_empty() || !bounds.extent().is_finite() {
        (Vec3::ZERO, 1.0)
    } else {
        (bounds.center(), (0.5 * bounds.extent().length()).max(1e-6))
    };
    let dir = normalize(front - 0.75 * right + 0.5 * up);
    // The narrower of the two fields of view must hold the sphere, with 10% to spare.
    let half_h = (DEFAULT_FOV * 0.5).to_radians();
    let half_v = (half_h.tan() * height as f32 / width.max(1) as f32).atan();
    let distance = 1.1 * radius / half_h.min(half_v).sin();
    Camera::look_at(
        center + dir * distance,
        center,
        up,
        DEFAULT_FOV,
        width,
        height,
    )
}

/// Front and right for a given vertical: +z and +x when y is up (as OBJ exporters
/// write), -y and +x when z is up.
fn horizontal_axes(up: Vec3) -> (Vec3, Vec3) {
    let helper = if up.z.abs() < 0.9 { Vec3::Z } else { -Vec3::Y };
    let right = cross(helper, up).normalize_or(Vec3::X);
    let right = if right.dot(Vec3::X) < 0.0 {
        -right
    } else {
        right
    };
    let front = normalize(cross(right, up));
    (front, right)
}

/// Adds the lights an unlit model needs to be seen from `camera` by a model that
/// gathers light from lights alone (whitted, classic): a key light from the camera's
/// upper left, a fill from its right at a third of the strength, where the studio's
/// softboxes are. Directional lights: the scale of the model does not matter. Their
/// irradiance is pi times the key's 0.9 and the fill's 0.3, so a white Lambert surface
/// facing the key shows 0.9.
pub fn add_default_lights(scene: &mut Scene, camera: &Camera) {
    let f = camera.frame();
    let up = -f.down;
    let key = normalize(-f.right + 1.2 * up - 0.6 * f.forward);
    let fill = normalize(f.right + 0.2 * up - 0.8 * f.forward);
    for (toward_light, share) in [(key, 0.9f32), (fill, 0.3)] {
        scene.lights.push(Light {
            kind: LightKind::Directional {
                direction: -toward_light,
            },
            intensity: share * std::f32::consts::PI,
            ..Light::point(Vec3::ZERO, Vec3::ONE)
        });
    }
    scene.ambient = scene.ambient.max(Vec3::splat(0.03));
}

/// Surrounds an unlit model with the default studio ([`super::studio`]), turned so
/// its key softbox is above `camera`'s left shoulder with `up` the vertical, where
/// the scene has no background of its own. It is what the path model is lit by, and
/// what mirrors and glass show in every model.
pub fn add_studio(scene: &mut Scene, camera: &Camera, up: Vec3) {
    if scene.background != Background::Black {
        return;
    }
    let up = up.normalize_or(Vec3::Y);
    let forward = camera.frame().forward;
    let forward = (forward - up * up.dot(forward)).normalize_or(-horizontal_axes(up).0);
    scene.images.push(super::studio::studio_image());
    scene.background = Background::Environment {
        image: (scene.images.len() - 1) as u32,
        up,
        forward,
        intensity: 1.0,
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_view_frames_the_bounds_from_front_left_above() {
        let bounds = Aabb {
            min: Vec3::new(-1.0, 0.0, -1.0),
            max: Vec3::new(1.0, 2.0, 1.0),
        };
        let c = three_quarter_view(bounds, Vec3::Y, 1600, 900);
        let f = c.frame();
        // Looks at the centre.
        let to_center = normalize(bounds.center() - c.eye);
        assert!((f.forward - to_center).length() < 1e-5);
        // From the front (+z), the left (-x) and above (+y).
        assert!(
            c.eye.z > 1.0 && c.eye.x < -1.0 && c.eye.y > 1.0,
            "{}",
            c.eye
        );
        // Every corner of the box is inside the frame.
        for i in 0..8 {
            let p = Vec3::new(
                if i & 1 == 0 { -1.0 } else { 1.0 },
                if i & 2 == 0 { 0.0 } else { 2.0 },
                if i & 4 == 0 { -1.0 } else { 1.0 },
            );
            let d = p - c.eye;
            let z = d.dot(f.forward);
            let x = d.dot(f.right) / z / (c.retina_scale * c.width as f32);
            let y = d.dot(f.down) / z / (c.retina_scale * c.height as f32);
            assert!(x.abs() < 1.0 && y.abs() < 1.0, "corner {p} at {x}, {y}");
        }
    }

    #[test]
    fn z_up_models_are_seen_upright() {
        let bounds = Aabb {
            min: Vec3::ZERO,
            max: Vec3::ONE,
        };
        let c = three_quarter_view(bounds, Vec3::Z, 960, 540);
        assert!(c.frame().down.z < -0.8, "{:?}", c.frame());
        assert!(c.eye.z > 1.0);
    }

    #[test]
    fn default_lighting_adds_a_key_and_a_fill_and_the_studio_about_the_camera() {
        let mut s = Scene::default();
        let c = three_quarter_view(Aabb::EMPTY, Vec3::Y, 16, 9);
        add_default_lights(&mut s, &c);
        add_studio(&mut s, &c, Vec3::Y);
        assert_eq!(s.lights.len(), 2);
        assert!(s.lights[0].intensity > s.lights[1].intensity);
        // The key light comes from above.
        let LightKind::Directional { direction } = s.lights[0].kind else {
            panic!("{:?}", s.lights[0]);
        };
        assert!(direction.y < 0.0);
        // The studio's centre looks along the camera's view made level, so its key
        // softbox sits where the key light comes from.
        let Background::Environment { up, forward, .. } = s.background else {
            panic!("{:?}", s.background);
        };
        assert_eq!(up, Vec3::Y);
        assert!(forward.y.abs() < 1e-6);
        let level = normalize(Vec3::new(c.frame().forward.x, 0.0, c.frame().forward.z));
        assert!((forward - level).length() < 1e-5, "{forward}");
        let image = &s.images[0];
        let key = image.sample_direction(-direction, up, forward);
        assert!(
            key.x > 4.0,
            "the key softbox is where the key light is: {key}"
        );
        // A scene's own background stays.
        let mut t = Scene {
            background: Background::Color(Vec3::ONE),
            ..Scene::default()
        };
        add_studio(&mut t, &c, Vec3::Y);
        assert_eq!(t.background, Background::Color(Vec3::ONE));
        assert!(t.images.is_empty());
    }
}
