//! A Wavefront OBJ file (with its MTL libraries) as a Prism scene: triangles, their
//! normals, texture coordinates and colours, materials in both shading models, images,
//! and every emissive material as an area light (SPEC 4.1-4.2; docs/formats.md).

use super::image_file::{Encoding, read_texture};
use super::mtl::{MtlMaterial, TextureMap};
use super::obj::{ObjFile, load_obj};
use super::{SceneDialect, SceneFile, SourceCounts};
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::scene::openpbr::{Channel, Color, Scalar};
use crate::scene::{
    Albedo, Group, ImageTexture, Material, MeshAttributes, MeshMaterials, OpenPbr, SceneBuilder,
    Surface, TextureSlot,
};
use crate::util::text::{shown, shown_path};
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Reads an OBJ file as a scene.
pub fn load(path: &Path) -> Result<SceneFile> {
    let obj = load_obj(path)?;
    from_obj(obj, path)
}

/// Builds the scene of a parsed OBJ file; textures are read from disk.
pub fn from_obj(obj: ObjFile, path: &Path) -> Result<SceneFile> {
    let mut warnings: Vec<String> = obj.warnings.iter().map(|w| w.to_string()).collect();
    let counts = SourceCounts {
        vertices: obj.positions.len(),
        normals: obj.normals.len(),
        texcoords: obj.texcoords.len(),
    };
    let mut scene = SceneBuilder::new();
    if obj.triangles.len() > u32::MAX as usize / 2 {
        return Err(Error::file(path, "more triangles than Prism can index"));
    }

    // Materials in library order, then the default for faces without one.
    let mut images = ImageCache::default();
    for m in &obj.materials {
        let (material, surface) = convert_material(m, &mut images, &mut warnings)?;
        scene.add_material(material, surface);
    }
    // One pass over the triangles finds what they use.
    let (any_default, any_vn, any_vt) = obj
        .triangles
        .par_iter()
        .map(|t| (t.material.is_none(), t.vn.is_some(), t.vt.is_some()))
        .reduce(
            || (false, false, false),
            |a, b| (a.0 || b.0, a.1 || b.1, a.2 || b.2),
        );
    let default_material = scene.material_count();
    if any_default {
        scene.add_material(Material::default_white(), Surface::default());
    }

    // Triangles, and the attributes they carry. Shapes are independent of each other;
    // the attributes a face lacks are appended in file order, so they stay on one thread.
    let n = obj.triangles.len();
    let positions = &obj.positions;
    let corners: Vec<[u32; 3]> = obj.triangles.par_iter().map(|t| t.v).collect();
    let mut material_of = Vec::new();
    obj.triangles
        .par_iter()
        .map(|t| t.material.unwrap_or(default_material))
        .collect_into_vec(&mut material_of);
    scene.add_mesh(positions, &corners, MeshMaterials::Each(&material_of), None);
    drop((corners, material_of));
    let mut mesh = MeshAttributes {
        first_shape: 0,
        len: n as u32,
        normals: obj.normals,
        texcoords: obj.texcoords,
        ..MeshAttributes::default()
    };
    if any_vn {
        mesh.normal_indices.reserve_exact(n);
        for (t, shape) in obj.triangles.iter().zip(scene.scene().shapes.iter()) {
            // Faces without normals keep their flat one: a normal of their own.
            let vn = t.vn.unwrap_or_else(|| {
                let i = mesh.normals.len() as u32;
                mesh.normals.push(shape.normal(positions[t.v[0] as usize]));
                [i; 3]
            });
            mesh.normal_indices.push(vn);
        }
    }
    if any_vt {
        mesh.texcoord_indices.reserve_exact(n);
        for t in &obj.triangles {
            let vt = t.vt.unwrap_or_else(|| {
                let i = mesh.texcoords.len() as u32;
                mesh.texcoords.push([0.0, 0.0]);
                [i; 3]
            });
            mesh.texcoord_indices.push(vt);
        }
    }
    let has_colors = !obj.colors.is_empty();
    if has_colors {
        obj.triangles
            .par_iter()
            .map(|t| t.v)
            .collect_into_vec(&mut mesh.color_indices);
    }
    if !any_vn {
        mesh.normals.clear();
    }
    if !any_vt {
        mesh.texcoords.clear();
    }
    if has_colors {
        mesh.colors = obj.colors;
    }
    mesh.check()
        .map_err(|e| Error::file(path, format!("inconsistent mesh: {e}")))?;
    if !(mesh.normals.is_empty() && mesh.texcoords.is_empty() && mesh.colors.is_empty()) {
        scene.add_attributes(mesh);
    }

    // Named objects and groups; one group per name, in order of first appearance.
    let mut group_of: HashMap<String, usize> = HashMap::new();
    let mut groups: Vec<Group> = Vec::new();
    for g in &obj.groups {
        if g.triangles.is_empty() || g.name.is_empty() {
            continue;
        }
        let index = *group_of.entry(g.name.clone()).or_insert_with(|| {
            groups.push(Group {
                name: g.name.clone(),
                ..Group::default()
            });
            groups.len() - 1
        });
        groups[index]
            .shapes
            .extend(g.triangles.clone().map(|i| i as u32));
    }
    for mut g in groups {
        g.shapes.sort_unstable();
        g.shapes.dedup();
        scene.add_group(g);
    }

    // Every emissive material's triangles form one area light.
    for name in scene.add_emissive_lights(DEFAULT_AREA_SAMPLES) {
        warnings.push(format!(
            "{}: material {} emits light but its faces have no area",
            path.display(),
            shown(&name)
        ));
    }
    for image in images.images {
        scene.add_image(image);
    }
    let scene = scene.finish();
    Ok(SceneFile {
        dialect: SceneDialect::WavefrontObj,
        scene,
        camera: None,
        cameras: Vec::new(),
        settings: Default::default(),
        warnings,
        counts,
    })
}

/// Shadow rays per shading point toward an emissive mesh: enough for a soft shadow
/// without visible banding at one camera ray per pixel.
pub const DEFAULT_AREA_SAMPLES: u32 = 16;

/// Images by (file, encoding), read once however many materials name them.
#[derive(Default)]
struct ImageCache {
    images: Vec<ImageTexture>,
    index: HashMap<(PathBuf, bool, u8), u32>,
}

impl ImageCache {
    /// The slot of `map`, reading its image once. A missing file is a warning (the
    /// material keeps its colour); a file that is there but cannot be used (too large,
    /// truncated, not an image, not a regular file) is an error naming the MTL line.
    fn slot(
        &mut self,
        map: &TextureMap,
        encoding: Encoding,
        material: &MtlMaterial,
        warnings: &mut Vec<String>,
    ) -> Result<Option<TextureSlot>> {
        let key = (map.path.clone(), map.clamp, encoding as u8);
        let image = match self.index.get(&key) {
            Some(&i) => i,
            None if std::fs::symlink_metadata(&map.path).is_err() => {
                warnings.push(format!(
                    "{}:{}: texture {} of material {} is missing; it is left out",
                    material.path.display(),
                    map.line,
                    shown_path(&map.path),
                    shown(&material.name)
                ));
                return Ok(None);
            }
            None => {
                let texture = read_texture(&map.path, encoding).map_err(|why| {
                    Error::parse(
                        &material.path,
                        map.line,
                        format!(
                            "cannot read texture {} of material {}: {why}",
                            shown_path(&map.path),
                            shown(&material.name)
                        ),
                    )
                })?;
                let i = self.images.len() as u32;
                self.images.push(texture);
                self.index.insert(key, i);
                i
            }
        };
        Ok(Some(TextureSlot {
            image,
            scale: [map.scale[0], map.scale[1]],
            offset: [map.offset[0], map.offset[1]],
            clamp: map.clamp,
            matrix: None,
        }))
    }
}

/// An MTL material in both shading models (SPEC 4.2).
fn convert_material(
    m: &MtlMaterial,
    images: &mut ImageCache,
    warnings: &mut Vec<String>,
) -> Result<(Material, Surface)> {
    let kd = m.kd.unwrap_or(Vec3::splat(0.8));
    let ks = m.ks.unwrap_or(Vec3::ZERO);
    let ka = m.ka.unwrap_or(Vec3::ZERO);
    let ke = m.ke.unwrap_or(Vec3::ZERO);
    let ns = m.ns.unwrap_or(10.0).clamp(0.0, 1e4);
    let ior = m.ni.filter(|&n| n > 0.0).unwrap_or(1.0);
    let d = m.d.unwrap_or(1.0).clamp(0.0, 1.0);
    let illum = m.illum.unwrap_or(2);
    let tf = m.tf;

    let mut s = Surface {
        albedo: Albedo::Color(kd),
        ambient: ka,
        specular: ks,
        shininess: ns,
        emission: ke,
        ior,
        ..Surface::default()
    };
    match illum {
        0 => s.lit = false,
        1 | 10 => s.specular = Vec3::ZERO,
        2 => {}
        3 | 8 => s.reflection = ks,
        5 => {
            s.reflection = nonzero_or_white(ks);
            s.fresnel = true;
        }
        4 | 6 | 9 => {
            s.reflection = ks;
            s.transmission = tf.unwrap_or(Vec3::ONE);
        }
        7 => {
            s.reflection = nonzero_or_white(ks);
            s.transmission = tf.unwrap_or(Vec3::ONE);
            s.fresnel = true;
        }
        other => warnings.push(format!(
            "{}:{}: illum {other} of material {} is not one of 0-10; read as 2",
            m.path.display(),
            m.line,
            shown(&m.name)
        )),
    }
    // Dissolve on an otherwise opaque material: light passes straight through.
    if d < 1.0 && !s.is_transmissive() {
        s.transmission = Vec3::splat(1.0 - d);
        s.ior = 1.0;
        s.diffuse = d;
        s.specular *= d;
    }
    if let Some(map) = &m.map_kd
        && let Some(slot) = images.slot(map, Encoding::Srgb, m, warnings)?
    {
        s.albedo = Albedo::Image {
            slot,
            tint: Vec3::ONE,
        };
    }
    if let Some(map) = &m.map_d {
        s.alpha_map = images.slot(map, Encoding::Mask, m, warnings)?;
    }
    if let Some(map) = &m.norm {
        s.normal_map = images.slot(map, Encoding::Linear, m, warnings)?;
    }
    for (map, slot) in [
        (&m.map_ks, &mut s.specular_map),
        (&m.map_ka, &mut s.ambient_map),
        (&m.map_ke, &mut s.emission_map),
    ] {
        if let Some(map) = map {
            *slot = images.slot(map, Encoding::Srgb, m, warnings)?;
        }
    }
    for (key, map) in [("bump", &m.bump), ("refl", &m.refl)] {
        if map.is_some() {
            warnings.push(format!(
                "{}:{}: {key} of material {} is read but not applied",
                m.path.display(),
                m.line,
                shown(&m.name)
            ));
        }
    }

    if m.pbr.is_given() {
        s = pbr_surface(m, s, images, warnings)?;
    }

    // The classic reading: display colour, the 2014 factors.
    let seen = s.resolved();
    let material = Material {
        name: m.name.clone(),
        color: linear_to_display(kd),
        ambient: 0.2,
        diffuse: 0.8,
        specular: ks.max_element().clamp(0.0, 1.0),
        shininess: ns.max(1.0),
        ior,
        reflect: seen.reflection.max_element().clamp(0.0, 1.0),
        refract: seen.transmission.max_element().clamp(0.0, 1.0),
        transparent: seen.is_transmissive(),
        texture: None,
    };
    Ok((material, s))
}

/// A material of MTL's PBR extension on OpenPBR, from the Phong reading `phong` of its
/// other keys (its colour, emission, maps): `Kd` the base colour, `Pm` the metalness,
/// `Pr` the roughness (without it, Blender's reading of `Ns`), `Ps` the fuzz, `Pc` and
/// `Pcr` the coat, `aniso` and `anisor` the anisotropy, `Ni` the index (1.5 where it
/// is absent or 1, which exporters write for opaque materials), and illumination
/// models 4, 6, 7 and 9 glass of colour `Tf`, `d` its presence. A map multiplies its key's value (1
/// when the key is absent) by its first channel. `Ks` is not read: the extension
/// keeps it for Phong readers.
fn pbr_surface(
    m: &MtlMaterial,
    phong: Surface,
    images: &mut ImageCache,
    warnings: &mut Vec<String>,
) -> Result<Surface> {
    let pbr = &m.pbr;
    let ns = m.ns.unwrap_or(10.0).clamp(0.0, 1000.0);
    let unit = |v: Option<f32>, or: f32| Scalar::constant(v.unwrap_or(or).clamp(0.0, 1.0));
    let mut p = OpenPbr {
        base_metalness: unit(pbr.metallic, 0.0),
        specular_roughness: unit(pbr.roughness, 1.0 - (ns / 1000.0).sqrt()),
        specular_roughness_anisotropy: unit(pbr.anisotropy, 0.0),
        specular_ior: Scalar::constant(m.ni.filter(|&n| n > 1.0).unwrap_or(1.5)),
        fuzz_weight: unit(pbr.sheen, 0.0),
        coat_weight: unit(pbr.clearcoat, 0.0),
        coat_roughness: unit(pbr.clearcoat_roughness, 0.0),
        tangent_rotation: pbr.anisotropy_rotation.unwrap_or(0.0).rem_euclid(1.0),
        ..OpenPbr::default()
    };
    for (map, given, scalar) in [
        (&pbr.map_roughness, pbr.roughness, &mut p.specular_roughness),
        (&pbr.map_metallic, pbr.metallic, &mut p.base_metalness),
        (&pbr.map_sheen, pbr.sheen, &mut p.fuzz_weight),
        (&pbr.map_clearcoat, pbr.clearcoat, &mut p.coat_weight),
        (
            &pbr.map_clearcoat_roughness,
            pbr.clearcoat_roughness,
            &mut p.coat_roughness,
        ),
    ] {
        if let Some(map) = map
            && let Some(slot) = images.slot(map, Encoding::Linear, m, warnings)?
        {
            scalar.value = given.map_or(1.0, |v| v.clamp(0.0, 1.0));
            scalar.texture = Some((slot, Channel::R));
        }
    }
    if matches!(m.illum, Some(4 | 6 | 7 | 9)) {
        p.transmission_weight = Scalar::constant(1.0);
        p.transmission_color =
            Color::constant(m.tf.unwrap_or(Vec3::ONE).clamp(Vec3::ZERO, Vec3::ONE));
    } else if let Some(d) = m.d.filter(|&d| d < 1.0) {
        p.geometry_opacity = Scalar::constant(d.clamp(0.0, 1.0));
    }
    Ok(Surface {
        albedo: phong.albedo,
        emission: phong.emission,
        emission_map: phong.emission_map,
        alpha_map: phong.alpha_map,
        normal_map: phong.normal_map,
        lit: phong.lit,
        ior: p.specular_ior.value,
        openpbr: Some(Box::new(p)),
        ..Surface::default()
    })
}

/// A Fresnel surface's reflection tint: white when the file gives none (a glass with
/// `Ks 0` still reflects what Fresnel says).
fn nonzero_or_white(c: Vec3) -> Vec3 {
    if c.max_element() > 0.0 { c } else { Vec3::ONE }
}

/// Linear colour to the 0..1 display values the classic model shows.
fn linear_to_display(c: Vec3) -> Vec3 {
    Vec3::from_array(c.to_array().map(|v| {
        let v = v.clamp(0.0, 1.0);
        if v <= 0.003_130_8 {
            v * 12.92
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        }
    }))
}

#[cfg(test)]
mod tests;
