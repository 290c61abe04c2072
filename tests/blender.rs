//! Runs the Blender add-on's tests (tests/blender) in Blender's own Python, from
//! `cargo test`, where Blender is installed (`blender` on the PATH, or the program
//! `PRISM_BLENDER` names; Debian's package in CI). Cycles, in the same Blender, is the
//! oracle of the units tests. The `prism` package they import is built into
//! `python/prism` first, as the Python suite builds it. The viewport's test runs Blender
//! with its interface under Xvfb (`xvfb-run`, Mesa's software OpenGL) where it is
//! installed; the same suite runs again on PyPI's `bpy` where `target/bpy-venv` has it.
//! The three are three tests, which run side by side. Without Blender, Python or Xvfb
//! each says what it skipped, and why, on standard error.

mod common;

use common::python_env::{build_extension, prepared, runs, skipped};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

fn blender() -> Option<PathBuf> {
    let program = std::env::var_os("PRISM_BLENDER")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("blender"));
    runs(&program, &["--version"]).then_some(program)
}

/// The environment with the extension built, made once for the three suites, which
/// run side by side: much of each is Blender starting and exporting on one core.
fn extension() -> Result<&'static Path, String> {
    static BUILT: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    BUILT
        .get_or_init(|| {
            let venv = prepared()?;
            build_extension(&venv);
            Ok(venv)
        })
        .as_deref()
        .map_err(Clone::clone)
}

#[test]
fn blender_suite() {
    let Some(blender) = blender() else {
        return skipped(
            "blender_suite",
            "Blender is not installed (apt-get install blender; or set PRISM_BLENDER)",
        );
    };
    if let Err(why) = extension() {
        return skipped("blender_suite", &why);
    }
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
}

/// Runs `command` with the `prism` package of `python/` and fails the test, naming
/// `what`, unless it succeeds. Its output is kept and printed through the test's own,
/// which `cargo test` shows for a failure only: the suites run side by side, and their
/// output would otherwise interleave.
///
/// Blender's temporary files go to a folder of the test's own, removed after it:
/// Blender leaves its session folder behind in the system's when it ends abruptly.
fn passes(repo: &Path, mut command: Command, what: &str) {
    let scratch = tempfile::tempdir().expect("a temporary folder");
    let output = command
        .env("PRISM_PYTHON_PATH", repo.join("python"))
        .env("TMPDIR", scratch.path())
        .output()
        .unwrap_or_else(|e| panic!("{what} could not start: {e}"));
    print!("{}", String::from_utf8_lossy(&output.stdout));
    print!("{}", String::from_utf8_lossy(&output.stderr));
    assert!(output.status.success(), "{what} failed (see above)");
}

/// The viewport's test: Blender with its interface under Xvfb.
#[test]
fn blender_viewport() {
    let Some(blender) = blender() else {
        return skipped("blender_viewport", "Blender is not installed");
    };
    if !runs(Path::new("xvfb-run"), &["--help"]) {
        return skipped(
            "blender_viewport",
            "xvfb-run is not installed (apt-get install xvfb xauth)",
        );
    }
    if let Err(why) = extension() {
        return skipped("blender_viewport", &why);
    }
    let repo = common::repo();
    let screenshots = tempfile::tempdir().expect("a temporary folder");
    let mut test = Command::new("xvfb-run");
    test.args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(&blender)
        .args(["--factory-startup", "--python"])
        .arg(repo.join("tests/blender/viewport.py"))
        .arg("--")
        .arg(screenshots.path());
    passes(&repo, test, "the viewport test");
}

/// The same suite on Blender as a Python module (PyPI's `bpy`, a newer Blender than
/// Debian's): from the Python `PRISM_BPY_PYTHON` names, or `target/bpy-venv` (which
/// CI makes: `python3 -m venv target/bpy-venv && target/bpy-venv/bin/pip install
/// bpy==5.0.1`). It is a gigabyte, so the test does not install it itself.
#[test]
fn bpy_module_suite() {
    let repo = common::repo();
    let python = std::env::var_os("PRISM_BPY_PYTHON")
        .map(PathBuf::from)
        .unwrap_or_else(|| repo.join("target/bpy-venv/bin/python"));
    if !runs(&python, &["-c", "import bpy"]) {
        return skipped(
            "bpy_module_suite",
            &format!(
                "{} cannot import bpy (python3 -m venv target/bpy-venv && \
                 target/bpy-venv/bin/pip install bpy==5.0.1)",
                python.display()
            ),
        );
    }
    if let Err(why) = extension() {
        return skipped("bpy_module_suite", &why);
    }
    let mut suite = Command::new(&python);
    suite.arg(repo.join("tests/blender/run.py"));
    passes(&repo, suite, "the Blender add-on's tests on PyPI's bpy");
}
