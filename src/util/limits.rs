//! Every bound Prism holds its inputs to, in one place: the readers check a file's
//! values against them where they are written (so the error names the line), and the
//! renderer checks a caller's options against the same numbers. They keep a typo from
//! asking for days of work or all the memory.

/// The longest side of an image, in pixels.
pub const MAX_SIDE: u32 = 1 << 16;
/// The largest anti-aliasing factor (per axis: `K × K` supersamples a pixel).
pub const MAX_AA: u32 = 16;
/// The most samples (camera rays) per supersampled pixel.
pub const MAX_SPP: u32 = 1 << 16;
/// Camera rays in one image: the report's heaviest setting (3840 x 2160, AA 4, 128
/// rays) is 1.7e10; a hundred times that is a typo.
pub const MAX_CAMERA_RAYS: u64 = 2_000_000_000_000;
/// The deepest reflection and refraction recursion a scene may ask for.
pub const MAX_DEPTH: u32 = 64;
/// More worker threads than this per core only adds switching: the render is CPU-bound.
pub const MAX_THREADS_PER_CORE: usize = 4;
/// The most shapes (triangles, mostly) a scene may hold: 2^28, about 40 GB of mesh and
/// BVH. Readers refuse a mesh that would pass it where they read its size.
pub const MAX_SHAPES: usize = 1 << 28;
/// The most triangles the lights of emissive meshes may name, those of instances counted
/// once per instance: 2^28, about 3 GB of lists (a copied emitter would cost more).
pub const MAX_LIGHT_TRIANGLES: u64 = 1 << 28;
/// The most instances a scene may place: 2^24, about 2.5 GB of transforms and tree.
pub const MAX_INSTANCES: usize = 1 << 24;
/// Largest 2014 scene, material or camera file: 1 GiB of text is tens of millions of
/// shapes, beyond what anyone writes by hand or converts.
pub const MAX_TEXT_BYTES: u64 = 1 << 30;
/// The largest linear image (EXR, Radiance HDR) decoded: 2^28 pixels (16384 × 16384),
/// 3 GiB as f32 RGB. Checked against the header, before anything is allocated.
pub const MAX_LINEAR_PIXELS: u64 = 1 << 28;

/// The most threads a render may ask for on this machine.
pub fn max_threads() -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    cores
        .saturating_mul(MAX_THREADS_PER_CORE)
        .max(MAX_THREADS_PER_CORE)
}
