//! `serve`'s part of the front door ([`door`](crate::web::door)): it takes a WebSocket opening
//! of `/api/live` for the live stream (which needs the socket itself, with its own timeouts)
//! and leaves every other connection to the server's workers.

use std::io::Write;
use std::net::TcpStream;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

use tungstenite::handshake::server::{Request, create_response, write_response};
use tungstenite::http::Version;
use tungstenite::protocol::{Role, WebSocket};

use crate::web::door::{Head, Take, refuse};
use crate::web::host::loopback_host;

use super::session::{Shared, run, ws_config};

/// Live streams served at once; more are refused with 503.
const MAX_STREAMS: usize = 16;

/// The front door's hook for `serve`: a `GET /api/live` becomes a live stream (numbered
/// `live-N`, its renders apart from other clients'); `loopback_only`: a foreign `Host` is
/// refused.
pub(in crate::web::serve) fn live_door(shared: Arc<Shared>, loopback_only: bool) -> Arc<Take> {
    let streams = Arc::new(AtomicUsize::new(0));
    let numbers = AtomicU64::new(0);
    Arc::new(move |client: TcpStream, head: Head| {
        if head.method != "GET" || head.path() != "/api/live" {
            return Some((client, head));
        }
        let name = format!("live-{}", numbers.fetch_add(1, Ordering::SeqCst));
        let counted = Stream::open(&streams);
        match opening(&head, loopback_only, counted.busy) {
            Ok(request) => match create_response(&request) {
                Ok(response) => {
                    let mut written = Vec::new();
                    let sent = write_response(&mut written, &response).is_ok()
                        && (&client).write_all(&written).is_ok();
                    if sent {
                        run(
                            WebSocket::from_raw_socket(client, Role::Server, Some(ws_config())),
                            name,
                            &shared,
                        );
                    }
                }
                Err(e) => refuse(&client, 400, &format!("not a WebSocket opening: {e}")),
            },
            Err((status, why)) => refuse(&client, status, why),
        }
        None
    })
}

/// A live stream counted while it runs; `busy` when there were already [`MAX_STREAMS`].
struct Stream<'a> {
    streams: &'a AtomicUsize,
    busy: bool,
}

impl<'a> Stream<'a> {
    fn open(streams: &'a AtomicUsize) -> Self {
        let busy = streams.fetch_add(1, Ordering::SeqCst) >= MAX_STREAMS;
        Stream { streams, busy }
    }
}

impl Drop for Stream<'_> {
    fn drop(&mut self) {
        self.streams.fetch_sub(1, Ordering::SeqCst);
    }
}

/// The head as the WebSocket handshake's request, unless it is refused: a foreign `Host` on a
/// loopback server, a page of another origin, or one stream too many.
fn opening(head: &Head, loopback_only: bool, busy: bool) -> Result<Request, (u16, &'static str)> {
    let host = head.header("Host");
    if loopback_only && !loopback_host(host) {
        return Err((
            403,
            "this server answers only requests addressed to localhost or 127.0.0.1",
        ));
    }
    // A page may open a WebSocket to any server: only this server's own page may stream.
    if let Some(origin) = head.header("Origin") {
        let origin_host = origin.split_once("://").map_or("", |(_, rest)| rest);
        if host != Some(origin_host) {
            return Err((403, "a page of another origin may not stream"));
        }
    }
    if busy {
        return Err((503, "too many live streams at once; try again later"));
    }
    let version = match head.version.as_str() {
        "HTTP/1.1" => Version::HTTP_11,
        _ => Version::HTTP_10,
    };
    let mut request = Request::builder()
        .method("GET")
        .uri(head.target.as_str())
        .version(version);
    for (name, value) in &head.headers {
        request = request.header(name, value);
    }
    request
        .body(())
        .map_err(|_| (400, "the request head is malformed"))
}
