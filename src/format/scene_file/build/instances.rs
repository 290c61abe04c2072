//! Instance objects: a mesh object given before placed again, by the instance's own
//! transform or by each matrix of a list (written in the file or handed over as an
//! array), as one shared object and its placements rather than copies.

use super::{Builder, Placed, add_materials, merge};
use crate::error::Result;
use crate::format::scene_file::lights;
use crate::format::scene_file::objects::placement_error;
use crate::format::scene_file::raw::{RawObject, Transforms};
use crate::format::scene_file::source::Source;
use crate::format::scene_file::transform::Transform;
use crate::math::Vec3;
use crate::scene::{Light, LightKind, NO_INSTANCE, Placement, Scene, SceneBuilder, ShapeId};
use toml::Spanned;

impl Builder {
    /// Instance object `o`: the mesh object named `of` placed by `t`, or once for
    /// each of its `transforms` (each applied before `t`).
    pub(super) fn instance(
        &mut self,
        source: &Source,
        o: &RawObject,
        of: &Spanned<String>,
        t: &Transform,
    ) -> Result<()> {
        if !self.meshes.contains_key(of.get_ref()) {
            return Err(source.error(
                of,
                format!(
                    "expected the name of a mesh object given before this instance, found \
                     \"{}\"",
                    of.get_ref()
                ),
            ));
        }
        // The placements are checked here and built one at a time as they are placed:
        // ten thousand of them are not held twice.
        let named = match o.transforms.as_ref().map(|l| (l, l.get_ref())) {
            Some((list, Transforms::Named(name))) => {
                Some(self.transforms.remove(name).ok_or_else(|| {
                    source.error(
                        list,
                        format!(
                            "expected transforms as a list of 4 x 4 matrices, found the \
                             name \"{name}\", which no array handed over holds"
                        ),
                    )
                })?)
            }
            _ => None,
        };
        let matrices = match (&o.transforms, &named) {
            (None, _) => Matrices::One,
            (Some(_), Some(named)) => Matrices::Named(named),
            (Some(list), None) => match list.get_ref() {
                Transforms::Listed(m) => Matrices::Listed(m),
                Transforms::Named(_) => unreachable!("named arrays are taken above"),
            },
        };
        let checked = match &o.transforms {
            Some(list) => check_transforms(source, list, &matrices),
            None => Ok(()),
        };
        let result = checked.and_then(|()| self.place_instances(source, o, of, t, &matrices));
        if let (Some(Transforms::Named(name)), Some(named)) =
            (o.transforms.as_ref().map(Spanned::get_ref), named)
        {
            self.transforms.insert(name.clone(), named);
        }
        result
    }

    /// Places the mesh `of` names by each of `matrices` (each applied before `t`).
    fn place_instances(
        &mut self,
        source: &Source,
        o: &RawObject,
        of: &Spanned<String>,
        t: &Transform,
        matrices: &Matrices,
    ) -> Result<()> {
        let mesh = &self.meshes[of.get_ref()];
        let placed = match &mesh.placed {
            Some(p) => p.clone(),
            None => {
                let (file, up_axis, smooth, material) = (
                    mesh.file.clone(),
                    mesh.up_axis.clone(),
                    mesh.smooth,
                    mesh.material,
                );
                let loaded = self.load_mesh(source, &file, &up_axis, smooth)?;
                let placed = as_object(&mut self.scene, loaded, material, of.get_ref())
                    .map_err(|m| placement_error(source, o, m))?;
                if let Some(mesh) = self.meshes.get_mut(of.get_ref()) {
                    mesh.placed = Some(placed.clone());
                }
                placed
            }
        };
        let material = self.meshes[of.get_ref()].material;
        // Whether the instances glow in the material they were given, and what each
        // instance's lights name: its object's glowing triangles.
        let glows = material
            .is_some_and(|m| self.scene.scene().surfaces[m as usize].emission != Vec3::ZERO);
        let emitting = match &placed {
            Placed::Object(object, lights) => {
                let own = self.scene.scene().objects[*object as usize].shapes.len() as u64;
                let file = lights.iter().map(|l| match &l.kind {
                    LightKind::Mesh { shapes, .. } => shapes.len() as u64,
                    _ => 0,
                });
                u64::from(glows) * own + file.sum::<u64>()
            }
            Placed::Copies(_) => 0,
        };
        if let Placed::Copies(loaded) = &placed {
            // Each placement copies the mesh: checked whole before the first copy, so
            // many placements of a large mesh fail at once rather than fill memory.
            let count = matrices.len() as u64;
            let limit = crate::util::limits::MAX_SHAPES;
            let triangles = count.saturating_mul(loaded.shapes.len() as u64);
            let vertices = count.saturating_mul(loaded.shapes.positions().len() as u64);
            if !self.scene.has_room_for(triangles, vertices) {
                return Err(source.error(
                    of,
                    format!(
                        "expected at most {limit} triangles and vertices in the scene, found \
                         {count} placements of a mesh that carries lights of its own (so each \
                         is a copy) of {} triangles and {} vertices",
                        loaded.shapes.len(),
                        loaded.shapes.positions().len()
                    ),
                ));
            }
        }
        for k in 0..matrices.len() {
            let m = matrices.placement(k, t);
            match &placed {
                Placed::Object(object, lights) => {
                    if self.scene.scene().instances.len() >= crate::util::limits::MAX_INSTANCES {
                        return Err(source.error(
                            of,
                            format!(
                                "the scene places more than {} instances",
                                crate::util::limits::MAX_INSTANCES
                            ),
                        ));
                    }
                    let placement = self
                        .scene
                        .add_instance(*object, glam::Affine3A::from_mat4(m.as_mat4()))
                        .map_err(|e| placement_error(source, o, e))?;
                    if placement == Placement::Nothing {
                        continue;
                    }
                    self.placed_emitters += emitting;
                    if self.placed_emitters > crate::util::limits::MAX_LIGHT_TRIANGLES {
                        return Err(source.error(
                            of,
                            format!(
                                "the scene's glowing instances place more than {} triangles \
                                 for their lights",
                                crate::util::limits::MAX_LIGHT_TRIANGLES
                            ),
                        ));
                    }
                    // Each placement lights its own triangles: an instance's, or the
                    // world copies of a flattened one.
                    let (instance, first) = match placement {
                        Placement::Instance(instance) => {
                            if glows {
                                self.instance_emitters(instance, lights::DEFAULT_AREA_SAMPLES);
                            }
                            (instance, 0)
                        }
                        Placement::Copies(copies) => {
                            if glows {
                                self.emitters(copies.start as usize, lights::DEFAULT_AREA_SAMPLES);
                            }
                            (NO_INSTANCE, copies.start)
                        }
                        Placement::Nothing => unreachable!("skipped above"),
                    };
                    for light in lights {
                        let LightKind::Mesh { shapes, .. } = &light.kind else {
                            unreachable!("objects carry mesh lights only")
                        };
                        let placed = shapes.iter().map(|s| ShapeId {
                            instance,
                            shape: first + s.shape,
                        });
                        if let Some(mesh) = Light::mesh(self.scene.scene(), placed) {
                            self.scene.add_light(Light {
                                position: Transform::from_matrix(m).point_f32(light.position),
                                kind: mesh.kind,
                                ..light.clone()
                            });
                        }
                    }
                }
                Placed::Copies(loaded) => {
                    let first = self.scene.scene().shapes.len();
                    merge(
                        &mut self.scene,
                        (**loaded).clone(),
                        &Transform::from_matrix(m),
                        material,
                    )
                    .map_err(|e| placement_error(source, o, e))?;
                    if material.is_some() {
                        self.emitters(first, lights::DEFAULT_AREA_SAMPLES);
                    }
                }
            }
        }
        Ok(())
    }
}

/// An instance object's placements: its own transform alone, or each of a list
/// written in the file or handed over (Python's arrays), rows of 4 x 4 matrices.
enum Matrices<'a> {
    One,
    Listed(&'a [[[crate::format::scene_file::values::Num; 4]; 4]]),
    Named(&'a [[[f64; 4]; 4]]),
}

impl Matrices<'_> {
    fn len(&self) -> usize {
        match self {
            Matrices::One => 1,
            Matrices::Listed(m) => m.len(),
            Matrices::Named(m) => m.len(),
        }
    }

    /// Matrix `k`'s rows.
    fn rows(&self, k: usize) -> [[f64; 4]; 4] {
        match self {
            Matrices::One => glam::DMat4::IDENTITY.transpose().to_cols_array_2d(),
            Matrices::Listed(m) => m[k].map(|row| row.map(|n| n.0)),
            Matrices::Named(m) => m[k],
        }
    }

    /// Placement `k`: its matrix, then the object's transform `t`.
    fn placement(&self, k: usize, t: &Transform) -> glam::DMat4 {
        match self {
            Matrices::One => t.matrix(),
            _ => t.matrix() * glam::DMat4::from_cols_array_2d(&self.rows(k)).transpose(),
        }
    }
}

/// Fails, naming the transform, unless every matrix of `list` is finite and affine.
fn check_transforms(
    source: &Source,
    list: &Spanned<Transforms>,
    matrices: &Matrices,
) -> Result<()> {
    if matrices.len() > crate::util::limits::MAX_INSTANCES {
        return Err(source.error(
            list,
            format!(
                "expected at most {} transforms, found {}",
                crate::util::limits::MAX_INSTANCES,
                matrices.len()
            ),
        ));
    }
    for k in 0..matrices.len() {
        let rows = matrices.rows(k);
        if !rows
            .iter()
            .flatten()
            .all(|v| v.is_finite() && v.abs() <= 1e30)
        {
            return Err(source.error(
                list,
                format!("expected finite numbers in transform {k}, found {rows:?}"),
            ));
        }
        if rows[3] != [0.0, 0.0, 0.0, 1.0] {
            return Err(source.error(
                list,
                format!(
                    "expected the last row of transform {k} to be [0, 0, 0, 1] (an affine \
                     transform), found {:?}",
                    rows[3]
                ),
            ));
        }
    }
    Ok(())
}

/// A loaded mesh as instances place it: an object of `scene` wearing its own materials
/// (added to the scene's) or `material`, with the mesh lights of its emissive ones; or,
/// where it carries lights of other kinds, copies.
fn as_object(
    scene: &mut SceneBuilder,
    loaded: Scene,
    material: Option<u32>,
    name: &str,
) -> Result<Placed, String> {
    if !(0..loaded.shapes.len()).all(|i| loaded.shapes.is_triangle(i)) {
        return Err(
            "instances place triangle meshes, and this mesh file holds spheres or rectangles"
                .into(),
        );
    }
    let mesh_lights = |l: &Light| matches!(l.kind, LightKind::Mesh { .. });
    if !loaded.lights.iter().all(mesh_lights) {
        return Ok(Placed::Copies(Box::new(loaded)));
    }
    // An overriding material's glow is lit run by run as each instance is placed;
    // the file's own emissive materials come with their lights.
    let lights = match material {
        Some(_) => Vec::new(),
        None => loaded.lights.clone(),
    };
    let material_base = add_materials(scene, &loaded, material);
    let object = crate::scene::Object {
        name: name.to_owned(),
        material_of: loaded
            .material_of
            .iter()
            .map(|&m| material.unwrap_or(m + material_base))
            .collect(),
        shapes: loaded.shapes,
        meshes: loaded.meshes,
    };
    Ok(Placed::Object(scene.add_object(object), lights))
}
