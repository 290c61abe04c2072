//! glTF's metallic-roughness terms at one hit (`Surface::metallic_roughness`, the
//! formulas in docs/formats.md): the factors times their map, the reflectance at
//! normal incidence, the highlight's exponent and Schlick's mirror weight.

use crate::math::Vec3;
use crate::scene::{MetallicRoughness, Scene, SurfacePoint};

/// A metallic-roughness surface at one hit.
pub(crate) struct PbrAt {
    pub metallic: f32,
    /// Perceptual roughness, 0 (mirror) to 1: the microfacet `alpha` is its square.
    pub roughness: f32,
    base_f0: Vec3,
    /// How much of the mirror reflection a rough surface keeps.
    gloss: f32,
}

impl PbrAt {
    /// The terms of `mr` at the hit `sp`: its factors times its map (green: roughness,
    /// blue: metallic).
    pub fn at(scene: &Scene, mr: &MetallicRoughness, sp: &SurfacePoint) -> PbrAt {
        let (metallic, roughness) = match &mr.map {
            Some(slot) => {
                let c = scene.images[slot.image as usize].sample_slot(slot, sp.uv);
                (mr.metallic * c.z, mr.roughness * c.y)
            }
            None => (mr.metallic, mr.roughness),
        };
        let metallic = metallic.clamp(0.0, 1.0);
        let roughness = roughness.clamp(0.0, 1.0);
        PbrAt {
            metallic,
            roughness,
            base_f0: mr.f0,
            gloss: (1.0 - roughness) * (1.0 - roughness),
        }
    }

    /// Reflectance at normal incidence: the dielectric's, or the metal's colour.
    pub fn f0(&self, albedo: Vec3) -> Vec3 {
        self.base_f0.lerp(albedo, self.metallic)
    }

    /// The mirror reflection's weight at incidence cosine `cos`: Schlick's Fresnel.
    pub fn mirror(&self, albedo: Vec3, cos: f32) -> Vec3 {
        let f0 = self.f0(albedo);
        let m = 1.0 - cos;
        let m5 = (m * m) * (m * m) * m;
        (f0 + (Vec3::ONE - f0) * m5) * self.gloss
    }
}
