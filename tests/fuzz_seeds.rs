//! Every fuzz target's checks (`fuzz/src/lib.rs`, what each target asks of an input) on
//! every seed of its corpus (`fuzz/seeds/TARGET`), in the ordinary test build: the
//! checks compile and hold without the nightly toolchain, and the seeds, which hold
//! the tricky inputs found so far, stay clean. Finding new inputs is the fuzzer's work
//! (`fuzz/run.sh`, docs/robustness.md).

// `then_workers_gone` is the fuzz targets' alone.
#[allow(dead_code)]
#[path = "../fuzz/src/lib.rs"]
mod checks;

mod common;

/// Runs `check` on every file of `fuzz/seeds/target`, naming the file that fails.
fn replay(target: &str, check: fn(&[u8])) {
    let folder = common::repo().join("fuzz/seeds").join(target);
    let mut seeds: Vec<_> = std::fs::read_dir(&folder)
        .unwrap_or_else(|e| panic!("{}: {e}", folder.display()))
        .map(|entry| entry.expect("a seed").path())
        .collect();
    seeds.sort();
    assert!(!seeds.is_empty(), "{} holds no seed", folder.display());
    for seed in &seeds {
        let bytes = std::fs::read(seed).unwrap_or_else(|e| panic!("{}: {e}", seed.display()));
        let passed = std::panic::catch_unwind(|| check(&bytes));
        assert!(
            passed.is_ok(),
            "the {target} check failed on {}",
            seed.display()
        );
    }
}

macro_rules! seeds {
    ($($target:ident),* $(,)?) => {$(
        #[test]
        fn $target() {
            replay(stringify!($target), checks::$target::check);
        }
    )*};
}

seeds!(
    objx,
    mtlx,
    cmr,
    obj,
    obj_full,
    mtl,
    ply,
    gltf,
    scene_toml,
    anim_toml,
    render_objx,
    render_toml,
    texture,
);
