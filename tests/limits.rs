//! Resource limits and read restrictions, end to end: a render over its memory budget,
//! a scene reaching outside `--restrict-paths`, and a full disk.

mod common;
use common::*;
use std::fs;
use std::path::Path;

/// A copy of the example scene in its own folder, so a restriction can name it.
fn example_copy(dir: &Path) {
    for f in ["example.objx", "example.mtlx", "example.cmr", "checker.ppm"] {
        fs::copy(example(f), dir.join(f)).unwrap();
    }
}

fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn a_render_over_the_memory_budget_is_refused_with_its_figures() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("big.png");
    let render = |extra: &[&str]| {
        run(prism()
            .args([example("example.objx"), example("example.cmr"), out.clone()])
            .args(extra))
    };
    // A 65536 x 65536 frame needs far more than a test machine has: refused, not aborted.
    let o = render(&["--width", "65536", "--height", "65536"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("more than the memory budget of"), "{err}");
    assert!(err.contains("film 192 GiB"), "{err}");
    assert!(!out.exists());
    // A budget below a small render's own needs, in the units a user types.
    let o = render(&["--width", "64", "--max-memory", "64K"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("budget of 64 KiB"), "{}", stderr(&o));
    assert!(!out.exists());
    let o = render(&["--width", "64", "--max-memory", "lots"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("expected a size such as 512M"),
        "{}",
        stderr(&o)
    );
    let o = render(&["--width", "64", "--max-memory", "256M"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.exists());
}

#[test]
fn the_octree_is_budgeted_by_its_copies() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.png");
    // The same render fits with the BVH and not with the octree under a budget between.
    let render = |accel: &str| {
        run(prism()
            .args([example("example.objx"), example("example.cmr"), out.clone()])
            .args(["--width", "8", "--max-memory", "2M", "--accel", accel]))
    };
    assert!(render("bvh").status.success());
    let big = tempfile::tempdir().unwrap();
    // 2 000 triangles: 8 MB of octree at its estimate, under 1 MB of BVH.
    let mut obj = String::new();
    for i in 0..2000 {
        let x = i as f32;
        obj.push_str(&format!("v {x} 0 0\nv {x} 1 0\nv {x} 0 1\n"));
    }
    for i in 0..2000 {
        obj.push_str(&format!("f {} {} {}\n", 3 * i + 1, 3 * i + 2, 3 * i + 3));
    }
    let mesh = big.path().join("strip.obj");
    fs::write(&mesh, obj).unwrap();
    let render = |accel: &str| {
        run(prism().args([mesh.clone(), out.clone()]).args([
            "--width",
            "8",
            "--max-memory",
            "4M",
            "--accel",
            accel,
        ]))
    };
    let o = render("bvh");
    assert!(o.status.success(), "{}", stderr(&o));
    let o = render("octree");
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("intersector 7.8 MiB"), "{}", stderr(&o));
}

#[test]
fn restricted_reads_stay_inside_their_folder() {
    let root = tempfile::tempdir().unwrap();
    let jail = root.path().join("jail");
    fs::create_dir(&jail).unwrap();
    example_copy(&jail);
    let out = root.path().join("out.png");
    let render = |scene: &Path| {
        run(prism()
            .arg("render")
            .args([scene, &jail.join("example.cmr"), &out])
            .args(["--width", "32", "--restrict-paths"])
            .arg(&jail))
    };
    let o = render(&jail.join("example.objx"));
    assert!(o.status.success(), "{}", stderr(&o));
    fs::remove_file(&out).unwrap();

    // A material library named through `..`, and one through a symbolic link.
    fs::write(root.path().join("outside.mtlx"), "").unwrap();
    let scene = fs::read_to_string(jail.join("example.objx")).unwrap();
    let escape = |name: &str, target: &str| {
        let path = jail.join(name);
        fs::write(&path, scene.replace("example.mtlx", target)).unwrap();
        path
    };
    let dotdot = escape("dotdot.objx", "../outside.mtlx");
    #[cfg(unix)]
    std::os::unix::fs::symlink(root.path().join("outside.mtlx"), jail.join("link.mtlx")).unwrap();
    let linked = escape("linked.objx", "link.mtlx");
    for scene in [&dotdot, &linked] {
        let o = render(scene);
        assert_eq!(o.status.code(), Some(2));
        let err = stderr(&o);
        assert!(err.contains("restricted to"), "{err}");
        assert!(err.contains(&format!("{}:", scene.display())), "{err}");
        assert!(!out.exists());
    }
    // The scene itself outside the folder.
    fs::copy(jail.join("example.objx"), root.path().join("example.objx")).unwrap();
    let o = render(&root.path().join("example.objx"));
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("restricted to"), "{}", stderr(&o));
    // And `prism info` obeys it too.
    let o = run(prism()
        .args(["info", "--restrict-paths"])
        .arg(&jail)
        .arg(&dotdot));
    assert_eq!(o.status.code(), Some(2));
    let o = run(prism()
        .args(["info", "--restrict-paths"])
        .arg(root.path().join("missing"))
        .arg(&dotdot));
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--restrict-paths"), "{}", stderr(&o));
}

/// A 64 KiB tmpfs: mounting needs root (or a user namespace); elsewhere the test says
/// why it skips.
#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_is_a_clear_error_and_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let mount = dir.path().join("small");
    fs::create_dir(&mount).unwrap();
    let mounted = std::process::Command::new("mount")
        .args(["-t", "tmpfs", "-o", "size=64k", "prism-full-disk-test"])
        .arg(&mount)
        .output();
    if !mounted.is_ok_and(|o| o.status.success()) {
        eprintln!("skipped: cannot mount a small tmpfs here (needs root)");
        return;
    }
    struct Unmount<'a>(&'a Path);
    impl Drop for Unmount<'_> {
        fn drop(&mut self) {
            let _ = std::process::Command::new("umount").arg(self.0).status();
        }
    }
    let _guard = Unmount(&mount);
    // 256 x 144 binary PPM: 110 KB, more than the disk holds.
    let out = mount.join("frame.ppm");
    let o = run(prism()
        .args([example("example.objx"), example("example.cmr"), out.clone()])
        .args(["--width", "256", "--quiet"]));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains(&out.display().to_string()), "{err}");
    assert!(err.to_lowercase().contains("no space"), "{err}");
    assert!(entries(&mount).is_empty(), "{:?}", entries(&mount));
    // A small image still fits afterwards: nothing was left taking the space.
    let o = run(prism()
        .args([example("example.objx"), example("example.cmr"), out.clone()])
        .args(["--width", "32", "--quiet"]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(entries(&mount), ["frame.ppm"]);
}

#[test]
fn messages_quote_a_short_excerpt_of_huge_names() {
    let dir = tempfile::tempdir().unwrap();
    let name = "n".repeat(1 << 20);
    let mtl = dir.path().join("m.mtl");
    fs::write(
        &mtl,
        format!("newmtl {name}\nillum 42\nmap_Kd {name}.png\n"),
    )
    .unwrap();
    let obj = dir.path().join("m.obj");
    fs::write(
        &obj,
        format!("mtllib m.mtl\nusemtl {name}\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    )
    .unwrap();
    let toml = dir.path().join("s.toml");
    fs::write(&toml, format!("[render]\n{name} = 1\n")).unwrap();
    let tonemap = dir.path().join("t.toml");
    fs::write(&tonemap, format!("[render]\ntonemap = \"{name}\"\n")).unwrap();
    for (file, code) in [(&obj, 0), (&toml, 2), (&tonemap, 2)] {
        let o = run(prism().arg("info").arg(file));
        assert_eq!(o.status.code(), Some(code), "{}", stderr(&o));
        let said = o.stdout.len() + o.stderr.len();
        assert!(said < 2000, "{} bytes for {}", said, file.display());
        let all = format!("{}{}", String::from_utf8_lossy(&o.stdout), stderr(&o));
        assert!(all.contains("nnnnnnnnnn..."), "{all}");
    }
}
