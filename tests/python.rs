//! Runs the Python package's test suite (python/tests) from `cargo test`, so that one
//! command tests everything.
//!
//! It needs a virtual environment with maturin, pytest and NumPy (and Ray and tqdm for
//! the cluster tests): `target/py-venv`, or the one `PRISM_PY_VENV` names. The test
//! creates the environment when it is missing but installs nothing into it (that
//! needs the network and minutes; CI does it once, see docs/python.md); without the
//! tools it says "skipped" and passes. With them it builds the extension into the
//! environment (`maturin develop`, the debug profile, sharing target/) and fails when
//! pytest fails. `PRISM_PY_TESTS="not ray"` is passed to pytest's `-m` (skip the Ray
//! tests, about 20 seconds).

use std::path::{Path, PathBuf};
use std::process::Command;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn venv() -> PathBuf {
    std::env::var_os("PRISM_PY_VENV")
        .map(PathBuf::from)
        .unwrap_or_else(|| repo().join("target").join("py-venv"))
}

fn runs(program: &Path, args: &[&str]) -> bool {
    Command::new(program)
        .args(args)
        .output()
        .is_ok_and(|o| o.status.success())
}

/// A command in the environment, with the environment active and none of the
/// variables this test binary got from Cargo (the nested build is Cargo's own).
fn in_venv(venv: &Path, program: &str) -> Command {
    let bin = venv.join("bin");
    let mut cmd = Command::new(bin.join(program));
    for (key, _) in std::env::vars_os() {
        if key.to_string_lossy().starts_with("CARGO_") && key != "CARGO_HOME" {
            cmd.env_remove(key);
        }
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    let mut paths = vec![bin];
    paths.extend(std::env::split_paths(&path));
    cmd.env("PATH", std::env::join_paths(paths).expect("PATH entries"))
        .env("VIRTUAL_ENV", venv)
        .current_dir(repo());
    cmd
}

#[test]
fn python_suite() {
    if !runs(Path::new("python3"), &["--version"]) {
        println!("skipped: python3 is not installed");
        return;
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
            println!(
                "skipped: cannot create a virtual environment at {}",
                venv.display()
            );
            return;
        }
    }
    let has_tools = runs(&python, &["-c", "import numpy, pytest"])
        && runs(&venv.join("bin").join("maturin"), &["--version"]);
    if !has_tools {
        println!(
            "skipped: the Python tests need maturin, pytest and numpy in {}: \
             {}/bin/pip install maturin numpy pytest tqdm ray",
            venv.display(),
            venv.display()
        );
        return;
    }
    let built = in_venv(&venv, "maturin")
        .args(["develop", "--quiet", "--manifest-path", "python/Cargo.toml"])
        .status()
        .expect("maturin runs");
    assert!(built.success(), "maturin develop failed");
    let mut pytest = in_venv(&venv, "python");
    pytest
        .args(["-m", "pytest", "-q", "python/tests"])
        .env("PRISM_BIN", env!("CARGO_BIN_EXE_prism"));
    if let Ok(marks) = std::env::var("PRISM_PY_TESTS") {
        pytest.args(["-m", &marks]);
    }
    let status = pytest.status().expect("pytest runs");
    assert!(status.success(), "the Python tests failed (see above)");
}
