//! `serve`'s front door: it accepts every connection on the public port, takes a WebSocket
//! opening of `/api/live` itself (the live stream needs the socket's own timeouts, which an
//! upgraded tiny_http connection hides), and passes every other connection through to the
//! HTTP server on a loopback port of its own.

use std::io::{ErrorKind, Read, Write};
use std::net::{Shutdown, SocketAddr, TcpListener, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::time::Duration;

use tungstenite::handshake::server::{ErrorResponse, Request, Response};
use tungstenite::http::StatusCode;

use crate::web::host::loopback_host;

use super::session::{Shared, run, ws_config};

/// How often the idle accept loop looks whether it should stop.
const ACCEPT_POLL: Duration = Duration::from_millis(5);
/// How long a new connection may take to send its request line.
const FIRST_LINE: Duration = Duration::from_secs(10);
/// Live streams served at once; more are refused with 503.
const MAX_STREAMS: usize = 16;

/// Accepts on `public` until `shared.stop`: live streams to [`run`], everything else
/// copied both ways to and from `http` (the HTTP server's loopback address).
pub(in crate::web::serve) fn accept(public: &TcpListener, http: SocketAddr, shared: &Arc<Shared>) {
    if public.set_nonblocking(true).is_err() {
        return;
    }
    let loopback_only = public.local_addr().is_ok_and(|a| a.ip().is_loopback());
    let streams = Arc::new(AtomicUsize::new(0));
    let numbers = Arc::new(AtomicU64::new(0));
    while !shared.stop.load(Ordering::SeqCst) {
        let client = match public.accept() {
            Ok((client, _)) => client,
            Err(e) if e.kind() == ErrorKind::WouldBlock => {
                std::thread::sleep(ACCEPT_POLL);
                continue;
            }
            // A connection that failed before it was accepted: keep going.
            Err(_) => continue,
        };
        let (shared, streams, numbers) = (shared.clone(), streams.clone(), numbers.clone());
        let _ = std::thread::Builder::new()
            .name("omnicloud-conn".into())
            .spawn(move || {
                if client.set_nonblocking(false).is_err() {
                    return;
                }
                if opens_live(&client) {
                    let name = format!("live-{}", numbers.fetch_add(1, Ordering::SeqCst));
                    live(client, name, loopback_only, &shared, &streams);
                } else {
                    pass_through(client, http);
                }
            });
    }
}

/// Whether the connection's first request line asks for `/api/live` (read without taking
/// it off the socket).
fn opens_live(client: &TcpStream) -> bool {
    let _ = client.set_read_timeout(Some(FIRST_LINE));
    let mut buf = [0u8; 64];
    let prefix = b"GET /api/live";
    loop {
        let n = match client.peek(&mut buf) {
            Ok(0) | Err(_) => return false,
            Ok(n) => n,
        };
        let seen = &buf[..n];
        if n > prefix.len() {
            return seen.starts_with(prefix) && matches!(seen[prefix.len()], b' ' | b'?');
        }
        if !prefix.starts_with(seen) {
            return false;
        }
        // Only part of the line has arrived: wait for more.
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// The WebSocket handshake (refusing a foreign `Host` on a loopback server, and a page of
/// another origin), then the stream.
// The handshake callback's error type is tungstenite's, large or not.
#[allow(clippy::result_large_err)]
fn live(
    client: TcpStream,
    name: String,
    loopback_only: bool,
    shared: &Shared,
    streams: &AtomicUsize,
) {
    let busy = streams.fetch_add(1, Ordering::SeqCst) >= MAX_STREAMS;
    let check = |request: &Request, response: Response| -> Result<Response, ErrorResponse> {
        let header = |name: &str| {
            request
                .headers()
                .get(name)
                .and_then(|v| v.to_str().ok())
                .map(str::to_owned)
        };
        let host = header("Host");
        let refuse = |status: StatusCode, why: &str| {
            let mut r = ErrorResponse::new(Some(format!("{why}\n")));
            *r.status_mut() = status;
            Err(r)
        };
        if loopback_only && !loopback_host(host.as_deref()) {
            return refuse(
                StatusCode::FORBIDDEN,
                "this server answers only requests addressed to localhost or 127.0.0.1",
            );
        }
        // A page may open a WebSocket to any server: only this server's own page may stream.
        if let Some(origin) = header("Origin") {
            let origin_host = origin.split_once("://").map_or("", |(_, rest)| rest);
            if host.as_deref() != Some(origin_host) {
                return refuse(
                    StatusCode::FORBIDDEN,
                    "a page of another origin may not stream",
                );
            }
        }
        if request.uri().path() != "/api/live" {
            return refuse(StatusCode::NOT_FOUND, "no such page");
        }
        if busy {
            return refuse(
                StatusCode::SERVICE_UNAVAILABLE,
                "too many live streams at once; try again later",
            );
        }
        Ok(response)
    };
    if let Ok(ws) = tungstenite::accept_hdr_with_config(client, check, Some(ws_config())) {
        run(ws, name, shared);
    }
    streams.fetch_sub(1, Ordering::SeqCst);
}

/// Copies bytes both ways between `client` and the HTTP server until either side closes.
fn pass_through(client: TcpStream, http: SocketAddr) {
    let _ = client.set_read_timeout(None);
    let Ok(server) = TcpStream::connect(http) else {
        let _ = client.shutdown(Shutdown::Both);
        return;
    };
    let _ = server.set_nodelay(true);
    let _ = client.set_nodelay(true);
    let (Ok(client_in), Ok(server_out)) = (client.try_clone(), server.try_clone()) else {
        return;
    };
    let upstream = std::thread::spawn(move || copy(client_in, server_out));
    let Ok(client_out) = client.try_clone() else {
        return;
    };
    copy(server, client_out);
    // The server closed: so does the client's side, which ends the other copy.
    let _ = client.shutdown(Shutdown::Both);
    let _ = upstream.join();
}

/// Copies `from` to `to` until `from` ends, then closes `to` for writing and `from` for
/// reading.
fn copy(mut from: TcpStream, mut to: TcpStream) {
    let mut buf = vec![0u8; 64 * 1024];
    loop {
        match from.read(&mut buf) {
            Ok(0) | Err(_) => break,
            Ok(n) => {
                if to.write_all(&buf[..n]).is_err() {
                    break;
                }
            }
        }
    }
    let _ = to.shutdown(Shutdown::Write);
    let _ = from.shutdown(Shutdown::Read);
}
