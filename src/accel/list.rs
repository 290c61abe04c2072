//! Brute force: every shape for every ray. Slow, obviously right: the reference the other
//! intersectors are tested against.

use super::Hit;
use crate::math::Ray;
use crate::scene::Shapes;

/// The brute-force intersector over a scene's shapes: no structure, nothing to build.
pub struct ListAccel<'s> {
    shapes: &'s Shapes,
}

impl<'s> ListAccel<'s> {
    /// An intersector over `shapes`, borrowed as is.
    pub fn new(shapes: &'s Shapes) -> ListAccel<'s> {
        ListAccel { shapes }
    }

    /// Number of shapes tested per ray.
    pub fn shape_count(&self) -> usize {
        self.shapes.len()
    }

    /// The nearest hit with `0 < t < t_max`, ties going to the lower shape index.
    pub fn closest(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        for (i, s) in self.shapes.iter().enumerate() {
            let shape = i as u32;
            if let Some(t) = s.intersect(ray, Hit::bound(&best, t_max))
                && Hit::beats(t, shape, &best)
            {
                best = Some(Hit::world(t, shape));
            }
        }
        best
    }

    /// Whether a shape for which `blocks(shape)` holds is hit with `0 < t < t_max`.
    pub fn occluded(&self, ray: &Ray, t_max: f32, blocks: impl Fn(u32) -> bool) -> bool {
        self.shapes
            .iter()
            .enumerate()
            .any(|(i, s)| blocks(i as u32) && s.intersect(ray, t_max).is_some())
    }
}
