//! The KHR material extensions the `gltf` crate leaves as JSON (clearcoat, sheen,
//! iridescence, anisotropy, dispersion, diffuse transmission), read onto OpenPBR's
//! parameters as docs/materials.md tables them.

use super::{Images, linear, transform};
use crate::math::Vec3;
use crate::scene::TextureSlot;
use crate::scene::openpbr::{Channel, OpenPbr};
use serde_json::Value;

/// An extension's object, for typed reads that name what is wrong.
struct Ext<'a> {
    name: &'static str,
    json: &'a serde_json::Map<String, Value>,
}

impl<'a> Ext<'a> {
    fn of(m: &'a gltf::Material, name: &'static str) -> Result<Option<Ext<'a>>, String> {
        match m.extension_value(name) {
            None => Ok(None),
            Some(Value::Object(json)) => Ok(Some(Ext { name, json })),
            Some(_) => Err(format!("{name}: expected an object")),
        }
    }

    /// A number in `range`, or `default` when absent.
    fn number(&self, key: &str, default: f32, range: (f32, f32)) -> Result<f32, String> {
        let Some(v) = self.json.get(key) else {
            return Ok(default);
        };
        let n = v
            .as_f64()
            .ok_or_else(|| format!("{}.{key}: expected a number", self.name))?
            as f32;
        if !(range.0..=range.1).contains(&n) {
            return Err(format!(
                "{}.{key}: expected a number from {} to {}, found {n}",
                self.name, range.0, range.1
            ));
        }
        Ok(n)
    }

    /// An RGB factor of 0..1 channels.
    fn color(&self, key: &str, default: Vec3) -> Result<Vec3, String> {
        let Some(v) = self.json.get(key) else {
            return Ok(default);
        };
        let bad = || format!("{}.{key}: expected three numbers from 0 to 1", self.name);
        let a = v.as_array().filter(|a| a.len() == 3).ok_or_else(bad)?;
        let mut c = [0.0; 3];
        for (c, v) in c.iter_mut().zip(a) {
            *c = v
                .as_f64()
                .filter(|x| (0.0..=1.0).contains(x))
                .ok_or_else(bad)? as f32;
        }
        Ok(linear(c))
    }

    /// A texture reference (`{"index", "texCoord", "extensions": {KHR_texture_transform}}`)
    /// as a slot, its set noted in `sets`.
    fn texture(
        &self,
        key: &str,
        srgb: bool,
        images: &mut Images,
        sets: &mut Vec<u32>,
    ) -> Result<Option<TextureSlot>, String> {
        let Some(info) = self.json.get(key) else {
            return Ok(None);
        };
        let at = format!("{}.{key}", self.name);
        let index = info
            .get("index")
            .and_then(Value::as_u64)
            .ok_or_else(|| format!("{at}: expected an `index`"))?;
        let texture = images
            .loaded
            .document
            .textures()
            .nth(index as usize)
            .ok_or_else(|| format!("{at}: no texture {index}"))?;
        let transform_json = info
            .get("extensions")
            .and_then(|e| e.get("KHR_texture_transform"));
        let set = transform_json
            .and_then(|t| t.get("texCoord"))
            .or_else(|| info.get("texCoord"))
            .and_then(Value::as_u64)
            .unwrap_or(0);
        sets.push(set.min(u32::MAX as u64) as u32);
        let mut slot = images.texture_slot(&texture, srgb)?;
        if let Some(t) = transform_json {
            let pair = |k: &str, d: [f32; 2]| {
                t.get(k)
                    .and_then(Value::as_array)
                    .filter(|a| a.len() == 2)
                    .and_then(|a| Some([a[0].as_f64()? as f32, a[1].as_f64()? as f32]))
                    .unwrap_or(d)
            };
            let rotation = t.get("rotation").and_then(Value::as_f64).unwrap_or(0.0) as f32;
            transform(
                &mut slot,
                pair("offset", [0.0, 0.0]),
                rotation,
                pair("scale", [1.0, 1.0]),
            );
        }
        Ok(Some(slot))
    }
}

/// Reads the extensions of `m` onto `p`, noting the texture sets they read in `sets`.
pub(super) fn read(
    m: &gltf::Material,
    p: &mut OpenPbr,
    images: &mut Images,
    sets: &mut Vec<u32>,
) -> Result<(), String> {
    let unit = (0.0, 1.0);
    if let Some(e) = Ext::of(m, "KHR_materials_clearcoat")? {
        p.coat_weight.value = e.number("clearcoatFactor", 0.0, unit)?;
        p.coat_weight.texture = e
            .texture("clearcoatTexture", false, images, sets)?
            .map(|s| (s, Channel::R));
        p.coat_roughness.value = e.number("clearcoatRoughnessFactor", 0.0, unit)?;
        p.coat_roughness.texture = e
            .texture("clearcoatRoughnessTexture", false, images, sets)?
            .map(|s| (s, Channel::G));
        // glTF's clear coat is a dielectric of index 1.5, uncoloured.
        p.coat_ior.value = 1.5;
        if let Some(slot) = e.texture("clearcoatNormalTexture", false, images, sets)? {
            let scale = e
                .json
                .get("clearcoatNormalTexture")
                .and_then(|t| t.get("scale"))
                .and_then(Value::as_f64)
                .unwrap_or(1.0) as f32;
            p.geometry_coat_normal = Some((slot, scale));
        }
    }
    if let Some(e) = Ext::of(m, "KHR_materials_sheen")? {
        let color = e.color("sheenColorFactor", Vec3::ZERO)?;
        let texture = e.texture("sheenColorTexture", true, images, sets)?;
        if color.max_element() > 0.0 {
            p.fuzz_weight.value = 1.0;
            p.fuzz_color.value = color;
            p.fuzz_color.texture = texture;
        }
        p.fuzz_roughness.value = e.number("sheenRoughnessFactor", 0.0, unit)?;
        p.fuzz_roughness.texture = e
            .texture("sheenRoughnessTexture", false, images, sets)?
            .map(|s| (s, Channel::A));
    }
    if let Some(e) = Ext::of(m, "KHR_materials_iridescence")? {
        p.thin_film_weight.value = e.number("iridescenceFactor", 0.0, unit)?;
        p.thin_film_weight.texture = e
            .texture("iridescenceTexture", false, images, sets)?
            .map(|s| (s, Channel::R));
        p.thin_film_ior.value = e.number("iridescenceIor", 1.3, (1.0, 3.0))?;
        let max = e.number("iridescenceThicknessMaximum", 400.0, (0.0, 1e5))?;
        // Nanometres to micrometres; a thickness map scales the maximum.
        p.thin_film_thickness.value = max / 1000.0;
        p.thin_film_thickness.texture = e
            .texture("iridescenceThicknessTexture", false, images, sets)?
            .map(|s| (s, Channel::G));
    }
    if let Some(e) = Ext::of(m, "KHR_materials_anisotropy")? {
        p.specular_roughness_anisotropy.value = e.number("anisotropyStrength", 0.0, unit)?;
        let rotation = e.number("anisotropyRotation", 0.0, (-1e4, 1e4))?;
        p.tangent_rotation = rotation / std::f32::consts::TAU;
        p.specular_roughness_anisotropy.texture = e
            .texture("anisotropyTexture", false, images, sets)?
            .map(|s| (s, Channel::B));
    }
    if let Some(e) = Ext::of(m, "KHR_materials_dispersion")? {
        let dispersion = e.number("dispersion", 0.0, (0.0, 1e4))?;
        if dispersion > 0.0 {
            p.transmission_dispersion_scale.value = 1.0;
            p.transmission_dispersion_abbe_number.value = 20.0 / dispersion;
        }
    }
    if let Some(e) = Ext::of(m, "KHR_materials_diffuse_transmission")? {
        p.subsurface_weight.value = e.number("diffuseTransmissionFactor", 0.0, unit)?;
        p.subsurface_weight.texture = e
            .texture("diffuseTransmissionTexture", false, images, sets)?
            .map(|s| (s, Channel::A));
        p.subsurface_color.value = e.color("diffuseTransmissionColorFactor", Vec3::ONE)?;
        p.subsurface_color.texture =
            e.texture("diffuseTransmissionColorTexture", true, images, sets)?;
    }
    Ok(())
}
