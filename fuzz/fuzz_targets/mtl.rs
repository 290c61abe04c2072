//! The MTL reader on arbitrary bytes: never a panic, texture options always finite.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(library) = prism::format::mtl::parse(data, Path::new("m.mtl")) {
        for m in &library.materials {
            for map in [&m.map_kd, &m.map_d, &m.bump].into_iter().flatten() {
                assert!(map.scale.iter().chain(&map.offset).all(|v| v.is_finite()));
            }
        }
    }
});
