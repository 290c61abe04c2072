//! What each fuzz target asks of one input, one module a target: `check` returns where
//! the input is refused or passes, and panics where Prism broke a promise (a panic of
//! its own, an index past its data, a non-finite value, two layouts disagreeing). The
//! targets in `fuzz_targets/` hand libFuzzer's inputs to these, and `cargo test` hands
//! them every seed in `fuzz/seeds/` (`tests/fuzz_seeds.rs`), so the checks build and
//! hold in the ordinary test suite as well as under the fuzzer.

/// The 2014 scene reader on arbitrary text. Every `mtllib` is served the same material
/// file from memory, so `usemtl` finds names and nothing is read from disk.
pub mod objx {
    use std::path::Path;

    const LIBRARY: &str = "newmtl red 200 40 30 10 1 15 8.5 1 0.2 0 0\n\
                           newmtl glass 230 240 255 0.1 0.1 20 20 1.5 0.2 1 1\n\
                           newmtl light 255 255 255 0 0 0 0 0 0 0 0\n";

    pub fn check(data: &[u8]) {
        let Ok(text) = std::str::from_utf8(data) else {
            return;
        };
        let path = Path::new("/nonexistent/prism-fuzz/scene.objx");
        let _ = prism::format::objx::parse(text, path, |_| Ok(LIBRARY.to_owned()));
    }
}

/// The 2014 material reader on arbitrary text, in a folder of its own that holds one
/// texture (`checker.ppm`). Inputs naming other folders are passed over, so textures
/// are only ever looked up inside that folder.
pub mod mtlx {
    use prism::format::mtlx;
    pub fn check(data: &[u8]) {
        let Ok(text) = std::str::from_utf8(data) else {
            return;
        };
        if text.contains(['/', '\\']) {
            return;
        }
        let folder = super::checker_folder();
        let path = folder.join("materials.mtlx");
        let _ = mtlx::parse(text, &path, &mut mtlx::MaterialLibrary::new());
    }
}

/// The 2014 camera reader on arbitrary text.
pub mod cmr {
    use std::path::Path;

    pub fn check(data: &[u8]) {
        if let Ok(text) = std::str::from_utf8(data) {
            let _ = prism::format::cmr::parse(text, Path::new("camera.cmr"));
        }
    }
}

/// The Wavefront OBJ reader on arbitrary text; a mesh it accepts names only its own
/// vertices.
pub mod obj {
    use std::path::Path;

    pub fn check(data: &[u8]) {
        let Ok(text) = std::str::from_utf8(data) else {
            return;
        };
        if let Ok(mesh) = prism::format::obj::parse_mesh(text, Path::new("mesh.obj")) {
            let n = mesh.vertices.len();
            assert!(mesh.triangles.iter().flatten().all(|&i| (i as usize) < n));
        }
    }
}

/// The full Wavefront OBJ reader (normals, texture coordinates, groups, materials) on
/// arbitrary bytes, with the libraries it names read from memory; then the scene built
/// from it. Every index it returns names an existing attribute.
pub mod obj_full {
    use std::path::Path;

    const LIBRARY: &[u8] = b"newmtl a\nKd 1 0 0\nKe 1 1 1\nnewmtl b\nillum 7\nNi 1.5\nd 0.5\n";

    pub fn check(data: &[u8]) {
        let path = Path::new("mesh.obj");
        let mut read = |_: &Path| Ok(LIBRARY.to_vec());
        let Ok(obj) = prism::format::obj::parse_obj_with(data, path, &mut read) else {
            return;
        };
        let (p, t, n) = (obj.positions.len(), obj.texcoords.len(), obj.normals.len());
        for tri in &obj.triangles {
            assert!(tri.v.iter().all(|&i| (i as usize) < p));
            assert!(tri.vt.iter().flatten().all(|&i| (i as usize) < t));
            assert!(tri.vn.iter().flatten().all(|&i| (i as usize) < n));
        }
        if let Ok(file) = prism::format::wavefront::from_obj(obj, path) {
            for mesh in &file.scene.meshes {
                assert!(mesh.check().is_ok());
            }
        }
    }
}

/// The MTL reader on arbitrary bytes: never a panic, texture options always finite.
pub mod mtl {
    use std::path::Path;

    pub fn check(data: &[u8]) {
        if let Ok(library) = prism::format::mtl::parse(data, Path::new("m.mtl")) {
            for m in &library.materials {
                for map in [&m.map_kd, &m.map_d, &m.bump].into_iter().flatten() {
                    assert!(map.scale.iter().chain(&map.offset).all(|v| v.is_finite()));
                }
            }
        }
    }
}

/// The PLY reader on arbitrary bytes; a mesh it accepts is finite, names only its own
/// vertices, and has one of each present attribute per vertex.
pub mod ply {
    use std::path::Path;

    pub fn check(data: &[u8]) {
        if let Ok(mesh) = prism::format::ply::parse(data, Path::new("mesh.ply")) {
            let n = mesh.positions.len();
            assert!(mesh.triangles.iter().flatten().all(|&i| (i as usize) < n));
            assert!(mesh.positions.iter().all(|p| p.is_finite()));
            for len in [mesh.normals.len(), mesh.colors.len(), mesh.texcoords.len()] {
                assert!(len == 0 || len == n);
            }
        }
    }
}

/// The glTF reader on arbitrary bytes (JSON or GLB, buffers in `data:` URIs): a scene it
/// builds holds finite triangles, a material for every shape and attributes that name
/// only their own vertices.
pub mod gltf {
    use std::path::Path;

    pub fn check(data: &[u8]) {
        // A folder that does not exist: external URIs are errors, never reads.
        let path = Path::new("/nonexistent/prism-fuzz/scene.gltf");
        let Ok(loaded) = prism::format::gltf::document::parse(data, path) else {
            return;
        };
        if let Ok(file) = prism::format::gltf::build(&loaded, path) {
            let scene = &file.scene;
            assert_eq!(scene.material_of.len(), scene.shapes.len());
            assert_eq!(scene.surfaces.len(), scene.materials.len());
            assert!(
                scene
                    .material_of
                    .iter()
                    .all(|&m| (m as usize) < scene.materials.len())
            );
            assert!(scene.shapes.positions().iter().all(|p| p.is_finite()));
            for mesh in &scene.meshes {
                assert!(mesh.check().is_ok());
            }
            assert!(file.camera.is_none() == file.cameras.is_empty());
        }
    }
}

/// The Prism scene file on arbitrary text. Inputs naming paths are skipped so the
/// fuzzer never reads files of the machine; everything else must load or fail cleanly.
pub mod scene_toml {
    use std::path::Path;

    pub fn check(data: &[u8]) {
        let Ok(text) = std::str::from_utf8(data) else {
            return;
        };
        if text.contains('/') || text.contains('\\') || text.contains("..") {
            return;
        }
        let _ = prism::format::scene_file::parse(text, Path::new("/nonexistent-prism/scene.toml"));
    }
}

/// The animation file reader on arbitrary text. The scene and camera it names are read
/// from disk, so the harness lays out the turntable example in a folder of its own and
/// passes over inputs that name other folders.
pub mod anim_toml {
    use std::path::PathBuf;
    use std::sync::OnceLock;

    static FOLDER: OnceLock<(tempfile::TempDir, PathBuf)> = OnceLock::new();

    fn lay_out() -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let turntable = dir.path().join("turntable");
        std::fs::create_dir_all(dir.path().join("example")).unwrap();
        std::fs::create_dir_all(&turntable).unwrap();
        let files: [(&str, &[u8]); 4] = [
            (
                "example/checker.ppm",
                include_bytes!("../../scenes/example/checker.ppm"),
            ),
            (
                "turntable/turntable.objx",
                include_bytes!("../../scenes/turntable/turntable.objx"),
            ),
            (
                "turntable/turntable.mtlx",
                include_bytes!("../../scenes/turntable/turntable.mtlx"),
            ),
            (
                "turntable/turntable.cmr",
                include_bytes!("../../scenes/turntable/turntable.cmr"),
            ),
        ];
        for (name, bytes) in files {
            std::fs::write(dir.path().join(name), bytes).unwrap();
        }
        (dir, turntable.join("animation.toml"))
    }

    pub fn check(data: &[u8]) {
        let Ok(text) = std::str::from_utf8(data) else {
            return;
        };
        if text.contains(['/', '\\']) {
            return;
        }
        let (_, path) = FOLDER.get_or_init(lay_out);
        let _ = prism::anim::file::parse(text, path);
    }
}

/// The whole pipeline: an arbitrary 2014 scene, the example's materials (served from
/// memory, with a texture from a folder of the harness's own) and a fixed camera,
/// rendered at 8x8 with one ray per pixel on one thread, once with each BVH layout:
/// the two images must be the same, bit for bit.
pub mod render_objx {
    use prism::accel::AccelKind;
    use prism::format::{cmr, objx};
    use prism::render::{RenderSettings, Renderer};
    const MATERIALS: &str = include_str!("../../scenes/example/example.mtlx");
    const CAMERA: &str = include_str!("../../scenes/example/example.cmr");

    pub fn check(data: &[u8]) {
        let Ok(text) = std::str::from_utf8(data) else {
            return;
        };
        let folder = super::checker_folder();
        let path = folder.join("scene.objx");
        let Ok(scene) = objx::parse(text, &path, |_| Ok(MATERIALS.to_owned())) else {
            return;
        };
        let camera = cmr::parse(CAMERA, &folder.join("camera.cmr")).unwrap();
        let settings = RenderSettings {
            width: Some(8),
            height: Some(8),
            aa: Some(1),
            spp: Some(1),
            threads: Some(1),
            ..RenderSettings::default()
        };
        let render = |accel| {
            let settings = RenderSettings {
                accel,
                ..settings.clone()
            };
            let renderer = Renderer::new(&scene, &camera, settings).unwrap();
            renderer.render(&()).unwrap().0
        };
        let image = render(AccelKind::Bvh);
        assert_eq!((image.width, image.height), (8, 8));
        let bits = |i: &prism::film::Image| -> Vec<u32> {
            i.pixels.iter().flatten().map(|x| x.to_bits()).collect()
        };
        assert_eq!(bits(&image), bits(&render(AccelKind::BvhCopied)));
    }
}

/// The whole pipeline on a Prism scene file: arbitrary text (inputs naming paths are
/// skipped, so no file of the machine is read), resolved as the command line resolves
/// it, then rendered with the whitted model at 8x8, one ray per pixel, on one thread,
/// once with each BVH layout: the two images must be the same, bit for bit. The path
/// model renders it too (two samples a pixel, at most four bounces), with the same
/// check. Area lights, glass, spot and directional lights, checkers and emitters all
/// come from the text, so every light kind's samples in lanes and every shadow path
/// runs.
pub mod render_toml {
    use prism::accel::AccelKind;
    use prism::job::{JobOptions, resolve};
    use prism::render::{IntegratorKind, Renderer};
    use std::path::Path;

    /// Light samples a scene may ask for in all: 64 pixels, a few bounces, each sample a
    /// shadow ray, kept to a few milliseconds an input.
    const MAX_SAMPLES: u64 = 512;
    const MAX_SHAPES: usize = 256;

    pub fn check(data: &[u8]) {
        let Ok(text) = std::str::from_utf8(data) else {
            return;
        };
        if text.contains('/') || text.contains('\\') || text.contains("..") {
            return;
        }
        let Ok(file) =
            prism::format::scene_file::parse(text, Path::new("/nonexistent-prism/scene.toml"))
        else {
            return;
        };
        let samples: u64 = file
            .scene
            .lights
            .iter()
            .map(|l| u64::from(l.samples.max(1)))
            .sum();
        if samples > MAX_SAMPLES || file.scene.shapes.len() > MAX_SHAPES {
            return;
        }
        let options = JobOptions {
            render: prism::options::RenderOptions {
                width: Some(8),
                height: Some(8),
                aa: Some(1),
                spp: Some(1),
                integrator: Some(IntegratorKind::Whitted),
                max_depth: Some(file.settings.max_depth.unwrap_or(4).min(4)),
                ..Default::default()
            },
            threads: Some(1),
            ..JobOptions::default()
        };
        let Ok(still) = resolve(file, &options) else {
            return;
        };
        let render_with = |accel, integrator, spp, max_depth| {
            let settings = prism::render::RenderSettings {
                accel,
                integrator,
                spp: Some(spp),
                max_depth,
                ..still.settings.clone()
            };
            let renderer = Renderer::new(&still.scene, &still.camera, settings).ok()?;
            Some(renderer.render(&()).ok()?.0)
        };
        let render =
            |accel| render_with(accel, IntegratorKind::Whitted, 1, still.settings.max_depth);
        let Some(image) = render(AccelKind::Bvh) else {
            return;
        };
        assert_eq!((image.width, image.height), (8, 8));
        let bits = |i: &prism::film::Image| -> Vec<u32> {
            i.pixels.iter().flatten().map(|x| x.to_bits()).collect()
        };
        let copied =
            render(AccelKind::BvhCopied).expect("the copied layout renders where the other did");
        assert_eq!(bits(&image), bits(&copied));
        let path = |accel| render_with(accel, IntegratorKind::Path, 2, 4);
        if let Some(image) = path(AccelKind::Bvh) {
            assert_eq!((image.width, image.height), (8, 8));
            let copied = path(AccelKind::BvhCopied).expect("the copied layout renders a path too");
            assert_eq!(bits(&image), bits(&copied));
            assert!(image.pixels.iter().flatten().all(|v| v.is_finite()));
        }
    }
}

/// The texture and background image decoders (`format::image_file::decode_texture`, what
/// `read_texture` runs on a file's bytes) on arbitrary bytes. The first byte picks the
/// file name's extension, which sends `.hdr` and `.exr` to the linear reader and the rest
/// to the 8-bit decoders by content, and the encoding; the rest is the file.
///
/// The pixel limit is 2^16 rather than `MAX_TEXTURE_PIXELS`: a legitimate texture at the
/// real limit takes up to 1 GiB (f32 RGBA), above the harness's `-malloc_limit_mb`,
/// whereas at 2^16 pixels the largest legitimate buffer is 1 MiB, so any allocation the
/// malloc limit catches is one the pixel limit failed to bound.
pub mod texture {
    use prism::format::image_file::{Encoding, decode_texture};
    use prism::scene::Texels;

    const MAX_PIXELS: u64 = 1 << 16;

    const NAMES: [&str; 8] = [
        "t.png", "t.jpg", "t.bmp", "t.tga", "t.ppm", "t.hdr", "t.exr", "t.tex",
    ];

    pub fn check(data: &[u8]) {
        let Some((&select, file)) = data.split_first() else {
            return;
        };
        let name = NAMES[usize::from(select & 7)];
        let encoding = match (select >> 3) % 3 {
            0 => Encoding::Srgb,
            1 => Encoding::Linear,
            _ => Encoding::Mask,
        };
        let Ok(texture) = decode_texture(file, name, encoding, MAX_PIXELS) else {
            return;
        };
        let pixels = u64::from(texture.width) * u64::from(texture.height);
        assert!(
            pixels > 0 && pixels <= MAX_PIXELS,
            "{}x{}",
            texture.width,
            texture.height
        );
        let texels = match &texture.texels {
            Texels::Rgba8 { texels, .. } => texels.len(),
            Texels::RgbaF32(texels) => texels.len(),
        };
        assert_eq!(texels as u64, pixels);
        if let Texels::RgbaF32(texels) = &texture.texels {
            assert!(texels.iter().flatten().all(|v| v.is_finite()));
        }
    }
}

/// Runs `check` on a render's input, then waits (up to a second) for the renderer's
/// worker threads to exit. The renderer's pool does not join its worker when dropped;
/// until the worker has exited its thread-local destructors hold memory that
/// LeakSanitizer, which libFuzzer runs when an input's mallocs and frees do not
/// balance, now and then reports as a leak.
pub fn then_workers_gone(check: fn(&[u8]), data: &[u8]) {
    let threads = thread_count();
    check(data);
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(1);
    while thread_count() > threads && std::time::Instant::now() < deadline {
        std::thread::sleep(std::time::Duration::from_micros(50));
    }
}

/// A folder of the harness's own holding the example's texture (`checker.ppm`), made
/// once: the 2014 readers look textures up beside the file they read.
fn checker_folder() -> &'static std::path::Path {
    static FOLDER: std::sync::OnceLock<tempfile::TempDir> = std::sync::OnceLock::new();
    FOLDER
        .get_or_init(|| {
            let dir = tempfile::tempdir().unwrap();
            let checker = include_bytes!("../../scenes/example/checker.ppm");
            std::fs::write(dir.path().join("checker.ppm"), checker).unwrap();
            dir
        })
        .path()
}

/// The threads of this process.
fn thread_count() -> usize {
    std::fs::read_dir("/proc/self/task").map_or(0, |d| d.count())
}
