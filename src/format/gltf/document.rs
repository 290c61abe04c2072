//! A glTF file's JSON (from a `.gltf`, or a `.glb`'s first chunk) and its buffers: the
//! GLB's binary chunk, base64 `data:` URIs and files beside it, every file read through
//! [`crate::util::file`].

use crate::error::Error;
use crate::error::Result;
use base64::Engine as _;
use gltf::Document;
use std::path::{Path, PathBuf};

/// Largest glTF file read (JSON or GLB), and largest external buffer.
pub const MAX_GLTF_BYTES: u64 = 1 << 32;

/// Extensions Prism reads (or safely ignores: see docs/formats.md), so a file that
/// requires them still loads.
pub const SUPPORTED: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_unlit",
    "KHR_texture_transform",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_volume",
    "KHR_materials_specular",
    "KHR_materials_emissive_strength",
    "KHR_materials_pbrSpecularGlossiness",
    "KHR_materials_clearcoat",
    "KHR_materials_sheen",
    "KHR_materials_iridescence",
    "KHR_materials_anisotropy",
    "KHR_materials_dispersion",
    "KHR_materials_diffuse_transmission",
    "KHR_mesh_quantization",
    // Each instance is placed as a copy of the mesh.
    "EXT_mesh_gpu_instancing",
    // Each primitive's default material is the one rendered.
    "KHR_materials_variants",
];

/// A parsed glTF file with its buffers loaded.
#[derive(Debug)]
pub struct Loaded {
    /// The file's JSON, parsed and validated against the glTF 2.0 schema.
    pub document: Document,
    /// `buffers[i]` holds buffer `i`'s bytes, at least its stated `byteLength`.
    pub buffers: Vec<Vec<u8>>,
    /// Where relative URIs resolve.
    pub folder: PathBuf,
    /// The extensions the file uses that Prism does not read.
    pub ignored_extensions: Vec<String>,
}

/// Reads `path` (`.gltf` or `.glb`) and its buffers.
pub fn load(path: &Path) -> Result<Loaded> {
    let bytes = crate::util::file::read_regular(path, MAX_GLTF_BYTES)
        .map_err(|e| Error::file(path, format!("cannot read: {e}")))?;
    parse(&bytes, path)
}

/// Parses the bytes of the glTF file `path` and loads its buffers (external ones
/// relative to `path`'s folder).
pub fn parse(bytes: &[u8], path: &Path) -> Result<Loaded> {
    let (json, blob) = if bytes.starts_with(b"glTF") {
        let (json, bin) = split_glb(bytes).map_err(|e| Error::file(path, e))?;
        (json, bin)
    } else if bytes.len() >= 4 && bytes[..4].iter().any(|b| !b.is_ascii()) && !is_utf8_bom(bytes) {
        return Err(Error::file(
            path,
            "not a glTF file: neither JSON nor a GLB (whose first four bytes are `glTF`)",
        ));
    } else {
        (strip_bom(bytes), None)
    };
    let json_error = |e: serde_json::Error| {
        let message = format!("invalid glTF JSON: {}", strip_position(&e.to_string()));
        if e.line() > 0 {
            Error::parse_at(path, e.line(), e.column(), message)
        } else {
            Error::file(path, message)
        }
    };
    let mut value: serde_json::Value = serde_json::from_slice(json).map_err(json_error)?;
    lenient(&mut value);
    let mut root: gltf::json::Root = match serde_path_to_error::deserialize(value) {
        Ok(root) => root,
        // The place in the text from the strict reading (which fails too), and the
        // JSON path from this one.
        Err(e) => {
            let at = e.path().to_string();
            let message = strip_position(&e.inner().to_string()).to_string();
            return Err(
                match gltf::json::deserialize::from_slice::<gltf::json::Root>(json) {
                    Err(strict) if strict.line() > 0 => Error::parse_at(
                        path,
                        strict.line(),
                        strict.column(),
                        format!("invalid glTF JSON: {at}: {message}"),
                    ),
                    _ => Error::file(path, format!("invalid glTF JSON: {at}: {message}")),
                },
            );
        }
    };
    if let Some(ext) = root
        .extensions_required
        .iter()
        .find(|e| !SUPPORTED.contains(&e.as_str()))
    {
        return Err(Error::file(
            path,
            format!(
                "requires the glTF extension {ext}, which Prism does not read (it reads {})",
                SUPPORTED.join(", ")
            ),
        ));
    }
    let ignored_extensions = root
        .extensions_used
        .iter()
        .filter(|e| !SUPPORTED.contains(&e.as_str()))
        .cloned()
        .collect();
    // Checked above against Prism's own list, which is not the crate's.
    root.extensions_required.clear();
    let document = validated(root).map_err(|e| Error::file(path, format!("invalid glTF: {e}")))?;
    let folder = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut blob = blob.map(<[u8]>::to_vec);
    let mut buffers = Vec::new();
    // All buffers together are bounded as one file is: a list naming one large file
    // many times must not read it without end.
    let mut total: u64 = 0;
    for buffer in document.buffers() {
        let at = format!("buffers[{}]", buffer.index());
        if total.saturating_add(buffer.length() as u64) > MAX_GLTF_BYTES {
            return Err(Error::file(
                path,
                format!("{at}: the buffers hold more than {MAX_GLTF_BYTES} bytes in all"),
            ));
        }
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                Error::file(
                    path,
                    format!("{at}: refers to the GLB binary chunk, which the file lacks"),
                )
            })?,
            gltf::buffer::Source::Uri(uri) => read_uri(uri, &folder, MAX_GLTF_BYTES)
                .map_err(|e| Error::file(path, format!("{at}: {e}")))?,
        };
        if data.len() < buffer.length() {
            return Err(Error::file(
                path,
                format!(
                    "{at}: byteLength is {} but the data holds {} bytes",
                    buffer.length(),
                    data.len()
                ),
            ));
        }
        total = total.saturating_add(data.len() as u64);
        if total > MAX_GLTF_BYTES {
            return Err(Error::file(
                path,
                format!("{at}: the buffers hold more than {MAX_GLTF_BYTES} bytes in all"),
            ));
        }
        buffers.push(data);
    }
    Ok(Loaded {
        document,
        buffers,
        folder,
        ignored_extensions,
    })
}

/// Mends what valid files hold that the schema crate refuses, none of which Prism
/// reads: a scene without `nodes` (optional in the spec), and animations (KHR_animation_
/// pointer's channels name no node).
fn lenient(value: &mut serde_json::Value) {
    let Some(root) = value.as_object_mut() else {
        return;
    };
    root.remove("animations");
    if let Some(scenes) = root.get_mut("scenes").and_then(|s| s.as_array_mut()) {
        for scene in scenes.iter_mut().filter_map(|s| s.as_object_mut()) {
            scene
                .entry("nodes")
                .or_insert_with(|| serde_json::Value::Array(Vec::new()));
        }
    }
}

/// The document, once every index in it names something that exists. POSITION
/// accessors without `min` and `max` are let by: Prism computes bounds itself.
fn validated(root: gltf::json::Root) -> std::result::Result<Document, String> {
    use gltf::json::validation::{Error as Invalid, Validate as _};
    // The crate's own check reads each primitive's POSITION accessor by index before
    // it checks that index: check it first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, index) in &prim.attributes {
                if index.value() >= root.accessors.len() {
                    return Err(format!(
                        "meshes[{m}].primitives[{p}].attributes.{}: accessor {} does not exist \
                         (the file has {})",
                        match semantic {
                            gltf::json::validation::Checked::Valid(s) => s.to_string(),
                            gltf::json::validation::Checked::Invalid => "?".into(),
                        },
                        index.value(),
                        root.accessors.len()
                    ));
                }
            }
        }
    }
    let mut errors = Vec::new();
    root.validate(&root, gltf::json::Path::new, &mut |path, error| {
        let path = path();
        let bounds = path.as_str().ends_with(".min") || path.as_str().ends_with(".max");
        if !(bounds && error == Invalid::Missing) {
            errors.push(format!("{}: {error}", path.as_str()));
        }
    });
    if !errors.is_empty() {
        errors.truncate(3);
        return Err(errors.join("; "));
    }
    Ok(Document::from_json_without_validation(root))
}

fn is_utf8_bom(bytes: &[u8]) -> bool {
    bytes.starts_with(&[0xEF, 0xBB, 0xBF])
}

fn strip_bom(bytes: &[u8]) -> &[u8] {
    if is_utf8_bom(bytes) {
        &bytes[3..]
    } else {
        bytes
    }
}

/// serde_json's message without its trailing ` at line L column C` (the error states
/// the place itself).
fn strip_position(message: &str) -> &str {
    match message.rfind(" at line ") {
        Some(i) => &message[..i],
        None => message,
    }
}

/// The JSON and binary chunks of a GLB file, checked against its header.
fn split_glb(bytes: &[u8]) -> std::result::Result<(&[u8], Option<&[u8]>), String> {
    let word = |at: usize| -> Option<u32> {
        bytes
            .get(at..at + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let version = word(4).ok_or("a GLB header is 12 bytes; the file is shorter")?;
    let length = word(8).ok_or("a GLB header is 12 bytes; the file is shorter")? as usize;
    if version != 2 {
        return Err(format!("GLB version {version}: Prism reads glTF 2.0"));
    }
    if length > bytes.len() || length < 12 {
        return Err(format!(
            "the GLB header states {length} bytes but the file holds {}",
            bytes.len()
        ));
    }
    let bytes = &bytes[..length];
    type Chunk<'a> = Option<(&'a [u8], [u8; 4])>;
    let chunk = |at: usize| -> std::result::Result<Chunk<'_>, String> {
        if at >= bytes.len() {
            return Ok(None);
        }
        let len = word(at).ok_or_else(|| format!("a GLB chunk header at byte {at} is cut off"))?;
        let kind: [u8; 4] = bytes
            .get(at + 4..at + 8)
            .ok_or_else(|| format!("a GLB chunk header at byte {at} is cut off"))?
            .try_into()
            .expect("four bytes");
        let data = bytes
            .get(at + 8..)
            .and_then(|rest| rest.get(..len as usize))
            .ok_or_else(|| {
                format!("the GLB chunk at byte {at} states {len} bytes, past the end of the file")
            })?;
        Ok(Some((data, kind)))
    };
    let (json, kind) = chunk(12)?.ok_or("the GLB has no JSON chunk")?;
    if &kind != b"JSON" {
        return Err("the GLB's first chunk is not its JSON".into());
    }
    let next = 20 + json.len().next_multiple_of(4);
    let bin = match chunk(next)? {
        Some((data, kind)) if &kind == b"BIN\0" => Some(data),
        Some(_) => None,
        None => None,
    };
    Ok((json, bin))
}

/// The bytes a buffer or image URI names: a base64 `data:` URI, or a file relative to
/// `folder` (percent-escapes decoded). Network URIs are refused.
pub fn read_uri(uri: &str, folder: &Path, max: u64) -> std::result::Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (header, data) = rest
            .split_once(',')
            .ok_or_else(|| "a data: URI without a comma".to_string())?;
        if !header.ends_with(";base64") {
            return Err("a data: URI that is not base64".into());
        }
        if data.len() as u64 / 4 * 3 > max {
            return Err(format!("a data: URI of more than {max} bytes"));
        }
        return base64::engine::general_purpose::STANDARD
            .decode(data.trim_end())
            .map_err(|e| format!("a data: URI that is not valid base64 ({e})"));
    }
    if let Some((scheme, _)) = uri.split_once(':')
        && scheme.len() > 1
        && scheme
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))
    {
        return Err(format!(
            "the URI {} is not a file beside the glTF file (Prism reads no network URIs)",
            crate::util::text::shown(uri)
        ));
    }
    let file = folder.join(percent_decoded(uri)?);
    crate::util::file::read_regular(&file, max)
        .map_err(|e| format!("cannot read {}: {e}", file.display()))
}

/// `uri` with its `%XX` escapes decoded (glTF URIs are RFC 3986 references).
fn percent_decoded(uri: &str) -> std::result::Result<String, String> {
    if !uri.contains('%') {
        return Ok(uri.to_owned());
    }
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| {
                    format!(
                        "a bad %-escape in the URI {}",
                        crate::util::text::shown(uri)
                    )
                })?;
            out.push(hex);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| "a URI that is not UTF-8 once decoded".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glb(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
        let pad = |v: &[u8], with: u8| {
            let mut v = v.to_vec();
            while !v.len().is_multiple_of(4) {
                v.push(with);
            }
            v
        };
        let json = pad(json, b' ');
        let mut body = Vec::new();
        body.extend((json.len() as u32).to_le_bytes());
        body.extend(b"JSON");
        body.extend(&json);
        if let Some(bin) = bin {
            let bin = pad(bin, 0);
            body.extend((bin.len() as u32).to_le_bytes());
            body.extend(b"BIN\0");
            body.extend(&bin);
        }
        let mut out = b"glTF".to_vec();
        out.extend(2u32.to_le_bytes());
        out.extend((12 + body.len() as u32).to_le_bytes());
        out.extend(body);
        out
    }

    const EMPTY: &[u8] = br#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":3}]}"#;

    #[test]
    fn a_glb_binary_chunk_is_buffer_zero() {
        let file = glb(EMPTY, Some(&[1, 2, 3]));
        let loaded = parse(&file, Path::new("a.glb")).unwrap();
        assert_eq!(&loaded.buffers[0][..3], &[1, 2, 3]);
    }

    #[test]
    fn broken_glb_headers_and_chunks_are_errors() {
        let good = glb(EMPTY, Some(&[1, 2, 3]));
        let mut long = good.clone();
        long[8..12].copy_from_slice(&9999u32.to_le_bytes());
        let mut short = good.clone();
        short[8..12].copy_from_slice(&4u32.to_le_bytes());
        let mut chunk = good.clone();
        chunk[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
        let mut version = good.clone();
        version[4] = 1;
        for (bytes, expected) in [
            (&long[..], "states 9999 bytes"),
            (&short[..], "states 4 bytes"),
            (&chunk[..], "past the end"),
            (&version[..], "GLB version 1"),
            (&good[..10], "header is 12 bytes"),
            (&glb(EMPTY, None)[..], "binary chunk, which the file lacks"),
        ] {
            let e = parse(bytes, Path::new("x.glb"))
                .expect_err(expected)
                .to_string();
            assert!(e.starts_with("x.glb: ") && e.contains(expected), "{e}");
        }
    }

    #[test]
    fn json_errors_give_line_and_column_and_validation_the_json_path() {
        let e = parse(b"{\"asset\":\n {\"version\": 2.0,}}", Path::new("s.gltf"))
            .err()
            .unwrap()
            .to_string();
        assert!(e.starts_with("s.gltf:2:"), "{e}");
        let wrong = b"{\"asset\": {\"version\": \"2.0\"},\n \"nodes\": [{}, {\"mesh\": \"a\"}]}";
        let e = parse(wrong, Path::new("s.gltf")).unwrap_err().to_string();
        assert!(e.starts_with("s.gltf:2:"), "{e}");
        assert!(
            e.contains("invalid glTF JSON: nodes[1].mesh: invalid type: string"),
            "{e}"
        );
        let bad_index = br#"{"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":7}}]}]}"#;
        let e = parse(bad_index, Path::new("s.gltf"))
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("meshes[0].primitives[0].attributes"), "{e}");
        assert!(e.contains("POSITION"), "{e}");
    }

    #[test]
    fn required_extensions_prism_does_not_read_are_named() {
        let json = br#"{"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],
            "extensionsRequired":["KHR_draco_mesh_compression"]}"#;
        let e = parse(json, Path::new("d.gltf")).err().unwrap().to_string();
        assert!(
            e.contains("requires the glTF extension KHR_draco_mesh_compression"),
            "{e}"
        );
        let used =
            br#"{"asset":{"version":"2.0"},"extensionsUsed":["EXT_foo","KHR_materials_ior"]}"#;
        let loaded = parse(used, Path::new("d.gltf")).unwrap();
        assert_eq!(loaded.ignored_extensions, ["EXT_foo"]);
    }

    #[test]
    fn data_uris_and_files_resolve_and_network_uris_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("my buffer.bin"), [7u8, 8, 9]).unwrap();
        assert_eq!(
            read_uri("my%20buffer.bin", dir.path(), 100).unwrap(),
            [7, 8, 9]
        );
        assert_eq!(
            read_uri("data:application/octet-stream;base64,BwgJ", dir.path(), 100).unwrap(),
            [7, 8, 9]
        );
        let e = read_uri("https://example.com/a.bin", dir.path(), 100).unwrap_err();
        assert!(e.contains("network"), "{e}");
        let e = read_uri("data:application/octet-stream;base64,@@@", dir.path(), 100).unwrap_err();
        assert!(e.contains("base64"), "{e}");
        let e = read_uri("missing.bin", dir.path(), 100).unwrap_err();
        assert!(e.contains("missing.bin"), "{e}");
    }
}
