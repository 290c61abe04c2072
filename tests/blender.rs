//! Runs the Blender add-on's tests (tests/blender) in Blender's own Python, from
//! `cargo test`, where Blender is installed (`blender` on the PATH, or the program
//! `PRISM_BLENDER` names; Debian's package in CI). Cycles, in the same Blender, is the
//! oracle of the units tests. The `prism` package they import is built into
//! `python/prism` first, as the Python suite builds it. The viewport's test runs Blender
//! with its interface under Xvfb (`xvfb-run`, Mesa's software OpenGL) where it is
//! installed. Without Blender, Python or Xvfb the test says what it skipped, and why,
//! on standard error.

mod common;

use common::python_env::{build_extension, prepared, runs, skipped};
use std::path::PathBuf;
use std::process::Command;

fn blender() -> Option<PathBuf> {
    let program = std::env::var_os("PRISM_BLENDER")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("blender"));
    runs(&program, &["--version"]).then_some(program)
}

#[test]
fn blender_suite() {
    let Some(blender) = blender() else {
        return skipped(
            "blender_suite",
            "Blender is not installed (apt-get install blender; or set PRISM_BLENDER)",
        );
    };
    let venv = match prepared() {
        Ok(venv) => venv,
        Err(why) => return skipped("blender_suite", &why),
    };
    build_extension(&venv);
    let repo = common::repo();
    let mut suite = Command::new(&blender);
    suite
        .args([
            "-b",
            "--factory-startup",
            "--python-exit-code",
            "1",
            "--python",
        ])
        .arg(repo.join("tests/blender/run.py"));
    passes(&repo, suite, "the Blender add-on's tests");
    viewport(&repo, &blender);
    bpy_module_suite(&repo);
}

/// Runs `command` with the `prism` package of `python/` and fails the test, naming
/// `what`, unless it succeeds (its output says why).
fn passes(repo: &std::path::Path, mut command: Command, what: &str) {
    let status = command
        .env("PRISM_PYTHON_PATH", repo.join("python"))
        .status()
        .unwrap_or_else(|e| panic!("{what} could not start: {e}"));
    assert!(status.success(), "{what} failed (see above)");
}

/// The viewport's test: Blender with its interface under Xvfb.
fn viewport(repo: &std::path::Path, blender: &std::path::Path) {
    if !runs(std::path::Path::new("xvfb-run"), &["--help"]) {
        return skipped(
            "blender_suite's viewport test",
            "xvfb-run is not installed (apt-get install xvfb xauth)",
        );
    }
    let screenshots = tempfile::tempdir().expect("a temporary folder");
    let mut test = Command::new("xvfb-run");
    test.args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(blender)
        .args(["--factory-startup", "--python"])
        .arg(repo.join("tests/blender/viewport.py"))
        .arg("--")
        .arg(screenshots.path());
    passes(repo, test, "the viewport test");
}

/// The same suite on Blender as a Python module (PyPI's `bpy`, a newer Blender than
/// Debian's): from the Python `PRISM_BPY_PYTHON` names, or `target/bpy-venv` (which
/// CI makes: `python3 -m venv target/bpy-venv && target/bpy-venv/bin/pip install
/// bpy==5.0.1`). It is a gigabyte, so the test does not install it itself.
fn bpy_module_suite(repo: &std::path::Path) {
    let python = std::env::var_os("PRISM_BPY_PYTHON")
        .map(PathBuf::from)
        .unwrap_or_else(|| repo.join("target/bpy-venv/bin/python"));
    if !runs(&python, &["-c", "import bpy"]) {
        return skipped(
            "blender_suite on PyPI's bpy",
            &format!(
                "{} cannot import bpy (python3 -m venv target/bpy-venv && \
                 target/bpy-venv/bin/pip install bpy==5.0.1)",
                python.display()
            ),
        );
    }
    let mut suite = Command::new(&python);
    suite.arg(repo.join("tests/blender/run.py"));
    passes(repo, suite, "the Blender add-on's tests on PyPI's bpy");
}
