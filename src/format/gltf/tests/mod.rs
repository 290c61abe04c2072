//! glTF scenes written here, small enough that geometry and optics give the answer.

use super::*;
use crate::film::Image;
use crate::job::{self, JobOptions};
use crate::render::Renderer;
use base64::Engine as _;
use serde_json::{Value, json};
use std::f32::consts::PI;
use std::path::PathBuf;

mod bad_input;
mod geometry;
mod lights;
mod materials;

/// A glTF file being written: its JSON and one buffer.
#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    meshes: Vec<Value>,
}

impl Builder {
    fn floats(&mut self, data: &[f32], kind: &str) -> usize {
        let n = match kind {
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" => 4,
            _ => 1,
        };
        let offset = self.bin.len();
        for v in data {
            self.bin.extend(v.to_le_bytes());
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": offset, "byteLength": data.len() * 4}));
        let mut acc = json!({"bufferView": self.views.len() - 1, "componentType": 5126,
            "count": data.len() / n, "type": kind});
        if kind == "VEC3" {
            let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
            for p in data.chunks(3) {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            acc["min"] = json!(lo);
            acc["max"] = json!(hi);
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }

    fn indices(&mut self, data: &[u16]) -> usize {
        let offset = self.bin.len();
        for v in data {
            self.bin.extend(v.to_le_bytes());
        }
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": offset, "byteLength": data.len() * 2}));
        self.accessors.push(
            json!({"bufferView": self.views.len() - 1, "componentType": 5123,
            "count": data.len(), "type": "SCALAR"}),
        );
        self.accessors.len() - 1
    }

    /// A mesh of `positions` (and `indices`, with `mode`) wearing `material`.
    fn mesh(
        &mut self,
        positions: &[f32],
        indices: Option<&[u16]>,
        mode: u32,
        material: Option<usize>,
    ) -> usize {
        let p = self.floats(positions, "VEC3");
        let mut prim = json!({"attributes": {"POSITION": p}, "mode": mode});
        if let Some(i) = indices {
            prim["indices"] = json!(self.indices(i));
        }
        if let Some(m) = material {
            prim["material"] = json!(m);
        }
        self.meshes.push(json!({"primitives": [prim]}));
        self.meshes.len() - 1
    }

    /// The document with `rest` (nodes, scenes, materials ...) merged in.
    fn finish(self, rest: Value) -> Value {
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&self.bin)
        );
        let mut doc = json!({
            "asset": {"version": "2.0"},
            "buffers": [{"byteLength": self.bin.len(), "uri": uri}],
            "bufferViews": self.views,
            "accessors": self.accessors,
            "meshes": self.meshes,
        });
        for (k, v) in rest.as_object().unwrap() {
            doc[k] = v.clone();
        }
        doc
    }
}

/// A square of half side `h` in the plane y = 0 (two triangles facing +y).
fn floor(h: f32) -> Vec<f32> {
    vec![
        -h, 0.0, -h, -h, 0.0, h, h, 0.0, h, -h, 0.0, -h, h, 0.0, h, h, 0.0, -h,
    ]
}

/// A square of half side `h` in the plane z = `z`, facing +z.
fn wall(h: f32, z: f32) -> Vec<f32> {
    vec![-h, -h, z, h, -h, z, h, h, z, -h, -h, z, h, h, z, -h, h, z]
}

fn write(doc: &Value) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.gltf");
    std::fs::write(&path, serde_json::to_vec_pretty(doc).unwrap()).unwrap();
    (dir, path)
}

fn render(path: &Path, options: &JobOptions) -> Image {
    let s = job::prepare(path, options).unwrap();
    Renderer::new(&s.scene, &s.camera, s.settings)
        .unwrap()
        .render(&())
        .unwrap()
        .0
}

fn sized(w: u32, h: u32) -> JobOptions {
    JobOptions {
        render: crate::options::RenderOptions {
            width: Some(w),
            height: Some(h),
            aa: Some(1),
            ..Default::default()
        },
        ..JobOptions::default()
    }
}

/// The rotation (x, y, z, w) that turns a node's -z (where cameras look) to -y.
const LOOK_DOWN: [f32; 4] = [
    -std::f32::consts::FRAC_1_SQRT_2,
    0.0,
    0.0,
    std::f32::consts::FRAC_1_SQRT_2,
];

/// Faces of `wall(h, z)` wound the other way: facing -z.
fn back_wall(h: f32, z: f32) -> Vec<f32> {
    let mut w = wall(h, z);
    for tri in w.chunks_mut(9) {
        let (a, b) = tri.split_at_mut(6);
        a[3..6].swap_with_slice(&mut b[0..3]);
    }
    w
}
