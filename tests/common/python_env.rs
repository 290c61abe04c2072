//! The Python environment the Python and Blender suites run from: `target/py-venv`
//! (or the one `PRISM_PY_VENV` names), with the `prism` extension built into
//! `python/prism` by `maturin develop`.

use std::path::{Path, PathBuf};
use std::process::Command;

pub fn venv() -> PathBuf {
    std::env::var_os("PRISM_PY_VENV")
        .map(PathBuf::from)
        .unwrap_or_else(|| super::repo().join("target").join("py-venv"))
}

pub fn runs(program: &Path, args: &[&str]) -> bool {
    Command::new(program)
        .args(args)
        .output()
        .is_ok_and(|o| o.status.success())
}

/// A command in the environment, with the environment active and none of the
/// variables this test binary got from Cargo (the nested build is Cargo's own), but
/// for the user's `CARGO_HOME` and `CARGO_INCREMENTAL` (CI's 0: an incremental
/// build of the extension would write its caches for nothing).
pub fn in_venv(venv: &Path, program: &str) -> Command {
    let bin = venv.join("bin");
    let mut cmd = Command::new(bin.join(program));
    for (key, _) in std::env::vars_os() {
        if key.to_string_lossy().starts_with("CARGO_")
            && key != "CARGO_HOME"
            && key != "CARGO_INCREMENTAL"
        {
            cmd.env_remove(key);
        }
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    let mut paths = vec![bin];
    paths.extend(std::env::split_paths(&path));
    cmd.env("PATH", std::env::join_paths(paths).expect("PATH entries"))
        .env("VIRTUAL_ENV", venv)
        .current_dir(super::repo());
    cmd
}

/// Says why a suite did not run where `cargo test` shows it: a passing test's
/// printed output is captured, but not what is written to standard error directly.
pub fn skipped(suite: &str, why: &str) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "{suite} skipped: {why}");
}

/// Whether pip installed `packages` into `venv` from the package index.
pub fn pip_install(venv: &Path, packages: &[&str]) -> bool {
    in_venv(venv, "python")
        .args([
            "-m",
            "pip",
            "install",
            "--quiet",
            "--disable-pip-version-check",
        ])
        .args(packages)
        .status()
        .is_ok_and(|s| s.success())
}

/// The tools the suites need, installed into the environment from the package index.
pub const TOOLS: [&str; 5] = ["maturin", "numpy", "pytest", "tqdm", "selenium"];

/// The environment, made and given its tools when missing (once: later runs find
/// them), or why it cannot be.
pub fn prepared() -> Result<PathBuf, String> {
    if !runs(Path::new("python3"), &["--version"]) {
        return Err("python3 is not installed".into());
    }
    let venv = venv();
    let python = venv.join("bin").join("python");
    if !python.is_file() {
        let made = Command::new("python3")
            .args(["-m", "venv"])
            .arg(&venv)
            .status()
            .is_ok_and(|s| s.success());
        if !made {
            return Err(format!(
                "cannot create a virtual environment at {} (python3 -m venv)",
                venv.display()
            ));
        }
    }
    let has_tools = |python: &Path| {
        runs(python, &["-c", "import numpy, pytest"])
            && runs(&venv.join("bin").join("maturin"), &["--version"])
    };
    if !has_tools(&python) {
        let installed = pip_install(&venv, &TOOLS);
        if !installed || !has_tools(&python) {
            return Err(format!(
                "the Python tests need {} in {}, and pip could not install them: \
                 {}/bin/pip install {}",
                TOOLS.join(", "),
                venv.display(),
                venv.display(),
                TOOLS.join(" ")
            ));
        }
    }
    Ok(venv)
}

/// Builds the extension into the environment (and into `python/prism`, which the
/// editable install points at): the debug profile, sharing target/.
pub fn build_extension(venv: &Path) {
    let built = in_venv(venv, "maturin")
        .args(["develop", "--quiet", "--manifest-path", "python/Cargo.toml"])
        .status()
        .expect("maturin runs");
    assert!(built.success(), "maturin develop failed");
}
