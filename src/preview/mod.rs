//! `prism preview`: the scene rendered in the browser as it forms, coarse pass first,
//! with the camera in hand and re-rendered when a file it reads is saved.
//!
//! The library does the work: [`session`] holds the scene, the camera in hand and the
//! render loop (every change a new generation; the old render stops at its next
//! tile), [`watch`] notices saved files, [`server`] serves the page built into the
//! binary and the frames. The command only starts a [`Preview`] and waits for Ctrl-C.

pub mod server;
pub mod session;
pub mod watch;

use crate::error::{Error, Result};
use crate::job::JobOptions;
use session::Session;
use std::net::{IpAddr, SocketAddr};
use std::path::Path;
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

/// Worker threads serving requests: a client waiting for a frame holds one, so a few
/// tabs and a save still get through.
const WORKERS: usize = 8;
/// How often the watched files are looked at.
const WATCH_EVERY: Duration = Duration::from_millis(300);
/// How long the watched files must stay as they are before the scene is read again.
const SETTLE: Duration = Duration::from_millis(60);

/// A running preview: its server, render loop and file watch.
pub struct Preview {
    session: Arc<Session>,
    server: Arc<tiny_http::Server>,
    url: String,
    threads: Vec<JoinHandle<()>>,
}

impl Preview {
    /// Reads the scene (an error if it does not read), binds `bind:port` (port 0: a
    /// free one) and starts serving and rendering.
    pub fn start(scene: &Path, options: JobOptions, bind: IpAddr, port: u16) -> Result<Preview> {
        let session = Session::new(scene, options)?;
        let server = tiny_http::Server::http(SocketAddr::new(bind, port))
            .map_err(|e| Error::Settings(format!("cannot listen on {bind}:{port}: {e}")))?;
        let addr = server
            .server_addr()
            .to_ip()
            .ok_or_else(|| Error::Settings("the server has no IP address".into()))?;
        let url = format!("http://{addr}/");
        let server = Arc::new(server);
        let mut threads = Vec::new();
        let spawn = |name: &str, f: Box<dyn FnOnce() + Send>| {
            std::thread::Builder::new()
                .name(name.into())
                .spawn(f)
                .map_err(|e| Error::Settings(format!("cannot start the preview: {e}")))
        };
        let s = Arc::clone(&session);
        threads.push(spawn(
            "prism-preview-render",
            Box::new(move || s.render_loop()),
        )?);
        let s = Arc::clone(&session);
        threads.push(spawn(
            "prism-preview-watch",
            Box::new(move || watch_files(&s)),
        )?);
        for _ in 0..WORKERS {
            let (s, server) = (Arc::clone(&session), Arc::clone(&server));
            let names = server::Names { port: addr.port() };
            threads.push(spawn(
                "prism-preview-http",
                Box::new(move || {
                    while !s.stopped() {
                        match server.recv_timeout(Duration::from_millis(200)) {
                            Ok(Some(request)) => server::handle(&s, &names, request),
                            Ok(None) => {}
                            Err(_) => break,
                        }
                    }
                }),
            )?);
        }
        Ok(Preview {
            session,
            server,
            url,
            threads,
        })
    }

    /// Where the page is: `http://127.0.0.1:PORT/`.
    pub fn url(&self) -> &str {
        &self.url
    }

    /// The session: its state and frames.
    pub fn session(&self) -> &Arc<Session> {
        &self.session
    }

    /// Stops rendering and serving, and waits for every thread.
    pub fn stop(self) {
        self.session.stop();
        self.server.unblock();
        for t in self.threads {
            let _ = t.join();
        }
    }
}

/// Reads the scene again whenever a file in its folder changes, until stopped.
fn watch_files(session: &Session) {
    let dir = session
        .scene_path()
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
        .to_path_buf();
    let reads = || session.state().reads.clone();
    let mut seen = watch::Snapshot::of(&dir, &reads());
    while !session.stopped() {
        std::thread::sleep(WATCH_EVERY);
        let mut now = watch::Snapshot::of(&dir, &reads());
        if now == seen {
            continue;
        }
        // Read once the files have settled: a file caught half-written (truncated,
        // then filled) would otherwise be read as it stood.
        loop {
            std::thread::sleep(SETTLE);
            let again = watch::Snapshot::of(&dir, &reads());
            if again == now || session.stopped() {
                break;
            }
            now = again;
        }
        session.reload();
        // What the new reading read is the new baseline.
        seen = watch::Snapshot::of(&dir, &reads());
    }
}
