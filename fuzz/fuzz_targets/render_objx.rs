//! `prism_fuzz::render_objx` (src/lib.rs) under libFuzzer.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| prism_fuzz::then_workers_gone(prism_fuzz::render_objx::check, data));
