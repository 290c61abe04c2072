//! Lights: the 2014 point light, and the kinds the physically based model adds
//! (SPEC 4.3): directional, spot, and area lights sampled with stratified shadow rays.

use super::{Scene, Shape, ShapeId};
use crate::math::{Vec3, cross};

pub mod sampling;
pub mod stratified;
pub mod tree;

pub use sampling::Incident;
pub use stratified::{LightSample, Strata};

/// A light. The classic model uses only `position` (every light is a white point light
/// there); the whitted model uses everything.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// Where a point or spot light sits; the centre of an area light (its shape is
    /// given relative to it, so moving the position moves the whole light).
    pub position: Vec3,
    /// Linear RGB. For point, spot and directional lights `color * intensity` is the
    /// irradiance a surface facing the light receives (before any falloff); for area
    /// lights it is the emitted radiance.
    pub color: Vec3,
    /// Scalar strength multiplying `color` (for a mesh light, its triangles' emission).
    pub intensity: f32,
    /// The light's geometry: point, directional, spot or one of the area shapes.
    pub kind: LightKind,
    /// Dimming with distance, applied to point and spot lights only.
    pub falloff: Falloff,
    /// Shadow rays per shading point for area lights (stratified, seeded per pixel).
    pub samples: u32,
    /// Whether the light is an object of the scene: seen by camera rays (an area
    /// light's glow) and casting shadows. Lights hidden from the camera are only their
    /// light: they light the scene and show in reflections, as Blender's lights do.
    pub camera_visible: bool,
}

/// The geometry of a light and how it is sampled.
#[derive(Clone, Debug, PartialEq)]
pub enum LightKind {
    /// Emits equally in all directions from `position`.
    Point,
    /// Light arriving from infinitely far along `direction` (the way it travels).
    Directional {
        /// Unit direction the light travels in, world space.
        direction: Vec3,
    },
    /// A point light shining along `direction`, full inside `cos_inner`, fading to
    /// nothing at `cos_outer` along the curve `edge` names.
    Spot {
        /// Unit axis of the cone, world space, pointing away from the light.
        direction: Vec3,
        /// Cosine of the inner cone's half-angle: full strength inside it.
        cos_inner: f32,
        /// Cosine of the outer cone's half-angle: no light outside it.
        cos_outer: f32,
        /// Fade curve between the two cones.
        edge: ConeEdge,
    },
    /// A parallelogram `position + s u + t v`, `s, t` in `[-1/2, 1/2]`, emitting on the
    /// side `u x v` points to.
    Quad {
        /// First full edge vector, world units.
        u: Vec3,
        /// Second full edge vector, world units; `|u x v|` is the light's area.
        v: Vec3,
    },
    /// A disk around `position` facing `normal`, emitting on that side.
    Disk {
        /// Direction the lit side faces (normalised when sampled; `+Y` if zero).
        normal: Vec3,
        /// Radius in world units.
        radius: f32,
    },
    /// A sphere around `position`, emitting outward.
    Sphere {
        /// Radius in world units; shading points are sampled over the cone it subtends.
        radius: f32,
    },
    /// Triangles of the scene (its own, or placed by instances) emitting with their
    /// material's emission: an emissive mesh. `cdf` holds their cumulative areas,
    /// normalised, so samples pick triangles in proportion to area; `area` is the total.
    Mesh {
        /// The emitting triangles, in ascending [`ShapeId::order`] where they are
        /// placed ones (so a hit finds its light by a binary search).
        shapes: Vec<ShapeId>,
        /// Cumulative area of `shapes` over the total, rising to 1.
        cdf: Vec<f32>,
        /// Total area of the triangles, in squared world units.
        area: f32,
    },
}

/// How a point or spot light dims with distance.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Falloff {
    /// No dimming, as in POV-Ray: easy to light a scene of any scale.
    #[default]
    None,
    /// `1 / d^2`: physically right.
    InverseSquare,
    /// `1 / d^2` brought smoothly to zero at `range`: `clamp(1 - (d / range)^4, 0, 1) /
    /// d^2` (glTF's KHR_lights_punctual, after Unreal).
    Range {
        /// Distance in world units at which the light reaches zero.
        range: f32,
    },
}

impl Falloff {
    /// What the light's strength is multiplied by at distance `d`.
    #[inline]
    pub fn at(self, d: f32) -> f32 {
        match self {
            Falloff::None => 1.0,
            Falloff::InverseSquare => 1.0 / (d * d),
            Falloff::Range { range } => {
                let q = d / range;
                let q2 = q * q;
                (1.0 - q2 * q2).clamp(0.0, 1.0) / (d * d)
            }
        }
    }
}

/// How a spot light fades between its inner and outer cone, in `t`, the cosine's place
/// from the outer (0) to the inner cone (1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ConeEdge {
    /// `smoothstep`: `3 t^2 - 2 t^3` (the scene file's spots).
    #[default]
    Smooth,
    /// `t^2` (glTF's KHR_lights_punctual).
    Squared,
    /// `smoothstep` times the cosine from the axis, inside the inner cone too: Blender's
    /// spot lights as Cycles renders them.
    SmoothCosine,
}

/// 0 below `lo`, 1 above `hi`, `3 t^2 - 2 t^3` between; a step at `hi` when the two meet.
#[inline]
fn smoothstep(lo: f32, hi: f32, x: f32) -> f32 {
    if hi <= lo {
        return if x >= hi { 1.0 } else { 0.0 };
    }
    let t = ((x - lo) / (hi - lo)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl ConeEdge {
    /// The strength at cosine `cos` from the axis, between the outer cone's cosine `lo`
    /// and the inner one's `hi`.
    #[inline]
    pub fn at(self, lo: f32, hi: f32, cos: f32) -> f32 {
        match self {
            ConeEdge::Smooth => smoothstep(lo, hi, cos),
            ConeEdge::SmoothCosine => smoothstep(lo, hi, cos) * cos.max(0.0),
            // KHR_lights_punctual's `saturate(cd * scale + offset)^2`, its scale bounded
            // where the cones meet.
            ConeEdge::Squared => {
                let scale = 1.0 / (hi - lo).max(1e-3);
                let t = ((cos - lo) * scale).clamp(0.0, 1.0);
                t * t
            }
        }
    }
}

impl Light {
    /// An emissive-mesh light over the triangles `shapes` of `scene`, in world space
    /// (shapes that are not triangles of it, or have no area, are skipped), or `None`
    /// when they have no area. The scene's own shapes keep the order given; placed
    /// ones follow them in ascending [`ShapeId::order`].
    pub fn mesh(scene: &Scene, shapes: impl IntoIterator<Item = ShapeId>) -> Option<Light> {
        let mut shapes: Vec<ShapeId> = shapes.into_iter().collect();
        let key = |id: &ShapeId| if id.is_world() { 0 } else { id.order() };
        if !shapes.is_sorted_by_key(key) {
            shapes.sort_by_key(key);
        }
        let mut kept = Vec::with_capacity(shapes.len());
        let mut cdf = Vec::with_capacity(shapes.len());
        let mut total = 0.0f64;
        for i in shapes {
            if let Some(Shape::Triangle(t)) = scene.try_shape_at(i) {
                let [a, b, c] = t.v;
                let area = 0.5 * f64::from(cross(b - a, c - a).length());
                if area > 0.0 && area.is_finite() {
                    total += area;
                    kept.push(i);
                    cdf.push(total);
                }
            }
        }
        if kept.is_empty() || !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let cdf = cdf.iter().map(|&c| (c / total) as f32).collect();
        Some(Light {
            kind: LightKind::Mesh {
                shapes: kept,
                cdf,
                area: total as f32,
            },
            ..Light::point(Vec3::ZERO, Vec3::ONE)
        })
    }

    /// Whether `shape` is one of the triangles of this emissive mesh (false for the
    /// other kinds). A placed shape is found by binary search, the scene's own by a
    /// scan: callers keep a table for those.
    pub fn emits_from(&self, shape: ShapeId) -> bool {
        let LightKind::Mesh { shapes, .. } = &self.kind else {
            return false;
        };
        if shape.is_world() {
            return shapes.contains(&shape);
        }
        let placed = &shapes[shapes.partition_point(|s| s.is_world())..];
        placed
            .binary_search_by_key(&shape.order(), |s| s.order())
            .is_ok()
    }

    /// A white point light of intensity 1 (the 2014 format's lights).
    pub fn point(position: Vec3, color: Vec3) -> Light {
        Light {
            position,
            color,
            intensity: 1.0,
            kind: LightKind::Point,
            falloff: Falloff::None,
            samples: 1,
            camera_visible: true,
        }
    }

    /// Whether the light has an extent, so its shadows are soft and it is sampled.
    pub fn is_area(&self) -> bool {
        matches!(
            self.kind,
            LightKind::Quad { .. }
                | LightKind::Disk { .. }
                | LightKind::Sphere { .. }
                | LightKind::Mesh { .. }
        )
    }

    /// The name of the light's kind, as the scene file and `prism info` spell it.
    pub fn kind_name(&self) -> &'static str {
        match self.kind {
            LightKind::Point => "point",
            LightKind::Directional { .. } => "directional",
            LightKind::Spot { .. } => "spot",
            LightKind::Quad { .. } => "quad",
            LightKind::Disk { .. } => "disk",
            LightKind::Sphere { .. } => "sphere",
            LightKind::Mesh { .. } => "mesh",
        }
    }
}
