//! `prism_fuzz::anim_toml` (src/lib.rs) under libFuzzer.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| prism_fuzz::anim_toml::check(data));
