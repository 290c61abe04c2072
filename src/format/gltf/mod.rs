//! glTF 2.0 scenes (`.gltf` with its buffers and images, or `.glb`): the default scene's
//! node tree with its meshes, cameras, KHR_lights_punctual lights and
//! metallic-roughness materials. docs/formats.md tables what each property becomes.
//!
//! - [`document`]: the JSON or GLB container, extensions, buffers;
//! - [`accessor`]: typed reads out of buffers, checked before they allocate;
//! - [`mesh`]: primitives as triangles with their attributes;
//! - [`material`]: materials, textures and images;
//! - [`lights`]: cameras and lights.
//!
//! Every error names the file and the JSON path of what is wrong
//! (`scene.gltf: meshes[2].primitives[0].attributes.POSITION: ...`).

pub mod accessor;
pub mod document;
mod instancing;
pub mod lights;
pub mod material;
pub mod mesh;

use super::scene_file::lights::DEFAULT_AREA_SAMPLES;
use super::{NamedCamera, SceneDialect, SceneFile, SourceCounts};
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::options::RenderOptions;
use crate::scene::{
    Group, MAX_SHAPES, Material, MeshAttributes, MeshMaterials, Object, SceneBuilder, Surface,
};
use crate::util::limits::MAX_INSTANCES;
use glam::{Affine3A, DMat3, DMat4, DQuat, DVec3};
use std::collections::HashMap;
use std::path::Path;

/// Stops of exposure that show a scene lit in Blender's exported photometric units as
/// Blender showed it: its exporter multiplies watts by 683 lm/W (and 1/4 pi for point
/// and spot lights, which Blender's own radiometric units also carry).
pub const BLENDER_EXPOSURE: f32 = -9.415_741;

/// Reads a `.gltf` or `.glb` scene.
pub fn load(path: &Path) -> Result<SceneFile> {
    let loaded = document::load(path)?;
    build(&loaded, path)
}

/// Builds the scene of a parsed file (its buffers loaded); `path` names it in messages
/// and resolves its images.
pub fn build(loaded: &document::Loaded, path: &Path) -> Result<SceneFile> {
    let err = |m: String| Error::file(path, m);
    let doc = &loaded.document;
    let mut warnings: Vec<String> = loaded
        .ignored_extensions
        .iter()
        .map(|e| {
            format!(
                "{}: uses the glTF extension {e}, which Prism ignores",
                path.display()
            )
        })
        .collect();
    let materials = material::read(loaded, path, &mut warnings).map_err(err)?;
    // Primitives without a material wear this one, added after the file's when used.
    let default_material = materials.materials.len() as u32;
    let mut scene = SceneBuilder::new();
    for image in materials.images {
        scene.add_image(image);
    }
    for (m, s) in materials.materials.into_iter().zip(materials.surfaces) {
        scene.add_material(m, s);
    }
    let texcoord_set = materials.texcoord_set;

    let roots = scene_roots(doc).map_err(err)?;
    let uses = mesh_uses(doc, &roots);
    // Meshes placed more than once become objects, placed by instances.
    let mut objects: HashMap<usize, u32> = HashMap::new();
    let mut meshes: HashMap<usize, Vec<mesh::Primitive>> = HashMap::new();
    let mut skipped = mesh::Skipped::default();
    let mut cameras = Vec::new();
    let mut counts = SourceCounts::default();
    let mut stack: Vec<(gltf::Node, DMat4)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, DMat4::IDENTITY))
        .collect();
    while let Some((node, parent)) = stack.pop() {
        let at = format!("nodes[{}]", node.index());
        let world = parent * local_matrix(&node.transform());
        if !world.is_finite() {
            return Err(err(format!("{at}: its transform is not finite")));
        }
        let first_shape = scene.scene().shapes.len() as u32;
        let first_light = scene.scene().lights.len() as u32;
        let first_instance = scene.scene().instances.len() as u32;
        if let Some(m) = node.mesh() {
            if let std::collections::hash_map::Entry::Vacant(slot) = meshes.entry(m.index()) {
                let read = mesh::read(doc, &loaded.buffers, &m, &mut skipped).map_err(err)?;
                for p in &read {
                    counts.vertices += p.positions.len();
                    counts.normals += p.normals.len();
                    counts.texcoords += p.texcoords[0].len();
                }
                slot.insert(read);
            }
            let placements = match instancing::transforms(doc, &loaded.buffers, &node)
                .map_err(|e| err(format!("{at}: {e}")))?
            {
                Some(instances) => instances.iter().map(|t| world * *t).collect(),
                None => vec![world],
            };
            let wears = |p: &mesh::Primitive| {
                let material = p
                    .material
                    .map_or(default_material, |i| i as u32)
                    .min(default_material);
                let set = texcoord_set.get(material as usize).copied().unwrap_or(0);
                (material, set)
            };
            let primitives = &meshes[&m.index()];
            if uses.get(&m.index()).is_some_and(|&n| n > 1) {
                let object = *objects
                    .entry(m.index())
                    .or_insert_with(|| scene.add_object(object_of(primitives, m.name(), &wears)));
                for (k, world) in placements.iter().enumerate() {
                    if !world.is_finite() {
                        return Err(err(format!("{at}: instance {k}'s transform is not finite")));
                    }
                    if scene.scene().instances.len() >= MAX_INSTANCES {
                        return Err(err(format!(
                            "{at}: the file places more than {MAX_INSTANCES} instances"
                        )));
                    }
                    scene
                        .add_instance(object, Affine3A::from_mat4(world.as_mat4()))
                        .map_err(|e| err(format!("{at}: instance {k}: {e}")))?;
                }
            } else {
                for (k, world) in placements.iter().enumerate() {
                    if !world.is_finite() {
                        return Err(err(format!("{at}: instance {k}'s transform is not finite")));
                    }
                    for p in primitives {
                        let (material, set) = wears(p);
                        place(&mut scene, p, world, material, set)
                            .map_err(|e| err(format!("{at}: {e}")))?;
                    }
                }
            }
        }
        if let Some(c) = node.camera() {
            let camera = lights::camera(&c, &world)
                .map_err(|e| err(format!("{at}: cameras[{}]: {e}", c.index())))?;
            cameras.push(NamedCamera {
                name: node.name().or(c.name()).map(str::to_owned),
                camera,
            });
        }
        if let Some(l) = node.light() {
            let light = lights::light(&l, &world).map_err(|e| {
                err(format!(
                    "{at}: extensions.KHR_lights_punctual.lights[{}]: {e}",
                    l.index()
                ))
            })?;
            scene.add_light(light);
        }
        if let Some(name) = node.name() {
            let shapes: Vec<u32> = (first_shape..scene.scene().shapes.len() as u32).collect();
            let lights: Vec<u32> = (first_light..scene.scene().lights.len() as u32).collect();
            let instances: Vec<u32> =
                (first_instance..scene.scene().instances.len() as u32).collect();
            if !shapes.is_empty() || !lights.is_empty() || !instances.is_empty() {
                scene.add_group(Group {
                    name: name.to_owned(),
                    shapes,
                    lights,
                    instances,
                });
            }
        }
        for child in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((child, world));
        }
    }
    if skipped.points_and_lines > 0 {
        warnings.push(format!(
            "{}: {} primitives of points or lines are not rendered",
            path.display(),
            skipped.points_and_lines
        ));
    }
    let wears_default = |m: &[u32]| m.contains(&default_material);
    if wears_default(&scene.scene().material_of)
        || scene
            .scene()
            .objects
            .iter()
            .any(|o| wears_default(&o.material_of))
    {
        // glTF's default material is a rough white metal, which the whitted model
        // shows nearly black; Prism's matte default (as for OBJ and PLY) is what users
        // of a model without materials expect.
        scene.add_material(Material::default_white(), Surface::default());
    }
    let emitting = scene.emissive_triangles();
    if emitting > crate::util::limits::MAX_LIGHT_TRIANGLES {
        return Err(err(format!(
            "its emissive meshes place {emitting} triangles, more than the {} lights may hold",
            crate::util::limits::MAX_LIGHT_TRIANGLES
        )));
    }
    for name in scene.add_emissive_lights(DEFAULT_AREA_SAMPLES) {
        warnings.push(format!(
            "{}: material {} emits light but its faces have no area",
            path.display(),
            super::text::shown(&name)
        ));
    }
    let scene = scene.finish();
    let settings = RenderOptions {
        exposure: blender_lit(doc).then_some(BLENDER_EXPOSURE),
        ..RenderOptions::default()
    };
    Ok(SceneFile {
        dialect: SceneDialect::Gltf,
        camera: cameras.first().map(|c| c.camera.clone()),
        cameras,
        scene,
        settings,
        warnings,
        counts,
    })
}

/// Whether Blender's exporter wrote the file and it has lights (in its photometric
/// units: see [`BLENDER_EXPOSURE`]).
fn blender_lit(doc: &gltf::Document) -> bool {
    let by_blender = doc
        .as_json()
        .asset
        .generator
        .as_deref()
        .is_some_and(|g| g.contains("Blender"));
    by_blender && doc.lights().is_some_and(|mut l| l.next().is_some())
}

/// The root nodes of the default scene (else scene 0; none without scenes), after
/// checking that the node graph is a forest: no node has two parents or is its own
/// ancestor, so the walk from the roots ends.
fn scene_roots(doc: &gltf::Document) -> std::result::Result<Vec<gltf::Node<'_>>, String> {
    let count = doc.nodes().len();
    let mut parent: Vec<Option<usize>> = vec![None; count];
    for node in doc.nodes() {
        for child in node.children() {
            let c = child.index();
            if let Some(p) = parent[c] {
                return Err(format!(
                    "nodes[{c}] has two parents, nodes[{p}] and nodes[{}]",
                    node.index()
                ));
            }
            parent[c] = Some(node.index());
        }
    }
    let Some(scene) = doc.default_scene().or_else(|| doc.scenes().next()) else {
        return Ok(Vec::new());
    };
    let mut seen = vec![false; count];
    let mut roots = Vec::new();
    for node in scene.nodes() {
        let i = node.index();
        if let Some(p) = parent[i] {
            return Err(format!(
                "scenes[{}] lists nodes[{i}] as a root, but it is a child of nodes[{p}]",
                scene.index()
            ));
        }
        if !std::mem::replace(&mut seen[i], true) {
            roots.push(node);
        }
    }
    // A cycle has no root, so it is never reached from one; a cycle with a root path
    // into it would give one of its nodes two parents.
    Ok(roots)
}

/// How many times the default scene places each mesh (by index): once a node, or once
/// an instance of a node using EXT_mesh_gpu_instancing.
fn mesh_uses(doc: &gltf::Document, roots: &[gltf::Node<'_>]) -> HashMap<usize, usize> {
    let mut uses = HashMap::new();
    let mut stack: Vec<gltf::Node> = roots.to_vec();
    while let Some(node) = stack.pop() {
        if let Some(m) = node.mesh() {
            *uses.entry(m.index()).or_insert(0) += instancing::count(doc, &node);
        }
        stack.extend(node.children());
    }
    uses
}

/// A mesh's primitives as one object in the mesh's own space, each wearing the
/// material and texture-coordinate set `wears` gives it.
fn object_of(
    primitives: &[mesh::Primitive],
    name: Option<&str>,
    wears: &dyn Fn(&mesh::Primitive) -> (u32, usize),
) -> Object {
    let mut object = Object {
        name: name.unwrap_or_default().to_owned(),
        ..Object::default()
    };
    for p in primitives.iter().filter(|p| !p.triangles.is_empty()) {
        let (material, set) = wears(p);
        let first = object.shapes.len() as u32;
        object.shapes.push_mesh(&p.positions, &p.triangles);
        object
            .material_of
            .extend(std::iter::repeat_n(material, p.triangles.len()));
        let mut attributes = MeshAttributes::per_vertex(
            &p.triangles,
            p.normals.clone(),
            p.texcoords[set].clone(),
            p.colors.clone(),
        );
        if !(attributes.normal_indices.is_empty()
            && attributes.texcoord_indices.is_empty()
            && attributes.color_indices.is_empty())
        {
            attributes.first_shape = first;
            object.meshes.push(attributes);
        }
    }
    object
}

/// A node's local transform: its `matrix`, or translation x rotation x scale.
fn local_matrix(t: &gltf::scene::Transform) -> DMat4 {
    match t {
        gltf::scene::Transform::Matrix { matrix } => {
            DMat4::from_cols_array_2d(&matrix.map(|c| c.map(f64::from)))
        }
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let [x, y, z, w] = rotation.map(f64::from);
            let q = DQuat::from_xyzw(x, y, z, w);
            let q = if q.length_squared() > 0.0 {
                q.normalize()
            } else {
                DQuat::IDENTITY
            };
            DMat4::from_scale_rotation_translation(
                DVec3::from_array(scale.map(f64::from)),
                q,
                DVec3::from_array(translation.map(f64::from)),
            )
        }
    }
}

/// Adds primitive `p` placed at `world` wearing `material`, its texture coordinates
/// from set `set`.
fn place(
    scene: &mut SceneBuilder,
    p: &mesh::Primitive,
    world: &DMat4,
    material: u32,
    set: usize,
) -> std::result::Result<(), String> {
    if p.triangles.is_empty() {
        return Ok(());
    }
    if !scene.has_room_for(p.triangles.len() as u64, p.positions.len() as u64) {
        return Err(format!(
            "placing its mesh would give the scene more than {MAX_SHAPES} triangles or \
             vertices"
        ));
    }
    let positions: Vec<Vec3> = p
        .positions
        .iter()
        .map(|v| {
            let w =
                world.transform_point3(DVec3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z)));
            Vec3::new(w.x as f32, w.y as f32, w.z as f32)
        })
        .collect();
    if positions.iter().any(|v| !v.is_finite()) {
        return Err("its transform takes a vertex past the range of floats".into());
    }
    // A mirroring transform turns faces inside out: the spec keeps them facing out by
    // reversing their winding.
    let linear = DMat3::from_mat4(*world);
    let triangles: Vec<[u32; 3]> = if linear.determinant() < 0.0 {
        p.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect()
    } else {
        p.triangles.clone()
    };
    // A transform that flattens the mesh onto a plane has no inverse, and its plane
    // still a normal.
    let normal_matrix = match linear.inverse().transpose() {
        m if m.is_finite() => m,
        _ => crate::math::cofactor(linear),
    };
    let normals: Vec<Vec3> = p
        .normals
        .iter()
        .map(|n| {
            let w = (normal_matrix * DVec3::new(f64::from(n.x), f64::from(n.y), f64::from(n.z)))
                .normalize_or_zero();
            Vec3::new(w.x as f32, w.y as f32, w.z as f32)
        })
        .collect();
    // Attributes are per vertex: they share the positions' index triples.
    let attributes = MeshAttributes::per_vertex(
        &triangles,
        normals,
        p.texcoords[set].clone(),
        p.colors.clone(),
    );
    scene.add_mesh(
        &positions,
        &triangles,
        MeshMaterials::All(material),
        Some(attributes),
    );
    Ok(())
}

#[cfg(test)]
mod tests;
