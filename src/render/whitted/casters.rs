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
    /// intersector serves and no second one is built.
    pub fn of(scene: &Scene, surfaces: &[Surface]) -> Option<Casters> {
        Casters::count(scene, surfaces)?;
        let clear = |i: usize| surfaces[scene.material_of[i] as usize].is_clear_to_shadows();
        let scene_index: Vec<u32> = (0..scene.shapes.len())
            .filter(|&i| !clear(i))
            .map(|i| i as u32)
            .collect();
        Some(Casters {
            shapes: scene.shapes.subset(&scene_index),
            scene_index,
        })
    }

    /// How many casters [`Casters::of`] would gather, or `None` where it gathers none:
    /// what the render's memory estimate counts before anything is built.
    pub fn count(scene: &Scene, surfaces: &[Surface]) -> Option<usize> {
        let n = scene.shapes.len();
        let clear_count = (0..n)
            .filter(|&i| surfaces[scene.material_of[i] as usize].is_clear_to_shadows())
            .count();
        (clear_count > 0 && clear_count > n - clear_count).then_some(n - clear_count)
    }

    /// The casters, in scene order, to build the shadow rays' intersector over.
    pub fn shapes(&self) -> &Shapes {
        &self.shapes
    }

    /// Entry `k` is the scene's index of caster `k`.
    pub fn scene_index(&self) -> &[u32] {
        &self.scene_index
    }
}
