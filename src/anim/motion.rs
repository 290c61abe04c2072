//! What a track moves (its target) and how (its motion), and the rigid transform a motion
//! amounts to at a given time.

use super::curve::Curve;
use glam::{DAffine3, DVec3};

/// Shapes and lights that move as one: what a target named in the animation file picked.
#[derive(Clone, Debug, PartialEq)]
pub struct Selection {
    /// Indices into the scene's shapes, ascending.
    pub shapes: Vec<u32>,
    /// Indices into the scene's lights, ascending.
    pub lights: Vec<u32>,
    /// Indices into the scene's instances, ascending.
    pub instances: Vec<u32>,
}

/// What a track moves.
#[derive(Clone, Debug, PartialEq)]
pub enum Target {
    /// The camera: its eye, view direction and (with `focus`) focal length.
    Camera,
    /// Shapes and lights, moved rigidly together.
    Objects(Selection),
}

/// Where a camera looks.
#[derive(Clone, Debug, PartialEq)]
pub enum Aim {
    /// A fixed point in world space.
    Point(DVec3),
    /// The centre of the selection's bounding box, wherever earlier tracks have put it.
    Objects(Selection),
}

/// How a track moves its target. Angles are in degrees, right-hand rule about the axis;
/// axes are unit vectors.
#[derive(Clone, Debug, PartialEq)]
pub enum Motion {
    /// Move by an offset.
    Translate(Curve<DVec3>),
    /// Turn rigidly about the axis through `center` (a camera's view turns with it).
    Rotate {
        /// Unit axis direction, world space.
        axis: DVec3,
        /// A point the axis passes through, world space.
        center: DVec3,
        /// Angle turned from the starting pose, in degrees, over time.
        angle: Curve<f64>,
    },
    /// Carry the target round the axis through `center`, keeping its orientation: it
    /// only moves (every point by the offset of the target's centre; a camera keeps its
    /// view direction). An orbit with `keep_orientation = false` in the file is a
    /// [`Motion::Rotate`].
    Orbit {
        /// Unit axis direction, world space.
        axis: DVec3,
        /// A point the axis passes through, world space.
        center: DVec3,
        /// Angle carried round from the starting pose, in degrees, over time.
        angle: Curve<f64>,
    },
    /// The camera turns to look at a point or at objects; with `focus`, the focal
    /// length becomes the distance from the eye to that point (the convention of the
    /// 2014 `scene.cmr`, whose focal length is its eye's distance to the glass sphere).
    LookAt {
        /// What the camera turns to.
        aim: Aim,
        /// Whether the focal length follows the distance to the aim point.
        focus: bool,
    },
}

/// One track of the animation file.
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    /// What the track moves.
    pub target: Target,
    /// How it moves it, as a function of time in seconds.
    pub motion: Motion,
    /// Line of the track's `[[track]]` header, for errors.
    pub line: usize,
}

/// Turn by `degrees` about the axis through `center`.
pub fn rotation_about(axis: DVec3, center: DVec3, degrees: f64) -> DAffine3 {
    DAffine3::from_translation(center)
        * DAffine3::from_axis_angle(axis, degrees.to_radians())
        * DAffine3::from_translation(-center)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_about_an_axis_through_a_point() {
        let r = rotation_about(DVec3::Z, DVec3::new(1.0, 0.0, 0.0), 90.0);
        let p = r.transform_point3(DVec3::new(2.0, 0.0, 5.0));
        assert!((p - DVec3::new(1.0, 1.0, 5.0)).length() < 1e-12, "{p}");
        // The centre stays put.
        let c = r.transform_point3(DVec3::new(1.0, 0.0, -3.0));
        assert!((c - DVec3::new(1.0, 0.0, -3.0)).length() < 1e-12);
    }
}
