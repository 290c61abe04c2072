//! `prism preview`: the scene rendered in the browser as it forms, coarse pass first,
//! with the camera in hand and re-rendered when a file it reads is saved.
//!
//! The library does the work: [`session`] holds the scene, the camera in hand and the
//! render loop (every change a new generation; the old render stops at its next
//! tile), [`watch`] notices saved files, [`server`] serves the page built into the
//! binary and the frames. The command only starts a [`Preview`] and waits for Ctrl-C.

pub mod http;
pub mod server;
pub mod session;
pub mod watch;

use crate::error::{Error, Result};
use crate::job::JobOptions;
use session::Session;
use std::net::{IpAddr, SocketAddr, TcpListener, TcpStream};
use std::path::Path;
use std::sync::mpsc::{Receiver, SyncSender, TrySendError, sync_channel};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Duration;

/// Worker threads serving requests: a client waiting for a frame holds one, so a few
/// tabs and a save still get through.
const WORKERS: usize = 8;
/// Connections accepted and waiting for a worker; one more is answered `503`.
const QUEUE: usize = 32;
/// How often the watched files are looked at.
const WATCH_EVERY: Duration = Duration::from_millis(300);
/// How long the watched files must stay as they are before the scene is read again.
const SETTLE: Duration = Duration::from_millis(60);

/// A running preview: its server, render loop and file watch.
pub struct Preview {
    session: Arc<Session>,
    url: String,
    threads: Vec<JoinHandle<()>>,
}

impl Preview {
    /// Reads the scene (an error if it does not read), binds `bind:port` (port 0: a
    /// free one) and starts serving and rendering.
    pub fn start(scene: &Path, options: JobOptions, bind: IpAddr, port: u16) -> Result<Preview> {
        let session = Session::new(scene, options)?;
        let cannot =
            |e: std::io::Error| Error::Settings(format!("cannot listen on {bind}:{port}: {e}"));
        let listener = TcpListener::bind(SocketAddr::new(bind, port)).map_err(cannot)?;
        let addr = listener.local_addr().map_err(cannot)?;
        // Non-blocking, so the accept loop sees a stop within its poll.
        listener.set_nonblocking(true).map_err(cannot)?;
        let url = format!("http://{addr}/");
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
        let (queue, waiting) = sync_channel::<TcpStream>(QUEUE);
        let waiting = Arc::new(Mutex::new(waiting));
        for _ in 0..WORKERS {
            let (s, waiting) = (Arc::clone(&session), Arc::clone(&waiting));
            let names = server::Names { port: addr.port() };
            threads.push(spawn(
                "prism-preview-http",
                Box::new(move || serve(&s, &names, &waiting)),
            )?);
        }
        let s = Arc::clone(&session);
        threads.push(spawn(
            "prism-preview-accept",
            Box::new(move || accept(&s, &listener, &queue)),
        )?);
        Ok(Preview {
            session,
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
        for t in self.threads {
            let _ = t.join();
        }
    }
}

/// Accepts connections into the workers' queue until stopped; one the queue has no
/// room for is answered `503` at once.
fn accept(session: &Session, listener: &TcpListener, queue: &SyncSender<TcpStream>) {
    while !session.stopped() {
        match listener.accept() {
            Ok((stream, _)) => {
                let _ = stream.set_nonblocking(false);
                if let Err(TrySendError::Full(mut stream)) = queue.try_send(stream) {
                    let busy = http::Response::text(503, "the preview is busy: try again");
                    http::write_response(&mut stream, &busy);
                }
            }
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                std::thread::sleep(Duration::from_millis(5));
            }
            Err(_) => std::thread::sleep(Duration::from_millis(50)),
        }
    }
}

/// A worker: serves queued connections, one request each, until stopped.
fn serve(session: &Arc<Session>, names: &server::Names, waiting: &Mutex<Receiver<TcpStream>>) {
    while !session.stopped() {
        let next = waiting
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .recv_timeout(Duration::from_millis(200));
        let Ok(mut stream) = next else {
            continue;
        };
        let response = match http::read_request(&mut stream) {
            Ok(request) => server::handle(session, names, &request),
            Err(refusal) => refusal,
        };
        http::write_response(&mut stream, &response);
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
