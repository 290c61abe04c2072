//! The image as it forms, streamed to the tev viewer over its TCP protocol (as pbrt-v4's
//! `--display-server` does), for users who keep tev open beside their editor.
//!
//! Packets are tev's: a little-endian `u32` length (itself included), a type byte, then
//! the fields. `CreateImage` (4) opens an `R`, `G`, `B` image of the render's size;
//! each band of finished rows follows as `UpdateImage` (6, tev's third version: channel
//! offsets and strides, then the pixels as interleaved `f32`), linear radiance as the
//! render made it. A send runs on a thread of its own, so the render never waits for
//! the network; if tev goes away the render carries on and says so once at the end.

use crate::error::{Error, Result};
use std::io::Write;
use std::net::{TcpStream, ToSocketAddrs};
use std::sync::Mutex;
use std::sync::mpsc::{Sender, channel};
use std::thread::JoinHandle;
use std::time::Duration;

/// How long connecting to tev may take before the render is refused.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(3);

/// Rows in one update packet at most: tev's own client tiles updates, and a packet of
/// a few MB keeps the viewer responsive.
const ROWS_PER_PACKET: usize = 64;

/// tev's packet types.
const CREATE_IMAGE: u8 = 4;
const UPDATE_IMAGE: u8 = 6;

/// A connection to tev showing one image.
pub struct TevStream {
    name: String,
    width: u32,
    packets: Mutex<Option<Sender<Vec<u8>>>>,
    sender: Option<JoinHandle<std::io::Result<()>>>,
}

impl TevStream {
    /// Connects to tev at `address` (`HOST:PORT`) and creates the image `name` of
    /// `width × height` pixels there.
    pub fn connect(address: &str, name: &str, width: u32, height: u32) -> Result<TevStream> {
        let cannot = |why: String| {
            Error::Settings(format!(
                "cannot connect to tev at {address}: {why} (start tev, or leave out --display)"
            ))
        };
        let addr = address
            .to_socket_addrs()
            .map_err(|e| cannot(e.to_string()))?
            .next()
            .ok_or_else(|| cannot("the address names no host".into()))?;
        let mut socket = TcpStream::connect_timeout(&addr, CONNECT_TIMEOUT)
            .map_err(|e| cannot(e.to_string()))?;
        let _ = socket.set_nodelay(true);
        socket
            .write_all(&create_image(name, width, height))
            .map_err(|e| cannot(e.to_string()))?;
        let (packets, queue) = channel::<Vec<u8>>();
        let sender = std::thread::Builder::new()
            .name("prism-tev".into())
            .spawn(move || {
                for packet in queue {
                    socket.write_all(&packet)?;
                }
                socket.flush()
            })
            .map_err(|e| cannot(e.to_string()))?;
        Ok(TevStream {
            name: name.to_string(),
            width,
            packets: Mutex::new(Some(packets)),
            sender: Some(sender),
        })
    }

    /// Whole rows of the image from `first_row` on (linear RGB), sent as they come.
    pub fn rows(&self, first_row: u32, pixels: &[[f32; 3]]) {
        let width = self.width as usize;
        if width == 0 {
            return;
        }
        let guard = self.packets.lock().unwrap_or_else(|e| e.into_inner());
        let Some(packets) = guard.as_ref() else {
            return;
        };
        for (i, chunk) in pixels.chunks(width * ROWS_PER_PACKET).enumerate() {
            let y = first_row as usize + i * ROWS_PER_PACKET;
            let packet = update_image(&self.name, y as u32, self.width, chunk);
            // A closed viewer is reported by `finish`.
            let _ = packets.send(packet);
        }
    }

    /// Waits for every packet to go out. An error says tev stopped listening on the
    /// way (the render itself is whole).
    pub fn finish(mut self) -> std::result::Result<(), String> {
        self.packets
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .take();
        match self.sender.take().map(JoinHandle::join) {
            Some(Ok(Ok(()))) | None => Ok(()),
            Some(Ok(Err(e))) => Err(format!("tev stopped receiving the image: {e}")),
            Some(Err(_)) => Err("the tev connection's thread failed".into()),
        }
    }
}

/// A packet: its length, its type, its fields.
fn packet(kind: u8, fields: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
    let mut out = vec![0u8; 4];
    out.push(kind);
    fields(&mut out);
    let len = out.len() as u32;
    out[..4].copy_from_slice(&len.to_le_bytes());
    out
}

/// A NUL-terminated string, as tev reads names (a NUL inside is dropped).
fn push_str(out: &mut Vec<u8>, s: &str) {
    out.extend(s.bytes().filter(|&b| b != 0));
    out.push(0);
}

const CHANNELS: [&str; 3] = ["R", "G", "B"];

fn create_image(name: &str, width: u32, height: u32) -> Vec<u8> {
    packet(CREATE_IMAGE, |out| {
        out.push(1); // grab focus
        push_str(out, name);
        out.extend((width as i32).to_le_bytes());
        out.extend((height as i32).to_le_bytes());
        out.extend((CHANNELS.len() as i32).to_le_bytes());
        for c in CHANNELS {
            push_str(out, c);
        }
    })
}

fn update_image(name: &str, y: u32, width: u32, rows: &[[f32; 3]]) -> Vec<u8> {
    let height = rows.len() / width.max(1) as usize;
    packet(UPDATE_IMAGE, |out| {
        out.push(0); // leave the focus where the user put it
        push_str(out, name);
        out.extend((CHANNELS.len() as i32).to_le_bytes());
        for c in CHANNELS {
            push_str(out, c);
        }
        for v in [0, y as i32, width as i32, height as i32] {
            out.extend(v.to_le_bytes());
        }
        // Interleaved RGB: channel c starts at c and steps by 3.
        for offset in 0..3i64 {
            out.extend(offset.to_le_bytes());
        }
        for _ in 0..3 {
            out.extend(3i64.to_le_bytes());
        }
        for p in rows {
            for v in p {
                out.extend(v.to_le_bytes());
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packets_carry_their_length_type_and_fields() {
        let p = create_image("a.png", 3, 2);
        assert_eq!(
            u32::from_le_bytes(p[..4].try_into().unwrap()) as usize,
            p.len()
        );
        assert_eq!(&p[4..7], &[CREATE_IMAGE, 1, b'a']);
        assert_eq!(&p[p.len() - 6..], b"R\0G\0B\0");
        let u = update_image("a", 1, 2, &[[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
        assert_eq!(
            u32::from_le_bytes(u[..4].try_into().unwrap()) as usize,
            u.len()
        );
        // Header, name, channel count and names, x y w h, offsets and strides, pixels.
        assert_eq!(u.len(), 4 + 1 + 1 + 2 + 4 + 6 + 16 + 48 + 24);
        let tail: Vec<f32> = u[u.len() - 24..]
            .chunks(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(tail, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    }
}
