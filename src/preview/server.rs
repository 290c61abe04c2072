//! The preview's web server: its page, the frames, the camera in hand and saving, on
//! loopback unless told otherwise.
//!
//! It serves only what it made: the page built into the binary, the frames it rendered
//! and its status; never a file by path. A request whose `Host` (or `Origin`, when the
//! browser sends one) is not the server's own is refused, so a web page elsewhere cannot
//! reach it through a name it points at 127.0.0.1 (DNS rebinding). Bodies are bounded,
//! and a fixed set of worker threads serves the connections.

use super::http::{Request, Response};
use super::session::Session;
use crate::job::LookAt;
use crate::math::Vec3;
use serde_json::{Value, json};
use std::sync::Arc;
use std::time::Duration;

/// The page, its script and style: built in, so the preview works offline.
const PAGE: &str = include_str!("page.html");
/// How long a client waiting for a new frame is held before it is answered anyway.
const LONG_POLL: Duration = Duration::from_secs(10);

/// Whom the server answers: requests naming it by `localhost` or by an IP address, on
/// its port. A name other than `localhost` is how a rebinding attack reaches a
/// loopback server, so none is admitted.
pub struct Names {
    /// The port the server listens on.
    pub port: u16,
}

impl Names {
    /// Whether a request's `Host` and `Origin` are the server's own.
    fn admits(&self, request: &Request) -> bool {
        let Some(host) = request.header("host") else {
            return false;
        };
        if !self.is_own(host) {
            return false;
        }
        match request.header("origin") {
            None => true,
            Some(origin) => origin.eq_ignore_ascii_case(&format!("http://{host}")),
        }
    }

    /// `localhost:PORT`, `127.0.0.1:PORT`, `[::1]:PORT` or another address literal.
    fn is_own(&self, host: &str) -> bool {
        let Some((name, port)) = host.rsplit_once(':') else {
            return false;
        };
        if port.parse::<u16>() != Ok(self.port) {
            return false;
        }
        let name = name.trim_start_matches('[').trim_end_matches(']');
        name.eq_ignore_ascii_case("localhost") || name.parse::<std::net::IpAddr>().is_ok()
    }
}

/// The answer to one request.
pub fn handle(session: &Arc<Session>, names: &Names, request: &Request) -> Response {
    if !names.admits(request) {
        return Response::text(403, "this preview answers only to its own address");
    }
    let body = || String::from_utf8_lossy(&request.body).into_owned();
    match (request.method.as_str(), request.path.as_str()) {
        ("GET", "/") => Response {
            code: 200,
            content_type: "text/html; charset=utf-8",
            headers: Vec::new(),
            body: PAGE.as_bytes().to_vec(),
        },
        ("GET", "/status") => {
            let after = request
                .query
                .split('&')
                .find_map(|kv| kv.strip_prefix("after="))
                .and_then(|v| v.parse::<u64>().ok());
            let status = status(session, after).to_string();
            Response::data("application/json", status.into_bytes())
        }
        ("GET", "/frame.png") => match session.state().frame.clone() {
            Some(frame) => Response::data("image/png", frame.png.to_vec()),
            None => Response::text(404, "no frame yet"),
        },
        ("GET", "/save.png") => save(session, "png"),
        ("GET", "/save.exr") => save(session, "exr"),
        ("POST", "/camera") => match look_of(&body()) {
            Ok(look) => answer(session.set_look(Some(look))),
            Err(why) => Response::text(400, &why),
        },
        ("POST", "/frame") => match body().trim().parse::<u32>() {
            Ok(k) => answer(session.set_frame(k)),
            Err(_) => Response::text(
                400,
                &format!("expected a frame number, found {:?}", body().trim()),
            ),
        },
        ("POST", "/camera/reset") => answer(session.set_look(None)),
        _ => Response::text(404, "not found"),
    }
}

/// `ok`, or the error as a bad request.
fn answer(done: crate::error::Result<()>) -> Response {
    match done {
        Ok(()) => Response::text(200, "ok"),
        Err(e) => Response::text(400, &e.to_string()),
    }
}

/// `{"from": [x, y, z], "at": [...], "up": [...], "fov": degrees}`.
fn look_of(text: &str) -> Result<LookAt, String> {
    let v: Value = serde_json::from_str(text).map_err(|e| format!("expected JSON: {e}"))?;
    let vec3 = |key: &str| -> Result<Option<Vec3>, String> {
        match v.get(key) {
            None | Some(Value::Null) => Ok(None),
            Some(Value::Array(a)) if a.len() == 3 => {
                let c: Option<Vec<f32>> = a.iter().map(|x| x.as_f64().map(|x| x as f32)).collect();
                match c.as_deref() {
                    Some(&[x, y, z]) if x.is_finite() && y.is_finite() && z.is_finite() => {
                        Ok(Some(Vec3::new(x, y, z)))
                    }
                    _ => Err(format!("expected `{key}` as three finite numbers")),
                }
            }
            Some(_) => Err(format!("expected `{key}` as three finite numbers")),
        }
    };
    let fov = match v.get("fov") {
        None | Some(Value::Null) => None,
        Some(f) => Some(f.as_f64().ok_or("expected `fov` as a number")? as f32),
    };
    Ok(LookAt {
        from: vec3("from")?,
        at: vec3("at")?,
        up: vec3("up")?,
        fov,
    })
}

fn vec3_json(v: Option<Vec3>) -> Value {
    v.map_or(Value::Null, |v| json!([v.x, v.y, v.z]))
}

/// What the page shows: the latest frame's figures, the error, the camera.
fn status(session: &Session, after: Option<u64>) -> Value {
    let state = match after {
        Some(v) => session.wait_newer(v, LONG_POLL),
        None => session.state(),
    };
    let look = match (&state.look, &state.job) {
        (Some(look), _) => Some(*look),
        (None, Some(job)) => Some(job.look()),
        (None, None) => None,
    };
    let frame = state.frame.as_ref().map(|f| {
        json!({
            "generation": f.generation,
            "pass": f.pass,
            "passes": f.passes,
            "samples": f.samples,
            "final": f.is_final(),
            "denoised": f.denoised,
            "width": f.width,
            "height": f.height,
            "elapsed": f.elapsed,
            "rays": f.rays,
            "mrays_per_second": f.rays as f64 / f.seconds.max(1e-9) / 1e6,
        })
    });
    let settings = state.job.as_ref().map(|job| {
        json!({
            "integrator": job.settings.integrator.name(),
            // The render's own (`--aa`, `--spp`, `[render]`), else the camera's.
            "aa": job.settings.aa.unwrap_or(job.camera.aa),
            "spp": job.settings.spp.unwrap_or(job.camera.spp),
            "filter": job.settings.filter.name(),
            "exposure": job.output.develop.exposure,
            "tonemap": job.output.develop.tonemap.name(),
        })
    });
    json!({
        "version": state.version,
        "generation": session.generation(),
        "scene": session.scene_path().display().to_string(),
        "frame": frame,
        "error": state.error,
        "settings": settings,
        "camera": look.map(|l| json!({
            "from": vec3_json(l.from),
            "at": vec3_json(l.at),
            "up": vec3_json(l.up),
            "fov": l.fov,
        })),
        "camera_in_hand": state.look.is_some(),
        "animation": state.animation.map(|t| json!({
            "frames": t.frames,
            "fps": t.fps,
            "frame": t.frame,
        })),
    })
}

/// The latest image as a file of the format `ext` names, written by the writers
/// `prism render` uses, as a download.
fn save(session: &Session, ext: &str) -> Response {
    let state = session.state();
    let (Some(frame), Some(job)) = (state.frame.clone(), state.job.clone()) else {
        return Response::text(404, "no frame yet");
    };
    drop(state);
    match crate::film::file_bytes(&frame.image, ext, &job.output) {
        Ok(bytes) => {
            let name = session
                .scene_path()
                .file_stem()
                .map_or("preview".into(), |s| s.to_string_lossy().into_owned());
            let kind = if ext == "png" {
                "image/png"
            } else {
                "image/x-exr"
            };
            let mut response = Response::data(kind, bytes);
            response.headers.push((
                "Content-Disposition",
                format!("attachment; filename=\"{}.{ext}\"", name.replace('"', "")),
            ));
            response
        }
        Err(e) => Response::text(500, &e.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_its_own_address_is_admitted() {
        let names = Names { port: 8123 };
        for own in [
            "127.0.0.1:8123",
            "localhost:8123",
            "[::1]:8123",
            "192.168.1.9:8123",
        ] {
            assert!(names.is_own(own), "{own}");
        }
        for foreign in [
            "evil.example:8123",
            "127.0.0.1:80",
            "localhost",
            "127.0.0.1.nip.io:8123",
        ] {
            assert!(!names.is_own(foreign), "{foreign}");
        }
    }

    #[test]
    fn a_camera_message_reads_three_numbers_a_point_and_a_fov() {
        let l = look_of(r#"{"from": [0, 1, 5], "at": [0, 1, 0], "fov": 40}"#).unwrap();
        assert_eq!(l.from, Some(Vec3::new(0.0, 1.0, 5.0)));
        assert_eq!((l.up, l.fov), (None, Some(40.0)));
        assert!(look_of(r#"{"from": [0, 1]}"#).is_err());
        assert!(look_of(r#"{"from": [0, 1, "x"]}"#).is_err());
        assert!(look_of("not json").is_err());
    }
}
