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

mod common;

use common::python_env::{build_extension, in_venv, pip_install, prepared, runs, skipped};

/// What `prism.denoise` imports (Open Image Denoise 2.5, as the `oidn` feature links):
/// installed only when `PRISM_TEST_OIDN=1` asks.
const OIDN_PACKAGE: &str = "pyoidn==2.5.1.0";

#[test]
fn python_suite() {
    let venv = match prepared() {
        Ok(venv) => venv,
        Err(why) => return skipped("python_suite", &why),
    };
    let python = venv.join("bin").join("python");
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
    build_extension(&venv);
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
