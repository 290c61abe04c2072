//! The path model's one light a vertex drawn from the light tree
//! ([`crate::scene::light::tree`]): the vertex's light sample over the odds of the
//! draw, and those odds for a light the BSDF's own sample meets.

use super::{Bsdf, Path, Weighing};
use crate::math::Vec3;
use crate::render::{PixelSampler, RayCount};
use crate::scene::light::tree::{LightTree, Picked};

impl Path<'_> {
    /// The odds that a vertex at `p` (normal `n`) draws light `k` to sample: 1 where
    /// every light is sampled.
    #[inline]
    pub(super) fn light_pmf(&self, p: Vec3, n: Vec3, k: u32) -> f32 {
        self.tree.as_ref().map_or(1.0, |tree| tree.pmf(p, n, k))
    }

    /// The odds that a vertex draws the environment to sample: 1 where every light is.
    #[inline]
    pub(super) fn environment_pmf(&self) -> f32 {
        self.tree.as_ref().map_or(1.0, LightTree::environment_pmf)
    }

    /// Light arriving at `p` (geometric normal `ng` on the path's side, shadow rays
    /// leaving from `from`) from one light the tree draws, sampled once, over the odds
    /// of the draw, and from each light beside the tree where those are few; weighed
    /// against the BSDF's own samples by `weighing`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn direct_from_tree(
        &self,
        (tree, weighing): (&LightTree, Weighing),
        bsdf: &Bsdf,
        p: Vec3,
        from: Vec3,
        ng: Vec3,
        sampler: &mut PixelSampler,
        count: &mut RayCount,
    ) -> Vec3 {
        // A light's (or the environment's) sample drawn with odds `pmf`: what it adds
        // unshadowed, its direction and distance.
        let sample = |picked: Picked, pmf: f32, u: (f32, f32)| match picked {
            Picked::Light(k) => {
                let inc = self.sample_incident(k as usize, p, u)?;
                let c = self.unshadowed(bsdf, weighing, inc.dir, inc.li, inc.pdf, pmf);
                Some((c, inc.dir, inc.dist))
            }
            Picked::Environment => {
                let (dir, le, pdf) = self.environment.as_ref()?.sample(self.scene, u)?;
                let c = self.unshadowed(bsdf, weighing, dir, le, pdf, pmf);
                Some((c, dir, f32::INFINITY))
            }
        };
        let mut l = Vec3::ZERO;
        if tree.samples_apart_each() {
            let apart = tree.apart().iter().map(|&k| Picked::Light(k));
            let sky = self.environment.is_some().then_some(Picked::Environment);
            for picked in apart.chain(sky) {
                if let Some((c, dir, dist)) = sample(picked, 1.0, sampler.next_2d()) {
                    l += self.shadowed(c, from, ng, dir, dist, count);
                }
            }
        }
        let pick = sampler.next_f32();
        let u = sampler.next_2d();
        if let Some((picked, pmf)) = tree.sample(p, ng, pick)
            && let Some((c, dir, dist)) = sample(picked, pmf, u)
        {
            l += self.shadowed(c, from, ng, dir, dist, count);
        }
        l
    }
}
