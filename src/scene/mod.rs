//! The scene model: plain data, no I/O and no rendering.

pub mod builder;
pub mod camera;
pub mod framing;
pub mod image;
pub mod instance;
pub mod light;
pub mod material;
pub mod mesh;
pub mod openpbr;
mod shading;
pub mod shape;
pub mod shapes;
pub mod studio;
mod surface_point;
pub mod texture;

pub use builder::{MeshMaterials, Placement, SceneBuilder};
pub use camera::{Camera, Frame, Projection};
pub use image::{ImageTexture, Texels};
pub use instance::{Instance, NO_INSTANCE, Object, ShapeId};
pub use light::{ConeEdge, Falloff, Light, LightKind};
pub use material::{Albedo, Highlight, Material, Surface, TextureSlot};
pub use mesh::MeshAttributes;
pub use openpbr::OpenPbr;
pub use shape::{Rectangle, Shape, Sphere, SurfaceCoords, Triangle};
pub use shapes::{Shapes, Stored};
pub use surface_point::SurfacePoint;
pub use texture::{FillMode, Texture};

use crate::math::Vec3;

/// A named set of shapes and lights (`g NAME` / `o NAME` in a scene file): what an
/// animation track can move as one.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Group {
    /// The file's name for it: what [`Scene::group`] and animation tracks look up.
    pub name: String,
    /// Indices into [`Scene::shapes`], ascending.
    pub shapes: Vec<u32>,
    /// Indices into [`Scene::lights`], ascending.
    pub lights: Vec<u32>,
    /// Indices into [`Scene::instances`], ascending.
    pub instances: Vec<u32>,
}

/// What a ray that hits nothing sees (the whitted model; classic rays see black).
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Background {
    /// Zero radiance.
    #[default]
    Black,
    /// The same linear RGB radiance in every direction.
    Color(Vec3),
    /// An equirectangular image (`Scene::images[image]`) whose top row looks along `up`
    /// and whose centre looks along `forward`, scaled by `intensity`.
    Environment {
        /// Index into [`Scene::images`].
        image: u32,
        /// Unit world-space direction the image's top row looks along.
        up: Vec3,
        /// Unit world-space direction of the image's centre, perpendicular to `up`.
        forward: Vec3,
        /// Factor on the image's linear radiance.
        intensity: f32,
    },
}

pub use crate::util::limits::MAX_SHAPES;

/// Everything that can be seen. `shapes[i]` wears `materials[material_of[i]]`; the two
/// arrays are parallel so the intersection loop touches geometry only.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// Every triangle, sphere and rectangle, in world space; a shape is its index here.
    pub shapes: Shapes,
    /// Index into `materials` of the material each shape wears, parallel to `shapes`.
    pub material_of: Vec<u32>,
    /// The classic (2014) terms of every material; shapes refer to them by index.
    pub materials: Vec<Material>,
    /// The 2014 textures, read with the 2014 mappings.
    pub textures: Vec<Texture>,
    /// Every light, area lights from emissive materials included.
    pub lights: Vec<Light>,
    /// Named groups, in order of first appearance; rendering ignores them.
    pub groups: Vec<Group>,
    /// The whitted terms of `materials[i]`; materials past its end (all of them, for
    /// the 2014 files) get [`Surface::from_classic`].
    pub surfaces: Vec<Surface>,
    /// Per-vertex normals, texture coordinates and colours of triangle meshes, in
    /// ascending order of `first_shape`; shapes outside every mesh have none.
    pub meshes: Vec<MeshAttributes>,
    /// Images read at texture coordinates (whitted materials, environment maps).
    pub images: Vec<ImageTexture>,
    /// La: the ambient light the whitted model multiplies by each surface's Ka.
    pub ambient: Vec3,
    /// What rays that escape the scene see (whitted model only).
    pub background: Background,
    /// Meshes placed by instances, each held once in its own space.
    pub objects: Vec<Object>,
    /// Placements of `objects`: their triangles are shapes of the scene too, named by
    /// [`ShapeId`]s.
    pub instances: Vec<Instance>,
}

impl Scene {
    /// Appends `shape` wearing `materials[material]`, keeping the two arrays parallel.
    pub fn push_shape(&mut self, shape: Shape, material: u32) {
        self.shapes.push(shape);
        self.material_of.push(material);
    }

    /// The classic material shape `shape` wears.
    pub fn material(&self, shape: u32) -> &Material {
        &self.materials[self.material_of[shape as usize] as usize]
    }

    /// The mesh that owns shape `shape`, with the shape's triangle number in it.
    #[inline]
    pub fn mesh_of(&self, shape: u32) -> Option<(&MeshAttributes, usize)> {
        mesh::owning(&self.meshes, shape)
    }

    /// The whitted terms of every material, derived from the classic terms where the
    /// scene gives none.
    pub fn resolved_surfaces(&self) -> Vec<Surface> {
        self.materials
            .iter()
            .enumerate()
            .map(|(i, m)| {
                self.surfaces
                    .get(i)
                    .map(Surface::resolved)
                    .unwrap_or_else(|| Surface::from_classic(m))
            })
            .collect()
    }

    /// The group called `name`, if the scene file named one.
    pub fn group(&self, name: &str) -> Option<&Group> {
        self.groups.iter().find(|g| g.name == name)
    }

    /// Surface colour at `p` on shape `shape`: its texel, or the material colour where
    /// there is no texture (or a fit-mode image leaves the surface bare).
    pub fn surface_color(&self, shape: u32, p: Vec3) -> Vec3 {
        self.surface_color_with(shape, || self.shapes.get(shape as usize).surface_coords(p))
    }

    /// [`Scene::surface_color`] of any shape, placed ones included.
    pub fn surface_color_at(&self, shape: ShapeId, p: Vec3) -> Vec3 {
        if shape.is_world() {
            return self.surface_color(shape.shape, p);
        }
        let m = &self.materials[self.material_index(shape) as usize];
        m.texture
            .and_then(|t| self.textures[t as usize].lookup(&self.shape_at(shape).surface_coords(p)))
            .unwrap_or(m.color)
    }

    /// [`Scene::surface_color`] where the caller knows the hit's texture coordinates
    /// (asked only when the material has a texture).
    #[inline]
    pub fn surface_color_with(&self, shape: u32, coords: impl FnOnce() -> SurfaceCoords) -> Vec3 {
        let m = self.material(shape);
        m.texture
            .and_then(|t| self.textures[t as usize].lookup(&coords()))
            .unwrap_or(m.color)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4 x 2 image whose texel (col, row) has red = col and green = row.
    fn grid(fill: FillMode) -> Texture {
        let texels = (0..2u8)
            .flat_map(|row| (0..4u8).map(move |col| [col, row, 0]))
            .collect();
        Texture::new(4, 2, texels, fill)
    }

    fn texel(col: u8, row: u8) -> Vec3 {
        Vec3::new(col as f32, row as f32, 0.0) / 255.0
    }

    const BARE: Vec3 = Vec3::new(0.5, 0.5, 0.5);

    /// A scene of one shape wearing the grid texture with `fill`.
    fn textured(shape: Shape, fill: FillMode) -> Scene {
        let mut s = Scene {
            materials: vec![Material {
                color: BARE,
                texture: Some(0),
                ..Material::default_white()
            }],
            textures: vec![grid(fill)],
            ..Scene::default()
        };
        s.push_shape(shape, 0);
        s
    }

    fn square(side: f32) -> Shape {
        Shape::Rectangle(Rectangle {
            v: [
                Vec3::ZERO,
                Vec3::new(8.0, 0.0, 0.0),
                Vec3::new(8.0, side, 0.0),
                Vec3::new(0.0, side, 0.0),
            ],
        })
    }

    #[test]
    fn rectangle_texels_in_every_fill_mode() {
        let at =
            |side, fill, x, y| textured(square(side), fill).surface_color(0, Vec3::new(x, y, 0.0));
        assert_eq!(at(4.0, FillMode::Stretch, 7.0, 3.0), texel(3, 1));
        assert_eq!(
            at(4.0, FillMode::Tile { scale: 1.0 }, 5.5, 2.5),
            texel(1, 0)
        );
        // 8 x 8 surface: fit letterboxes the 4 x 2 image into rows y in [2, 6).
        assert_eq!(at(8.0, FillMode::Fit, 1.0, 1.0), BARE);
        assert_eq!(at(8.0, FillMode::Fit, 1.0, 5.5), texel(0, 1));
        // Crop: 4 units per texel, columns from x = -4.
        assert_eq!(at(8.0, FillMode::Crop, 0.5, 0.5), texel(1, 0));
    }

    #[test]
    fn triangle_texels_in_every_fill_mode() {
        // Frame: x along v0 - v1 = +x, y toward v2 = +y; extent [-8, 0] x [0, 4].
        let tri = Shape::Triangle(Triangle {
            v: [
                Vec3::ZERO,
                Vec3::new(-8.0, 0.0, 0.0),
                Vec3::new(0.0, 4.0, 0.0),
            ],
        });
        let p = Vec3::new(-2.0, 2.0, 0.0);
        let at = |fill| textured(tri, fill).surface_color(0, p);
        assert_eq!(at(FillMode::Stretch), texel(3, 1));
        assert_eq!(at(FillMode::Tile { scale: 1.0 }), texel(2, 0));
        assert_eq!(at(FillMode::Fit), texel(3, 1));
        assert_eq!(at(FillMode::Crop), texel(3, 1));
    }

    #[test]
    fn sphere_texels_in_every_fill_mode() {
        let ball = Shape::Sphere(Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        });
        // Equator at azimuth pi/2: (x, y) = (1/2, 1/3); at 3 pi/2: (1/2, 2/3).
        let at = |fill, p| textured(ball, fill).surface_color(0, p);
        assert_eq!(at(FillMode::Stretch, Vec3::Y), texel(2, 0));
        assert_eq!(at(FillMode::Stretch, -Vec3::Y), texel(2, 1));
        assert_eq!(at(FillMode::Tile { scale: 0.25 }, Vec3::Y), texel(2, 1));
        // Unit square, 4 x 2 image: fit shows it in rows y in [1/4, 3/4).
        assert_eq!(at(FillMode::Fit, Vec3::Y), texel(2, 0));
        assert_eq!(at(FillMode::Fit, Vec3::Z), BARE);
        assert_eq!(at(FillMode::Crop, Vec3::Y), texel(2, 0));
    }
}
