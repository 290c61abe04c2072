//! [`SceneBuilder`]: how a reader (or code) fills a [`Scene`] — materials with their
//! whitted surfaces, images, shapes and indexed meshes with their attributes, lights
//! and named groups — keeping its parallel arrays aligned, and turning emissive
//! materials into area lights the same way for every format.

use super::{
    Background, Group, ImageTexture, Instance, Light, Material, MeshAttributes, Object, Scene,
    Shape, ShapeId, Surface, Texture,
};
use crate::math::Vec3;
use std::ops::Range;

/// What [`SceneBuilder::add_instance`] placed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Placement {
    /// An instance: its index into [`Scene::instances`].
    Instance(u32),
    /// Copies of the object's triangles in world space, flattened onto a plane: their
    /// range of [`Scene::shapes`].
    Copies(Range<u32>),
    /// Nothing that can be seen.
    Nothing,
}

/// Fills a [`Scene`]. Indices it hands back (materials, images, shapes, lights) are the
/// scene's own.
///
/// ```
/// use prism::math::Vec3;
/// use prism::scene::{Albedo, Light, Material, SceneBuilder, Shape, Sphere, Surface};
///
/// let mut b = SceneBuilder::new();
/// let red = b.add_material(
///     Material::default_white(),
///     Surface { albedo: Albedo::Color(Vec3::new(0.8, 0.1, 0.1)), ..Surface::default() },
/// );
/// b.add_shape(Shape::Sphere(Sphere { center: Vec3::ZERO, radius: 1.0 }), red);
/// b.add_light(Light::point(Vec3::new(0.0, 4.0, 4.0), Vec3::ONE));
/// let scene = b.finish();
///
/// // Rendered with the whitted model: the ball fills the middle of the frame.
/// use prism::render::{IntegratorKind, RenderSettings, Renderer};
/// use prism::scene::Camera;
/// let camera = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 40.0, 16, 16);
/// let settings = RenderSettings { integrator: IntegratorKind::Whitted, ..Default::default() };
/// let (image, _) = Renderer::new(&scene, &camera, settings)?.render(&())?;
/// let [r, g, _] = image.pixels[8 * 16 + 8];
/// assert!(r > 0.1 && g < r / 4.0);
/// # Ok::<(), prism::Error>(())
/// ```
#[derive(Debug, Default)]
pub struct SceneBuilder {
    scene: Scene,
    /// Whether a material without whitted terms (a 2014 one) has been added: the
    /// surfaces of later materials would not line up with theirs.
    classic_only: bool,
}

/// Which materials a mesh's triangles wear.
pub enum MeshMaterials<'a> {
    /// Every triangle the same.
    All(u32),
    /// One per triangle.
    Each(&'a [u32]),
}

impl SceneBuilder {
    /// An empty scene: no shapes, black background, no ambient light.
    pub fn new() -> SceneBuilder {
        SceneBuilder::default()
    }

    /// The scene so far, to read (bounds, counts) while building.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// A material with its whitted terms; returns its index.
    pub fn add_material(&mut self, material: Material, surface: Surface) -> u32 {
        assert!(
            !self.classic_only,
            "a material with whitted terms after one without"
        );
        self.scene.materials.push(material);
        self.scene.surfaces.push(surface);
        self.scene.materials.len() as u32 - 1
    }

    /// A 2014 material, whose whitted terms are derived when it is rendered that way
    /// ([`Surface::from_classic`]).
    pub fn add_classic_material(&mut self, material: Material) -> u32 {
        self.classic_only = true;
        self.scene.materials.push(material);
        self.scene.materials.len() as u32 - 1
    }

    /// Materials added so far; the next one added gets this index.
    pub fn material_count(&self) -> u32 {
        self.scene.materials.len() as u32
    }

    /// Images added so far: the index the next one takes.
    pub fn image_count(&self) -> u32 {
        self.scene.images.len() as u32
    }

    /// An image read at texture coordinates; returns its index (for `TextureSlot`s).
    pub fn add_image(&mut self, image: ImageTexture) -> u32 {
        self.scene.images.push(image);
        self.scene.images.len() as u32 - 1
    }

    /// A 2014 texture; returns its index.
    pub fn add_texture(&mut self, texture: Texture) -> u32 {
        self.scene.textures.push(texture);
        self.scene.textures.len() as u32 - 1
    }

    /// One shape; returns its index.
    pub fn add_shape(&mut self, shape: Shape, material: u32) -> u32 {
        self.scene.push_shape(shape, material);
        self.scene.shapes.len() as u32 - 1
    }

    /// An indexed triangle mesh: `positions`, `triangles` indexing them, the materials
    /// they wear, and per-vertex attributes (`first_shape` and `len` are set here; a
    /// mesh without any attribute keeps none). Returns the shapes it became.
    pub fn add_mesh(
        &mut self,
        positions: &[Vec3],
        triangles: &[[u32; 3]],
        materials: MeshMaterials,
        attributes: Option<MeshAttributes>,
    ) -> Range<u32> {
        let first = self.scene.shapes.len() as u32;
        self.scene.shapes.push_mesh(positions, triangles);
        match materials {
            MeshMaterials::All(m) => self
                .scene
                .material_of
                .extend(std::iter::repeat_n(m, triangles.len())),
            MeshMaterials::Each(m) => {
                assert_eq!(m.len(), triangles.len(), "a material per triangle");
                self.scene.material_of.extend_from_slice(m);
            }
        }
        let end = self.scene.shapes.len() as u32;
        if let Some(mut a) = attributes
            && !(a.normal_indices.is_empty()
                && a.texcoord_indices.is_empty()
                && a.color_indices.is_empty())
        {
            a.first_shape = first;
            a.len = end - first;
            self.scene.meshes.push(a);
        }
        first..end
    }

    /// Replaces shape `i` (a placeholder sized once the rest of the scene is known).
    pub fn set_shape(&mut self, i: usize, shape: Shape) {
        self.scene.shapes.set(i, shape);
    }

    /// The shapes of another scene placed by `point` (and `sphere` for its spheres),
    /// their windings reversed where `mirrors`, wearing `materials` (one per shape).
    pub fn add_placed<E>(
        &mut self,
        shapes: &super::Shapes,
        point: impl Fn(Vec3) -> Vec3 + Sync,
        mirrors: bool,
        sphere: impl Fn(super::Sphere) -> Result<super::Sphere, E>,
        materials: impl IntoIterator<Item = u32>,
    ) -> Result<Range<u32>, E> {
        let first = self.scene.shapes.len() as u32;
        self.scene
            .shapes
            .append_placed(shapes, point, mirrors, sphere)?;
        self.scene.material_of.extend(materials);
        assert_eq!(self.scene.material_of.len(), self.scene.shapes.len());
        Ok(first..self.scene.shapes.len() as u32)
    }

    /// Attributes of shapes already added (`first_shape` and `len` say which).
    pub fn add_attributes(&mut self, attributes: MeshAttributes) {
        self.scene.meshes.push(attributes);
    }

    /// A mesh to be placed by instances; returns its index. Its shapes must all be
    /// triangles wearing materials already added.
    pub fn add_object(&mut self, object: Object) -> u32 {
        assert!((0..object.shapes.len()).all(|i| object.shapes.is_triangle(i)));
        assert_eq!(object.material_of.len(), object.shapes.len());
        self.scene.objects.push(object);
        self.scene.objects.len() as u32 - 1
    }

    /// Whether the scene can take `triangles` more triangles over `vertices` more
    /// vertices and stay within [`crate::util::limits::MAX_SHAPES`] of each: what a
    /// reader asks before it places a mesh, so a scene never grows past the bound.
    pub fn has_room_for(&self, triangles: u64, vertices: u64) -> bool {
        let limit = crate::util::limits::MAX_SHAPES as u64;
        let shapes = &self.scene.shapes;
        (shapes.len() as u64).saturating_add(triangles) <= limit
            && (shapes.positions().len() as u64).saturating_add(vertices) <= limit
    }

    /// Places object `object` by `to_world`: as an instance where the transform can
    /// be undone, which is every finite transform of a solid; as copies of its
    /// triangles in world space where it flattens the object onto a plane (a scale of
    /// 0 along one axis, which a ray cannot be taken back through); and not at all
    /// where it leaves a line or a point, or is not finite. An error where the copies
    /// would take the scene past [`crate::util::limits::MAX_SHAPES`].
    pub fn add_instance(
        &mut self,
        object: u32,
        to_world: glam::Affine3A,
    ) -> Result<Placement, String> {
        assert!((object as usize) < self.scene.objects.len());
        if !to_world.is_finite() {
            return Ok(Placement::Nothing);
        }
        let instance = Instance::new(object, to_world);
        if instance.to_world().matrix3.determinant() != 0.0 && instance.from_world().is_finite() {
            self.scene.instances.push(instance);
            return Ok(Placement::Instance(self.scene.instances.len() as u32 - 1));
        }
        let linear = glam::DMat3::from_cols_array(&to_world.matrix3.to_cols_array().map(f64::from));
        let normals = crate::math::cofactor(linear);
        if normals == glam::DMat3::ZERO {
            return Ok(Placement::Nothing);
        }
        self.add_flattened(&instance, normals.as_mat3().into())
            .map(Placement::Copies)
    }

    /// The triangles of the object `placement` places, copied into world space by its
    /// transform, their normals by `normals`; the copies' range of shapes.
    fn add_flattened(
        &mut self,
        placement: &Instance,
        normals: glam::Mat3A,
    ) -> Result<Range<u32>, String> {
        let object = &self.scene.objects[placement.object() as usize];
        let (triangles, vertices) = (object.shapes.len(), object.shapes.positions().len());
        if !self.has_room_for(triangles as u64, vertices as u64) {
            return Err(format!(
                "placing \"{}\" flat (its transform's determinant is 0) copies its \
                 triangles, and the copies would give the scene more than {} \
                 triangles or vertices",
                object.name,
                crate::util::limits::MAX_SHAPES
            ));
        }
        // The corners of the object's box bound every placed coordinate.
        let placed = placement.world_bounds(&object.bounds());
        if triangles > 0 && !(placed.min.is_finite() && placed.max.is_finite()) {
            return Err(format!(
                "placing \"{}\" takes a vertex past the range of floats",
                object.name
            ));
        }
        let to_world = placement.to_world();
        let Scene {
            objects,
            shapes,
            material_of,
            meshes,
            ..
        } = &mut self.scene;
        let object = &objects[placement.object() as usize];
        let first = shapes.len() as u32;
        shapes
            .append_placed(
                &object.shapes,
                |p| to_world.transform_point3a(p),
                false,
                Ok::<_, std::convert::Infallible>,
            )
            .unwrap_or_else(|never| match never {});
        material_of.extend_from_slice(&object.material_of);
        for mesh in &object.meshes {
            meshes.push(MeshAttributes {
                first_shape: first + mesh.first_shape,
                len: mesh.len,
                normals: mesh.normals.iter().map(|&n| normals * n).collect(),
                normal_indices: mesh.normal_indices.clone(),
                texcoords: mesh.texcoords.clone(),
                texcoord_indices: mesh.texcoord_indices.clone(),
                colors: mesh.colors.clone(),
                color_indices: mesh.color_indices.clone(),
            });
        }
        Ok(first..shapes.len() as u32)
    }

    /// A light; returns its index.
    pub fn add_light(&mut self, light: Light) -> u32 {
        self.scene.lights.push(light);
        self.scene.lights.len() as u32 - 1
    }

    /// A named group of shapes and lights (an animation track can move it).
    pub fn add_group(&mut self, group: Group) {
        self.scene.groups.push(group);
    }

    /// Sets La, the linear RGB ambient light the whitted model multiplies each Ka by.
    pub fn set_ambient(&mut self, ambient: Vec3) {
        self.scene.ambient = ambient;
    }

    /// Sets what escaping rays see (the whitted model; classic rays see black).
    pub fn set_background(&mut self, background: Background) {
        self.scene.background = background;
    }

    /// The triangles [`SceneBuilder::add_emissive_lights`] would light: the scene's own
    /// emissive ones and those the instances place, each counted once per instance (a
    /// reader checks them against [`crate::util::limits::MAX_LIGHT_TRIANGLES`] first).
    pub fn emissive_triangles(&self) -> u64 {
        let scene = &self.scene;
        let emits = |m: &u32| {
            scene
                .surfaces
                .get(*m as usize)
                .is_some_and(|s| s.emission.max_element() > 0.0)
        };
        let per_object: Vec<u64> = scene
            .objects
            .iter()
            .map(|o| o.material_of.iter().filter(|m| emits(m)).count() as u64)
            .collect();
        let own = scene.material_of.iter().filter(|m| emits(m)).count() as u64;
        scene.instances.iter().fold(own, |n, i| {
            n.saturating_add(per_object[i.object() as usize])
        })
    }

    /// Every emissive material's triangles as one area light of `samples` shadow rays,
    /// in material order: the scene's own, then those each instance places, in
    /// instance order. The names of the emissive materials whose faces have no area
    /// (so no light) come back for the reader to warn of.
    pub fn add_emissive_lights(&mut self, samples: u32) -> Vec<String> {
        let scene = &mut self.scene;
        let emits = |m: u32| {
            scene
                .surfaces
                .get(m as usize)
                .is_some_and(|s| s.emission.max_element() > 0.0)
        };
        let mut emissive: Vec<Vec<ShapeId>> = vec![Vec::new(); scene.materials.len()];
        for (i, &m) in scene.material_of.iter().enumerate() {
            if emits(m) {
                emissive[m as usize].push(ShapeId::world(i as u32));
            }
        }
        // Each object's emitting triangles, found once however often it is placed.
        let object_emitters: Vec<Vec<(u32, u32)>> = scene
            .objects
            .iter()
            .map(|o| {
                let shapes = o.material_of.iter().enumerate();
                shapes
                    .filter(|&(_, &m)| emits(m))
                    .map(|(i, &m)| (m, i as u32))
                    .collect()
            })
            .collect();
        for (k, instance) in scene.instances.iter().enumerate() {
            for &(m, shape) in &object_emitters[instance.object() as usize] {
                emissive[m as usize].push(ShapeId {
                    instance: k as u32,
                    shape,
                });
            }
        }
        let mut dark = Vec::new();
        for (m, shapes) in emissive.into_iter().enumerate() {
            if shapes.is_empty() {
                continue;
            }
            match Light::mesh(scene, shapes) {
                Some(mut light) => {
                    light.samples = samples;
                    scene.lights.push(light);
                }
                None => dark.push(scene.materials[m].name.clone()),
            }
        }
        dark
    }

    /// The scene. Its arrays line up: a material for every shape, mesh attributes in
    /// order of their shapes and within them.
    pub fn finish(self) -> Scene {
        let s = self.scene;
        assert_eq!(s.material_of.len(), s.shapes.len());
        debug_assert!(
            s.material_of
                .iter()
                .all(|&m| (m as usize) < s.materials.len())
        );
        debug_assert!(
            s.meshes
                .windows(2)
                .all(|w| w[0].first_shape + w[0].len <= w[1].first_shape)
        );
        debug_assert!(
            s.meshes
                .iter()
                .all(|m| (m.first_shape + m.len) as usize <= s.shapes.len())
        );
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Rectangle, Triangle};

    #[test]
    fn meshes_keep_their_attributes_and_emitters_become_lights() {
        let mut b = SceneBuilder::new();
        let glow = b.add_material(
            Material::default_white(),
            Surface {
                emission: Vec3::ONE,
                ..Surface::default()
            },
        );
        let matte = b.add_material(Material::default_white(), Surface::default());
        b.add_shape(
            Shape::Rectangle(Rectangle {
                v: [Vec3::ZERO, Vec3::X, Vec3::ONE, Vec3::Y],
            }),
            matte,
        );
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let normals = MeshAttributes {
            normals: vec![Vec3::Z; 4],
            normal_indices: vec![[0, 1, 2], [0, 2, 3]],
            ..MeshAttributes::default()
        };
        let shapes = b.add_mesh(
            &positions,
            &[[0, 1, 2], [0, 2, 3]],
            MeshMaterials::Each(&[glow, matte]),
            Some(normals),
        );
        assert_eq!(shapes, 1..3);
        // Without attributes, no mesh entry.
        b.add_mesh(&positions, &[[0, 1, 3]], MeshMaterials::All(glow), None);
        // A zero-area emitter gives no light, only its name back.
        let dark = b.add_material(
            Material {
                name: "dark".into(),
                ..Material::default_white()
            },
            Surface {
                emission: Vec3::ONE,
                ..Surface::default()
            },
        );
        b.add_shape(Shape::Triangle(Triangle { v: [Vec3::ZERO; 3] }), dark);
        assert_eq!(b.add_emissive_lights(4), ["dark"]);
        let s = b.finish();
        assert_eq!(s.material_of, [matte, glow, matte, glow, dark]);
        assert_eq!(
            (s.meshes.len(), s.meshes[0].first_shape, s.meshes[0].len),
            (1, 1, 2)
        );
        assert_eq!(s.lights.len(), 1);
        let crate::scene::LightKind::Mesh { shapes, .. } = &s.lights[0].kind else {
            panic!()
        };
        assert_eq!(shapes, &[ShapeId::world(1), ShapeId::world(3)]);
        assert_eq!(s.lights[0].samples, 4);
    }

    /// Glowing triangles placed by instances join their material's light after the
    /// scene's own, instance by instance, and are counted once per instance.
    #[test]
    fn placed_emitters_join_their_materials_light() {
        let mut b = SceneBuilder::new();
        let glow = b.add_material(
            Material::default_white(),
            Surface {
                emission: Vec3::ONE,
                ..Surface::default()
            },
        );
        let matte = b.add_material(Material::default_white(), Surface::default());
        let tri = Shape::Triangle(Triangle {
            v: [Vec3::ZERO, Vec3::X, Vec3::Y],
        });
        b.add_shape(tri, glow);
        let mut shapes = super::super::Shapes::new();
        for _ in 0..3 {
            shapes.push(tri);
        }
        let object = b.add_object(Object {
            shapes,
            material_of: vec![matte, glow, glow],
            ..Object::default()
        });
        let twice = glam::Affine3A::from_scale(glam::Vec3::new(2.0, 1.0, 1.0));
        b.add_instance(object, twice).unwrap();
        b.add_instance(object, glam::Affine3A::IDENTITY).unwrap();
        assert_eq!(b.emissive_triangles(), 5);
        assert!(b.add_emissive_lights(1).is_empty());
        let s = b.finish();
        let crate::scene::LightKind::Mesh { shapes, cdf, area } = &s.lights[0].kind else {
            panic!()
        };
        let placed = |instance, shape| ShapeId { instance, shape };
        assert_eq!(
            shapes,
            &[
                ShapeId::world(0),
                placed(0, 1),
                placed(0, 2),
                placed(1, 1),
                placed(1, 2)
            ]
        );
        // Areas 0.5, 1, 1, 0.5, 0.5: cumulative over 3.5.
        assert_eq!(*area, 3.5);
        assert_eq!(cdf[1], (1.5f64 / 3.5) as f32);
        assert!(s.lights[0].emits_from(placed(1, 2)));
        assert!(!s.lights[0].emits_from(placed(1, 0)));
        assert!(!s.lights[0].emits_from(placed(2, 1)));
    }
}
