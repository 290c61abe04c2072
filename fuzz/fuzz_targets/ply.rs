//! `prism_fuzz::ply` (src/lib.rs) under libFuzzer.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| prism_fuzz::ply::check(data));
