//! glTF cameras and KHR_lights_punctual lights, placed by their nodes' world
//! transforms. Both look down their node's -z with +y up.

use crate::math::Vec3;
use crate::scene::framing::DEFAULT_SIZE;
use crate::scene::{Camera, ConeEdge, Falloff, Light, LightKind, Projection};
use glam::{DMat4, DVec3};

fn f(v: DVec3) -> Vec3 {
    Vec3::new(v.x as f32, v.y as f32, v.z as f32)
}

/// Where a node at `world` sits and the unit directions of its -z (forward) and +y.
fn frame(world: &DMat4) -> (Vec3, Vec3, Vec3) {
    let eye = world.transform_point3(DVec3::ZERO);
    let forward = world.transform_vector3(DVec3::NEG_Z).normalize_or_zero();
    let up = world.transform_vector3(DVec3::Y).normalize_or_zero();
    (f(eye), f(forward), f(up))
}

/// The output size a camera of aspect `aspect` (width / height) renders at unless told:
/// the default width, the height following the aspect.
fn size_for(aspect: f64) -> (u32, u32) {
    let (w, _) = DEFAULT_SIZE;
    let h = (f64::from(w) / aspect)
        .round()
        .clamp(1.0, f64::from(crate::util::limits::MAX_SIDE));
    (w, h as u32)
}

/// A camera node's camera, or why it cannot be one.
pub fn camera(c: &gltf::Camera, world: &DMat4) -> Result<Camera, String> {
    let (eye, forward, up) = frame(world);
    if forward == Vec3::ZERO || up == Vec3::ZERO || !eye.is_finite() {
        return Err("its node's transform is degenerate".into());
    }
    match c.projection() {
        gltf::camera::Projection::Perspective(p) => {
            let yfov = f64::from(p.yfov());
            if !(yfov > 0.0 && yfov < std::f64::consts::PI) {
                return Err(format!("yfov {yfov} is not between 0 and pi"));
            }
            let (dw, dh) = DEFAULT_SIZE;
            let aspect = match p.aspect_ratio() {
                Some(a) if a > 0.0 && a.is_finite() => f64::from(a),
                Some(a) => return Err(format!("aspectRatio {a} is not positive")),
                None => f64::from(dw) / f64::from(dh),
            };
            let (w, h) = size_for(aspect);
            let half_h = (yfov / 2.0).tan();
            let mut camera = Camera::look_at(eye, eye + forward, up, 60.0, w, h);
            // The vertical field of view is the file's, exactly.
            camera.retina_scale = (half_h / f64::from(h)) as f32;
            Ok(camera)
        }
        gltf::camera::Projection::Orthographic(o) => {
            let (xmag, ymag) = (f64::from(o.xmag()), f64::from(o.ymag()));
            if !(xmag > 0.0 && ymag > 0.0 && xmag.is_finite() && ymag.is_finite()) {
                return Err(format!("xmag {xmag} and ymag {ymag} must be positive"));
            }
            let (w, h) = size_for(xmag / ymag);
            let mut camera = Camera::look_at(eye, eye + forward, up, 60.0, w, h);
            camera.retina_scale = (xmag / f64::from(w)) as f32;
            camera.projection = Projection::Orthographic;
            Ok(camera)
        }
    }
}

/// A KHR_lights_punctual light placed at `world`: candela for point and spot lights,
/// lux for directional ones, as the extension states them.
pub fn light(l: &gltf::khr_lights_punctual::Light, world: &DMat4) -> Result<Light, String> {
    let (position, forward, _) = frame(world);
    let color = Vec3::from_array(l.color()).max(Vec3::ZERO);
    let intensity = l.intensity();
    if !(intensity >= 0.0 && intensity.is_finite() && color.is_finite()) {
        return Err(format!("intensity {intensity} is not a finite number >= 0"));
    }
    if !position.is_finite() {
        return Err("its node's position is not finite".into());
    }
    let falloff = match l.range() {
        Some(r) if r > 0.0 && r.is_finite() => Falloff::Range { range: r },
        Some(r) if r > 0.0 => Falloff::InverseSquare,
        Some(r) => return Err(format!("range {r} is not positive")),
        None => Falloff::InverseSquare,
    };
    let directed = || {
        if forward == Vec3::ZERO {
            Err("its node's transform is degenerate".to_string())
        } else {
            Ok(forward)
        }
    };
    let (kind, falloff) = match l.kind() {
        gltf::khr_lights_punctual::Kind::Point => (LightKind::Point, falloff),
        gltf::khr_lights_punctual::Kind::Directional => (
            LightKind::Directional {
                direction: directed()?,
            },
            Falloff::None,
        ),
        gltf::khr_lights_punctual::Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => {
            let half_pi = std::f32::consts::FRAC_PI_2;
            if !(0.0..half_pi + 1e-6).contains(&outer_cone_angle)
                || !(0.0..=outer_cone_angle).contains(&inner_cone_angle)
            {
                return Err(format!(
                    "spot cone angles {inner_cone_angle} and {outer_cone_angle}: expected 0 <= \
                     inner <= outer <= pi/2"
                ));
            }
            (
                LightKind::Spot {
                    direction: directed()?,
                    cos_inner: inner_cone_angle.cos(),
                    cos_outer: outer_cone_angle.cos(),
                    edge: ConeEdge::Squared,
                },
                falloff,
            )
        }
    };
    Ok(Light {
        position,
        color,
        intensity,
        kind,
        falloff,
        samples: 1,
        camera_visible: true,
    })
}
