//! What every stage may read, at the bottom of the flow: the bounds on inputs
//! ([`limits`]), the one opener of files ([`file`](mod@file)), text as files are decoded and
//! messages quote it ([`text`]), and linear images with their codecs ([`image`],
//! [`hdr`]: the readers of textures and the writers of renders share them), and memory
//! given back between stages.

pub mod file;
pub mod hdr;
pub mod image;
pub mod limits;
pub mod text;

/// Returns memory the allocator holds freed to the system (glibc's `malloc_trim`;
/// nothing elsewhere), so that what a finished stage used is not counted again at the
/// next one's peak: a scene file's parse of ten thousand transforms leaves 2 KB an
/// instance behind otherwise.
pub fn give_back_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `malloc_trim` releases free memory only; it has no preconditions.
    unsafe {
        libc::malloc_trim(0);
    }
}

/// Says why a test skipped where `cargo test` shows it: the harness keeps what a
/// passing test prints with `println!` or `eprintln!`, not what it writes to stderr.
#[cfg(test)]
pub(crate) fn skipped(why: impl std::fmt::Display) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "skipped: {why}");
}
