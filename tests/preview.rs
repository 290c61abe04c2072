//! `prism preview` without a browser: a client of its HTTP server receives the passes
//! and the last equals `prism render`'s file byte for byte (for the path model after
//! sample passes of growing samples); a camera message renders
//! what `prism render --look-from …` writes; a saved edit re-renders, a broken one
//! shows its line and keeps the image; foreign hosts are refused; a burst of camera
//! moves leaves one render and no extra threads.

mod common;
use common::*;
use prism::job::JobOptions;
use prism::preview::Preview;
use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::time::{Duration, Instant};

/// A raw HTTP/1.1 exchange: the status code and the body.
fn http(
    url: &str,
    method: &str,
    path: &str,
    headers: &[(&str, &str)],
    body: &str,
) -> (u16, Vec<u8>) {
    let addr = url.trim_start_matches("http://").trim_end_matches('/');
    let mut s = TcpStream::connect(addr).unwrap();
    let mut req = format!("{method} {path} HTTP/1.1\r\nConnection: close\r\n");
    if !headers.iter().any(|(k, _)| k.eq_ignore_ascii_case("host")) {
        req += &format!("Host: {addr}\r\n");
    }
    for (k, v) in headers {
        req += &format!("{k}: {v}\r\n");
    }
    req += &format!("Content-Length: {}\r\n\r\n{body}", body.len());
    s.write_all(req.as_bytes()).unwrap();
    let mut out = Vec::new();
    s.read_to_end(&mut out).unwrap();
    let split = out.windows(4).position(|w| w == b"\r\n\r\n").unwrap();
    let head = String::from_utf8_lossy(&out[..split]).to_string();
    let code = head.split(' ').nth(1).unwrap().parse().unwrap();
    let mut body = out[split + 4..].to_vec();
    if head
        .to_ascii_lowercase()
        .contains("transfer-encoding: chunked")
    {
        body = unchunk(&body);
    }
    (code, body)
}

fn unchunk(mut b: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let line = b.windows(2).position(|w| w == b"\r\n").unwrap();
        let n = usize::from_str_radix(std::str::from_utf8(&b[..line]).unwrap().trim(), 16).unwrap();
        if n == 0 {
            return out;
        }
        out.extend_from_slice(&b[line + 2..line + 2 + n]);
        b = &b[line + 2 + n + 2..];
    }
}

fn status(url: &str, after: Option<u64>) -> serde_json::Value {
    let path = after.map_or("/status".to_string(), |v| format!("/status?after={v}"));
    let (code, body) = http(url, "GET", &path, &[], "");
    assert_eq!(code, 200);
    serde_json::from_slice(&body).unwrap()
}

/// Waits for the final frame of a generation after `generation` (or any, with 0).
fn final_after(url: &str, generation: u64, within: Duration) -> serde_json::Value {
    let start = Instant::now();
    let mut after = None;
    loop {
        let s = status(url, after);
        let f = &s["frame"];
        if f["final"] == true && f["generation"].as_u64().unwrap() > generation {
            return s;
        }
        assert!(
            start.elapsed() < within,
            "no final frame within {within:?}: {s}"
        );
        after = s["version"].as_u64();
    }
}

/// Every frame a long poll sees up to the first final one (a frame published while
/// the client is away is missed).
fn frames_until_final(url: &str) -> Vec<serde_json::Value> {
    let mut frames = Vec::new();
    let mut after = None;
    let begun = Instant::now();
    loop {
        let s = status(url, after);
        after = s["version"].as_u64();
        let f = s["frame"].clone();
        if f.is_object() && frames.last() != Some(&f) {
            frames.push(f.clone());
        }
        if f["final"] == true {
            return frames;
        }
        assert!(
            begun.elapsed() < Duration::from_secs(60),
            "no final frame: {s}"
        );
    }
}

/// The tests of this file one at a time: two of them count the process's threads.
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// A preview of `scene` on a free port, and its address.
fn start(scene: &Path) -> (Preview, String) {
    start_with(scene, JobOptions::default())
}

/// [`start`] with options, as `prism preview`'s flags give them.
fn start_with(scene: &Path, options: JobOptions) -> (Preview, String) {
    let preview = Preview::start(scene, options, [127, 0, 0, 1].into(), 0).unwrap();
    let url = preview.url().to_string();
    (preview, url)
}

const SCENE: &str = "[camera]\nfrom = [0, 1.5, 6]\nat = [0, 0.5, 0]\nfov = 50\n\
     [render]\nwidth = 96\nheight = 64\naa = 2\n\
     [[light]]\ntype = \"point\"\nposition = [3, 5, 4]\nintensity = 40\n\
     [[object]]\ntype = \"sphere\"\ncenter = [0, 0.8, 0]\nradius = 0.8\nmaterial = \"red\"\n\
     [[object]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\n\
     [[material]]\nname = \"red\"\ncolor = [0.8, 0.2, 0.1]\n";

fn scene_in(dir: &Path) -> std::path::PathBuf {
    let p = dir.join("scene.toml");
    std::fs::write(&p, SCENE).unwrap();
    p
}

/// [`SCENE`] with the path model.
fn path_scene_in(dir: &Path) -> std::path::PathBuf {
    let p = dir.join("scene.toml");
    let path = SCENE.replace("aa = 2\n", "aa = 2\nintegrator = \"path\"\n");
    std::fs::write(&p, path).unwrap();
    p
}

fn rendered(args: &[&str]) -> Vec<u8> {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cli.png");
    let o = run(prism().arg("render").args(args).arg(&out).arg("--quiet"));
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::read(out).unwrap()
}

#[test]
fn passes_end_on_the_image_prism_render_writes_and_a_camera_message_moves_it() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_in(dir.path());
    let (preview, url) = start(&scene);
    let (code, page) = http(&url, "GET", "/", &[], "");
    assert_eq!(code, 200);
    assert!(String::from_utf8_lossy(&page).contains("<title>Prism preview</title>"));
    let s = final_after(&url, 0, Duration::from_secs(30));
    // 96 x 64: passes at 1/8, 1/4, 1/2 and the full size.
    assert_eq!(s["frame"]["passes"].as_u64(), Some(4), "{s}");
    let (_, png) = http(&url, "GET", "/frame.png", &[], "");
    assert_eq!(png, rendered(&[scene.to_str().unwrap()]));
    // The camera in hand, as the page sends it.
    let generation = s["frame"]["generation"].as_u64().unwrap();
    let camera = r#"{"from": [2, 2, 5], "at": [0, 0.6, 0], "up": [0, 1, 0], "fov": 45}"#;
    let (code, _) = http(&url, "POST", "/camera", &[], camera);
    assert_eq!(code, 200);
    let s = final_after(&url, generation, Duration::from_secs(30));
    assert_eq!(s["camera_in_hand"], true);
    let (_, png) = http(&url, "GET", "/frame.png", &[], "");
    let flags = [
        "--look-from",
        "2,2,5",
        "--look-at",
        "0,0.6,0",
        "--up",
        "0,1,0",
        "--fov",
        "45",
    ];
    let mut args = vec![scene.to_str().unwrap()];
    args.extend(flags);
    assert_eq!(png, rendered(&args));
    // Saving goes through the writers: the PNG is the frame's.
    let (code, saved) = http(&url, "GET", "/save.png", &[], "");
    assert_eq!((code, saved), (200, png));
    let (code, _) = http(&url, "POST", "/camera", &[], r#"{"from": [1, 2]}"#);
    assert_eq!(code, 400);
    preview.stop();
}

/// The path model: after the coarse passes, full-size passes whose samples grow to
/// the job's, the last `prism render`'s image byte for byte.
#[test]
fn the_path_model_refines_sample_pass_by_sample_pass_to_the_image_prism_render_writes() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let scene = path_scene_in(dir.path());
    // `--spp 16`.
    let mut options = JobOptions::default();
    options.render.spp = Some(16);
    let (preview, url) = start_with(&scene, options);
    let frames = frames_until_final(&url);
    let field = |f: &serde_json::Value, k: &str| f[k].as_u64().unwrap();
    // The page's settings are the render's, `--spp` included.
    let s = status(&url, None);
    assert_eq!(
        (field(&s["settings"], "aa"), field(&s["settings"], "spp")),
        (2, 16)
    );
    let last = frames.last().unwrap();
    // Passes at 1/8, 1/4 and 1/2 of 96 x 64, then 1, 2, 4, 8 and 16 samples.
    assert_eq!(
        (field(last, "passes"), field(last, "samples")),
        (8, 16),
        "{last}"
    );
    for pair in frames.windows(2) {
        assert!(
            field(&pair[0], "pass") < field(&pair[1], "pass"),
            "{pair:?}"
        );
        assert!(
            field(&pair[0], "samples") <= field(&pair[1], "samples"),
            "{pair:?}"
        );
    }
    // The last pass takes as long as every pass before it: the one before is seen.
    let refining = frames
        .iter()
        .filter(|f| field(f, "width") == 96 && field(f, "samples") < 16)
        .count();
    assert!(refining >= 1, "{frames:?}");
    let (_, png) = http(&url, "GET", "/frame.png", &[], "");
    assert_eq!(png, rendered(&[scene.to_str().unwrap(), "--spp", "16"]));
    preview.stop();
}

#[test]
fn a_saved_edit_re_renders_and_a_broken_one_shows_its_line_and_keeps_the_image() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_in(dir.path());
    let (preview, url) = start(&scene);
    let s = final_after(&url, 0, Duration::from_secs(30));
    let generation = s["frame"]["generation"].as_u64().unwrap();
    std::thread::sleep(Duration::from_millis(20));
    let edited = SCENE.replace("[0.8, 0.2, 0.1]", "[0.1, 0.3, 0.9]");
    let saved = Instant::now();
    std::fs::write(&scene, &edited).unwrap();
    let s = final_after(&url, generation, Duration::from_secs(10));
    let took = saved.elapsed();
    assert!(took < Duration::from_secs(2), "re-rendered after {took:?}");
    let (_, png) = http(&url, "GET", "/frame.png", &[], "");
    assert_eq!(png, rendered(&[scene.to_str().unwrap()]));
    // Broken: the message with its place; the image stays.
    let generation = s["frame"]["generation"].as_u64().unwrap();
    std::fs::write(&scene, edited.replace("radius = 0.8", "radius = -1")).unwrap();
    let start = Instant::now();
    let mut version = s["version"].as_u64();
    let s = loop {
        let s = status(&url, version);
        if s["error"].is_string() {
            break s;
        }
        assert!(
            start.elapsed() < Duration::from_secs(10),
            "no error shown: {s}"
        );
        version = s["version"].as_u64();
    };
    let e = s["error"].as_str().unwrap();
    assert!(e.contains("scene.toml:") && e.contains("radius"), "{e}");
    assert_eq!(s["frame"]["generation"].as_u64(), Some(generation));
    let (code, kept) = http(&url, "GET", "/frame.png", &[], "");
    assert_eq!((code, kept), (200, png));
    preview.stop();
}

#[test]
fn foreign_hosts_and_origins_are_refused() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let (preview, url) = start(&scene_in(dir.path()));
    let port = url
        .rsplit(':')
        .next()
        .unwrap()
        .trim_end_matches('/')
        .to_string();
    let evil = format!("evil.example:{port}");
    assert_eq!(http(&url, "GET", "/", &[("Host", &evil)], "").0, 403);
    let own = format!("localhost:{port}");
    assert_eq!(http(&url, "GET", "/", &[("Host", &own)], "").0, 200);
    let origin = [("Origin", "http://evil.example")];
    assert_eq!(http(&url, "POST", "/camera/reset", &origin, "").0, 403);
    let big = "x".repeat(10_000);
    assert_eq!(http(&url, "POST", "/camera", &[], &big).0, 413);
    assert_eq!(http(&url, "GET", "/../../etc/passwd", &[], "").0, 404);
    preview.stop();
}

fn threads() -> usize {
    std::fs::read_dir("/proc/self/task").map_or(0, |d| d.count())
}

#[test]
fn a_hundred_quick_camera_moves_leave_one_render_and_no_more_threads() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let (preview, url) = start(&scene_in(dir.path()));
    final_after(&url, 0, Duration::from_secs(30));
    let before = threads();
    for i in 0..100 {
        let camera = format!(
            r#"{{"from": [{}, 2, 5], "at": [0, 0.6, 0], "up": [0, 1, 0]}}"#,
            i as f32 * 0.01
        );
        assert_eq!(http(&url, "POST", "/camera", &[], &camera).0, 200);
    }
    let last = preview.session().generation();
    let s = final_after(&url, last - 1, Duration::from_secs(30));
    assert_eq!(s["frame"]["generation"].as_u64(), Some(last));
    // The render pools of the abandoned generations are gone.
    std::thread::sleep(Duration::from_millis(200));
    let after = threads();
    assert!(after <= before, "{before} threads before, {after} after");
    preview.stop();
}

#[test]
fn an_animation_previews_one_frame_at_a_time_as_prism_animate_renders_it() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("bounce.toml");
    std::fs::write(
        &scene,
        "[camera]\nfrom = [0, 1, 5]\nat = [0, 0.5, 0]\nfov = 50\n\
         [render]\nwidth = 48\nheight = 32\n\
         [animation]\nframes = 3\nfps = 2\n\
         [[material]]\nname = \"red\"\ncolor = [0.8, 0.1, 0.1]\n\
         [[object]]\nname = \"ball\"\ntype = \"sphere\"\ncenter = [0, 0.5, 0]\nradius = 0.5\n\
         material = \"red\"\n\
         [[object]]\ntype = \"plane\"\n\
         [[light]]\nname = \"sun\"\ntype = \"directional\"\ndirection = [-1, -2, -1]\n\
         [[track]]\ntarget = \"object:ball\"\nmotion = \"translate\"\n\
         keys = [[0, [0, 0, 0]], [1, [1, 0, 0]]]\n",
    )
    .unwrap();
    let frames = dir.path().join("frames");
    let o = run(prism()
        .arg("animate")
        .arg(&scene)
        .arg(&frames)
        .arg("--quiet"));
    assert!(o.status.success(), "{}", stderr(&o));
    let (preview, url) = start(&scene);
    let s = final_after(&url, 0, Duration::from_secs(30));
    assert_eq!(s["animation"]["frames"].as_u64(), Some(3), "{s}");
    let (_, png) = http(&url, "GET", "/frame.png", &[], "");
    assert_eq!(png, std::fs::read(frames.join("frame_0000.png")).unwrap());
    let generation = s["frame"]["generation"].as_u64().unwrap();
    assert_eq!(http(&url, "POST", "/frame", &[], "2").0, 200);
    let s = final_after(&url, generation, Duration::from_secs(30));
    assert_eq!(s["animation"]["frame"].as_u64(), Some(2));
    let (_, png) = http(&url, "GET", "/frame.png", &[], "");
    assert_eq!(png, std::fs::read(frames.join("frame_0002.png")).unwrap());
    assert_eq!(http(&url, "POST", "/frame", &[], "two").0, 400);
    preview.stop();
}

/// A mesh the scene reads from outside its folder is watched too.
#[test]
fn a_mesh_saved_outside_the_scene_folder_re_renders() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("scene")).unwrap();
    let mesh = dir.path().join("tri.obj");
    std::fs::write(&mesh, "v -1 0 0\nv 1 0 0\nv 0 1.5 0\nf 1 2 3\n").unwrap();
    let scene = dir.path().join("scene/scene.toml");
    std::fs::write(
        &scene,
        "[camera]\nfrom = [0, 0.7, 4]\nat = [0, 0.7, 0]\nfov = 50\n\
         [render]\nwidth = 48\nheight = 32\n\
         [[light]]\ntype = \"point\"\nposition = [0, 2, 4]\nintensity = 20\n\
         [[object]]\ntype = \"mesh\"\nfile = \"../tri.obj\"\n",
    )
    .unwrap();
    let (preview, url) = start(&scene);
    let s = final_after(&url, 0, Duration::from_secs(30));
    let (_, before) = http(&url, "GET", "/frame.png", &[], "");
    std::fs::write(&mesh, "v -1 0 0\nv 1 0 0\nv 0 0.5 0\nf 1 2 3\n").unwrap();
    let generation = s["frame"]["generation"].as_u64().unwrap();
    final_after(&url, generation, Duration::from_secs(10));
    let (_, after) = http(&url, "GET", "/frame.png", &[], "");
    assert_ne!(before, after);
    assert_eq!(after, rendered(&[scene.to_str().unwrap()]));
    preview.stop();
}

/// Connections are bounded: a flood of idle ones starts no threads, and those beyond
/// the queue are answered 503 at once.
#[test]
fn a_flood_of_idle_connections_starts_no_threads() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let (preview, url) = start(&scene_in(dir.path()));
    final_after(&url, 0, Duration::from_secs(30));
    let before = threads();
    let addr = url.trim_start_matches("http://").trim_end_matches('/');
    let mut idle: Vec<TcpStream> = (0..80).map(|_| TcpStream::connect(addr).unwrap()).collect();
    std::thread::sleep(Duration::from_millis(300));
    assert!(
        threads() <= before,
        "{before} threads before, {} after",
        threads()
    );
    // The last ones found the queue full. The others stay open until then: closed, they
    // would free the workers and the queue for a connection not yet accepted.
    let last = idle.last_mut().unwrap();
    last.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    let mut answer = String::new();
    let _ = last.read_to_string(&mut answer);
    assert!(answer.starts_with("HTTP/1.1 503"), "{answer}");
    drop(idle);
    preview.stop();
}

/// `--denoise` in a Prism without Open Image Denoise is refused before the preview
/// starts, as `prism render --denoise` is.
#[cfg(not(feature = "oidn"))]
#[test]
fn without_oidn_a_denoised_preview_is_refused_before_it_starts() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_in(dir.path());
    let anim = dir.path().join("orbit.toml");
    std::fs::write(
        &anim,
        "scene = \"scene.toml\"\nframes = 4\nfps = 4\n[render]\nwidth = 32\nheight = 24\n",
    )
    .unwrap();
    // A still scene and an animation alike.
    for file in [&scene, &anim] {
        let o = run(prism().arg("preview").arg(file).arg("--denoise"));
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(
            stderr(&o).starts_with(
                "error: cannot denoise: this Prism was built without Intel Open Image Denoise"
            ),
            "{}",
            stderr(&o)
        );
    }
}

/// A denoised preview of the path model: the coarse passes as they are, every
/// full-size pass denoised, and the last `prism render --denoise`'s image byte for byte.
#[cfg(feature = "oidn")]
#[test]
fn a_denoised_preview_denoises_its_full_size_passes_and_ends_on_the_denoised_render() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let scene = path_scene_in(dir.path());
    let mut options = JobOptions::default();
    options.render.spp = Some(4);
    options.render.denoise = Some(true);
    let (preview, url) = start_with(&scene, options);
    let frames = frames_until_final(&url);
    for f in &frames {
        let full = f["width"].as_u64() == Some(96);
        assert_eq!(f["denoised"].as_bool(), Some(full), "{f}");
    }
    let (_, png) = http(&url, "GET", "/frame.png", &[], "");
    assert_eq!(
        png,
        rendered(&[scene.to_str().unwrap(), "--spp", "4", "--denoise"])
    );
    assert_ne!(png, rendered(&[scene.to_str().unwrap(), "--spp", "4"]));
    preview.stop();
}
