//! The scene model: plain data, no I/O and no rendering.

pub mod camera;
pub mod material;
pub mod shape;
pub mod texture;

pub use camera::{Camera, Frame};
pub use material::Material;
pub use shape::{Rectangle, Shape, Sphere, SurfaceCoords, Triangle};
pub use texture::{FillMode, Texture};

use crate::math::{Aabb, Vec3};

/// A point light. Its colour is ignored by the classic shading model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    pub position: Vec3,
    pub color: Vec3,
}

/// Everything that can be seen. `shapes[i]` wears `materials[material_of[i]]`; the two
/// arrays are parallel so the intersection loop touches geometry only.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    pub shapes: Vec<Shape>,
    pub material_of: Vec<u32>,
    pub materials: Vec<Material>,
    pub textures: Vec<Texture>,
    pub lights: Vec<Light>,
}

impl Scene {
    pub fn push_shape(&mut self, shape: Shape, material: u32) {
        self.shapes.push(shape);
        self.material_of.push(material);
    }

    pub fn material(&self, shape: u32) -> &Material {
        &self.materials[self.material_of[shape as usize] as usize]
    }

    pub fn bounds(&self) -> Aabb {
        self.shapes
            .iter()
            .fold(Aabb::EMPTY, |b, s| b.union(s.bounds()))
    }

    /// Surface colour at `p` on shape `shape`: its texel, or the material colour where
    /// there is no texture (or a fit-mode image leaves the surface bare).
    pub fn surface_color(&self, shape: u32, p: Vec3) -> Vec3 {
        let m = self.material(shape);
        m.texture
            .and_then(|t| {
                let coords = self.shapes[shape as usize].surface_coords(p);
                self.textures[t as usize].lookup(&coords)
            })
            .unwrap_or(m.color)
    }
}
