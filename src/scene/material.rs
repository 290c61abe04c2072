//! Surface materials of the 2014 format (report section 5.2.2).

use crate::math::Vec3;

#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    /// Base colour, 0..1 per channel (the file gives 0..255). Ignored under a texture.
    pub color: Vec3,
    pub ambient: f32,
    pub diffuse: f32,
    pub specular: f32,
    pub shininess: f32,
    /// Refractive index of the medium inside the surface.
    pub ior: f32,
    /// Intensity factor of the mirror child ray.
    pub reflect: f32,
    /// Intensity factor of the refracted child ray.
    pub refract: f32,
    /// Transparent surfaces cast no shadows.
    pub transparent: bool,
    /// Index into `Scene::textures`.
    pub texture: Option<u32>,
}

impl Material {
    /// A plain matte white, for shapes that name no material.
    pub fn default_white() -> Material {
        Material {
            name: "default".into(),
            color: Vec3::ONE,
            ambient: 1.0,
            diffuse: 1.0,
            specular: 0.0,
            shininess: 1.0,
            ior: 1.0,
            reflect: 0.0,
            refract: 0.0,
            transparent: false,
            texture: None,
        }
    }
}
