//! Instances: one mesh placed many times. An [`Object`] holds its triangles once, in
//! its own space; each [`Instance`] places it with an affine transform. A forest of ten
//! thousand trees costs one tree and ten thousand transforms.
//!
//! A placed triangle is the triangle whose corners are [`Instance::place`]d, wound the
//! other way by a mirroring transform; its vertex normals go through
//! [`Instance::normal_matrix`]. [`Scene::flattened`] copies every instance out with those
//! same functions, so a scene of instances renders bit for bit as its flattened twin.

use super::{LightKind, MeshAttributes, Scene, Shape, Shapes, Stored, Triangle};
use crate::math::{Aabb, Vec3};
use glam::Affine3A;
use rayon::prelude::*;

/// Up to this many placed vertices, [`Scene::bounds`] places them all.
pub const EXACT_BOUNDS_VERTICES: u64 = 1 << 24;

/// The instance of a shape that is not in one: the scene's own shapes.
pub const NO_INSTANCE: u32 = u32::MAX;

/// Which shape a ray met: shape `shape` of the scene ([`NO_INSTANCE`]), or shape
/// `shape` of the object instance `instance` places.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ShapeId {
    /// Index into [`Scene::instances`], or [`NO_INSTANCE`].
    pub instance: u32,
    /// Index into the scene's shapes, or into the instance's object's.
    pub shape: u32,
}

impl ShapeId {
    /// Shape `shape` of the scene itself.
    #[inline]
    pub const fn world(shape: u32) -> ShapeId {
        ShapeId {
            instance: NO_INSTANCE,
            shape,
        }
    }

    /// Whether the shape is the scene's own, in no instance.
    #[inline]
    pub fn is_world(self) -> bool {
        self.instance == NO_INSTANCE
    }

    /// The order shapes win ties in: the scene's own first, then each instance's in
    /// turn, which is the order of the flattened twin's shape indices.
    #[inline]
    pub fn order(self) -> u64 {
        (u64::from(self.instance.wrapping_add(1)) << 32) | u64::from(self.shape)
    }
}

/// A mesh placed by instances: triangles only, in its own space, each wearing a scene
/// material.
#[derive(Clone, Debug, Default)]
pub struct Object {
    /// The name the file gave it.
    pub name: String,
    /// Its triangles (nothing but triangles: a sphere does not stay one under every
    /// transform).
    pub shapes: Shapes,
    /// Index into [`Scene::materials`] of each shape's material.
    pub material_of: Vec<u32>,
    /// Vertex attributes, `first_shape` counting the object's own shapes.
    pub meshes: Vec<MeshAttributes>,
}

impl Object {
    /// The mesh owning shape `shape`, with the triangle's number in it.
    #[inline]
    pub fn mesh_of(&self, shape: u32) -> Option<(&MeshAttributes, usize)> {
        super::mesh::owning(&self.meshes, shape)
    }

    /// The box around its triangles, in its own space.
    pub fn bounds(&self) -> Aabb {
        self.shapes.bounds()
    }
}

/// An affine transform in twelve floats. [`Affine3A`] pads each of its four columns to
/// sixteen bytes, and a scene holds two transforms an instance: unpacked where used,
/// the same floats, so the same arithmetic.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Packed([glam::Vec3; 4]);

impl Packed {
    fn pack(a: &Affine3A) -> Packed {
        let m = &a.matrix3;
        Packed([m.x_axis, m.y_axis, m.z_axis, a.translation].map(glam::Vec3::from))
    }

    #[inline(always)]
    fn unpack(&self) -> Affine3A {
        let [x, y, z, w] = self.0.map(Vec3::from);
        Affine3A::from_cols(x, y, z, w)
    }
}

/// One placement of an object: its index and the transform, and no more. The inverse
/// is worked out where it is needed (a ray entering the instance's box, a vertex
/// normal), from the same floats by the same arithmetic, so every use sees the same
/// bits; held, it would be half an instance's bytes.
#[derive(Clone, Copy, Debug)]
pub struct Instance {
    /// Index into [`Scene::objects`] in the low 31 bits; the top bit set where
    /// `to_world` mirrors.
    object_flip: u32,
    /// Object space to world space.
    to_world: Packed,
}

/// The bit of [`Instance::object_flip`] that says the transform mirrors.
const FLIP: u32 = 1 << 31;

impl Instance {
    /// `object` placed by `to_world`, which must be invertible and finite.
    pub fn new(object: u32, to_world: Affine3A) -> Instance {
        // A scene holds fewer objects than it has bytes for, so far fewer than 2^31.
        debug_assert!(object < FLIP);
        let flip = if to_world.matrix3.determinant() < 0.0 {
            FLIP
        } else {
            0
        };
        Instance {
            object_flip: object & !FLIP | flip,
            to_world: Packed::pack(&to_world),
        }
    }

    /// Index into [`Scene::objects`] of the object placed.
    #[inline(always)]
    pub fn object(&self) -> u32 {
        self.object_flip & !FLIP
    }

    /// Whether the transform mirrors (a negative determinant): its triangles are wound
    /// the other way, so they face out as they did.
    #[inline(always)]
    pub fn flip(&self) -> bool {
        self.object_flip & FLIP != 0
    }

    /// Object space to world space.
    #[inline(always)]
    pub fn to_world(&self) -> Affine3A {
        self.to_world.unpack()
    }

    /// World space to object space (the inverse of [`Instance::to_world`], rounded).
    #[inline(always)]
    pub fn from_world(&self) -> Affine3A {
        self.to_world().inverse()
    }

    /// A point of the object, in world space.
    #[inline(always)]
    pub fn place(&self, p: Vec3) -> Vec3 {
        self.to_world().transform_point3a(p)
    }

    /// The corners of a triangle of the object, in world space, in the placed winding.
    #[inline(always)]
    pub fn place_corners(&self, v: [Vec3; 3]) -> [Vec3; 3] {
        place_corners(&self.to_world(), self.flip(), v)
    }

    /// A per-corner index triple (of an attribute) in the placed winding.
    #[inline]
    pub fn wind(&self, t: [u32; 3]) -> [u32; 3] {
        if self.flip() { [t[0], t[2], t[1]] } else { t }
    }

    /// What takes the object's normals into world space (not normalised: interpolation
    /// does): the inverse transpose, `from_world`'s matrix being that inverse. Worked
    /// out once for a triangle's or a mesh's normals.
    #[inline]
    pub fn normal_matrix(&self) -> glam::Mat3A {
        self.from_world().matrix3.transpose()
    }

    /// The world box around `bounds` (a box of the object) placed.
    pub fn world_bounds(&self, bounds: &Aabb) -> Aabb {
        let mut out = Aabb::EMPTY;
        for i in 0..8 {
            let corner = Vec3::new(
                if i & 1 == 0 {
                    bounds.min.x
                } else {
                    bounds.max.x
                },
                if i & 2 == 0 {
                    bounds.min.y
                } else {
                    bounds.max.y
                },
                if i & 4 == 0 {
                    bounds.min.z
                } else {
                    bounds.max.z
                },
            );
            out = out.grow(self.place(corner));
        }
        out
    }

    /// The object's attributes placed as the flattened twin holds them: normals in
    /// world space, index triples in the placed winding.
    fn placed_mesh(&self, mesh: &MeshAttributes, first_shape: u32) -> MeshAttributes {
        let wind = |t: &Vec<[u32; 3]>| t.iter().map(|&t| self.wind(t)).collect();
        MeshAttributes {
            first_shape,
            len: mesh.len,
            normals: {
                let m = self.normal_matrix();
                mesh.normals.iter().map(|&n| m * n).collect()
            },
            normal_indices: wind(&mesh.normal_indices),
            texcoords: mesh.texcoords.clone(),
            texcoord_indices: wind(&mesh.texcoord_indices),
            colors: mesh.colors.clone(),
            color_indices: wind(&mesh.color_indices),
        }
    }
}

/// A triangle's attributes as a hit reads them: a mesh of the scene, or of an object
/// placed by an instance (normals turned into world space, triples in its winding).
#[derive(Clone, Copy)]
pub struct MeshView<'a> {
    mesh: &'a MeshAttributes,
    tri: usize,
    placed: Option<&'a Instance>,
}

impl MeshView<'_> {
    fn triple(&self, indices: &[[u32; 3]]) -> Option<[u32; 3]> {
        let t = *indices.get(self.tri)?;
        Some(self.placed.map_or(t, |i| i.wind(t)))
    }

    /// The vertex normals, in world space.
    pub fn vertex_normals(&self) -> Option<[Vec3; 3]> {
        let t = self.triple(&self.mesh.normal_indices)?;
        let n = t.map(|k| self.mesh.normals[k as usize]);
        Some(match self.placed {
            Some(i) => {
                let m = i.normal_matrix();
                n.map(|n| m * n)
            }
            None => n,
        })
    }

    /// The interpolated unit normal at barycentrics `b`.
    pub fn normal(&self, b: [f32; 3]) -> Option<Vec3> {
        super::mesh::interpolate_normal(self.vertex_normals()?, b)
    }

    /// The interpolated texture coordinates at barycentrics `b`.
    pub fn texcoord(&self, b: [f32; 3]) -> Option<[f32; 2]> {
        let t = self.triple(&self.mesh.texcoord_indices)?;
        Some(super::mesh::interpolate_texcoord(
            t.map(|k| self.mesh.texcoords[k as usize]),
            b,
        ))
    }

    /// The interpolated vertex colour at barycentrics `b`.
    pub fn color(&self, b: [f32; 3]) -> Option<Vec3> {
        let t = self.triple(&self.mesh.color_indices)?;
        let [a, c, d] = t.map(|k| self.mesh.colors[k as usize]);
        Some(a * b[0] + c * b[1] + d * b[2])
    }
}

impl Scene {
    /// The shape `id` names, in world space.
    #[inline]
    pub fn shape_at(&self, id: ShapeId) -> Shape {
        if id.is_world() {
            return self.shapes.get(id.shape as usize);
        }
        let instance = &self.instances[id.instance as usize];
        placed_shape(
            instance,
            &self.objects[instance.object() as usize],
            id.shape as usize,
        )
    }

    /// The shape `id` names, in world space; `None` when the scene has no such shape.
    pub fn try_shape_at(&self, id: ShapeId) -> Option<Shape> {
        if id.is_world() {
            return self.shapes.try_get(id.shape as usize);
        }
        let instance = self.instances.get(id.instance as usize)?;
        let object = self.objects.get(instance.object() as usize)?;
        ((id.shape as usize) < object.shapes.len())
            .then(|| placed_shape(instance, object, id.shape as usize))
    }

    /// Index into `materials` of the material shape `id` wears.
    #[inline]
    pub fn material_index(&self, id: ShapeId) -> u32 {
        if id.is_world() {
            self.material_of[id.shape as usize]
        } else {
            let object = self.instances[id.instance as usize].object();
            self.objects[object as usize].material_of[id.shape as usize]
        }
    }

    /// The vertex attributes of shape `id`, if it is a triangle of a mesh.
    #[inline]
    pub fn mesh_at(&self, id: ShapeId) -> Option<MeshView<'_>> {
        if id.is_world() {
            let (mesh, tri) = self.mesh_of(id.shape)?;
            return Some(MeshView {
                mesh,
                tri,
                placed: None,
            });
        }
        let instance = &self.instances[id.instance as usize];
        let (mesh, tri) = self.objects[instance.object() as usize].mesh_of(id.shape)?;
        Some(MeshView {
            mesh,
            tri,
            placed: Some(instance),
        })
    }

    /// Triangles the instances place (each counted once per instance).
    pub fn placed_triangles(&self) -> u64 {
        self.instances
            .iter()
            .map(|i| self.objects[i.object() as usize].shapes.len() as u64)
            .sum()
    }

    /// The scene with every instance copied out into shapes of its own, appended after
    /// the scene's in instance order (its emissive meshes' lights naming the copies):
    /// what a scene of instances must render as, bit for bit.
    pub fn flattened(&self) -> Scene {
        let mut flat = Scene {
            objects: Vec::new(),
            instances: Vec::new(),
            ..self.clone()
        };
        let mut first_of_instance = Vec::with_capacity(self.instances.len());
        for instance in &self.instances {
            first_of_instance.push(flat.shapes.len() as u32);
            let object = &self.objects[instance.object() as usize];
            let first = flat.shapes.len() as u32;
            for (i, &material) in object.material_of.iter().enumerate() {
                flat.push_shape(placed_shape(instance, object, i), material);
            }
            for mesh in &object.meshes {
                flat.meshes
                    .push(instance.placed_mesh(mesh, first + mesh.first_shape));
            }
        }
        for light in &mut flat.lights {
            if let LightKind::Mesh { shapes, .. } = &mut light.kind {
                for id in shapes.iter_mut().filter(|id| !id.is_world()) {
                    *id = ShapeId::world(first_of_instance[id.instance as usize] + id.shape);
                }
            }
        }
        flat
    }

    /// World box around every shape, placed ones included ([`Aabb::EMPTY`] when there
    /// are none): the flattened twin's
    /// exactly, or where the instances place more than [`EXACT_BOUNDS_VERTICES`]
    /// vertices, a box around each instance's placed object box.
    pub fn bounds(&self) -> Aabb {
        let own = self.shapes.bounds();
        let placed: u64 = self
            .instances
            .iter()
            .map(|i| self.objects[i.object() as usize].shapes.positions().len() as u64)
            .sum();
        if placed <= EXACT_BOUNDS_VERTICES {
            return self
                .instances
                .par_iter()
                .map(|i| {
                    let object = &self.objects[i.object() as usize];
                    object
                        .shapes
                        .positions()
                        .iter()
                        .fold(Aabb::EMPTY, |b, &p| b.grow(i.place(p)))
                })
                .reduce(|| own, Aabb::union);
        }
        own.union(self.instance_boxes())
    }

    /// A box around every instance: the union of each one's placed object box (a
    /// little larger than its placed triangles' under a rotation), cheap however many
    /// triangles the instances place.
    pub fn instance_boxes(&self) -> Aabb {
        let objects: Vec<Aabb> = self.objects.iter().map(Object::bounds).collect();
        self.instances.iter().fold(Aabb::EMPTY, |b, i| {
            b.union(i.world_bounds(&objects[i.object() as usize]))
        })
    }
}

/// The corners `v` of a triangle placed by `to_world` ([`Instance::to_world`], unpacked
/// once for many triangles), in the placed winding (reversed where `flip`).
#[inline(always)]
pub fn place_corners(to_world: &Affine3A, flip: bool, v: [Vec3; 3]) -> [Vec3; 3] {
    let [a, b, c] = v.map(|p| to_world.transform_point3a(p));
    if flip { [a, c, b] } else { [a, b, c] }
}

/// Shape `i` of `object` as `instance` places it.
#[inline]
fn placed_shape(instance: &Instance, object: &Object, i: usize) -> Shape {
    match object.shapes.stored(i) {
        Stored::Triangle(c) => {
            let p = object.shapes.positions();
            Shape::Triangle(Triangle {
                v: instance.place_corners(c.map(|k| p[k as usize])),
            })
        }
        Stored::Other(_) => unreachable!("objects hold triangles only"),
    }
}
