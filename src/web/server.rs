//! The viewer's HTTP server: a front door ([`door`](super::door)) on the public port, tiny_http
//! on a loopback port behind it, and a few worker threads that answer with a route function
//! ([`routes::route`](super::routes::route) for `view`) until stopped.

use std::io::Read;
use std::net::{SocketAddr, TcpListener};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use tiny_http::{Header, Response, Server};

use super::WebError;
use super::door::{self, Take};
use super::host::loopback_host;
use super::panorama::Panorama;
use super::routes::{Body, Reply, route};

/// Requests answered at once: a frame being sent does not hold up the page or the next frame.
const WORKERS: usize = 4;

/// How often an idle worker looks whether it should stop.
const STOP_POLL: Duration = Duration::from_millis(100);

/// A bound public port with its front door ([`door`](super::door)), the HTTP server behind it
/// on a loopback port, and the stop flag: what `view` and `serve` share.
pub(crate) struct Listener {
    public: TcpListener,
    server: Arc<Server>,
    addr: SocketAddr,
    internal: SocketAddr,
    stop: Arc<AtomicBool>,
}

impl Listener {
    /// Listens on `host:port` (port 0: any free port).
    pub(crate) fn bind(host: &str, port: u16) -> Result<Self, WebError> {
        let bind_err = |addr: String, reason: String| WebError::Bind { addr, reason };
        let public = TcpListener::bind((host, port))
            .map_err(|e| bind_err(format!("{host}:{port}"), e.to_string()))?;
        let addr = public
            .local_addr()
            .map_err(|e| bind_err(format!("{host}:{port}"), e.to_string()))?;
        let behind = TcpListener::bind("127.0.0.1:0")
            .map_err(|e| bind_err("127.0.0.1:0".into(), e.to_string()))?;
        let internal = behind
            .local_addr()
            .map_err(|e| bind_err("127.0.0.1:0".into(), e.to_string()))?;
        let server = Server::from_listener(behind, None)
            .map_err(|e| bind_err(internal.to_string(), e.to_string()))?;
        Ok(Self {
            public,
            server: Arc::new(server),
            addr,
            internal,
            stop: Arc::new(AtomicBool::new(false)),
        })
    }

    /// The address it listens on (with the real port when bound to port 0).
    pub(crate) fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// Its stop flag, for threads that serve beside it.
    pub(crate) fn stop_flag(&self) -> Arc<AtomicBool> {
        self.stop.clone()
    }

    /// A handle that stops [`serve`](Self::serve).
    pub(crate) fn stopper(&self) -> Stopper {
        Stopper(self.stop.clone())
    }

    /// Answers requests with `route(method, url)` on `workers` threads until stopped, the
    /// front door offering each connection to `take` first. A bad request gets its error
    /// reply and changes nothing.
    pub(crate) fn serve(
        &self,
        workers: usize,
        route: &(dyn Fn(&str, &str) -> Reply + Sync),
        take: Option<Arc<Take>>,
    ) {
        let loopback_only = self.addr.ip().is_loopback();
        std::thread::scope(|scope| {
            scope.spawn(|| door::accept(&self.public, self.internal, &self.stop, take));
            for _ in 0..workers {
                scope.spawn(|| {
                    while !self.stop.load(Ordering::SeqCst) {
                        // Err: a connection failed before its request was read; keep going.
                        if let Ok(Some(request)) = self.server.recv_timeout(STOP_POLL) {
                            answer(request, loopback_only, route);
                        }
                    }
                });
            }
        });
    }
}

/// A bound viewer server, not yet serving.
pub struct ViewServer {
    listener: Listener,
    panorama: Arc<Panorama>,
}

/// Stops a serving server (`view`'s or `serve`'s) from another thread (a Ctrl-C handler, a
/// test).
#[derive(Clone)]
pub struct Stopper(Arc<AtomicBool>);

impl Stopper {
    /// Asks the server to stop; `serve` returns within a fraction of a second.
    pub fn stop(&self) {
        self.0.store(true, Ordering::SeqCst);
    }
}

impl ViewServer {
    /// Listens on `host:port` (port 0: any free port) for requests about `panorama`.
    pub fn bind(host: &str, port: u16, panorama: Panorama) -> Result<Self, WebError> {
        Ok(Self {
            listener: Listener::bind(host, port)?,
            panorama: Arc::new(panorama),
        })
    }

    /// The address it listens on (with the real port when bound to port 0).
    pub fn addr(&self) -> SocketAddr {
        self.listener.addr()
    }

    /// A handle that stops [`serve`](Self::serve).
    pub fn stopper(&self) -> Stopper {
        self.listener.stopper()
    }

    /// Answers requests until stopped. A bad request gets its error reply and changes nothing.
    pub fn serve(self) {
        let panorama = &self.panorama;
        self.listener
            .serve(WORKERS, &|method, url| route(method, url, panorama), None);
    }

    /// Serves on a background thread; the returned handle stops it and waits.
    pub fn spawn(self) -> Running {
        Running::start(self.addr(), self.stopper(), move || self.serve())
    }
}

/// A server serving on its own thread; dropping it stops the server.
pub struct Running {
    addr: SocketAddr,
    stopper: Stopper,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Running {
    /// Runs `serve` on a new thread; `stopper` must stop it.
    pub(crate) fn start(
        addr: SocketAddr,
        stopper: Stopper,
        serve: impl FnOnce() + Send + 'static,
    ) -> Self {
        Running {
            addr,
            stopper,
            thread: Some(std::thread::spawn(serve)),
        }
    }

    /// The address it listens on.
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        self.stopper.stop();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn answer(
    request: tiny_http::Request,
    loopback_only: bool,
    route: &(dyn Fn(&str, &str) -> Reply + Sync),
) {
    let header = |name: &'static str| {
        request
            .headers()
            .iter()
            .find(|h| h.field.equiv(name))
            .map(|h| h.value.as_str().to_owned())
    };
    let host = header("Host");
    let range = header("Range");
    let reply = if loopback_only && !loopback_host(host.as_deref()) {
        Reply::error(
            403,
            "this server answers only requests addressed to localhost or 127.0.0.1",
        )
    } else {
        route(request.method().as_str(), request.url())
    };
    let extra = &reply.headers;
    // A client that went away while we answered is no concern of the server's.
    let _ = match reply.body {
        Body::Static(text) => request.respond(with_headers(
            Response::from_data(text.as_bytes()),
            reply.status,
            reply.content_type,
            extra,
        )),
        Body::Text(text) => request.respond(with_headers(
            Response::from_data(text.into_bytes()),
            reply.status,
            reply.content_type,
            extra,
        )),
        Body::Bytes(bytes) => request.respond(with_headers(
            Response::from_data(bytes),
            reply.status,
            reply.content_type,
            extra,
        )),
        Body::File(path) => match open_range(&path, range.as_deref()) {
            Ok((file, FileRange::Whole(len))) => request.respond(
                with_headers(
                    Response::new(
                        200.into(),
                        Vec::new(),
                        file.take(len),
                        Some(len as usize),
                        None,
                    ),
                    reply.status,
                    reply.content_type,
                    extra,
                )
                .with_header(header_pair("Accept-Ranges", "bytes")),
            ),
            Ok((file, FileRange::Part { start, end, len })) => request.respond(
                with_headers(
                    Response::new(
                        206.into(),
                        Vec::new(),
                        file.take(end - start + 1),
                        Some((end - start + 1) as usize),
                        None,
                    ),
                    206,
                    reply.content_type,
                    extra,
                )
                .with_header(header_pair("Accept-Ranges", "bytes"))
                .with_header(header_pair(
                    "Content-Range",
                    &format!("bytes {start}-{end}/{len}"),
                )),
            ),
            Ok((_, FileRange::Unsatisfiable(len))) => request.respond(
                with_headers(
                    Response::from_data(format!("the file has {len} bytes\n")),
                    416,
                    "text/plain; charset=utf-8",
                    &[],
                )
                .with_header(header_pair("Content-Range", &format!("bytes */{len}"))),
            ),
            Err(e) => request.respond(with_headers(
                Response::from_data(format!("cannot read {}: {e}\n", path.display())),
                500,
                "text/plain; charset=utf-8",
                &[],
            )),
        },
    };
}

/// The part of a file a reply sends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileRange {
    /// All of its `len` bytes.
    Whole(u64),
    /// Bytes `start..=end` of `len`.
    Part { start: u64, end: u64, len: u64 },
    /// A range that starts past the end of `len` bytes.
    Unsatisfiable(u64),
}

/// Opens `path` positioned at the start of the part `range` (a `Range` header) asks for.
fn open_range(
    path: &std::path::Path,
    range: Option<&str>,
) -> std::io::Result<(std::fs::File, FileRange)> {
    use std::io::{Seek, SeekFrom};
    let mut file = std::fs::File::open(path)?;
    let len = file.metadata()?.len();
    let part = range.map_or(FileRange::Whole(len), |r| byte_range(r, len));
    if let FileRange::Part { start, .. } = part {
        file.seek(SeekFrom::Start(start))?;
    }
    Ok((file, part))
}

/// Reads a `Range: bytes=...` header for a file of `len` bytes. One range is served; a form
/// this server does not serve (several ranges, other units, garbage) gets the whole file, as
/// RFC 9110 allows.
pub fn byte_range(header: &str, len: u64) -> FileRange {
    let Some(spec) = header.trim().strip_prefix("bytes=") else {
        return FileRange::Whole(len);
    };
    let Some((first, last)) = spec.trim().split_once('-') else {
        return FileRange::Whole(len);
    };
    if spec.contains(',') {
        return FileRange::Whole(len);
    }
    let number = |s: &str| s.trim().parse::<u64>().ok();
    match (first.trim().is_empty(), number(first), number(last)) {
        // `bytes=-N`: the last N bytes.
        (true, _, Some(n)) if n > 0 && len > 0 => FileRange::Part {
            start: len.saturating_sub(n),
            end: len - 1,
            len,
        },
        (true, _, _) => FileRange::Unsatisfiable(len),
        (false, Some(start), _) if start >= len => FileRange::Unsatisfiable(len),
        (false, Some(start), None) if last.trim().is_empty() => FileRange::Part {
            start,
            end: len - 1,
            len,
        },
        (false, Some(start), Some(end)) if end >= start => FileRange::Part {
            start,
            end: end.min(len - 1),
            len,
        },
        _ => FileRange::Whole(len),
    }
}

fn header_pair(name: &str, value: &str) -> Header {
    Header::from_bytes(name.as_bytes(), value.as_bytes()).expect("ASCII header")
}

fn with_headers<R: std::io::Read>(
    response: Response<R>,
    status: u16,
    content_type: &str,
    extra: &[(&'static str, String)],
) -> Response<R> {
    let header = |name: &str, value: &str| {
        Header::from_bytes(name.as_bytes(), value.as_bytes()).expect("ASCII header")
    };
    // Every body's length is known: send it as Content-Length, never chunked, so clients
    // see the size up front.
    let mut response = response.with_chunked_threshold(usize::MAX);
    for (name, value) in extra {
        response = response.with_header(header(name, value));
    }
    response
        .with_status_code(status)
        .with_header(header("Content-Type", content_type))
        .with_header(header("Cache-Control", "no-cache"))
        .with_header(header("X-Content-Type-Options", "nosniff"))
        .with_header(header("Referrer-Policy", "no-referrer"))
        .with_header(header(
            "Content-Security-Policy",
            "default-src 'self'; img-src 'self' blob:; style-src 'self' 'unsafe-inline'",
        ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_ranges_follow_rfc_9110() {
        let part = |start, end| FileRange::Part {
            start,
            end,
            len: 1000,
        };
        assert_eq!(byte_range("bytes=0-", 1000), part(0, 999));
        assert_eq!(byte_range("bytes=100-199", 1000), part(100, 199));
        assert_eq!(byte_range("bytes=900-5000", 1000), part(900, 999));
        assert_eq!(byte_range("bytes=-100", 1000), part(900, 999));
        assert_eq!(byte_range("bytes=-5000", 1000), part(0, 999));
        assert_eq!(
            byte_range("bytes=1000-", 1000),
            FileRange::Unsatisfiable(1000)
        );
        assert_eq!(byte_range("bytes=-0", 1000), FileRange::Unsatisfiable(1000));
        for whole in [
            "items=0-1",
            "bytes=0-1,5-6",
            "bytes=5-1",
            "bytes=a-b",
            "bytes=5",
        ] {
            assert_eq!(byte_range(whole, 1000), FileRange::Whole(1000), "{whole}");
        }
    }
}
