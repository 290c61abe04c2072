//! Runs the Python package's test suite (python/tests) from `cargo test`, so that one
//! command tests everything.
//!
//! It needs a virtual environment with maturin, pytest and NumPy (and Ray and tqdm for
//! the cluster tests): `target/py-venv`, or the one `PRISM_PY_VENV` names. Wherever
//! Python 3 is present the test creates the environment and installs maturin, NumPy,
//! pytest and tqdm into it from the package index when they are missing (once: later
//! runs find them; Ray stays CI's, see docs/python.md). Where it truly cannot, it says
//! why on standard error, which `cargo test` shows, and passes. With them it builds the extension into the
//! environment (`maturin develop`, the debug profile, sharing target/) and fails when
//! pytest fails. `PRISM_PY_TESTS="not ray"` is passed to pytest's `-m` (skip the Ray
//! tests, about 20 seconds). `PRISM_TEST_OIDN=1` asks for the denoising tests too: it
//! installs `pyoidn` (which ships Intel Open Image Denoise, an 87 MB wheel) into the
//! environment when it is missing, and those tests then fail rather than skip without
//! it; unasked, nothing is downloaded for them and they skip, saying why.

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

/// Says why the suite did not run where `cargo test` shows it: a passing test's
/// printed output is captured, but not what is written to standard error directly.
fn skipped(why: &str) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "python_suite skipped: {why}");
}

/// Whether pip installed `packages` into `venv` from the package index.
fn pip_install(venv: &Path, packages: &[&str]) -> bool {
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

/// The tools the suite needs, installed into `venv` from the package index.
const TOOLS: [&str; 5] = ["maturin", "numpy", "pytest", "tqdm", "selenium"];

/// What `prism.denoise` imports (Open Image Denoise 2.5, as the `oidn` feature links):
/// installed only when `PRISM_TEST_OIDN=1` asks.
const OIDN_PACKAGE: &str = "pyoidn==2.5.1.0";

#[test]
fn python_suite() {
    if !runs(Path::new("python3"), &["--version"]) {
        skipped("python3 is not installed");
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
            skipped(&format!(
                "cannot create a virtual environment at {} (python3 -m venv)",
                venv.display()
            ));
            return;
        }
    }
    let has_tools = |python: &Path| {
        runs(python, &["-c", "import numpy, pytest"])
            && runs(&venv.join("bin").join("maturin"), &["--version"])
    };
    if !has_tools(&python) {
        // A fresh machine: set the environment up, once (later runs find it).
        let installed = pip_install(&venv, &TOOLS);
        if !installed || !has_tools(&python) {
            skipped(&format!(
                "the Python tests need {} in {}, and pip could not install them: \
                 {}/bin/pip install {}",
                TOOLS.join(", "),
                venv.display(),
                venv.display(),
                TOOLS.join(" ")
            ));
            return;
        }
    }
    let wants_oidn = std::env::var("PRISM_TEST_OIDN").is_ok_and(|v| v == "1");
    if wants_oidn && !runs(&python, &["-c", "import pyoidn"]) {
        let installed = pip_install(&venv, &[OIDN_PACKAGE]);
        assert!(
            installed && runs(&python, &["-c", "import pyoidn"]),
            "PRISM_TEST_OIDN=1 asks for the denoising tests, and pip could not install \
             {OIDN_PACKAGE} into {}",
            venv.display()
        );
    }
    let built = in_venv(&venv, "maturin")
        .args(["develop", "--quiet", "--manifest-path", "python/Cargo.toml"])
        .status()
        .expect("maturin runs");
    assert!(built.success(), "maturin develop failed");
    let mut pytest = in_venv(&venv, "python");
    pytest
        .args(["-m", "pytest", "-q", "-rs", "python/tests"])
        .env("PRISM_BIN", env!("CARGO_BIN_EXE_prism"));
    if let Ok(marks) = std::env::var("PRISM_PY_TESTS") {
        pytest.args(["-m", &marks]);
    }
    let status = pytest.status().expect("pytest runs");
    assert!(status.success(), "the Python tests failed (see above)");
}
