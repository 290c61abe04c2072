//! Wavefront MTL material libraries, read into plain data ([`MtlMaterial`]): the colours,
//! scalars and texture maps Prism can use, with texture options applied and texture
//! paths resolved against the library's folder. No image is loaded here.
//!
//! Keys are case-sensitive as in the Wavefront manual, except that `map_bump`,
//! `map_Bump` and `bump` all name the bump map. The PBR extension's keys (`Pr`, `Pm`,
//! `Ps`, `Pc`, `Pcr`, `aniso`, `anisor`, and the maps of the first five) are read; keys Prism does not use
//! (`map_aniso`, `disp`, `map_Ns`, ...) are counted and reported, never fatal; a malformed number is
//! an error at its line and column. `docs/formats.md` ("OBJ/MTL") lists every decision.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::obj::{
    Line, Lines, Token, Tokens, Warning, decode_name, number, parse_f64, parse_integer, read_file,
    shown, without_bom,
};
use crate::error::{Error, Result};
use crate::math::Vec3;

/// One `newmtl` and what follows it. `None` means the key was not given.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MtlMaterial {
    /// As written after `newmtl`, spaces inside kept, ends trimmed.
    pub name: String,
    /// `Ka`, the ambient colour, as written (one number sets all three channels).
    pub ka: Option<Vec3>,
    /// `Kd`, the diffuse colour, as written.
    pub kd: Option<Vec3>,
    /// `Ks`, the specular (highlight) colour, as written.
    pub ks: Option<Vec3>,
    /// `Ke`, the emitted colour, as written.
    pub ke: Option<Vec3>,
    /// `Tf`, or its synonym `Kt`.
    pub tf: Option<Vec3>,
    /// `Ns`, the highlight exponent.
    pub ns: Option<f32>,
    /// `Ni`, the index of refraction inside the surface.
    pub ni: Option<f32>,
    /// `d`, or `1 - Tr` when only `Tr` is given (`d` wins whatever the order).
    pub d: Option<f32>,
    /// `illum`, the illumination model (Wavefront's are 0 to 10; others are kept, with a
    /// warning).
    pub illum: Option<u32>,
    /// `map_Kd`: image multiplying the diffuse colour.
    pub map_kd: Option<TextureMap>,
    /// `map_Ks`: image multiplying the specular colour.
    pub map_ks: Option<TextureMap>,
    /// `map_Ka`: image multiplying the ambient colour.
    pub map_ka: Option<TextureMap>,
    /// `map_Ke`: image multiplying the emitted colour.
    pub map_ke: Option<TextureMap>,
    /// `map_d`: image of the dissolve (opacity), for alpha cut-outs.
    pub map_d: Option<TextureMap>,
    /// `map_bump`, `map_Bump` or `bump`.
    pub bump: Option<TextureMap>,
    /// `norm`: a tangent-space normal map.
    pub norm: Option<TextureMap>,
    /// `refl`: a reflection map; for a cube map, its first face.
    pub refl: Option<TextureMap>,
    /// The PBR extension's scalars and their maps.
    pub pbr: MtlPbr,
    /// The library that defines it, and the line of its `newmtl`, for messages.
    pub path: PathBuf,
    /// 1-based line of the `newmtl` in `path`.
    pub line: usize,
}

/// The PBR extension of MTL (Exocortex's, as tinyobjloader, Blender and three.js read
/// it): scalars in 0..1, each optionally multiplied by a map's first channel.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MtlPbr {
    /// `Pr`, the roughness.
    pub roughness: Option<f32>,
    /// `Pm`, the metalness.
    pub metallic: Option<f32>,
    /// `Ps`, the sheen.
    pub sheen: Option<f32>,
    /// `Pc`, the clear coat's thickness (its weight).
    pub clearcoat: Option<f32>,
    /// `Pcr`, the clear coat's roughness.
    pub clearcoat_roughness: Option<f32>,
    /// `aniso`, the anisotropy of the roughness.
    pub anisotropy: Option<f32>,
    /// `anisor`, the anisotropy's direction: a rotation of the tangent in turns.
    pub anisotropy_rotation: Option<f32>,
    /// `map_Pr`.
    pub map_roughness: Option<TextureMap>,
    /// `map_Pm`.
    pub map_metallic: Option<TextureMap>,
    /// `map_Ps`.
    pub map_sheen: Option<TextureMap>,
    /// `map_Pc`.
    pub map_clearcoat: Option<TextureMap>,
    /// `map_Pcr`.
    pub map_clearcoat_roughness: Option<TextureMap>,
}

impl MtlPbr {
    /// Whether the material says anything in the PBR extension.
    pub fn is_given(&self) -> bool {
        *self != MtlPbr::default()
    }
}

/// A texture statement: the file and the options Prism applies; the others are kept
/// as written in `other_options`.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureMap {
    /// The file name as written (spaces kept, backslashes kept).
    pub name: String,
    /// `name` resolved against the library's folder, `\` read as `/`.
    pub path: PathBuf,
    /// `-s u [v [w]]`: missing components are 1.
    pub scale: [f32; 3],
    /// `-o u [v [w]]`: missing components are 0.
    pub offset: [f32; 3],
    /// `-clamp on|off`.
    pub clamp: bool,
    /// `-bm`.
    pub bump_multiplier: f32,
    /// `-colorspace NAME` (an extension: `sRGB`, `linear`...).
    pub colorspace: Option<String>,
    /// Options read but not applied, each as written: `-mm 0.1 0.3`, `-type sphere`.
    pub other_options: Vec<String>,
    /// The line of the library that names it, for messages about the image.
    pub line: usize,
}

impl TextureMap {
    fn new(name: String, path: PathBuf) -> TextureMap {
        TextureMap {
            name,
            path,
            scale: [1.0; 3],
            offset: [0.0; 3],
            clamp: false,
            bump_multiplier: 1.0,
            colorspace: None,
            other_options: Vec::new(),
            line: 0,
        }
    }
}

/// The materials of one library, with what was skipped.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MtlLibrary {
    /// The materials in file order, duplicates of a name included.
    pub materials: Vec<MtlMaterial>,
    /// What was read but not used, or read with a guess, each at its line.
    pub warnings: Vec<Warning>,
    /// Keys skipped, by name (`Pr`, `disp`, ..., `unknown`), with their counts.
    pub skipped: BTreeMap<String, usize>,
}

/// Reads a material library file (a regular file of at most 2 GiB).
pub fn load(path: &Path) -> Result<MtlLibrary> {
    let bytes = read_file(path, super::obj::MAX_FILE_BYTES)?;
    parse(&bytes, path)
}

/// Parses MTL text; `path` names it in messages and its folder resolves texture names.
pub fn parse(text: &[u8], path: &Path) -> Result<MtlLibrary> {
    let text = without_bom(text);
    let mut parser = Parser {
        path,
        folder: path.parent().unwrap_or(Path::new("")).to_path_buf(),
        library: MtlLibrary::default(),
        current: None,
        first_skipped: BTreeMap::new(),
        orphan_warned: false,
    };
    let mut lines = Lines::new(&text);
    while let Some(line) = lines.next_line() {
        parser.statement(&line)?;
    }
    parser.finish_material();
    for (kind, line) in std::mem::take(&mut parser.first_skipped) {
        let count = parser.library.skipped[&kind];
        let message = match kind.as_str() {
            "unknown" => format!("{count} unknown material statements skipped"),
            _ => format!("{count} `{kind}` statements skipped: Prism does not use them"),
        };
        parser.warn(line, message);
    }
    Ok(parser.library)
}

/// Keys read and not used, counted under their own name.
const SKIPPED_KEYS: &[&str] = &[
    "map_Ns",
    "map_NS",
    "disp",
    "decal",
    "map_Tr",
    "map_aat",
    "sharpness",
    "map_aniso",
    "map_anisor",
    "Km",
];

/// A material being read, with what `d` / `Tr` need to settle at its end.
struct Current {
    material: MtlMaterial,
    tr: Option<(f32, usize)>,
}

struct Parser<'p> {
    path: &'p Path,
    folder: PathBuf,
    library: MtlLibrary,
    current: Option<Current>,
    first_skipped: BTreeMap<String, usize>,
    orphan_warned: bool,
}

/// How many arguments a texture option takes.
#[derive(Clone, Copy)]
enum Arguments {
    /// One number, then up to two more if the tokens are numbers.
    UpToThreeNumbers,
    /// One number, then one more if it is a number.
    UpToTwoNumbers,
    OneNumber,
    OnOff,
    OneWord,
}

fn option_arguments(option: &[u8]) -> Option<Arguments> {
    Some(match option {
        b"-s" | b"-o" | b"-t" => Arguments::UpToThreeNumbers,
        b"-mm" => Arguments::UpToTwoNumbers,
        b"-bm" | b"-boost" => Arguments::OneNumber,
        b"-clamp" | b"-blendu" | b"-blendv" | b"-cc" => Arguments::OnOff,
        b"-colorspace" | b"-imfchan" | b"-type" | b"-texres" => Arguments::OneWord,
        _ => return None,
    })
}

impl Parser<'_> {
    fn error(&self, line: &Line, offset: usize, message: impl Into<String>) -> Error {
        let (number, column) = line.place(offset);
        Error::parse_at(self.path, number, column, message)
    }

    fn warn(&mut self, line: usize, message: impl Into<String>) {
        self.library.warnings.push(Warning {
            path: self.path.to_path_buf(),
            line,
            message: message.into(),
        });
    }

    fn skip(&mut self, kind: &str, line: usize) {
        *self.library.skipped.entry(kind.to_owned()).or_insert(0) += 1;
        self.first_skipped.entry(kind.to_owned()).or_insert(line);
    }

    fn statement(&mut self, line: &Line) -> Result<()> {
        let mut tokens = line.tokens();
        let Some(keyword) = tokens.next() else {
            return Ok(());
        };
        if keyword.bytes == b"newmtl" {
            self.finish_material();
            let name = line.rest_from(keyword.start + keyword.bytes.len());
            if name.is_empty() {
                self.warn(
                    line.number,
                    "newmtl without a name: the material is named \"\"",
                );
            }
            self.current = Some(Current {
                material: MtlMaterial {
                    name: decode_name(name),
                    path: self.path.to_path_buf(),
                    line: line.number,
                    ..MtlMaterial::default()
                },
                tr: None,
            });
            return Ok(());
        }
        let known = std::str::from_utf8(keyword.bytes)
            .ok()
            .filter(|k| SKIPPED_KEYS.contains(k));
        if let Some(kind) = known {
            self.skip(kind, line.number);
            return Ok(());
        }
        let Some(mut current) = self.current.take() else {
            if !self.orphan_warned {
                self.orphan_warned = true;
                self.warn(
                    line.number,
                    format!(
                        "{} comes before any newmtl: it is ignored, and so is what follows \
                         until the first newmtl",
                        shown(keyword.bytes)
                    ),
                );
            }
            return Ok(());
        };
        let result = self.material_statement(line, keyword, tokens, &mut current);
        self.current = Some(current);
        result
    }

    fn material_statement(
        &mut self,
        line: &Line,
        keyword: Token,
        tokens: Tokens,
        current: &mut Current,
    ) -> Result<()> {
        let m = &mut current.material;
        match keyword.bytes {
            b"Ka" => m.ka = self.color(line, keyword, tokens)?.or(m.ka),
            b"Kd" => m.kd = self.color(line, keyword, tokens)?.or(m.kd),
            b"Ks" => m.ks = self.color(line, keyword, tokens)?.or(m.ks),
            b"Ke" => m.ke = self.color(line, keyword, tokens)?.or(m.ke),
            b"Tf" | b"Kt" => m.tf = self.color(line, keyword, tokens)?.or(m.tf),
            b"Ns" => m.ns = Some(self.scalar(line, keyword, tokens, "the shininess")?),
            b"Ni" => m.ni = Some(self.scalar(line, keyword, tokens, "the index of refraction")?),
            b"d" => {
                let mut tokens = tokens;
                let mut look = tokens.clone();
                if look.next().is_some_and(|t| t.bytes == b"-halo") {
                    self.warn(line.number, "d -halo is read as a plain d");
                    tokens = look;
                }
                m.d = Some(self.scalar(line, keyword, tokens, "the dissolve (opacity)")?);
            }
            b"Tr" => {
                let tr = self.scalar(line, keyword, tokens, "the transparency")?;
                current.tr = Some((tr, line.number));
            }
            b"illum" => m.illum = Some(self.illumination(line, keyword, tokens)?),
            b"Pr" => m.pbr.roughness = Some(self.scalar(line, keyword, tokens, "the roughness")?),
            b"Pm" => m.pbr.metallic = Some(self.scalar(line, keyword, tokens, "the metalness")?),
            b"Ps" => m.pbr.sheen = Some(self.scalar(line, keyword, tokens, "the sheen")?),
            b"Pc" => {
                m.pbr.clearcoat = Some(self.scalar(line, keyword, tokens, "the clear coat")?)
            }
            b"Pcr" => {
                let what = "the clear coat's roughness";
                m.pbr.clearcoat_roughness = Some(self.scalar(line, keyword, tokens, what)?)
            }
            b"aniso" => {
                m.pbr.anisotropy = Some(self.scalar(line, keyword, tokens, "the anisotropy")?)
            }
            b"anisor" => {
                let what = "the anisotropy's rotation";
                m.pbr.anisotropy_rotation = Some(self.scalar(line, keyword, tokens, what)?)
            }
            b"map_Pr" | b"map_Pm" | b"map_Ps" | b"map_Pc" | b"map_Pcr" => {
                let map = self.texture(line, keyword, tokens)?;
                let slot = match keyword.bytes {
                    b"map_Pr" => &mut m.pbr.map_roughness,
                    b"map_Pm" => &mut m.pbr.map_metallic,
                    b"map_Ps" => &mut m.pbr.map_sheen,
                    b"map_Pc" => &mut m.pbr.map_clearcoat,
                    _ => &mut m.pbr.map_clearcoat_roughness,
                };
                *slot = map.or(slot.take());
            }
            b"map_Kd" => m.map_kd = self.texture(line, keyword, tokens)?.or(m.map_kd.take()),
            b"map_Ks" => m.map_ks = self.texture(line, keyword, tokens)?.or(m.map_ks.take()),
            b"map_Ka" => m.map_ka = self.texture(line, keyword, tokens)?.or(m.map_ka.take()),
            b"map_Ke" => m.map_ke = self.texture(line, keyword, tokens)?.or(m.map_ke.take()),
            b"map_d" => m.map_d = self.texture(line, keyword, tokens)?.or(m.map_d.take()),
            b"map_bump" | b"map_Bump" | b"bump" => {
                m.bump = self.texture(line, keyword, tokens)?.or(m.bump.take())
            }
            b"norm" => m.norm = self.texture(line, keyword, tokens)?.or(m.norm.take()),
            b"refl" => {
                // Cube maps give one `refl -type cube_...` per face: the first is kept.
                let map = self.texture(line, keyword, tokens)?;
                if m.refl.is_none() {
                    m.refl = map;
                }
            }
            _ => {
                if !self.library.skipped.contains_key("unknown") {
                    self.warn(
                        line.number,
                        format!(
                            "unknown material statement {} skipped",
                            shown(keyword.bytes)
                        ),
                    );
                }
                self.skip("unknown", line.number);
            }
        }
        Ok(())
    }

    /// Settles `d` and `Tr` and stores the material being read.
    fn finish_material(&mut self) {
        let Some(Current { mut material, tr }) = self.current.take() else {
            return;
        };
        match (material.d, tr) {
            (Some(_), Some((_, line))) => self.warn(
                line,
                format!(
                    "material {} gives both d and Tr: d is used",
                    shown(material.name.as_bytes())
                ),
            ),
            (None, Some((tr, _))) => material.d = Some(1.0 - tr),
            _ => {}
        }
        self.library.materials.push(material);
    }

    /// `r [g b]` (one value is grey); the spectral and CIE XYZ forms give a warning
    /// and no colour.
    fn color(&mut self, line: &Line, keyword: Token, mut tokens: Tokens) -> Result<Option<Vec3>> {
        let key = String::from_utf8_lossy(keyword.bytes).into_owned();
        let Some(first) = tokens.next() else {
            return Err(self.error(
                line,
                tokens.offset(),
                format!("expected a colour after {key} (r g b), found the end of the line"),
            ));
        };
        if first.bytes == b"spectral" || first.bytes == b"xyz" {
            self.warn(
                line.number,
                format!(
                    "{key} {} is not supported: the colour is left unset",
                    shown(first.bytes)
                ),
            );
            return Ok(None);
        }
        let r = number(self.path, line, first, &format!("the red of {key}"))?;
        let Some(green) = tokens.next() else {
            return Ok(Some(Vec3::splat(r)));
        };
        let g = number(self.path, line, green, &format!("the green of {key}"))?;
        let Some(blue) = tokens.next() else {
            return Err(self.error(
                line,
                tokens.offset(),
                format!("expected r g b after {key}, the blue is missing"),
            ));
        };
        let b = number(self.path, line, blue, &format!("the blue of {key}"))?;
        self.no_more(line, &key, tokens)?;
        Ok(Some(Vec3::new(r, g, b)))
    }

    fn scalar(&self, line: &Line, keyword: Token, mut tokens: Tokens, what: &str) -> Result<f32> {
        let key = String::from_utf8_lossy(keyword.bytes).into_owned();
        let Some(token) = tokens.next() else {
            return Err(self.error(
                line,
                tokens.offset(),
                format!("expected {what} after {key}, found the end of the line"),
            ));
        };
        let value = number(self.path, line, token, what)?;
        self.no_more(line, &key, tokens)?;
        Ok(value)
    }

    fn no_more(&self, line: &Line, key: &str, mut tokens: Tokens) -> Result<()> {
        match tokens.next() {
            Some(extra) => Err(self.error(
                line,
                extra.start,
                format!(
                    "expected the end of the line after {key}'s values, found {}",
                    shown(extra.bytes)
                ),
            )),
            None => Ok(()),
        }
    }

    fn illumination(&mut self, line: &Line, keyword: Token, mut tokens: Tokens) -> Result<u32> {
        let Some(token) = tokens.next() else {
            return Err(self.error(
                line,
                keyword.start + keyword.bytes.len(),
                "expected an illumination model (0 to 10) after illum, found the end of the line",
            ));
        };
        let Some(model) = parse_integer(token.bytes).and_then(|n| u32::try_from(n).ok()) else {
            return Err(self.error(
                line,
                token.start,
                format!(
                    "expected an illumination model (0 to 10) after illum, found {}",
                    shown(token.bytes)
                ),
            ));
        };
        if model > 10 {
            self.warn(
                line.number,
                format!("illum {model} is not one of Wavefront's 0 to 10"),
            );
        }
        self.no_more(line, "illum", tokens)?;
        Ok(model)
    }

    /// `map_X [options] file name`: the options, then the rest of the line as the name.
    fn texture(
        &mut self,
        line: &Line,
        keyword: Token,
        mut tokens: Tokens,
    ) -> Result<Option<TextureMap>> {
        let key = String::from_utf8_lossy(keyword.bytes).into_owned();
        let mut map = TextureMap::new(String::new(), PathBuf::new());
        map.line = line.number;
        loop {
            let mut look = tokens.clone();
            let Some(option) = look.next() else { break };
            let Some(arguments) = option_arguments(option.bytes) else {
                break;
            };
            tokens = look;
            let mut written = vec![String::from_utf8_lossy(option.bytes).into_owned()];
            let what = format!("{key}'s {}", String::from_utf8_lossy(option.bytes));
            let mut numbers = [0.0f32; 3];
            let (required, optional) = match arguments {
                Arguments::UpToThreeNumbers => (1, 2),
                Arguments::UpToTwoNumbers => (1, 1),
                Arguments::OneNumber => (1, 0),
                Arguments::OnOff | Arguments::OneWord => (0, 0),
            };
            let mut count = 0;
            for _ in 0..required {
                let Some(token) = tokens.next() else {
                    return Err(self.error(
                        line,
                        tokens.offset(),
                        format!("expected a number for {what}, found the end of the line"),
                    ));
                };
                numbers[count] = number(self.path, line, token, &what)?;
                written.push(String::from_utf8_lossy(token.bytes).into_owned());
                count += 1;
            }
            for _ in 0..optional {
                let mut look = tokens.clone();
                let Some(token) = look.next() else { break };
                if parse_f64(token.bytes).is_none() {
                    break;
                }
                tokens = look;
                // A number beyond f32 (or not finite) is an error, as anywhere else.
                numbers[count] = number(self.path, line, token, &what)?;
                written.push(String::from_utf8_lossy(token.bytes).into_owned());
                count += 1;
            }
            let mut word = String::new();
            if matches!(arguments, Arguments::OnOff | Arguments::OneWord) {
                let Some(token) = tokens.next() else {
                    return Err(self.error(
                        line,
                        tokens.offset(),
                        format!("expected a value for {what}, found the end of the line"),
                    ));
                };
                word = decode_name(token.bytes);
                if matches!(arguments, Arguments::OnOff) && word != "on" && word != "off" {
                    return Err(self.error(
                        line,
                        token.start,
                        format!(
                            "expected on or off for {what}, found {}",
                            shown(token.bytes)
                        ),
                    ));
                }
                written.push(word.clone());
            }
            match option.bytes {
                b"-s" => map.scale = fill(numbers, count, 1.0),
                b"-o" => map.offset = fill(numbers, count, 0.0),
                b"-bm" => map.bump_multiplier = numbers[0],
                b"-clamp" => map.clamp = word == "on",
                b"-colorspace" => map.colorspace = Some(word),
                _ => map.other_options.push(written.join(" ")),
            }
        }
        let Some(first) = tokens.clone().next() else {
            self.warn(line.number, format!("{key} without a file name is ignored"));
            return Ok(None);
        };
        let name = line.rest_from(first.start);
        if let Some(late) = tokens.skip(1).find(|t| option_arguments(t.bytes).is_some()) {
            self.warn(
                line.number,
                format!(
                    "{key}'s file name {} holds the option {}: options must come before \
                     the file name, so it is read as part of the name",
                    shown(name),
                    shown(late.bytes)
                ),
            );
        }
        map.name = decode_name(name);
        map.path = self.folder.join(map.name.replace('\\', "/"));
        Ok(Some(map))
    }
}

/// The first `count` of `numbers`, the rest `default`.
fn fill(numbers: [f32; 3], count: usize, default: f32) -> [f32; 3] {
    std::array::from_fn(|i| if i < count { numbers[i] } else { default })
}

#[cfg(test)]
mod tests;
