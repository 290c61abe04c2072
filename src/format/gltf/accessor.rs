//! Accessors read out of their buffers: every component type (normalized integers
//! too), strided and interleaved views, sparse substitutions. Every size and offset is
//! checked against the bytes before anything is allocated or read.

use gltf::accessor::{DataType, Dimensions};
use gltf::{Accessor, Document};

/// Most elements one accessor may hold: far beyond any mesh a scene may carry.
pub const MAX_ELEMENTS: usize = 1 << 30;

/// Most elements of an accessor without a buffer view (zeros under sparse values):
/// nothing in the file bounds them.
pub const MAX_UNBACKED: usize = 1 << 24;

type Res<T> = std::result::Result<T, String>;

fn component_size(t: DataType) -> usize {
    match t {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

fn components(d: Dimensions) -> usize {
    match d {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 => 4,
        Dimensions::Mat2 => 4,
        Dimensions::Mat3 => 9,
        Dimensions::Mat4 => 16,
    }
}

fn dimensions_name(n: usize) -> &'static str {
    match n {
        1 => "SCALAR",
        2 => "VEC2",
        3 => "VEC3",
        _ => "VEC4",
    }
}

/// One component as a float: normalized integers mapped to [0, 1] or [-1, 1] as the
/// spec says, other integers as their value.
#[inline]
fn component(bytes: &[u8], t: DataType, normalized: bool) -> f32 {
    match t {
        DataType::F32 => f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]),
        DataType::U8 if normalized => f32::from(bytes[0]) / 255.0,
        DataType::U8 => f32::from(bytes[0]),
        DataType::I8 if normalized => (f32::from(bytes[0] as i8) / 127.0).max(-1.0),
        DataType::I8 => f32::from(bytes[0] as i8),
        DataType::U16 => {
            let v = f32::from(u16::from_le_bytes([bytes[0], bytes[1]]));
            if normalized { v / 65535.0 } else { v }
        }
        DataType::I16 => {
            let v = f32::from(i16::from_le_bytes([bytes[0], bytes[1]]));
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U32 => {
            let v = u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
            if normalized {
                (f64::from(v) / f64::from(u32::MAX)) as f32
            } else {
                v as f32
            }
        }
    }
}

/// The bytes of `count` elements of `element` bytes each, `stride` apart, starting
/// `offset` into buffer view `view`: checked against the view and its buffer.
fn strided<'b>(
    document: &Document,
    buffers: &'b [Vec<u8>],
    view: usize,
    offset: usize,
    count: usize,
    element: usize,
    stride: Option<usize>,
) -> Res<(&'b [u8], usize)> {
    let v = document
        .views()
        .nth(view)
        .ok_or_else(|| format!("buffer view {view} does not exist"))?;
    let stride = stride.or(v.stride()).unwrap_or(element);
    if stride < element {
        return Err(format!(
            "buffer view {view}'s byteStride {stride} is less than an element ({element} bytes)"
        ));
    }
    let buffer = &buffers[v.buffer().index()];
    let view_bytes = v
        .offset()
        .checked_add(v.length())
        .and_then(|end| buffer.get(v.offset()..end))
        .ok_or_else(|| {
            format!(
                "buffer view {view} (bytes {} to {}) lies past the end of buffer {} ({} bytes)",
                v.offset(),
                v.offset().saturating_add(v.length()),
                v.buffer().index(),
                buffer.len()
            )
        })?;
    if count == 0 {
        return Ok((&[], stride));
    }
    let needed = (count - 1)
        .checked_mul(stride)
        .and_then(|n| n.checked_add(element))
        .and_then(|n| n.checked_add(offset));
    match needed {
        Some(n) if n <= view_bytes.len() => Ok((&view_bytes[offset..n], stride)),
        _ => Err(format!(
            "{count} elements of {element} bytes from byte {offset} need more than buffer view \
             {view}'s {} bytes",
            view_bytes.len()
        )),
    }
}

/// Accessor `accessor`'s elements as `N` floats each. Its type must have `N`
/// components, or `alt` (COLOR_0 may be VEC3 or VEC4: pass 3 and 4, read with `N = 4`,
/// a VEC3 getting alpha 1).
pub fn read_floats<const N: usize>(
    document: &Document,
    buffers: &[Vec<u8>],
    accessor: &Accessor,
    accepted: &[usize],
) -> Res<Vec<[f32; N]>> {
    let n = components(accessor.dimensions());
    if !accepted.contains(&n)
        || matches!(
            accessor.dimensions(),
            Dimensions::Mat2 | Dimensions::Mat3 | Dimensions::Mat4
        )
    {
        let names: Vec<_> = accepted.iter().map(|&k| dimensions_name(k)).collect();
        return Err(format!(
            "accessor {} is {:?}, expected {}",
            accessor.index(),
            accessor.dimensions(),
            names.join(" or ")
        ));
    }
    let count = accessor.count();
    if count > MAX_ELEMENTS {
        return Err(format!(
            "accessor {} holds {count} elements, more than Prism reads",
            accessor.index()
        ));
    }
    let t = accessor.data_type();
    let size = component_size(t);
    let element = size * n;
    let normalized = accessor.normalized();
    let fill = |out: &mut [f32; N], bytes: &[u8]| {
        for (c, v) in out.iter_mut().enumerate().take(n) {
            *v = component(&bytes[c * size..], t, normalized);
        }
    };
    let mut blank = [0.0; N];
    if n < N {
        blank[N - 1] = 1.0;
    }
    let mut out = match accessor.view() {
        Some(view) => {
            let (bytes, stride) = strided(
                document,
                buffers,
                view.index(),
                accessor.offset(),
                count,
                element,
                None,
            )?;
            let mut out = vec![blank; count];
            for (i, o) in out.iter_mut().enumerate() {
                fill(o, &bytes[i * stride..]);
            }
            out
        }
        None => {
            // No view: zeros, then the sparse values.
            if accessor.sparse().is_none() {
                return Err(format!(
                    "accessor {} has neither a bufferView nor sparse values",
                    accessor.index()
                ));
            }
            if count > MAX_UNBACKED {
                return Err(format!(
                    "accessor {} has no bufferView and {count} elements, more than the {MAX_UNBACKED} \
                     Prism fills with zeros",
                    accessor.index()
                ));
            }
            vec![blank; count]
        }
    };
    if let Some(sparse) = accessor.sparse() {
        let k = sparse.count();
        if k > count {
            return Err(format!(
                "accessor {}'s sparse count {k} exceeds its count {count}",
                accessor.index()
            ));
        }
        let indices = sparse.indices();
        let index_type = match indices.index_type() {
            gltf::accessor::sparse::IndexType::U8 => DataType::U8,
            gltf::accessor::sparse::IndexType::U16 => DataType::U16,
            gltf::accessor::sparse::IndexType::U32 => DataType::U32,
        };
        let isize = component_size(index_type);
        let (ib, istride) = strided(
            document,
            buffers,
            indices.view().index(),
            indices.offset(),
            k,
            isize,
            Some(isize),
        )?;
        let values = sparse.values();
        let (vb, vstride) = strided(
            document,
            buffers,
            values.view().index(),
            values.offset(),
            k,
            element,
            Some(element),
        )?;
        for j in 0..k {
            let i = index(&ib[j * istride..], index_type);
            let slot = out.get_mut(i as usize).ok_or_else(|| {
                format!(
                    "accessor {}'s sparse index {i} is past its count {count}",
                    accessor.index()
                )
            })?;
            fill(slot, &vb[j * vstride..]);
        }
    }
    Ok(out)
}

#[inline]
fn index(bytes: &[u8], t: DataType) -> u32 {
    match t {
        DataType::U8 => u32::from(bytes[0]),
        DataType::U16 => u32::from(u16::from_le_bytes([bytes[0], bytes[1]])),
        _ => u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]),
    }
}

/// An index accessor's values (SCALAR of unsigned bytes, shorts or ints).
pub fn read_indices(
    document: &Document,
    buffers: &[Vec<u8>],
    accessor: &Accessor,
) -> Res<Vec<u32>> {
    let t = accessor.data_type();
    if accessor.dimensions() != Dimensions::Scalar
        || !matches!(t, DataType::U8 | DataType::U16 | DataType::U32)
    {
        return Err(format!(
            "index accessor {} is not a SCALAR of unsigned integers",
            accessor.index()
        ));
    }
    if accessor.sparse().is_some() || accessor.view().is_none() {
        // Rare for indices: read through the general path, values as floats are exact
        // up to 2^24 and refused past it.
        let v = read_floats::<1>(document, buffers, accessor, &[1])?;
        return v
            .into_iter()
            .map(|[x]| {
                if x < 16_777_216.0 {
                    Ok(x as u32)
                } else {
                    Err(format!(
                        "index accessor {} holds an index past 2^24 in sparse values",
                        accessor.index()
                    ))
                }
            })
            .collect();
    }
    let count = accessor.count();
    if count > MAX_ELEMENTS {
        return Err(format!(
            "accessor {} holds {count} elements, more than Prism reads",
            accessor.index()
        ));
    }
    let size = component_size(t);
    let view = accessor.view().expect("checked above");
    let (bytes, stride) = strided(
        document,
        buffers,
        view.index(),
        accessor.offset(),
        count,
        size,
        None,
    )?;
    Ok((0..count).map(|i| index(&bytes[i * stride..], t)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn document(json: &str) -> Document {
        let root: gltf::json::Root = gltf::json::deserialize::from_str(json).unwrap();
        Document::from_json(root).unwrap()
    }

    #[test]
    fn normalized_integers_interleaved_views_and_sparse_values() {
        // Buffer: 2 interleaved elements (u8 x2 normalized + i16 x2), stride 8.
        let mut buf = vec![255u8, 0, 0, 0];
        buf.extend(i16::MIN.to_le_bytes());
        buf.extend(100i16.to_le_bytes());
        buf.extend([51u8, 102, 0, 0]);
        buf.extend(0i16.to_le_bytes());
        buf.extend(32767i16.to_le_bytes());
        // Sparse: index 1 (u8) -> VEC2 u8 (0, 255).
        buf.extend([1u8, 0, 255, 0]);
        let json = r#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":20}],
          "bufferViews":[{"buffer":0,"byteLength":16,"byteStride":8},
                         {"buffer":0,"byteOffset":16,"byteLength":1},
                         {"buffer":0,"byteOffset":17,"byteLength":2}],
          "accessors":[
            {"bufferView":0,"componentType":5121,"normalized":true,"count":2,"type":"VEC2"},
            {"bufferView":0,"byteOffset":4,"componentType":5122,"normalized":true,"count":2,"type":"VEC2"},
            {"bufferView":0,"componentType":5121,"normalized":true,"count":2,"type":"VEC2",
             "sparse":{"count":1,"indices":{"bufferView":1,"componentType":5121},
                       "values":{"bufferView":2}}},
            {"componentType":5126,"count":3,"type":"VEC2",
             "sparse":{"count":1,"indices":{"bufferView":1,"componentType":5121},
                       "values":{"bufferView":2}}}]}"#;
        let d = document(json);
        let bufs = vec![buf];
        let a = |i| d.accessors().nth(i).unwrap();
        let u8s = read_floats::<2>(&d, &bufs, &a(0), &[2]).unwrap();
        assert_eq!(u8s, [[1.0, 0.0], [0.2, 0.4]]);
        let i16s = read_floats::<2>(&d, &bufs, &a(1), &[2]).unwrap();
        assert_eq!(i16s, [[-1.0, 100.0 / 32767.0], [0.0, 1.0]]);
        let sparse = read_floats::<2>(&d, &bufs, &a(2), &[2]).unwrap();
        assert_eq!(sparse, [[1.0, 0.0], [0.0, 1.0]]);
        // No view: zeros under the sparse values. Its values are read as floats, so the
        // view of 2 bytes is too short for one VEC2 of f32.
        let e = read_floats::<2>(&d, &bufs, &a(3), &[2]).unwrap_err();
        assert!(e.contains("need more than buffer view 2"), "{e}");
        let e = read_floats::<3>(&d, &bufs, &a(0), &[3]).unwrap_err();
        assert!(e.contains("expected VEC3"), "{e}");
    }

    #[test]
    fn short_views_and_buffers_are_refused_before_reading() {
        let json = r#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":8}],
          "bufferViews":[{"buffer":0,"byteLength":8},{"buffer":0,"byteOffset":4,"byteLength":8}],
          "accessors":[
            {"bufferView":0,"componentType":5126,"count":1000000000,"type":"VEC3"},
            {"bufferView":1,"componentType":5126,"count":1,"type":"SCALAR"},
            {"bufferView":0,"componentType":5123,"count":4,"type":"SCALAR"}]}"#;
        let d = document(json);
        let bufs = vec![vec![0u8; 8]];
        let a = |i| d.accessors().nth(i).unwrap();
        let e = read_floats::<3>(&d, &bufs, &a(0), &[3]).unwrap_err();
        assert!(e.contains("need more than buffer view 0's 8 bytes"), "{e}");
        let e = read_floats::<1>(&d, &bufs, &a(1), &[1]).unwrap_err();
        assert!(e.contains("past the end of buffer 0"), "{e}");
        assert_eq!(read_indices(&d, &bufs, &a(2)).unwrap(), [0, 0, 0, 0]);
    }
}
