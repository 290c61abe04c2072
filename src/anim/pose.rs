//! The scene and camera at one instant: the tracks applied, in file order, to the scene
//! and camera the animation starts from.
//!
//! Objects move rigidly. Each shape and light accumulates one transform in f64 and is
//! moved once from its starting place, so long animations do not drift. A sphere's
//! centre moves and its radius stays; its texture does not turn with it (the 2014 sphere
//! mapping is fixed to the world axes). Shapes and lights no track touches are left
//! bit for bit as they were.
//!
//! The 2014 camera has a view direction (θ, φ) and no roll: its image-right vector is
//! always horizontal. Turning a camera turns its view direction; where the direction
//! ends up vertical, φ keeps its last value.

use super::motion::{Aim, Motion, Selection, Target, Track, rotation_about};
use crate::math::Vec3;
use crate::scene::{Camera, Instance, Rectangle, Scene, Shape, Sphere, Triangle};
use glam::{DAffine3, DVec3};
use std::collections::HashMap;

/// Why a pose cannot be rendered, and which track caused it.
#[derive(Clone, Debug, PartialEq)]
pub struct PoseError {
    /// Line of the offending track's `[[track]]` header in the animation file.
    pub line: usize,
    /// What went wrong, and at what time.
    pub message: String,
}

/// Closer than this (relative to the coordinates' size, and at least 1e-9) the eye is
/// on its look-at point and has no view direction.
const DEGENERATE: f64 = 1e-9;

/// The camera alone at time `t`: cheap, for checking every frame before rendering.
/// Only the tracks up to the last camera track matter; objects they move cost in
/// proportion to their size, never the scene's.
pub fn pose_camera(
    scene: &Scene,
    camera: &Camera,
    tracks: &[Track],
    t: f64,
) -> Result<Camera, PoseError> {
    let last = tracks.iter().rposition(|t| t.target == Target::Camera);
    let mut state = State::new(scene, camera);
    state.apply(&tracks[..last.map_or(0, |i| i + 1)], t)?;
    Ok(state.camera())
}

/// The scene and camera at time `t` (seconds).
pub fn pose(
    scene: &Scene,
    camera: &Camera,
    tracks: &[Track],
    t: f64,
) -> Result<(Scene, Camera), PoseError> {
    let mut posed = scene.clone();
    let camera = pose_into(scene, camera, tracks, t, &mut posed)?;
    Ok((posed, camera))
}

/// Poses `posed`, a copy of `scene` that earlier calls with the same tracks may have
/// posed at other times, at time `t`, and returns the camera. Only the shapes and
/// lights the tracks move are written (the same ones at every instant), so the cost
/// is in proportion to them, not to the scene, and textures are never copied.
pub fn pose_into(
    scene: &Scene,
    camera: &Camera,
    tracks: &[Track],
    t: f64,
    posed: &mut Scene,
) -> Result<Camera, PoseError> {
    let mut state = State::new(scene, camera);
    state.apply(tracks, t)?;
    state.write_scene(posed);
    Ok(state.camera())
}

/// Transforms accumulated so far, and the camera being moved.
struct State<'s> {
    base: &'s Scene,
    base_camera: &'s Camera,
    /// Transform of each shape and light a track has moved, by index: as many entries
    /// as moved shapes, whatever the scene's size.
    shapes: HashMap<u32, DAffine3>,
    lights: HashMap<u32, DAffine3>,
    instances: HashMap<u32, DAffine3>,
    eye: DVec3,
    /// Unit view direction; `None` while no track has turned it.
    forward: Option<DVec3>,
    focal_length: Option<f64>,
}

/// A number for a message: at most three decimals, no trailing zeros.
fn short(x: f64) -> String {
    let s = format!("{x:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

fn dvec(v: Vec3) -> DVec3 {
    DVec3::new(v.x as f64, v.y as f64, v.z as f64)
}

fn fvec(v: DVec3) -> Vec3 {
    Vec3::new(v.x as f32, v.y as f32, v.z as f32)
}

impl<'s> State<'s> {
    fn new(base: &'s Scene, base_camera: &'s Camera) -> State<'s> {
        State {
            base,
            base_camera,
            shapes: HashMap::new(),
            lights: HashMap::new(),
            instances: HashMap::new(),
            eye: dvec(base_camera.eye),
            forward: None,
            focal_length: None,
        }
    }

    fn apply(&mut self, tracks: &[Track], t: f64) -> Result<(), PoseError> {
        for track in tracks {
            self.apply_one(track, t)?;
        }
        Ok(())
    }

    fn view(&self) -> DVec3 {
        self.forward
            .unwrap_or_else(|| dvec(self.base_camera.frame().forward))
    }

    fn apply_one(&mut self, track: &Track, t: f64) -> Result<(), PoseError> {
        let error = |message: String| PoseError {
            line: track.line,
            message,
        };
        match (&track.target, &track.motion) {
            (Target::Camera, Motion::Translate(offset)) => self.eye += offset.at(t),
            (
                Target::Camera,
                Motion::Rotate {
                    axis,
                    center,
                    angle,
                },
            ) => {
                let r = rotation_about(*axis, *center, angle.at(t));
                self.eye = r.transform_point3(self.eye);
                self.forward = Some(r.transform_vector3(self.view()).normalize());
            }
            (
                Target::Camera,
                Motion::Orbit {
                    axis,
                    center,
                    angle,
                },
            ) => {
                let r = rotation_about(*axis, *center, angle.at(t));
                self.eye = r.transform_point3(self.eye);
            }
            (Target::Camera, Motion::LookAt { aim, focus }) => {
                let point = match aim {
                    Aim::Point(p) => *p,
                    Aim::Objects(s) => self.center_of(s),
                };
                let to = point - self.eye;
                let scale = self.eye.abs().max_element().max(point.abs().max_element());
                if to.length() <= DEGENERATE * scale.max(1.0) || !to.is_finite() {
                    return Err(error(format!(
                        "at {} s the camera's eye ({}, {}, {}) is on the point it looks at: \
                         it has no view direction",
                        short(t),
                        short(self.eye.x),
                        short(self.eye.y),
                        short(self.eye.z)
                    )));
                }
                self.forward = Some(to.normalize());
                if *focus {
                    self.focal_length = Some(to.length());
                }
            }
            (Target::Objects(s), Motion::Translate(offset)) => {
                self.transform(s, DAffine3::from_translation(offset.at(t)))
            }
            (
                Target::Objects(s),
                Motion::Rotate {
                    axis,
                    center,
                    angle,
                },
            ) => self.transform(s, rotation_about(*axis, *center, angle.at(t))),
            (
                Target::Objects(s),
                Motion::Orbit {
                    axis,
                    center,
                    angle,
                },
            ) => {
                let c = self.center_of(s);
                let moved = rotation_about(*axis, *center, angle.at(t)).transform_point3(c);
                self.transform(s, DAffine3::from_translation(moved - c));
            }
            (Target::Objects(_), Motion::LookAt { .. }) => {
                return Err(error("only the camera can look at something".into()));
            }
        }
        Ok(())
    }

    fn transform(&mut self, s: &Selection, by: DAffine3) {
        for &i in &s.shapes {
            let x = self.shapes.entry(i).or_insert(DAffine3::IDENTITY);
            *x = by * *x;
        }
        for &i in &s.lights {
            let x = self.lights.entry(i).or_insert(DAffine3::IDENTITY);
            *x = by * *x;
        }
        for &i in &s.instances {
            let x = self.instances.entry(i).or_insert(DAffine3::IDENTITY);
            *x = by * *x;
        }
    }

    fn shape_transform(&self, i: u32) -> DAffine3 {
        self.shapes.get(&i).copied().unwrap_or(DAffine3::IDENTITY)
    }

    /// Centre of the bounding box of the selection where it is now.
    fn center_of(&self, s: &Selection) -> DVec3 {
        let mut min = DVec3::splat(f64::INFINITY);
        let mut max = DVec3::splat(f64::NEG_INFINITY);
        let mut grow = |p: DVec3, r: f64| {
            min = min.min(p - r);
            max = max.max(p + r);
        };
        for &i in &s.shapes {
            let x = self.shape_transform(i);
            match &self.base.shapes.get(i as usize) {
                Shape::Sphere(sp) => grow(x.transform_point3(dvec(sp.center)), sp.radius as f64),
                Shape::Triangle(tr) => {
                    tr.v.iter()
                        .for_each(|&p| grow(x.transform_point3(dvec(p)), 0.0))
                }
                Shape::Rectangle(re) => {
                    re.v.iter()
                        .for_each(|&p| grow(x.transform_point3(dvec(p)), 0.0))
                }
            }
        }
        for &i in &s.lights {
            let x = self.lights.get(&i).copied().unwrap_or(DAffine3::IDENTITY);
            grow(
                x.transform_point3(dvec(self.base.lights[i as usize].position)),
                0.0,
            );
        }
        for &i in &s.instances {
            let x = self
                .instances
                .get(&i)
                .copied()
                .unwrap_or(DAffine3::IDENTITY);
            let base = &self.base.instances[i as usize];
            let b = base.world_bounds(&self.base.objects[base.object() as usize].bounds());
            if !b.is_empty() {
                for corner in [b.min, b.max] {
                    grow(x.transform_point3(dvec(corner)), 0.0);
                }
            }
        }
        (min + max) / 2.0
    }

    /// Writes the moved shapes and lights into `posed`, a copy of the base scene, each
    /// moved from its place in the base scene.
    fn write_scene(&self, posed: &mut Scene) {
        let moved = |x: &DAffine3, p: Vec3| fvec(x.transform_point3(dvec(p)));
        if !self.shapes.is_empty() {
            // Moved triangles get positions of their own (their corners may be shared
            // with shapes that stay): start again from the base scene's each frame.
            posed.shapes.clone_from(&self.base.shapes);
        }
        for (&i, x) in &self.shapes {
            let i = i as usize;
            let placed = match self.base.shapes.get(i) {
                Shape::Sphere(s) => Shape::Sphere(Sphere {
                    center: moved(x, s.center),
                    radius: s.radius,
                }),
                Shape::Triangle(tr) => Shape::Triangle(Triangle {
                    v: tr.v.map(|p| moved(x, p)),
                }),
                Shape::Rectangle(re) => Shape::Rectangle(Rectangle {
                    v: re.v.map(|p| moved(x, p)),
                }),
            };
            posed.shapes.set(i, placed);
        }
        for (&i, x) in &self.lights {
            let i = i as usize;
            posed.lights[i].position = moved(x, self.base.lights[i].position);
        }
        for (&i, x) in &self.instances {
            let base = &self.base.instances[i as usize];
            let to_world = glam::DMat4::from(*x) * glam::DMat4::from(base.to_world().as_daffine3());
            posed.instances[i as usize] =
                Instance::new(base.object(), glam::Affine3A::from_mat4(to_world.as_mat4()));
        }
    }

    fn camera(&self) -> Camera {
        let mut camera = self.base_camera.clone();
        camera.eye = fvec(self.eye);
        if let Some(f) = self.forward {
            camera.theta_deg = f.z.clamp(-1.0, 1.0).acos().to_degrees() as f32;
            if f.x.hypot(f.y) > 1e-12 {
                camera.phi_deg = f.y.atan2(f.x).to_degrees() as f32;
            }
        }
        if let Some(f) = self.focal_length {
            camera.focal_length = f as f32;
        }
        camera
    }
}
