//! glTF materials on the whitted model, and the images and samplers their textures
//! read. What each property becomes is tabled in docs/formats.md.

use super::document::{Loaded, read_uri};
use crate::format::image_file::{self, Encoding, MAX_IMAGE_FILE_BYTES, MAX_TEXTURE_PIXELS};
use crate::math::Vec3;
use crate::scene::material::linear_to_srgb;
use crate::scene::openpbr::{Channel, Color, Scalar};
use crate::scene::{Albedo, ImageTexture, Material, OpenPbr, Surface, TextureSlot};
use gltf::material::AlphaMode;
use gltf::texture::WrappingMode;

mod extensions;
use std::collections::HashMap;
use std::path::Path;

/// The scene's materials from a glTF file: `surfaces[i]` and `materials[i]` for glTF
/// material `i` (the scene adds Prism's default after them where a primitive names
/// none).
pub struct Materials {
    /// Classic placeholders: matte white under the glTF material's name (or
    /// `material i`), for the shapes to refer to.
    pub materials: Vec<Material>,
    /// The whitted terms each glTF material maps to: what is rendered.
    pub surfaces: Vec<Surface>,
    /// The decoded images the surfaces' texture slots index, each image once per
    /// encoding (sRGB colour, linear data).
    pub images: Vec<ImageTexture>,
    /// The texture-coordinate set (0 or 1) each material's textures read.
    pub texcoord_set: Vec<usize>,
}

/// The reflectance at normal incidence of a dielectric of index `ior` in air.
pub fn dielectric_f0(ior: f32) -> f32 {
    let r = (ior - 1.0) / (ior + 1.0);
    r * r
}

struct Images<'a> {
    loaded: &'a Loaded,
    path: &'a Path,
    images: Vec<ImageTexture>,
    index: HashMap<(usize, EncodingKey), u32>,
    warnings: &'a mut Vec<String>,
}

#[derive(Clone, Copy, Hash, PartialEq, Eq)]
enum EncodingKey {
    Srgb,
    Linear,
}

impl Images<'_> {
    /// The image of texture `texture` decoded as `encoding`, once per pair.
    fn image(&mut self, texture: &gltf::Texture, srgb: bool) -> Result<u32, String> {
        let image = texture.source();
        let key = (
            image.index(),
            if srgb {
                EncodingKey::Srgb
            } else {
                EncodingKey::Linear
            },
        );
        if let Some(&i) = self.index.get(&key) {
            return Ok(i);
        }
        let at = format!("images[{}]", image.index());
        let (bytes, name) = match image.source() {
            gltf::image::Source::Uri { uri, .. } => {
                let bytes = read_uri(uri, &self.loaded.folder, MAX_IMAGE_FILE_BYTES)
                    .map_err(|e| format!("{at}: {e}"))?;
                let name = if uri.starts_with("data:") {
                    format!("{}#{at}", self.path.display())
                } else {
                    self.loaded.folder.join(uri).display().to_string()
                };
                (bytes, name)
            }
            gltf::image::Source::View { view, mime_type } => {
                let buffer = &self.loaded.buffers[view.buffer().index()];
                let bytes = view
                    .offset()
                    .checked_add(view.length())
                    .and_then(|end| buffer.get(view.offset()..end))
                    .ok_or_else(|| {
                        format!(
                            "{at}: buffer view {} lies past its buffer's end",
                            view.index()
                        )
                    })?
                    .to_vec();
                let ext = mime_type.rsplit('/').next().unwrap_or("");
                (bytes, format!("{}#{at}.{ext}", self.path.display()))
            }
        };
        let encoding = if srgb {
            Encoding::Srgb
        } else {
            Encoding::Linear
        };
        let mut texture = image_file::decode_texture(&bytes, &name, encoding, MAX_TEXTURE_PIXELS)
            .map_err(|e| format!("{at}: cannot decode the image: {e}"))?;
        texture.name = name;
        let i = self.images.len() as u32;
        self.images.push(texture);
        self.index.insert(key, i);
        Ok(i)
    }

    /// A 1 x 1 image of alpha 0: the cut-out of a surface that is wholly transparent.
    fn clear(&mut self) -> u32 {
        let i = self.images.len() as u32;
        self.images.push(ImageTexture {
            name: "(transparent)".into(),
            width: 1,
            height: 1,
            texels: crate::scene::Texels::Rgba8 {
                texels: vec![[0; 4]],
                srgb: false,
            },
        });
        i
    }

    /// A texture reference as a slot: its image, its sampler's wrapping and its
    /// KHR_texture_transform.
    fn slot(&mut self, info: &gltf::texture::Info, srgb: bool) -> Result<TextureSlot, String> {
        let mut slot = self.texture_slot(&info.texture(), srgb)?;
        if let Some(tt) = info.texture_transform() {
            transform(&mut slot, tt.offset(), tt.rotation(), tt.scale());
        }
        Ok(slot)
    }

    /// A texture as a slot: its image and its sampler's wrapping.
    fn texture_slot(&mut self, texture: &gltf::Texture, srgb: bool) -> Result<TextureSlot, String> {
        let image = self.image(texture, srgb)?;
        let mut slot = TextureSlot::new(image);
        let sampler = texture.sampler();
        let (s, t) = (sampler.wrap_s(), sampler.wrap_t());
        slot.clamp = s == WrappingMode::ClampToEdge && t == WrappingMode::ClampToEdge;
        if (s == WrappingMode::ClampToEdge) != (t == WrappingMode::ClampToEdge)
            || s == WrappingMode::MirroredRepeat
            || t == WrappingMode::MirroredRepeat
        {
            self.warnings.push(format!(
                "{}: textures[{}]: its sampler's wrap modes ({s:?}, {t:?}) are read as {}",
                self.path.display(),
                texture.index(),
                if slot.clamp { "clamped" } else { "repeating" }
            ));
        }
        Ok(slot)
    }
}

/// Sets `slot` to look up KHR_texture_transform's `offset + R(rotation) scale uv`,
/// worked in glTF's texture space (v down) for coordinates Prism keeps with v up.
pub fn transform(slot: &mut TextureSlot, offset: [f32; 2], rotation: f32, scale: [f32; 2]) {
    // glTF space: (u', v') = A (u, v) + o, A = R S with R = [[c, s], [-s, c]] (the
    // extension's example: rotation by pi/2 turns the image clockwise).
    // Prism's v is 1 - v on both sides, so the lookup is A' (u, v) + o' with A' =
    // [[a, -b], [-c, d]] and o' = (b + o.x, 1 - d - o.y).
    let (s, c) = rotation.sin_cos();
    let a = [[c * scale[0], s * scale[1]], [-s * scale[0], c * scale[1]]];
    slot.offset = [a[0][1] + offset[0], 1.0 - a[1][1] - offset[1]];
    if rotation == 0.0 {
        slot.scale = [a[0][0], a[1][1]];
        slot.matrix = None;
    } else {
        slot.matrix = Some([[a[0][0], -a[0][1]], [-a[1][0], a[1][1]]]);
    }
}

/// The 2014 terms closest to a glTF material, for `--integrator classic`: its base
/// colour in display values, a mirror share from a smooth metal, and a glass's
/// refraction.
fn classic(name: String, s: &Surface) -> Material {
    let color = match &s.albedo {
        Albedo::Color(c) => *c,
        Albedo::Image { tint, .. } => *tint,
        _ => Vec3::ONE,
    };
    let mut m = Material {
        name,
        color: linear_to_srgb(color.clamp(Vec3::ZERO, Vec3::ONE)),
        ..Material::default_white()
    };
    if let Some(p) = &s.openpbr {
        let smooth = 1.0 - p.specular_roughness.value.clamp(0.0, 1.0);
        let transmission = p.transmission_weight.value.clamp(0.0, 1.0);
        m.reflect = p.base_metalness.value.clamp(0.0, 1.0) * smooth * smooth;
        m.refract = transmission;
        m.transparent = transmission > 0.0;
        m.ior = p.specular_ior.value;
        m.specular = 0.5 * smooth;
        // The Blinn-Phong exponent whose highlight is as wide as GGX's of this roughness.
        let a2 = p.specular_roughness.value.clamp(0.0, 1.0).powi(4);
        m.shininess = (2.0 / a2.max(2e-4) - 2.0).clamp(0.0, 1e4);
        m.diffuse = 1.0 - transmission;
    }
    m
}

/// Every material of the file.
pub fn read(loaded: &Loaded, path: &Path, warnings: &mut Vec<String>) -> Result<Materials, String> {
    let mut images = Images {
        loaded,
        path,
        images: Vec::new(),
        index: HashMap::new(),
        warnings,
    };
    let mut materials = Vec::new();
    let mut surfaces = Vec::new();
    let mut texcoord_set = Vec::new();
    for m in loaded.document.materials() {
        let i = m.index().expect("a material of the list has an index");
        let at = format!("materials[{i}]");
        let name = m
            .name()
            .map_or_else(|| format!("material {i}"), str::to_owned);
        let (surface, set) = surface(&m, &mut images).map_err(|e| format!("{at}: {e}"))?;
        materials.push(classic(name, &surface));
        surfaces.push(surface);
        texcoord_set.push(set);
    }
    Ok(Materials {
        materials,
        surfaces,
        images: images.images,
        texcoord_set,
    })
}

fn linear(c: [f32; 3]) -> Vec3 {
    Vec3::from_array(c).max(Vec3::ZERO)
}

/// One material's whitted terms and the texture-coordinate set its textures read.
fn surface(m: &gltf::Material, images: &mut Images) -> Result<(Surface, usize), String> {
    let pbr = m.pbr_metallic_roughness();
    let mut s = Surface::default();
    let mut sets = Vec::new();
    let note = |sets: &mut Vec<u32>, info: &gltf::texture::Info| {
        sets.push(
            info.texture_transform()
                .and_then(|t| t.tex_coord())
                .unwrap_or(info.tex_coord()),
        )
    };
    let spec_gloss = m.pbr_specular_glossiness();
    let (base, base_texture, mut metallic, mut roughness, mr_texture) = match &spec_gloss {
        // Specular-glossiness: its diffuse colour as the albedo, glossiness as
        // smoothness.
        Some(sg) => (
            sg.diffuse_factor(),
            sg.diffuse_texture(),
            0.0,
            1.0 - sg.glossiness_factor(),
            None,
        ),
        None => (
            pbr.base_color_factor(),
            pbr.base_color_texture(),
            pbr.metallic_factor(),
            pbr.roughness_factor(),
            pbr.metallic_roughness_texture(),
        ),
    };
    metallic = metallic.clamp(0.0, 1.0);
    roughness = roughness.clamp(0.0, 1.0);
    let tint = linear([base[0], base[1], base[2]]);
    s.albedo = match &base_texture {
        Some(info) => {
            note(&mut sets, info);
            Albedo::Image {
                slot: images.slot(info, true)?,
                tint,
            }
        }
        None => Albedo::Color(tint),
    };
    let mut blend = 1.0;
    match m.alpha_mode() {
        AlphaMode::Opaque => {}
        AlphaMode::Mask | AlphaMode::Blend => {
            // BLEND has no order-free meaning for rays: a texture's alpha is cut at
            // half, as MASK; a constant alpha is the surface's presence.
            let cutoff = if m.alpha_mode() == AlphaMode::Mask {
                m.alpha_cutoff().unwrap_or(0.5)
            } else {
                0.5
            };
            let alpha = base[3].clamp(0.0, 1.0);
            match &base_texture {
                // Alpha is never sRGB-encoded: the colour map's slot serves.
                Some(info) if alpha > 0.0 => {
                    s.alpha_map = Some(images.slot(info, true)?);
                    s.alpha_cutoff = cutoff / alpha;
                }
                // A constant alpha blended: the surface is that much present.
                _ if m.alpha_mode() == AlphaMode::Blend => blend = alpha,
                // A constant alpha masked: the whole surface is there or is not.
                _ if alpha < cutoff => s.alpha_map = Some(TextureSlot::new(images.clear())),
                _ => {}
            }
        }
    }
    if m.unlit() {
        s.lit = false;
        return Ok((s, first_set(&sets)));
    }
    let mut p = OpenPbr {
        base_metalness: Scalar::constant(metallic),
        specular_roughness: Scalar::constant(roughness),
        specular_ior: Scalar::constant(m.ior().unwrap_or(1.5)),
        ..OpenPbr::default()
    };
    if let Some(info) = &mr_texture {
        note(&mut sets, info);
        let slot = images.slot(info, false)?;
        p.specular_roughness.texture = Some((slot, Channel::G));
        p.base_metalness.texture = Some((slot, Channel::B));
    }
    if let Some(sg) = &spec_gloss {
        // Specular-glossiness: its specular colour is the dielectric's reflectance at
        // normal incidence, as a weight on that of index 1.5 and a tint.
        let f0 = linear(sg.specular_factor());
        let weight = f0.max_element() / dielectric_f0(1.5);
        p.specular_weight = Scalar::constant(weight);
        if weight > 0.0 {
            p.specular_color = Color::constant(f0 / f0.max_element());
        }
    }
    if let Some(spec) = m.specular() {
        p.specular_weight = Scalar::constant(spec.specular_factor().max(0.0));
        if let Some(info) = spec.specular_texture() {
            note(&mut sets, &info);
            p.specular_weight.texture = Some((images.slot(&info, false)?, Channel::A));
        }
        // glTF's specular colour does not tint metals; OpenPBR's would be their edge.
        if metallic < 1.0 || mr_texture.is_some() {
            p.specular_color = Color::constant(linear(spec.specular_color_factor()));
            if let Some(info) = spec.specular_color_texture() {
                note(&mut sets, &info);
                p.specular_color.texture = Some(images.slot(&info, true)?);
            }
        }
    }
    if let Some(t) = m.transmission() {
        p.transmission_weight = Scalar::constant(t.transmission_factor().clamp(0.0, 1.0));
        if let Some(info) = t.transmission_texture() {
            note(&mut sets, &info);
            p.transmission_weight.texture = Some((images.slot(&info, false)?, Channel::R));
        }
        // Light crossing takes the base colour.
        p.transmission_color = Color::constant(tint);
    }
    // Without KHR_materials_volume glTF calls a transmissive surface thin; Blender
    // writes its solid glass so, and reads it back as a solid: Prism reads it as
    // Blender does. A volume of thickness 0 is thin.
    if let Some(v) = m.volume() {
        p.geometry_thin_walled = v.thickness_factor() <= 0.0;
        let d = v.attenuation_distance();
        if !p.geometry_thin_walled && d.is_finite() && d > 0.0 {
            // Beer: attenuationColor is what remains after `d`.
            p.transmission_color = Color::constant(linear(v.attenuation_color()));
            p.transmission_depth = Scalar::constant(d);
            s.absorption = p.absorption();
        }
    }
    p.geometry_opacity = Scalar::constant(blend);
    extensions::read(m, &mut p, images, &mut sets)?;
    // Diffuse transmission without a volume is a thin sheet's (glTF's reading): there
    // is no medium under it to walk through.
    if m.volume().is_none() && p.subsurface_weight.value > 0.0 && p.transmission_weight.value == 0.0
    {
        p.geometry_thin_walled = true;
    }
    s.ior = p.specular_ior.value;
    s.openpbr = Some(Box::new(p));
    if let Some(normal) = m.normal_texture() {
        sets.push(normal.tex_coord());
        let texture = normal.texture();
        let image = images.image(&texture, false)?;
        s.normal_map = Some(TextureSlot {
            clamp: texture.sampler().wrap_s() == WrappingMode::ClampToEdge
                && texture.sampler().wrap_t() == WrappingMode::ClampToEdge,
            ..TextureSlot::new(image)
        });
        s.normal_scale = normal.scale();
    }
    let strength = m.emissive_strength().unwrap_or(1.0).max(0.0);
    let emission = linear(m.emissive_factor()) * strength;
    if emission.max_element() > 0.0 && emission.is_finite() {
        s.emission = emission;
        if let Some(info) = m.emissive_texture() {
            note(&mut sets, &info);
            s.emission_map = Some(images.slot(&info, true)?);
        }
    }
    Ok((s, first_set(&sets)))
}

fn first_set(sets: &[u32]) -> usize {
    match sets.first() {
        Some(&1) => 1,
        _ => 0,
    }
}
