//! The memory a render will need, estimated before anything large is allocated, and the
//! budget it must fit: `--max-memory`, by default half of the machine's memory (or of
//! the container's limit, where one is set).
//!
//! The estimate is an upper bound of the big allocations only (shapes, intersector,
//! images, film), so a refusal names figures a user can act on: fewer triangles, a
//! smaller image, the BVH instead of the octree, or a larger budget.

use crate::accel::{AccelKind, INDOOR_SHAPES};
use crate::error::{Error, Result};
use crate::scene::{Scene, Texels};

/// Peak bytes per shape while the BVH is built (bounds, centres, the binary tree and
/// the final eight-wide nodes and leaf indices live together for a moment); measured at
/// 140–150 on the bunny and a 2 M-triangle mesh when leaves still copied their
/// triangles, 128–134 on meshes since, so a bound on meshes (scattered shapes, one to a
/// leaf, take more nodes a shape).
pub const BVH_BYTES_PER_SHAPE: u64 = 224;
/// The same for `bvh-copied`: the tree above, and then each leaf's copies, at worst a
/// 192-byte block of four lanes for a leaf of one shape.
pub const BVH_COPIED_BYTES_PER_SHAPE: u64 = BVH_BYTES_PER_SHAPE + 192;
/// The octree copies a shape into every cell it touches: 2 KB a triangle on the bunny.
pub const OCTREE_BYTES_PER_SHAPE: u64 = 4096;
/// Per output pixel: the traced band rows and the film (three f32), the developed image
/// and the encoder's copy.
pub const FILM_BYTES_PER_PIXEL: u64 = 48;
/// The budget when the machine's memory cannot be read.
pub const FALLBACK_BUDGET: u64 = 8 << 30;

/// Bytes an instance holds: its transform, and its box and place in the top tree
/// (about 43 bytes, `an_instance_holds_under_100_bytes`, rounded up).
const INSTANCE_BYTES: u64 = size_of::<crate::scene::Instance>() as u64 + 48;

/// Bytes of a mesh's vertex attributes and their index triples.
fn attribute_bytes(m: &crate::scene::MeshAttributes) -> u64 {
    (m.normals.len() * 12
        + m.texcoords.len() * 8
        + m.colors.len() * 12
        + m.normal_indices.len() * 12
        + m.texcoord_indices.len() * 12
        + m.color_indices.len() * 12) as u64
}

/// The big allocations of one render, in bytes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MemoryEstimate {
    /// Shapes, their material indices and mesh attributes (and any caster copy).
    pub shapes: u64,
    /// The intersector at its build's peak: a set number of bytes a shape for each
    /// [`AccelKind`].
    pub accel: u64,
    /// Texels of every image and 2014 texture.
    pub images: u64,
    /// Output pixels (film, developed image, encoder copy) and each thread's band of
    /// supersampled rows.
    pub film: u64,
}

impl MemoryEstimate {
    /// The sum of the four parts, saturating: what is checked against the budget.
    pub fn total(&self) -> u64 {
        self.shapes
            .saturating_add(self.accel)
            .saturating_add(self.images)
            .saturating_add(self.film)
    }

    /// What rendering `scene` into a `width` x `height` frame with `accel` needs.
    pub fn of(scene: &Scene, accel: AccelKind, width: u32, height: u32, aa: u32) -> Self {
        let n = scene.shapes.len() as u64;
        let attributes: u64 = scene.meshes.iter().map(attribute_bytes).sum();
        let images = scene
            .images
            .iter()
            .map(|i| match &i.texels {
                Texels::Rgba8 { texels, .. } => texels.len() as u64 * 4,
                Texels::RgbaF32(texels) => texels.len() as u64 * 16,
            })
            .sum::<u64>()
            + scene
                .textures
                .iter()
                .map(|t| t.texels.len() as u64 * 3)
                .sum::<u64>();
        // Instances: each object's shapes, attributes and BVH once, and a transform,
        // box and top-tree node an instance.
        let object_shapes: u64 = scene.objects.iter().map(|o| o.shapes.len() as u64).sum();
        let object_bytes: u64 = scene
            .objects
            .iter()
            .map(|o| {
                o.shapes.memory_bytes() as u64
                    + o.shapes.len() as u64 * size_of::<u32>() as u64
                    + o.meshes.iter().map(attribute_bytes).sum::<u64>()
            })
            .sum();
        let instances = scene.instances.len() as u64 * INSTANCE_BYTES;
        let accel = world_accel_bytes(accel, n)
            .saturating_add(object_shapes.saturating_mul(accel_bytes_per_shape(AccelKind::Bvh)))
            .saturating_add(instances);
        let pixels = u64::from(width) * u64::from(height);
        // Supersampled rows are traced a band at a time; the output pixels stay.
        let band = u64::from(width) * u64::from(aa) * u64::from(aa) * 32 * 12;
        let threads = std::thread::available_parallelism().map_or(1, |t| t.get()) as u64;
        MemoryEstimate {
            shapes: (scene.shapes.memory_bytes() as u64)
                .saturating_add(n.saturating_mul(size_of::<u32>() as u64))
                .saturating_add(attributes)
                .saturating_add(object_bytes),
            accel,
            images,
            film: pixels
                .saturating_mul(FILM_BYTES_PER_PIXEL)
                .saturating_add(band.saturating_mul(threads)),
        }
    }

    /// This estimate and the shadow casters of the whitted model (`casters` of the
    /// scene's shapes, gathered when shapes clear to shadows outnumber them): their copy,
    /// at most the scene's shapes with an index each (and, while it is made, a table of
    /// four bytes a position), and their own intersector.
    pub fn with_casters(self, scene: &Scene, accel: AccelKind, casters: usize) -> Self {
        let casters = casters as u64;
        let positions = scene.shapes.positions().len() as u64;
        MemoryEstimate {
            shapes: self
                .shapes
                .saturating_add(scene.shapes.memory_bytes() as u64)
                .saturating_add(positions.saturating_mul(size_of::<u32>() as u64))
                .saturating_add(casters.saturating_mul(size_of::<u32>() as u64)),
            accel: self
                .accel
                .saturating_add(casters.saturating_mul(accel_bytes_per_shape(accel))),
            ..self
        }
    }

    /// An error naming the figures when the estimate exceeds `budget` bytes; `accel` is
    /// the intersector in use (the advice names the smallest only when it is not).
    pub fn check(&self, budget: u64, accel: AccelKind) -> Result<()> {
        if self.total() <= budget {
            return Ok(());
        }
        let triangles = if accel == AccelKind::Bvh {
            "fewer triangles"
        } else {
            "fewer triangles or the bvh intersector"
        };
        Err(Error::Settings(format!(
            "the render needs about {} (shapes {}, intersector {}, images {}, film {}), \
             more than the memory budget of {}: render a smaller image (--width), use \
             {triangles}, or raise --max-memory",
            human(self.total()),
            human(self.shapes),
            human(self.accel),
            human(self.images),
            human(self.film),
            human(budget),
        )))
    }
}

/// The intersector over a scene's own `n` shapes: a BVH of a small scene holds a
/// second tree for its shadow rays, without the walls of its box.
fn world_accel_bytes(accel: AccelKind, n: u64) -> u64 {
    let trees = match accel {
        AccelKind::Bvh | AccelKind::BvhCopied if n <= INDOOR_SHAPES as u64 => 2,
        _ => 1,
    };
    n.saturating_mul(accel_bytes_per_shape(accel)) * trees
}

fn accel_bytes_per_shape(accel: AccelKind) -> u64 {
    match accel {
        AccelKind::List => 0,
        AccelKind::Bvh => BVH_BYTES_PER_SHAPE,
        AccelKind::BvhCopied => BVH_COPIED_BYTES_PER_SHAPE,
        AccelKind::Octree => OCTREE_BYTES_PER_SHAPE,
    }
}

/// The default budget: half of the machine's memory, or of the container's limit.
pub fn default_budget() -> u64 {
    physical_memory().map_or(FALLBACK_BUDGET, |m| m / 2)
}

/// The memory this process may use: the smaller of the machine's memory and a cgroup
/// limit. `None` where neither can be read.
pub fn physical_memory() -> Option<u64> {
    let total = read_small("/proc/meminfo").and_then(|t| {
        let line = t.lines().find(|l| l.starts_with("MemTotal:"))?;
        let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
        kib.checked_mul(1024)
    });
    let cgroup = [
        "/sys/fs/cgroup/memory.max",
        "/sys/fs/cgroup/memory/memory.limit_in_bytes",
    ]
    .into_iter()
    .find_map(|p| read_small(p)?.trim().parse::<u64>().ok());
    match (total, cgroup) {
        (Some(t), Some(c)) => Some(t.min(c)),
        (t, c) => t.or(c),
    }
}

/// A small system file: these are regular files of stated size 0, so they are read
/// with a bound of their own rather than through the scene reader.
fn read_small(path: &str) -> Option<String> {
    use std::io::Read as _;
    let mut text = String::new();
    std::fs::File::open(path)
        .ok()?
        .take(64 * 1024)
        .read_to_string(&mut text)
        .ok()?;
    Some(text)
}

/// Parses a size such as `512M`, `4G`, `4GiB`, `1.5G` or a number of bytes. Units are
/// binary (K = 1024).
pub fn parse_size(s: &str) -> std::result::Result<u64, String> {
    let t = s.trim();
    let digits = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (number, unit) = t.split_at(digits);
    let shift = match unit.trim().to_ascii_uppercase().as_str() {
        "" | "B" => 0,
        "K" | "KB" | "KIB" => 10,
        "M" | "MB" | "MIB" => 20,
        "G" | "GB" | "GIB" => 30,
        "T" | "TB" | "TIB" => 40,
        _ => return Err(format!("expected a size such as 512M or 4G, found `{s}`")),
    };
    let value: f64 = number
        .parse()
        .map_err(|_| format!("expected a size such as 512M or 4G, found `{s}`"))?;
    let bytes = value * (1u64 << shift) as f64;
    if !(bytes >= 1.0 && bytes < u64::MAX as f64) {
        return Err(format!("expected a size of at least 1 byte, found `{s}`"));
    }
    Ok(bytes as u64)
}

/// `1.5 GiB`, `300 MiB`, `12 KiB`, `80 B`.
pub fn human(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} B")
    } else if value < 10.0 {
        format!("{value:.1} {}", UNITS[unit])
    } else {
        format!("{value:.0} {}", UNITS[unit])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;
    use crate::scene::{Material, Shape, Sphere};

    #[test]
    fn sizes_parse_with_binary_units() {
        assert_eq!(parse_size("4G"), Ok(4 << 30));
        assert_eq!(parse_size("512M"), Ok(512 << 20));
        assert_eq!(parse_size("1.5GiB"), Ok(3 << 29));
        assert_eq!(parse_size("2048"), Ok(2048));
        assert_eq!(parse_size(" 16 kb "), Ok(16 << 10));
        for bad in ["", "G", "-1G", "4X", "1e3", "0", "nanG", "99999999999T"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn human_sizes() {
        assert_eq!(human(80), "80 B");
        assert_eq!(human(3 << 29), "1.5 GiB");
        assert_eq!(human(300 << 20), "300 MiB");
    }

    fn spheres(n: usize) -> Scene {
        let mut scene = Scene {
            materials: vec![Material::default_white()],
            ..Scene::default()
        };
        for i in 0..n {
            let center = Vec3::new(i as f32, 0.0, 0.0);
            scene.push_shape(
                Shape::Sphere(Sphere {
                    center,
                    radius: 0.5,
                }),
                0,
            );
        }
        scene
    }

    /// An object is counted once, however many instances place it; each instance
    /// adds its own few bytes.
    #[test]
    fn the_estimate_counts_an_object_once_and_bytes_an_instance() {
        let mut object = crate::scene::Object::default();
        for i in 0..100 {
            let x = i as f32;
            object.shapes.push(Shape::Triangle(crate::scene::Triangle {
                v: [Vec3::new(x, 0.0, 0.0), Vec3::X, Vec3::Y],
            }));
            object.material_of.push(0);
        }
        let estimate = |instances: usize| {
            let scene = Scene {
                objects: vec![object.clone()],
                instances: vec![
                    crate::scene::Instance::new(0, glam::Affine3A::IDENTITY);
                    instances
                ],
                ..Scene::default()
            };
            MemoryEstimate::of(&scene, AccelKind::Bvh, 10, 10, 1)
        };
        let (one, many) = (estimate(1), estimate(1001));
        assert!(one.shapes >= 100 * 40, "{one:?}");
        assert_eq!(many.shapes, one.shapes);
        assert_eq!(many.accel - one.accel, 1000 * INSTANCE_BYTES);
    }

    #[test]
    fn the_estimate_counts_shapes_intersector_and_film() {
        let scene = spheres(1000);
        let e = MemoryEstimate::of(&scene, AccelKind::Bvh, 100, 50, 1);
        assert_eq!(e.shapes, scene.shapes.memory_bytes() as u64 + 1000 * 4);
        assert!(e.shapes >= 1000 * (size_of::<Shape>() + 4) as u64);
        // A small scene's tree twice: the second for its shadow rays.
        assert_eq!(e.accel, 2 * 1000 * BVH_BYTES_PER_SHAPE);
        assert_eq!(e.images, 0);
        assert!(e.film >= 5000 * FILM_BYTES_PER_PIXEL);
        let copied = MemoryEstimate::of(&scene, AccelKind::BvhCopied, 100, 50, 1);
        assert_eq!(copied.accel, 2 * 1000 * BVH_COPIED_BYTES_PER_SHAPE);
        let octree = MemoryEstimate::of(&scene, AccelKind::Octree, 100, 50, 1);
        assert_eq!(octree.accel, 1000 * OCTREE_BYTES_PER_SHAPE);
        assert_eq!(
            MemoryEstimate::of(&scene, AccelKind::List, 1, 1, 1).accel,
            0
        );
    }

    #[test]
    fn a_built_intersector_keeps_less_than_its_estimate() {
        // Scattered triangles, far apart: leaves of one shape, the copies' worst case.
        let mut scene = spheres(0);
        for i in 0..2000u32 {
            let c = Vec3::new(
                (i % 13) as f32 * 40.0,
                (i / 13) as f32 * 40.0,
                (i % 7) as f32,
            );
            let v = [c, c + Vec3::X, c + Vec3::Y];
            scene.push_shape(Shape::Triangle(crate::scene::Triangle { v }), 0);
        }
        for kind in AccelKind::ALL {
            let accel = crate::accel::Accel::build(kind, &scene.shapes);
            let kept = accel.memory_bytes() as u64;
            assert!(
                kept <= world_accel_bytes(kind, 2000),
                "{kind}: {kept} bytes"
            );
        }
    }

    #[test]
    fn shadow_casters_add_their_copy_and_their_intersector() {
        let scene = spheres(1000);
        for kind in AccelKind::ALL {
            let e = MemoryEstimate::of(&scene, kind, 100, 50, 1);
            let with = e.with_casters(&scene, kind, 300);
            let positions = scene.shapes.positions().len() as u64;
            assert_eq!(
                with.shapes,
                e.shapes + scene.shapes.memory_bytes() as u64 + positions * 4 + 300 * 4
            );
            assert_eq!(with.accel, e.accel + 300 * accel_bytes_per_shape(kind));
            assert_eq!((with.images, with.film), (e.images, e.film));
        }
    }

    #[test]
    fn an_estimate_over_budget_is_refused_with_its_figures() {
        let e = MemoryEstimate::of(&spheres(10), AccelKind::Bvh, 65536, 65536, 1);
        assert!(e.film > 100 << 30);
        let msg = e.check(8 << 30, AccelKind::Bvh).unwrap_err().to_string();
        assert!(
            msg.contains("more than the memory budget of 8.0 GiB"),
            "{msg}"
        );
        assert!(msg.contains("film 192 GiB"), "{msg}");
        // The bvh intersector is suggested only when another is in use.
        assert!(!msg.contains("bvh intersector"), "{msg}");
        let msg = e.check(8 << 30, AccelKind::List).unwrap_err().to_string();
        assert!(msg.contains("or the bvh intersector"), "{msg}");
        assert!(e.check(u64::MAX, AccelKind::Bvh).is_ok());
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn the_machine_memory_is_read() {
        let m = physical_memory().expect("/proc/meminfo");
        assert!(m >= 64 << 20, "{m}");
        assert_eq!(default_budget(), m / 2);
    }
}
