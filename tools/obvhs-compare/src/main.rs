//! Prism's 4-wide BVH (`prism::accel::Accel`, `AccelKind::Bvh`) against obvhs's CWBVH
//! (compressed wide BVH8, PLOC + reinsertion builder) on the same rays, one thread.
//!
//! Usage: obvhs-cmp [SCENE.obj] [CAMERA.cmr] [MIN_SECONDS_PER_ENGINE_PER_QUERY]
//! Defaults: the Stanford bunny in ../shared beside the repository and
//! benches/bunny.cmr (1280x720), 2 s.
//!
//! Primary: closest hit of every camera ray, t in (0, inf).
//! Shadow: one segment per Prism primary hit point p, between p and a point light at
//! the camera eye; cast from the light toward p (as Prism's own bench does, so neither
//! engine can self-hit the triangle p lies on) with t_max = |p - light| * (1 - 1e-4).
//! Passes alternate Prism, obvhs, Prism, obvhs, ... until each engine has run for at
//! least MIN_SECONDS and at least 3 passes; we report the best pass and the total rate.

use std::hint::black_box;
use std::time::{Duration, Instant};

use glam::Vec3A;
use obvhs::{
    BvhBuildParams,
    bvh2::{Bvh2, builder::build_bvh2_from_tris, node::Bvh2Node},
    cwbvh::{CwBvh, builder::build_cwbvh_from_tris, node::CwBvhNode},
    ray::{Ray as ORay, RayHit},
    rt_triangle::RtTriangle,
    triangle::Triangle as OTriangle,
};
use prism::accel::{Accel, AccelKind};
use prism::math::Ray;
use prism::scene::Shape;

const REL_TOL: f32 = 1e-4;

/// obvhs's two BVH layouts.
enum Tree {
    /// Compressed wide BVH8 (80-byte nodes), obvhs's headline CPU/GPU layout.
    Cw(CwBvh),
    /// Binary BVH after leaf collapse (up to 8 triangles a leaf with these presets).
    B2(Bvh2),
}

/// An obvhs BVH plus the triangles reordered into BVH order (the layout obvhs's
/// examples recommend: the traversal callback then indexes the triangles directly).
struct Obvhs {
    tree: Tree,
    tris: Vec<RtTriangle>,
}

impl Obvhs {
    fn build(tris: &[OTriangle], params: BvhBuildParams, cw: bool) -> Obvhs {
        let tree = if cw {
            Tree::Cw(build_cwbvh_from_tris(
                tris,
                params,
                &mut Duration::default(),
            ))
        } else {
            Tree::B2(build_bvh2_from_tris(tris, params, &mut Duration::default()))
        };
        let tris = Self::indices_of(&tree)
            .iter()
            .map(|&i| RtTriangle::from(&tris[i as usize]))
            .collect();
        Obvhs { tree, tris }
    }

    fn indices_of(tree: &Tree) -> &[u32] {
        match tree {
            Tree::Cw(b) => &b.primitive_indices,
            Tree::B2(b) => &b.primitive_indices,
        }
    }

    /// Closest hit: (t, original triangle index).
    #[inline]
    fn closest(&self, r: &Ray) -> Option<(f32, u32)> {
        let ray = ORay::new(r.origin, r.dir, 0.0, f32::INFINITY);
        let mut hit = RayHit::none();
        let f = |ray: &ORay, id: usize| self.tris[id].intersect(ray);
        let found = match &self.tree {
            Tree::Cw(b) => b.ray_traverse(ray, &mut hit, f),
            Tree::B2(b) => b.ray_traverse(ray, &mut hit, f),
        };
        found.then(|| {
            (
                hit.t,
                Self::indices_of(&self.tree)[hit.primitive_id as usize],
            )
        })
    }

    #[inline]
    fn occluded(&self, r: &Ray, t_max: f32) -> bool {
        let ray = ORay::new(r.origin, r.dir, 0.0, t_max);
        let f = |ray: &ORay, id: usize| self.tris[id].intersect(ray);
        !match &self.tree {
            Tree::Cw(b) => b.ray_traverse_miss(ray, f),
            Tree::B2(b) => b.ray_traverse_miss(ray, f),
        }
    }

    /// Bytes of (nodes, primitive indices, reordered triangles), by length (obvhs's
    /// vectors are over-allocated after the build; shrink_to_fit would give these).
    fn memory(&self) -> (usize, usize, usize, usize) {
        let (nb, n) = match &self.tree {
            Tree::Cw(b) => (b.nodes.len() * size_of::<CwBvhNode>(), b.nodes.len()),
            Tree::B2(b) => (b.nodes.len() * size_of::<Bvh2Node>(), b.nodes.len()),
        };
        (
            nb,
            Self::indices_of(&self.tree).len() * size_of::<u32>(),
            self.tris.len() * size_of::<RtTriangle>(),
            n,
        )
    }
}

/// (label, preset, CWBVH?) for every obvhs variant measured.
fn presets() -> Vec<(&'static str, BvhBuildParams, bool)> {
    vec![
        ("cw fastest", BvhBuildParams::fastest_build(), true),
        ("cw very_fast", BvhBuildParams::very_fast_build(), true),
        ("cw fast", BvhBuildParams::fast_build(), true),
        ("cw medium", BvhBuildParams::medium_build(), true),
        ("cw slow", BvhBuildParams::slow_build(), true),
        ("cw very_slow", BvhBuildParams::very_slow_build(), true),
        ("bvh2 medium", BvhBuildParams::medium_build(), false),
        ("bvh2 very_slow", BvhBuildParams::very_slow_build(), false),
    ]
}

/// Best of `n` runs of `f`, in seconds, and the last result.
fn best_of<T>(n: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..n {
        let t0 = Instant::now();
        let r = black_box(f());
        best = best.min(t0.elapsed().as_secs_f64());
        out = Some(r);
    }
    (best, out.unwrap())
}

#[derive(Default)]
struct Timing {
    passes: usize,
    total: f64,
    best: f64,
}

impl Timing {
    fn add(&mut self, s: f64) {
        if self.passes == 0 || s < self.best {
            self.best = s;
        }
        self.passes += 1;
        self.total += s;
    }
    fn best_mrays(&self, n: usize) -> f64 {
        n as f64 / self.best / 1e6
    }
    fn mean_mrays(&self, n: usize) -> f64 {
        n as f64 * self.passes as f64 / self.total / 1e6
    }
}

/// Alternates the two passes until each has run `min_s` seconds and 3 times.
fn alternate(
    min_s: f64,
    mut a: impl FnMut() -> u64,
    mut b: impl FnMut() -> u64,
) -> (Timing, Timing) {
    let (mut ta, mut tb) = (Timing::default(), Timing::default());
    while ta.passes < 3 || tb.passes < 3 || ta.total < min_s || tb.total < min_s {
        let t0 = Instant::now();
        black_box(a());
        ta.add(t0.elapsed().as_secs_f64());
        let t0 = Instant::now();
        black_box(b());
        tb.add(t0.elapsed().as_secs_f64());
    }
    (ta, tb)
}

/// A path relative to the Prism repository.
fn root(relative: &str) -> String {
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    repo.join(relative).display().to_string()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scene_path = args
        .get(1)
        .cloned()
        .unwrap_or_else(|| root("../shared/models/stanford-bunny/stanford-bunny.obj"));
    let camera_path = args
        .get(2)
        .cloned()
        .unwrap_or_else(|| root("benches/bunny.cmr"));
    let min_s: f64 = args.get(3).map_or(2.0, |s| s.parse().expect("seconds"));

    println!(
        "target features: avx2={} fma={} sse4.1={}",
        cfg!(target_feature = "avx2"),
        cfg!(target_feature = "fma"),
        cfg!(target_feature = "sse4.1")
    );

    let scene = prism::format::load_scene(std::path::Path::new(&scene_path)).expect("scene");
    let camera = prism::format::load_camera(std::path::Path::new(&camera_path)).expect("camera");
    let rays: Vec<Ray> = prism::bench::primary_rays(&camera);
    let tris: Vec<OTriangle> = scene
        .shapes
        .iter()
        .map(|s| match s {
            Shape::Triangle(t) => OTriangle {
                v0: t.v[0],
                v1: t.v[1],
                v2: t.v[2],
            },
            other => panic!("not a triangle: {other:?}"),
        })
        .collect();
    println!(
        "scene {scene_path}: {} triangles; camera {}x{}, {} rays",
        tris.len(),
        camera.width,
        camera.height,
        rays.len()
    );

    // ---- Builds ---------------------------------------------------------------------
    let (prism_build_s, accel) = best_of(5, || Accel::build(AccelKind::Bvh, &scene.shapes));
    let prism_bytes = accel.memory_bytes();
    println!(
        "prism Accel::build(Bvh): best of 5 {:.1} ms, memory_bytes {} ({:.1} B/tri)",
        prism_build_s * 1e3,
        prism_bytes,
        prism_bytes as f64 / tris.len() as f64
    );

    // Prism's answers: the reference for the correctness counts.
    let prism_hits: Vec<Option<(f32, u32)>> = rays
        .iter()
        .map(|r| accel.closest(r, f32::INFINITY).map(|h| (h.t, h.shape)))
        .collect();
    let hit_count = prism_hits.iter().filter(|h| h.is_some()).count();
    println!(
        "prism hits {hit_count} of {} ({:.1} %)",
        rays.len(),
        100.0 * hit_count as f64 / rays.len() as f64
    );

    // Shadow segments: from the light (camera eye) toward each primary hit point.
    let light: Vec3A = camera.eye;
    let shadow: Vec<(Ray, f32)> = rays
        .iter()
        .zip(&prism_hits)
        .filter_map(|(r, h)| h.map(|(t, _)| r.at(t)))
        .filter_map(|p| {
            let d = p - light;
            let dist = d.length();
            (dist > 0.0).then(|| {
                (
                    Ray {
                        origin: light,
                        dir: d / dist,
                    },
                    dist * (1.0 - REL_TOL),
                )
            })
        })
        .collect();
    let prism_occl: Vec<bool> = shadow
        .iter()
        .map(|(r, tm)| accel.occluded(r, *tm, |_| true))
        .collect();

    println!();
    println!(
        "{:<16} {:>9} {:>9} {:>10} {:>10} {:>10} {:>8} {:>8} {:>8} {:>9} {:>9} {:>9} {:>9}",
        "obvhs preset",
        "prism ms",
        "build ms",
        "bytes",
        "nodes",
        "prim idx",
        "miss/hit",
        "t>1e-4",
        "tri id",
        "shadow≠",
        "occl pr",
        "occl ob",
        ""
    );
    let mut built = Vec::new();
    for (name, params, cw) in presets() {
        // Build times: alternate Prism and obvhs builds, 5 each, best of each.
        let (mut build_s, mut prism_s, mut ob) = (f64::INFINITY, f64::INFINITY, None);
        for _ in 0..5 {
            let (s, a) = best_of(1, || Accel::build(AccelKind::Bvh, &scene.shapes));
            drop(a);
            prism_s = prism_s.min(s);
            let (s, o) = best_of(1, || Obvhs::build(&tris, params, cw));
            build_s = build_s.min(s);
            ob = Some(o);
        }
        let ob = ob.unwrap();
        let (n_b, i_b, t_b, n_nodes) = ob.memory();
        // Correctness against Prism.
        let (mut hm, mut td, mut id) = (0usize, 0usize, 0usize);
        for (r, ph) in rays.iter().zip(&prism_hits) {
            let oh = ob.closest(r);
            match (ph, oh) {
                (Some((pt, ps)), Some((ot, os))) => {
                    if (pt - ot).abs() > REL_TOL * pt.abs().max(ot.abs()) {
                        td += 1;
                    }
                    if *ps != os {
                        id += 1;
                    }
                }
                (None, None) => {}
                _ => hm += 1,
            }
        }
        let mut sd = 0usize;
        let mut ob_occ = 0usize;
        for ((r, tm), po) in shadow.iter().zip(&prism_occl) {
            let oo = ob.occluded(r, *tm);
            ob_occ += oo as usize;
            sd += (oo != *po) as usize;
        }
        let pr_occ = prism_occl.iter().filter(|&&b| b).count();
        println!(
            "{:<16} {:>9.1} {:>9.1} {:>10} {:>10} {:>10} {:>8} {:>8} {:>8} {:>9} {:>9} {:>9}   (incl. {} B reordered RtTriangles; {} nodes)",
            name,
            prism_s * 1e3,
            build_s * 1e3,
            n_b + i_b + t_b,
            n_b,
            i_b,
            hm,
            td,
            id,
            sd,
            pr_occ,
            ob_occ,
            t_b,
            n_nodes
        );
        built.push((name, build_s, ob, hm, td, id, sd));
    }

    // ---- Throughput, one thread, alternating ------------------------------------------
    println!();
    println!(
        "one thread, alternating Prism/obvhs passes, >= 3 passes and >= {min_s} s each; primary {} rays, shadow {} rays",
        rays.len(),
        shadow.len()
    );
    println!(
        "{:<16} {:>12} {:>12} {:>12} {:>12} {:>8} | {:>12} {:>12} {:>12} {:>12} {:>8}",
        "obvhs preset",
        "prism prim",
        "obvhs prim",
        "(mean pr)",
        "(mean ob)",
        "ratio",
        "prism shad",
        "obvhs shad",
        "(mean pr)",
        "(mean ob)",
        "ratio"
    );
    for (name, _, ob, ..) in &built {
        let prim_prism = || {
            let mut n = 0u64;
            for r in &rays {
                if let Some(h) = accel.closest(black_box(r), f32::INFINITY) {
                    n += 1 + (h.t.to_bits() as u64 & 1);
                }
            }
            n
        };
        let prim_ob = || {
            let mut n = 0u64;
            for r in &rays {
                if let Some((t, _)) = ob.closest(black_box(r)) {
                    n += 1 + (t.to_bits() as u64 & 1);
                }
            }
            n
        };
        let (tp, to) = alternate(min_s, prim_prism, prim_ob);
        let shad_prism = || {
            shadow
                .iter()
                .filter(|(r, tm)| accel.occluded(black_box(r), *tm, |_| true))
                .count() as u64
        };
        let shad_ob = || {
            shadow
                .iter()
                .filter(|(r, tm)| ob.occluded(black_box(r), *tm))
                .count() as u64
        };
        let (sp, so) = alternate(min_s, shad_prism, shad_ob);
        let (np, ns) = (rays.len(), shadow.len());
        println!(
            "{:<16} {:>12.3} {:>12.3} {:>12.3} {:>12.3} {:>8.3} | {:>12.3} {:>12.3} {:>12.3} {:>12.3} {:>8.3}",
            name,
            tp.best_mrays(np),
            to.best_mrays(np),
            tp.mean_mrays(np),
            to.mean_mrays(np),
            to.best_mrays(np) / tp.best_mrays(np),
            sp.best_mrays(ns),
            so.best_mrays(ns),
            sp.mean_mrays(ns),
            so.mean_mrays(ns),
            so.best_mrays(ns) / sp.best_mrays(ns),
        );
    }
    println!(
        "(Mrays/s; first four columns of each half are best pass and mean over all passes; ratio = obvhs/prism, best pass)"
    );
}
