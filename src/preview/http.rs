//! The little HTTP/1.1 the preview speaks: one request a connection, read within
//! bounds (head, body and time), answered and closed. The preview owns its accept loop
//! so that it can bound connections: a fixed set of workers serves them from a short
//! queue, and a connection beyond it is answered `503` at once.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::Duration;

/// The largest request head (request line and headers) read.
const MAX_HEAD: usize = 16 * 1024;
/// The largest request body read (a camera is about a hundred bytes).
pub const MAX_BODY: usize = 4096;
/// How long a client may take to send its request.
const READ_TIMEOUT: Duration = Duration::from_secs(5);
/// The most of an oversized body read (and dropped) before it is refused.
const MAX_DRAIN: usize = 1 << 20;
/// Headers read at most.
const MAX_HEADERS: usize = 32;

/// A request: method, path, query, headers (names lower-cased) and body.
pub struct Request {
    /// `GET`, `POST`, …
    pub method: String,
    /// The path, without the query.
    pub path: String,
    /// What follows `?`, or empty.
    pub query: String,
    /// The headers, names lower-cased.
    pub headers: Vec<(String, String)>,
    /// The body (at most [`MAX_BODY`] bytes).
    pub body: Vec<u8>,
}

impl Request {
    /// The value of header `name` (lower case), if sent.
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }
}

/// A response: status, content type, extra headers, body.
pub struct Response {
    /// The status code.
    pub code: u16,
    /// The `Content-Type`.
    pub content_type: &'static str,
    /// More headers.
    pub headers: Vec<(&'static str, String)>,
    /// The body.
    pub body: Vec<u8>,
}

impl Response {
    /// A plain-text response.
    pub fn text(code: u16, message: &str) -> Response {
        Response {
            code,
            content_type: "text/plain; charset=utf-8",
            headers: Vec::new(),
            body: message.as_bytes().to_vec(),
        }
    }

    /// A response of `body` as `content_type`, not to be cached.
    pub fn data(content_type: &'static str, body: Vec<u8>) -> Response {
        Response {
            code: 200,
            content_type,
            headers: vec![("Cache-Control", "no-store".into())],
            body,
        }
    }
}

/// Reads one request from `stream`; an error is the response to send instead.
pub fn read_request(stream: &mut TcpStream) -> Result<Request, Response> {
    let _ = stream.set_read_timeout(Some(READ_TIMEOUT));
    let mut buf = Vec::with_capacity(1024);
    let mut chunk = [0u8; 2048];
    let head_len = loop {
        if let Some(end) = buf.windows(4).position(|w| w == b"\r\n\r\n") {
            break end + 4;
        }
        if buf.len() > MAX_HEAD {
            return Err(Response::text(431, "request head too large"));
        }
        match stream.read(&mut chunk) {
            Ok(0) | Err(_) => return Err(Response::text(400, "incomplete request")),
            Ok(n) => buf.extend_from_slice(&chunk[..n]),
        }
    };
    let mut headers = [httparse::EMPTY_HEADER; MAX_HEADERS];
    let mut parsed = httparse::Request::new(&mut headers);
    match parsed.parse(&buf[..head_len]) {
        Ok(httparse::Status::Complete(_)) => {}
        _ => return Err(Response::text(400, "malformed request")),
    }
    let method = parsed.method.unwrap_or("").to_string();
    let target = parsed.path.unwrap_or("/");
    let (path, query) = target.split_once('?').unwrap_or((target, ""));
    let headers: Vec<(String, String)> = parsed
        .headers
        .iter()
        .map(|h| {
            (
                h.name.to_ascii_lowercase(),
                String::from_utf8_lossy(h.value).into_owned(),
            )
        })
        .collect();
    let length = headers
        .iter()
        .find(|(k, _)| k == "content-length")
        .map_or(Ok(0), |(_, v)| v.trim().parse::<usize>())
        .map_err(|_| Response::text(400, "bad Content-Length"))?;
    if length > MAX_BODY {
        // Read what was sent (up to a bound) before answering: closing a socket with
        // unread data resets it, and the client would never see the answer.
        let mut left = (length - (buf.len() - head_len)).min(MAX_DRAIN);
        while left > 0 {
            let take = left.min(chunk.len());
            match stream.read(&mut chunk[..take]) {
                Ok(0) | Err(_) => break,
                Ok(n) => left -= n,
            }
        }
        return Err(Response::text(
            413,
            &format!("a body of at most {MAX_BODY} bytes"),
        ));
    }
    let mut body = buf[head_len..].to_vec();
    body.truncate(length);
    while body.len() < length {
        match stream.read(&mut chunk) {
            Ok(0) | Err(_) => return Err(Response::text(400, "incomplete body")),
            Ok(n) => body.extend_from_slice(&chunk[..n.min(length - body.len())]),
        }
    }
    Ok(Request {
        method,
        path: path.to_string(),
        query: query.to_string(),
        headers,
        body,
    })
}

/// Writes `response` and closes the exchange.
pub fn write_response(stream: &mut TcpStream, response: &Response) {
    let reason = match response.code {
        200 => "OK",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        413 => "Payload Too Large",
        431 => "Request Header Fields Too Large",
        500 => "Internal Server Error",
        503 => "Service Unavailable",
        _ => "",
    };
    let mut head = format!(
        "HTTP/1.1 {} {reason}\r\nContent-Type: {}\r\nContent-Length: {}\r\nConnection: close\r\n",
        response.code,
        response.content_type,
        response.body.len()
    );
    for (k, v) in &response.headers {
        head += &format!("{k}: {v}\r\n");
    }
    head += "\r\n";
    let _ = stream.write_all(head.as_bytes());
    let _ = stream.write_all(&response.body);
    let _ = stream.flush();
}
