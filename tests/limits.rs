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
        skipped("cannot mount a small tmpfs here (needs root)");
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

/// Bits into bytes, least significant first, as DEFLATE packs them.
struct Bits {
    bytes: Vec<u8>,
    used: u32,
}

impl Bits {
    fn put(&mut self, value: u32, count: u32) {
        for k in 0..count {
            if self.used.is_multiple_of(8) {
                self.bytes.push(0);
            }
            let bit = (value >> k & 1) as u8;
            *self.bytes.last_mut().unwrap() |= bit << (self.used % 8);
            self.used += 1;
        }
    }

    /// A Huffman code: sent most significant bit first.
    fn code(&mut self, code: u32, len: u32) {
        for k in (0..len).rev() {
            self.put(code >> k & 1, 1);
        }
    }
}

/// A zlib stream of `n` zero bytes (n > 258) in a few bytes per 258: one literal 0,
/// then copies of length 258 at distance 1 (fixed Huffman codes), then a shorter copy.
fn zlib_zeros(n: usize) -> Vec<u8> {
    let mut bits = Bits {
        bytes: vec![0x78, 0x01],
        used: 16,
    };
    bits.put(1, 1); // last block
    bits.put(1, 2); // fixed Huffman codes
    bits.code(0x30, 8); // literal 0
    let mut left = n - 1;
    while left > 0 {
        let len = left.min(258);
        let len = if left - len > 0 && left - len < 3 {
            len - 3
        } else {
            len
        };
        match len {
            258 => bits.code(0b1100_0101, 8),           // code 285
            3..=10 => bits.code(len as u32 - 3 + 1, 7), // codes 257-264
            _ => {
                // Codes 265-284 carry extra bits; find the code whose range holds len.
                let bases = [
                    11, 13, 15, 17, 19, 23, 27, 31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195,
                    227,
                ];
                let i = bases.iter().rposition(|&b| b <= len).unwrap();
                let extra = (i / 4 + 1) as u32;
                let code = 265 + i as u32;
                if code <= 279 {
                    bits.code(code - 256, 7);
                } else {
                    bits.code(code - 280 + 0b1100_0000, 8);
                }
                bits.put((len - bases[i]) as u32, extra);
            }
        }
        bits.code(0, 5); // distance 1
        left -= len;
    }
    bits.code(0, 7); // end of block
    // Adler-32 of zeros: a = 1, b = n mod 65521.
    let b = (n % 65521) as u32;
    bits.bytes.extend_from_slice(&((b << 16) | 1).to_be_bytes());
    bits.bytes
}

fn png_chunk(png: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    png.extend_from_slice(&(data.len() as u32).to_be_bytes());
    png.extend_from_slice(kind);
    png.extend_from_slice(data);
    let crc = crc32(kind.iter().chain(data));
    png.extend_from_slice(&crc.to_be_bytes());
}

fn crc32<'a>(bytes: impl Iterator<Item = &'a u8>) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

#[test]
fn a_decompression_bomb_texture_is_refused_before_it_is_decoded() {
    // A valid one-bit PNG of 22000 x 22000 pixels: 60 MB of zeros compressed to about
    // 380 KB, and 1.9 GB as the RGBA texels a decoder would allocate.
    let png = one_bit_png(22000, 22000);
    assert!(png.len() < 500_000);

    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("bomb.png"), &png).unwrap();
    // The same encoder makes a small PNG that decodes: the bomb is a real image.
    let small = one_bit_png(1000, 9);
    let image = image::load_from_memory(&small).unwrap().to_luma8();
    assert_eq!(image.dimensions(), (1000, 9));
    assert!(image.pixels().all(|p| p.0 == [0]));
    let scene = dir.path().join("bomb.toml");
    fs::write(
        &scene,
        "[[material]]\nname = \"m\"\ntexture = \"bomb.png\"\n\n\
         [[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n",
    )
    .unwrap();
    let out = dir.path().join("out.png");
    let start = std::time::Instant::now();
    let o = run(prism()
        .args(["render", "--width", "16", "--height", "16"])
        .args([&scene, &out]));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("22000x22000"), "{err}");
    assert!(err.contains("bomb.toml"), "{err}");
    assert!(start.elapsed() < std::time::Duration::from_secs(10));
    assert!(!out.exists());
}

/// A black one-bit greyscale PNG of `w` x `h` pixels.
fn one_bit_png(w: u32, h: u32) -> Vec<u8> {
    let row = 1 + w.div_ceil(8) as usize;
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&w.to_be_bytes());
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[1, 0, 0, 0, 0]);
    png_chunk(&mut png, b"IHDR", &ihdr);
    png_chunk(&mut png, b"IDAT", &zlib_zeros(row * h as usize));
    png_chunk(&mut png, b"IEND", &[]);
    png
}

/// Says why a test skipped where `cargo test` shows it: the harness keeps what a
/// passing test prints with `println!` or `eprintln!`, not what it writes to stderr.
fn skipped(why: impl std::fmt::Display) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "skipped: {why}");
}
