//! What every stage may read, at the bottom of the flow: the bounds on inputs
//! ([`limits`]), the one opener of files ([`file`]), text as files are decoded and
//! messages quote it ([`text`]), and linear images with their codecs ([`image`],
//! [`hdr`]: the readers of textures and the writers of renders share them).

pub mod file;
pub mod hdr;
pub mod image;
pub mod limits;
pub mod text;

/// Says why a test skipped where `cargo test` shows it: the harness keeps what a
/// passing test prints with `println!` or `eprintln!`, not what it writes to stderr.
#[cfg(test)]
pub(crate) fn skipped(why: impl std::fmt::Display) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "skipped: {why}");
}
