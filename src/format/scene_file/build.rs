//! Puts the parsed files together into one [`Scene`]: materials first (so objects may
//! name materials defined anywhere), then objects and lights in file order, then the
//! planes (sized by the rest), the camera and the tracks.

use super::images::ImageCache;
use super::include::Document;
use super::materials::{self, BuiltMaterial, DEFAULT_COLOR};
use super::objects::{self, Geometry, place, placement_error};
use super::raw::{MaterialRef, RawObject, RawTrack};
use super::source::{Source, regular_file};
use super::transform::Transform;
use super::{camera, lights, settings, tracks};
use crate::error::Result;
use crate::math::{Aabb, Vec3, cross};
use crate::options::RenderOptions;
use crate::scene::material::linear_to_srgb;
use crate::scene::{
    Albedo, Camera, Falloff, Group, Light, LightKind, Material, Rectangle, Scene, SceneBuilder,
    Shape, ShapeId, Surface,
};
use std::collections::HashMap;
use toml::Spanned;

mod instances;

/// A plane is a square this many times the diagonal of everything else in the scene
/// (shapes and the camera's eye) on a side. From anywhere inside the scene its edge then
/// lies within about half a degree of the true horizon, while hits on it stay far from
/// f32's limits (a relative error of 1e-5 of the scene's size at the edge).
pub const PLANE_SCALE: f32 = 100.0;

/// What a name in the group namespace belongs to.
#[derive(Clone, Copy, PartialEq)]
enum Named {
    Object,
    Light,
}

#[derive(Default)]
struct Builder {
    scene: SceneBuilder,
    /// Material name to index, with where it was defined.
    materials: HashMap<String, (u32, String)>,
    default_material: Option<u32>,
    names: HashMap<String, Named>,
    /// Placeholder shapes of planes: index, point and unit normal.
    planes: Vec<(usize, Vec3, Vec3)>,
    images: ImageCache,
    warnings: Vec<String>,
    /// Meshes given in memory (Python's arrays), by the `file` name objects use.
    arrays: HashMap<String, Scene>,
    /// Placements given in memory (Python's arrays), by the `transforms` name
    /// instance objects use.
    transforms: HashMap<String, Vec<[[f64; 4]; 4]>>,
    /// Named mesh objects, which instances place by name.
    meshes: HashMap<String, MeshObject>,
    /// Triangles the lights of glowing instances name so far, each counted once per
    /// instance.
    placed_emitters: u64,
}

/// A named mesh object as instances place it: its file and how it was read, and once
/// an instance has placed it, what it became.
struct MeshObject {
    file: Spanned<String>,
    material: Option<u32>,
    up_axis: Option<Spanned<String>>,
    smooth: bool,
    placed: Option<Placed>,
}

impl MeshObject {
    /// The mesh file `file` read as object `o` asks, wearing `material`.
    fn of(o: &RawObject, file: &Spanned<String>, material: Option<u32>) -> MeshObject {
        MeshObject {
            file: file.clone(),
            material,
            up_axis: o.up_axis.clone(),
            smooth: o.smooth.as_ref().is_some_and(|s| *s.get_ref()),
            placed: None,
        }
    }
}

/// What instances of a mesh place.
#[derive(Clone)]
enum Placed {
    /// An object of the scene, held once, with the mesh lights its file gave (over
    /// its triangles, by their index in the object): each instance lights its own.
    Object(u32, Vec<Light>),
    /// A mesh that carries lights of other kinds: each placement copies it, so they
    /// are lights of the scene.
    Copies(Box<Scene>),
}

pub type Built = (Scene, Option<Camera>, RenderOptions, Vec<String>);

pub fn build(documents: &[Document], given: super::InMemory) -> Result<Built> {
    let mut b = Builder {
        arrays: given.meshes,
        transforms: given.transforms,
        ..Builder::default()
    };
    for doc in documents {
        for m in &doc.raw.material {
            b.named_material(&doc.source, m)?;
        }
    }
    for doc in documents {
        for (i, o) in doc.raw.object.iter().enumerate() {
            b.object(&doc.source, o, i)?;
        }
        for l in &doc.raw.light {
            b.light(&doc.source, l)?;
        }
    }
    let main = documents.last().expect("the main file is always read");
    let (source, raw) = (&main.source, &main.raw);
    let settings = match &raw.render {
        Some(r) => settings::render(source, r.get_ref())?,
        None => RenderOptions::default(),
    };
    let eye = raw
        .camera
        .as_ref()
        .and_then(|c| c.get_ref().from.as_ref())
        .map(|f| f.get_ref().vec3());
    b.size_planes(eye);
    if let Some(a) = &raw.ambient {
        b.scene.set_ambient(settings::ambient(source, a.get_ref())?);
    }
    if let Some(bg) = &raw.background {
        let background = settings::background(source, bg, &mut b.scene, &mut b.images)?;
        b.scene.set_background(background);
    }
    let camera = match &raw.camera {
        None => None,
        Some(c) => Some(camera::build(source, c, &settings, |name| {
            b.object_center(name)
        })?),
    };
    b.check_tracks(source, &raw.track)?;
    Ok((b.scene.finish(), camera, settings, b.warnings))
}

impl Builder {
    fn push_material(&mut self, built: BuiltMaterial) -> u32 {
        self.scene.add_material(built.material, built.surface)
    }

    fn named_material(
        &mut self,
        source: &Source,
        m: &Spanned<super::raw::RawMaterial>,
    ) -> Result<()> {
        let name = m
            .get_ref()
            .name
            .as_ref()
            .ok_or_else(|| source.error(m, "a [[material]] needs `name`"))?;
        let (line, column) = source.line_column(name.span().start);
        let here = format!("{}:{line}:{column}", source.path.display());
        if let Some((_, first)) = self.materials.get(name.get_ref()) {
            return Err(source.error(
                name,
                format!(
                    "material \"{}\" is defined twice (first at {first})",
                    name.get_ref()
                ),
            ));
        }
        let built = materials::build(
            source,
            m.get_ref(),
            name.get_ref().clone(),
            &mut self.scene,
            &mut self.images,
        )?;
        let index = self.push_material(built);
        self.materials.insert(name.get_ref().clone(), (index, here));
        Ok(())
    }

    fn default_material(&mut self) -> u32 {
        if let Some(i) = self.default_material {
            return i;
        }
        let surface = Surface {
            albedo: Albedo::Color(DEFAULT_COLOR),
            ambient: DEFAULT_COLOR,
            shininess: materials::DEFAULT_SHININESS,
            ..Surface::default()
        };
        let material = Material {
            name: "default".into(),
            color: linear_to_srgb(DEFAULT_COLOR),
            ..Material::default_white()
        };
        let i = self.push_material(BuiltMaterial { material, surface });
        self.default_material = Some(i);
        i
    }

    /// The material an object wears: `None` for a mesh that keeps its file's own.
    fn object_material(
        &mut self,
        source: &Source,
        o: &RawObject,
        label: &str,
    ) -> Result<Option<u32>> {
        let Some(m) = &o.material else {
            return Ok((o.kind.get_ref() != "mesh").then(|| self.default_material()));
        };
        match m.get_ref() {
            MaterialRef::Name(name) => match self.materials.get(name) {
                Some((i, _)) => Ok(Some(*i)),
                None => {
                    let mut known: Vec<&str> = self.materials.keys().map(String::as_str).collect();
                    known.sort_unstable();
                    known.truncate(12);
                    Err(source.error(
                        m,
                        format!(
                            "unknown material \"{name}\": expected one of the [[material]] names ({})",
                            if known.is_empty() { "there are none".to_string() } else { known.join(", ") }
                        ),
                    ))
                }
            },
            MaterialRef::Inline(raw) => {
                let built = materials::build(
                    source,
                    raw,
                    label.to_string(),
                    &mut self.scene,
                    &mut self.images,
                )?;
                Ok(Some(self.push_material(built)))
            }
        }
    }

    fn claim_name(&mut self, source: &Source, name: &Spanned<String>, what: Named) -> Result<()> {
        if name.get_ref().is_empty() {
            return Err(source.error(name, "expected a name that is not empty"));
        }
        if self.names.insert(name.get_ref().clone(), what).is_some() {
            return Err(source.error(
                name,
                format!(
                    "the name \"{}\" is already taken: objects and lights share one namespace",
                    name.get_ref()
                ),
            ));
        }
        Ok(())
    }

    fn object(&mut self, source: &Source, at: &Spanned<RawObject>, index: usize) -> Result<()> {
        let o = at.get_ref();
        if let Some(name) = &o.name {
            self.claim_name(source, name, Named::Object)?;
        }
        let label = match &o.name {
            Some(n) => n.get_ref().clone(),
            None => {
                let (line, _) = source.line_column(at.span().start);
                format!("{} object {} (line {line})", o.kind.get_ref(), index + 1)
            }
        };
        let transform = Transform::new(source, o)?;
        let geometry = objects::geometry(source, o)?;
        if let Geometry::Instance(what) = &geometry {
            let of = match what {
                objects::InstanceOf::Object(of) => {
                    if let Some(m) = &o.material {
                        return Err(source.error(
                            m,
                            "an instance wears the materials of the mesh it places: give \
                             `material` to that mesh object",
                        ));
                    }
                    of.clone()
                }
                objects::InstanceOf::File(file) => {
                    let material = match &o.material {
                        Some(_) => self.object_material(source, o, &label)?,
                        None => None,
                    };
                    // Held under the instance's name, for later instances' `of`.
                    let key = o
                        .name
                        .clone()
                        .unwrap_or_else(|| Spanned::new(file.span(), format!("\0{label}")));
                    self.meshes
                        .insert(key.get_ref().clone(), MeshObject::of(o, file, material));
                    key
                }
            };
            let first_instance = self.scene.scene().instances.len() as u32;
            let first = self.scene.scene().shapes.len() as u32;
            let first_light = self.scene.scene().lights.len() as u32;
            self.instance(source, o, &of, &transform)?;
            // A named instance object is a group an animation moves as one: its
            // instances, or the copies of a glowing mesh.
            if let Some(name) = &o.name {
                let scene = self.scene.scene();
                self.scene.add_group(Group {
                    name: name.get_ref().clone(),
                    shapes: (first..scene.shapes.len() as u32).collect(),
                    lights: (first_light..scene.lights.len() as u32).collect(),
                    instances: (first_instance..scene.instances.len() as u32).collect(),
                });
            }
            return Ok(());
        }
        let material = self.object_material(source, o, &label)?;
        if let (Geometry::Mesh(file), Some(name)) = (&geometry, &o.name) {
            self.meshes
                .insert(name.get_ref().clone(), MeshObject::of(o, file, material));
        }
        let emissive =
            |b: &Builder, m: u32| b.scene.scene().surfaces[m as usize].emission != Vec3::ZERO;
        let glowing = material.is_some_and(|m| emissive(self, m));
        let first = self.scene.scene().shapes.len();
        let first_light = self.scene.scene().lights.len();
        // A mesh file's own emissive materials come with their lights; planes are seen
        // glowing but light nothing (they are far too large to sample).
        let make_emitters = match geometry {
            Geometry::Instance(_) => unreachable!("instances return above"),
            Geometry::Mesh(_) => material.is_some(),
            Geometry::Plane { .. } => false,
            Geometry::Local(_) => true,
        };
        match geometry {
            Geometry::Local(local) => {
                let material = material.expect("primitives always wear a material");
                let placed = place(&local, &transform, glowing)
                    .map_err(|m| placement_error(source, o, m))?;
                if let Some(mut attributes) = placed.attributes {
                    attributes.first_shape = first as u32;
                    self.scene.add_attributes(attributes);
                }
                for shape in placed.shapes {
                    self.scene.add_shape(shape, material);
                }
            }
            Geometry::Plane { point, normal } => {
                let p = transform.point(point);
                let n =
                    transform.normal(Vec3::new(normal.x as f32, normal.y as f32, normal.z as f32));
                self.planes.push((first, p, n));
                let placeholder = Shape::Rectangle(Rectangle { v: [p; 4] });
                self.scene
                    .add_shape(placeholder, material.expect("planes wear a material"));
            }
            Geometry::Mesh(file) => self.merge_mesh(source, o, &file, &transform, material)?,
            Geometry::Instance(_) => unreachable!("instances return above"),
        }
        let samples = match &o.samples {
            None => lights::DEFAULT_AREA_SAMPLES,
            Some(n) if (1..=lights::MAX_AREA_SAMPLES).contains(n.get_ref()) => *n.get_ref(),
            Some(n) => {
                return Err(source.error(
                    n,
                    format!(
                        "expected samples between 1 and {}, found {}",
                        lights::MAX_AREA_SAMPLES,
                        n.get_ref()
                    ),
                ));
            }
        };
        if make_emitters {
            self.emitters(first, samples);
        }
        if let Some(n) = &o.samples
            && self.scene.scene().lights.len() == first_light
        {
            return Err(source.error(
                n,
                "`samples` applies to glowing objects (a material with `emission`) only",
            ));
        }
        if let Some(name) = &o.name {
            let scene = self.scene.scene();
            let (shapes, lights) = (scene.shapes.len() as u32, scene.lights.len() as u32);
            self.scene.add_group(Group {
                name: name.get_ref().clone(),
                shapes: (first as u32..shapes).collect(),
                lights: (first_light as u32..lights).collect(),
                instances: Vec::new(),
            });
        }
        Ok(())
    }

    /// Mesh lights for the glowing triangles instance `instance` places: one per run
    /// of triangles with one emissive material, as [`Builder::emitters`] makes them for
    /// a copy.
    fn instance_emitters(&mut self, instance: u32, samples: u32) {
        let scene = self.scene.scene();
        let object = &scene.objects[scene.instances[instance as usize].object() as usize];
        let material_of = &object.material_of;
        let mut runs = Vec::new();
        let mut i = 0;
        while i < material_of.len() {
            let m = material_of[i];
            let end = (i..material_of.len())
                .find(|&j| material_of[j] != m)
                .unwrap_or(material_of.len());
            let emission = scene.surfaces[m as usize].emission;
            if emission != Vec3::ZERO {
                runs.push((i as u32..end as u32, emission));
            }
            i = end;
        }
        for (run, emission) in runs {
            let shapes = run.map(|shape| ShapeId { instance, shape });
            if let Some(light) = mesh_light(self.scene.scene(), shapes, emission, samples) {
                self.scene.add_light(light);
            }
        }
    }

    /// Area lights for the glowing shapes from `first` on: a sphere light per sphere,
    /// a mesh light per run of triangles with one emissive material.
    fn emitters(&mut self, first: usize, samples: u32) {
        let end = self.scene.scene().shapes.len();
        let mut i = first;
        while i < end {
            let m = self.scene.scene().material_of[i];
            let emission = self.scene.scene().surfaces[m as usize].emission;
            if emission == Vec3::ZERO {
                i += 1;
                continue;
            }
            match self.scene.scene().shapes.get(i) {
                Shape::Sphere(s) => {
                    self.scene.add_light(Light {
                        position: s.center,
                        color: emission,
                        intensity: 1.0,
                        kind: LightKind::Sphere { radius: s.radius },
                        falloff: Default::default(),
                        samples,
                        camera_visible: true,
                    });
                    i += 1;
                }
                Shape::Rectangle(_) => i += 1,
                Shape::Triangle(_) => {
                    let run_end = (i..end)
                        .find(|&j| {
                            self.scene.scene().material_of[j] != m
                                || !matches!(self.scene.scene().shapes.get(j), Shape::Triangle(_))
                        })
                        .unwrap_or(end);
                    let run = (i as u32..run_end as u32).map(ShapeId::world);
                    if let Some(light) = mesh_light(self.scene.scene(), run, emission, samples) {
                        self.scene.add_light(light);
                    }
                    i = run_end;
                }
            }
        }
    }

    fn merge_mesh(
        &mut self,
        source: &Source,
        o: &RawObject,
        file: &Spanned<String>,
        t: &Transform,
        material: Option<u32>,
    ) -> Result<()> {
        let smooth = o.smooth.as_ref().is_some_and(|s| *s.get_ref());
        let loaded = self.load_mesh(source, file, &o.up_axis, smooth)?;
        merge(&mut self.scene, loaded, t, material).map_err(|m| placement_error(source, o, m))
    }

    /// The mesh `file` names (Python's arrays, or a file beside the scene), turned
    /// to y up and smoothed as its object asks.
    fn load_mesh(
        &self,
        source: &Source,
        file: &Spanned<String>,
        up_axis: &Option<Spanned<String>>,
        smooth: bool,
    ) -> Result<Scene> {
        if let Some(mesh) = self.arrays.get(file.get_ref()) {
            let mut loaded = mesh.clone();
            prepare_mesh(source, up_axis, smooth, &mut loaded)?;
            return Ok(loaded);
        }
        let path = source.resolve(file.get_ref());
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        if !["obj", "objx", "ply", "gltf", "glb"].contains(&ext.as_str()) {
            return Err(source.error(
                file,
                format!(
                    "expected a mesh file .obj, .ply, .gltf, .glb or .objx, found {}",
                    path.display()
                ),
            ));
        }
        regular_file(source, file, &path)?;
        let mut loaded = crate::format::load_scene(&path)?;
        if !loaded.instances.is_empty() {
            // A mesh object is one mesh: the instances of a file (a glTF's reused
            // meshes) become its own triangles.
            loaded = loaded.flattened();
        }
        prepare_mesh(source, up_axis, smooth, &mut loaded)?;
        Ok(loaded)
    }

    fn light(&mut self, source: &Source, at: &Spanned<super::raw::RawLight>) -> Result<()> {
        let raw = at.get_ref();
        if let Some(name) = &raw.name {
            self.claim_name(source, name, Named::Light)?;
        }
        let light = lights::build(source, raw)?;
        let index = self.scene.add_light(light);
        if let Some(name) = &raw.name {
            self.scene.add_group(Group {
                name: name.get_ref().clone(),
                lights: vec![index],
                ..Group::default()
            });
        }
        Ok(())
    }

    /// Replaces each plane's placeholder by a square [`PLANE_SCALE`] times the size
    /// of the rest of the scene.
    fn size_planes(&mut self, eye: Option<Vec3>) {
        let is_plane: Vec<usize> = self.planes.iter().map(|p| p.0).collect();
        let mut bounds = self
            .scene
            .scene()
            .shapes
            .iter()
            .enumerate()
            .filter(|(i, _)| !is_plane.contains(i))
            .fold(Aabb::EMPTY, |b, (_, s)| b.union(s.bounds()))
            .union(self.scene.scene().instance_boxes());
        if let Some(eye) = eye {
            bounds = bounds.grow(eye);
        }
        let size = if bounds.is_empty() {
            1.0
        } else {
            bounds.extent().length().max(1.0)
        };
        let half = 0.5 * PLANE_SCALE * size;
        for &(i, p, n) in &self.planes {
            let t1 = n.any_orthonormal_vector();
            let t2 = cross(n, t1);
            let (a, b) = (t1 * half, t2 * half);
            self.scene.set_shape(
                i,
                Shape::Rectangle(Rectangle {
                    v: [p - a - b, p + a - b, p + a + b, p - a + b],
                }),
            );
        }
    }

    fn object_center(&self, name: &str) -> Option<Vec3> {
        if self.names.get(name) != Some(&Named::Object) {
            return None;
        }
        let group = self.scene.scene().group(name)?;
        let bounds = group.shapes.iter().fold(Aabb::EMPTY, |b, &i| {
            b.union(self.scene.scene().shapes.get(i as usize).bounds())
        });
        (!bounds.is_empty()).then(|| bounds.center())
    }

    fn check_tracks(&self, source: &Source, raw: &[Spanned<RawTrack>]) -> Result<()> {
        let objects = |kind: Named| {
            let mut v: Vec<&str> = self
                .names
                .iter()
                .filter(|(_, k)| **k == kind)
                .map(|(n, _)| n.as_str())
                .collect();
            v.sort_unstable();
            v
        };
        let targets = tracks::Names {
            objects: objects(Named::Object),
            lights: objects(Named::Light),
            materials: self.materials.keys().map(String::as_str).collect(),
        };
        for t in raw {
            tracks::check(source, t, &targets)?;
        }
        Ok(())
    }
}

/// A mesh file's scene as its object asks: turned from +z up (`up_axis = "z"`), and
/// smooth where it has no normals (`smooth = true`).
fn prepare_mesh(
    source: &Source,
    up_axis: &Option<Spanned<String>>,
    smooth: bool,
    loaded: &mut Scene,
) -> Result<()> {
    match up_axis.as_ref().map(|a| (a, a.get_ref().as_str())) {
        None | Some((_, "y")) => {}
        Some((_, "z")) => crate::scene::mesh::turn_z_up_to_y_up(loaded),
        Some((a, other)) => {
            return Err(source.error(
                a,
                format!("expected up_axis \"y\" or \"z\", found \"{other}\""),
            ));
        }
    }
    if smooth {
        crate::scene::mesh::smooth_all(loaded);
    }
    Ok(())
}

/// Adds the materials, textures and images of `loaded` to `scene` unless `material`
/// overrides them; returns the index its first material gets.
fn add_materials(scene: &mut SceneBuilder, loaded: &Scene, material: Option<u32>) -> u32 {
    let image_base = scene.scene().images.len() as u32;
    let texture_base = scene.scene().textures.len() as u32;
    let material_base = scene.material_count();
    if material.is_none() {
        for (m, mut s) in loaded
            .materials
            .iter()
            .cloned()
            .zip(loaded.resolved_surfaces())
        {
            let mut m = m;
            m.texture = m.texture.map(|i| i + texture_base);
            for slot in s.image_slots_mut() {
                slot.image += image_base;
            }
            scene.add_material(m, s);
        }
        for texture in &loaded.textures {
            scene.add_texture(texture.clone());
        }
        for image in &loaded.images {
            scene.add_image(image.clone());
        }
    }
    material_base
}

/// The emitting triangles `shapes` as one area light, sampled in proportion to area.
fn mesh_light(
    scene: &Scene,
    shapes: impl Iterator<Item = ShapeId> + Clone,
    emission: Vec3,
    samples: u32,
) -> Option<Light> {
    let mut light = Light::mesh(scene, shapes.clone())?;
    let bounds = shapes.fold(Aabb::EMPTY, |b, i| b.union(scene.shape_at(i).bounds()));
    light.position = bounds.center();
    light.color = emission;
    light.samples = samples;
    Some(light)
}

/// Appends a scene read from a mesh file, placed by `t`: its shapes, meshes and lights,
/// and (unless `material` overrides them) its materials with their textures and images.
fn merge(
    scene: &mut SceneBuilder,
    loaded: Scene,
    t: &Transform,
    material: Option<u32>,
) -> Result<(), String> {
    let (triangles, vertices) = (loaded.shapes.len(), loaded.shapes.positions().len());
    if !scene.has_room_for(triangles as u64, vertices as u64) {
        return Err(format!(
            "placing this mesh would give the scene more than {} triangles or vertices",
            crate::util::limits::MAX_SHAPES
        ));
    }
    let shape_base = scene.scene().shapes.len() as u32;
    let mirrors = t.mirrors();
    let scale = t.uniform_scale();
    let material_base = add_materials(scene, &loaded, material);
    // Triangles keep their shared corners; a mirror reverses every winding.
    scene.add_placed(
        &loaded.shapes,
        |p| t.point_f32(p),
        mirrors,
        |mut s| {
            let k = scale.ok_or(
                "the mesh file holds spheres, which cannot be scaled differently along \
                 different axes: give one number to `scale`",
            )?;
            s.radius = (f64::from(s.radius) * k) as f32;
            Ok::<_, &str>(s)
        },
        loaded
            .material_of
            .iter()
            .map(|&m| material.unwrap_or(m + material_base)),
    )?;
    for mut mesh in loaded.meshes {
        mesh.first_shape += shape_base;
        for n in &mut mesh.normals {
            *n = t.normal(*n);
        }
        if mirrors {
            for idx in [
                &mut mesh.normal_indices,
                &mut mesh.texcoord_indices,
                &mut mesh.color_indices,
            ] {
                for tri in idx.iter_mut() {
                    tri.swap(1, 2);
                }
            }
        }
        scene.add_attributes(mesh);
    }
    let radius_scale = scale.unwrap_or_else(|| t.volume_scale()) as f32;
    for mut light in loaded.lights {
        light.position = t.point_f32(light.position);
        if let Falloff::Range { range } = &mut light.falloff {
            *range *= radius_scale;
        }
        match &mut light.kind {
            LightKind::Point => {}
            LightKind::Directional { direction } | LightKind::Spot { direction, .. } => {
                *direction = t.vector(*direction).normalize_or_zero();
            }
            LightKind::Quad { u, v } => {
                (*u, *v) = (t.vector(*u), t.vector(*v));
            }
            LightKind::Disk { normal, radius } => {
                *normal = t.normal(*normal);
                *radius *= radius_scale;
            }
            LightKind::Sphere { radius } => *radius *= radius_scale,
            // Its triangles now wear the overriding material instead.
            LightKind::Mesh { .. } if material.is_some() => continue,
            LightKind::Mesh { shapes, .. } => {
                // The placed triangles' areas: a scale changes them all, and an
                // uneven one their shares.
                let placed = shapes.iter().map(|s| ShapeId::world(s.shape + shape_base));
                let Some(mesh) = Light::mesh(scene.scene(), placed) else {
                    continue;
                };
                light.kind = mesh.kind;
            }
        }
        scene.add_light(light);
    }
    Ok(())
}
