//! Shadow casters: the shapes a shadow ray can be stopped or tinted by, for scenes made
//! mostly of surfaces clear to shadows (clear glass, white transmission: crossing one
//! multiplies the light by one).
//!
//! A shadow ray cannot stop at such a surface, so in the scene's own intersector it
//! walks every node along its segment. Under a clear glass dragon of 100 000 triangles
//! on a floor that is nearly all of a render's time. An intersector over the casters
//! alone (the floor) gives the same answers, since every shape it leaves out is one
//! the shadow query passes by.

use crate::scene::{Scene, Shapes, Surface};

/// The shapes of a scene that are not clear to shadows, and where each sits in the
/// scene.
pub struct Casters {
    shapes: Shapes,
    scene_index: Vec<u32>,
}

impl Casters {
    /// The casters of `scene` (whose materials resolve to `surfaces`), when shapes clear
    /// to shadows outnumber them: then most of a shadow ray's traversal of the scene is
    /// spent among shapes that cannot affect it. `None` otherwise, where the scene's
    /// intersector serves and no second one is built (its memory, at most half the
    /// scene's shapes copied with their tree, stays within the render's estimate, which
    /// counts the scene's tree at the peak of its build).
    pub fn of(scene: &Scene, surfaces: &[Surface]) -> Option<Casters> {
        let clear = |i: usize| surfaces[scene.material_of[i] as usize].is_clear_to_shadows();
        let n = scene.shapes.len();
        let clear_count = (0..n).filter(|&i| clear(i)).count();
        if clear_count == 0 || clear_count <= n - clear_count {
            return None;
        }
        let mut shapes = Shapes::new();
        let mut scene_index = Vec::with_capacity(n - clear_count);
        for i in (0..n).filter(|&i| !clear(i)) {
            shapes.push(scene.shapes.get(i));
            scene_index.push(i as u32);
        }
        Some(Casters {
            shapes,
            scene_index,
        })
    }

    pub fn shapes(&self) -> &Shapes {
        &self.shapes
    }

    /// Entry `k` is the scene's index of caster `k`.
    pub fn scene_index(&self) -> &[u32] {
        &self.scene_index
    }
}
