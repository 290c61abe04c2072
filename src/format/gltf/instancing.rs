//! `EXT_mesh_gpu_instancing`: a node that places its mesh many times, each placement a
//! translation, rotation and scale read from accessors of one count, applied to the
//! mesh before the node's own transform.

use super::accessor::read_floats;
use glam::{DMat4, DQuat, DVec3};
use gltf::Document;

/// The extension's name.
pub const EXTENSION: &str = "EXT_mesh_gpu_instancing";

/// How many times `node` places its mesh: its instances' count (that of its first
/// attribute; [`transforms`] checks the rest), else once.
pub fn count(document: &Document, node: &gltf::Node) -> usize {
    node.extension_value(EXTENSION)
        .and_then(|ext| {
            ext.get("attributes")?
                .as_object()?
                .values()
                .next()?
                .as_u64()
        })
        .and_then(|i| document.accessors().nth(usize::try_from(i).ok()?))
        .map_or(1, |a| a.count())
}

/// The object-to-node transforms of `node`'s instances, or `None` where the node does
/// not use the extension (it then places its mesh once).
pub fn transforms(
    document: &Document,
    buffers: &[Vec<u8>],
    node: &gltf::Node,
) -> Result<Option<Vec<DMat4>>, String> {
    let Some(ext) = node.extension_value(EXTENSION) else {
        return Ok(None);
    };
    let at = format!("extensions.{EXTENSION}");
    let attributes = ext
        .get("attributes")
        .and_then(|a| a.as_object())
        .ok_or_else(|| format!("{at}: expected an object \"attributes\""))?;
    let accessor = |name: &str| -> Result<Option<gltf::Accessor>, String> {
        let Some(v) = attributes.get(name) else {
            return Ok(None);
        };
        let i = v
            .as_u64()
            .ok_or_else(|| format!("{at}.attributes.{name}: expected an accessor index"))?;
        document
            .accessors()
            .nth(usize::try_from(i).unwrap_or(usize::MAX))
            .map(Some)
            .ok_or_else(|| format!("{at}.attributes.{name}: there is no accessor {i}"))
    };
    let read3 = |name: &str| -> Result<Option<Vec<[f32; 3]>>, String> {
        accessor(name)?
            .map(|a| read_floats::<3>(document, buffers, &a, &[3]))
            .transpose()
            .map_err(|e| format!("{at}.attributes.{name}: {e}"))
    };
    let translation = read3("TRANSLATION")?;
    let scale = read3("SCALE")?;
    let rotation = accessor("ROTATION")?
        .map(|a| read_floats::<4>(document, buffers, &a, &[4]))
        .transpose()
        .map_err(|e| format!("{at}.attributes.ROTATION: {e}"))?;
    let counts = [
        translation.as_ref().map(Vec::len),
        rotation.as_ref().map(Vec::len),
        scale.as_ref().map(Vec::len),
    ];
    let mut known = counts.iter().flatten();
    let Some(&count) = known.next() else {
        return Err(format!(
            "{at}: expected at least one of TRANSLATION, ROTATION and SCALE"
        ));
    };
    if known.any(|&c| c != count) {
        return Err(format!(
            "{at}: its attributes have different counts (TRANSLATION, ROTATION, SCALE: \
             {counts:?})"
        ));
    }
    let f = |v: [f32; 3]| DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]));
    (0..count)
        .map(|i| {
            let t = translation.as_ref().map_or(DVec3::ZERO, |v| f(v[i]));
            let s = scale.as_ref().map_or(DVec3::ONE, |v| f(v[i]));
            let r = rotation.as_ref().map_or(DQuat::IDENTITY, |v| {
                let [x, y, z, w] = v[i].map(f64::from);
                DQuat::from_xyzw(x, y, z, w)
            });
            let m = DMat4::from_scale_rotation_translation(s, r.normalize(), t);
            if m.is_finite() {
                Ok(m)
            } else {
                Err(format!("{at}: instance {i}'s transform is not finite"))
            }
        })
        .collect::<Result<Vec<_>, String>>()
        .map(Some)
}
