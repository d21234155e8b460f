//! The front door of `view`'s and `serve`'s servers. It accepts every connection on the public
//! port, reads its request head within a size limit and a deadline, refuses what breaks them
//! with the status that says why, hands the rest to the server's workers for a reply and sends
//! it ([`respond`](super::respond)): one request per connection, every head read here.

use std::io::{ErrorKind, Read, Write};
use std::net::{Shutdown, TcpListener, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc::{self, Sender};
use std::time::{Duration, Instant};

use super::respond;
use super::routes::Reply;

/// Longest request line (method, target and version) read; a longer one gets 414.
pub const MAX_REQUEST_LINE: usize = 8 * 1024;
/// Most bytes of a request head (request line and headers); more get 431.
pub const MAX_HEAD_BYTES: usize = 16 * 1024;
/// Most header lines of a request; more get 431.
pub const MAX_HEADERS: usize = 100;
/// How long a client may take to send its whole request head; slower ones get 408.
pub const HEAD_TIME: Duration = Duration::from_secs(10);
/// Connections served at once (live streams included); more are answered 503 at once.
pub const MAX_CONNECTIONS: usize = 128;
/// Connections past [`MAX_CONNECTIONS`] answered 503 at once; more are closed unanswered.
const MAX_TURNING_AWAY: usize = 32;
/// How long a write to a client may stall before the connection is dropped (a client that
/// stops reading frees its thread).
const STALL: Duration = Duration::from_secs(10);
/// How often the idle accept loop looks whether it should stop.
const ACCEPT_POLL: Duration = Duration::from_millis(5);

/// A request head as the client sent it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Head {
    /// `GET`, ...
    pub method: String,
    /// The request target: path and query.
    pub target: String,
    /// `HTTP/1.1`, ...
    pub version: String,
    /// Header names and values, in order, values trimmed.
    pub headers: Vec<(String, String)>,
}

impl Head {
    /// The first value of header `name` (any case).
    pub(crate) fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(k, _)| k.eq_ignore_ascii_case(name))
            .map(|(_, v)| v.as_str())
    }

    /// The target's path, without its query.
    pub(crate) fn path(&self) -> &str {
        self.target.split('?').next().unwrap_or("")
    }
}

/// Why no head was read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum HeadError {
    /// The client closed or failed before sending a whole head: no one to answer.
    Gone,
    /// The head breaks a limit or the protocol: the status and why.
    Refused(u16, &'static str),
}

const TOO_LONG_LINE: HeadError = HeadError::Refused(414, "the request line is too long");
const TOO_LARGE_HEAD: HeadError = HeadError::Refused(431, "the request headers are too large");
const TOO_MANY_HEADERS: HeadError = HeadError::Refused(431, "the request has too many headers");
const TOO_SLOW: HeadError = HeadError::Refused(408, "the request head did not arrive in time");
const MALFORMED: HeadError = HeadError::Refused(400, "the request head is malformed");

/// A function that may take a connection for itself (`serve`'s live stream) once its head is
/// read; it hands back the connections it leaves to the server's workers.
pub(crate) type Take = dyn Fn(TcpStream, Head) -> Option<(TcpStream, Head)> + Send + Sync;

/// Accepts on `public` until `stop`: each connection on a thread of its own (at most
/// [`MAX_CONNECTIONS`]), its head read and checked, then offered to `take` and else sent as a
/// [`Job`] to the workers, whose reply it sends.
pub(crate) fn accept(
    public: &TcpListener,
    stop: &AtomicBool,
    take: Option<Arc<Take>>,
    jobs: Sender<Job>,
) {
    if public.set_nonblocking(true).is_err() {
        return;
    }
    let open = Arc::new(AtomicUsize::new(0));
    let turning = Arc::new(AtomicUsize::new(0));
    while !stop.load(Ordering::SeqCst) {
        let client = match public.accept() {
            Ok((client, _)) => client,
            Err(e) if e.kind() == ErrorKind::WouldBlock => {
                std::thread::sleep(ACCEPT_POLL);
                continue;
            }
            // A connection that failed before it was accepted: keep going.
            Err(_) => continue,
        };
        if open.load(Ordering::SeqCst) >= MAX_CONNECTIONS {
            turn_away(client, &turning);
            continue;
        }
        let slot = Slot::new(open.clone());
        let (take, jobs) = (take.clone(), jobs.clone());
        // Should no thread start, the closure is dropped and with it the connection.
        let _ = std::thread::Builder::new()
            .name("omnicloud-conn".into())
            .spawn(move || {
                let _slot = slot;
                connection(client, take.as_deref(), &jobs);
            });
    }
}

/// One place among the open connections, given back when dropped.
struct Slot(Arc<AtomicUsize>);

impl Slot {
    fn new(open: Arc<AtomicUsize>) -> Self {
        open.fetch_add(1, Ordering::SeqCst);
        Slot(open)
    }
}

impl Drop for Slot {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Answers 503 on a short thread of its own (at most [`MAX_TURNING_AWAY`] at once; past
/// that the connection is closed unanswered), so that what the client sends meanwhile is
/// read off and the close does not reset the connection before the reply is read.
fn turn_away(client: TcpStream, turning: &Arc<AtomicUsize>) {
    if turning.load(Ordering::SeqCst) >= MAX_TURNING_AWAY {
        return;
    }
    let slot = Slot::new(turning.clone());
    let _ = std::thread::Builder::new()
        .name("omnicloud-busy".into())
        .spawn(move || {
            let _slot = slot;
            if client.set_nonblocking(false).is_ok() {
                refuse(
                    &client,
                    503,
                    "too many connections at once; try again later",
                );
            }
        });
}

/// A request for the server's workers: its head, and where its reply goes.
pub(crate) struct Job {
    /// The request.
    pub head: Head,
    reply: Sender<Reply>,
}

impl Job {
    /// Hands `reply` back to the connection, which sends it.
    pub(crate) fn answer(self, reply: Reply) {
        // A connection that is gone no longer wants it.
        let _ = self.reply.send(reply);
    }
}

fn connection(client: TcpStream, take: Option<&Take>, jobs: &Sender<Job>) {
    if client.set_nonblocking(false).is_err() || client.set_write_timeout(Some(STALL)).is_err() {
        return;
    }
    let head = match read_head(&client, Instant::now() + HEAD_TIME) {
        Ok(head) => head,
        Err(HeadError::Gone) => return,
        Err(HeadError::Refused(status, why)) => return refuse(&client, status, why),
    };
    let passed = match take {
        Some(take) => take(client, head),
        None => Some((client, head)),
    };
    let Some((client, head)) = passed else {
        return;
    };
    let (reply, answer) = mpsc::channel();
    let job = Job {
        head: head.clone(),
        reply,
    };
    let Some(reply) = jobs.send(job).ok().and_then(|()| answer.recv().ok()) else {
        return refuse(&client, 503, "the server is stopping");
    };
    let _ = client.set_nodelay(true);
    respond::send(&client, &head, reply);
    close(&client);
}

/// Reads a request head off `client` by `deadline`, taking no byte past its blank line (what
/// follows is the body, or a WebSocket's first frame).
pub(crate) fn read_head(client: &TcpStream, deadline: Instant) -> Result<Head, HeadError> {
    let mut head: Vec<u8> = Vec::new();
    let mut seen = [0u8; 4096];
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() || client.set_read_timeout(Some(left)).is_err() {
            return Err(TOO_SLOW);
        }
        let n = match client.peek(&mut seen) {
            Ok(0) => return Err(HeadError::Gone),
            Ok(n) => n,
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {
                return Err(TOO_SLOW);
            }
            Err(_) => return Err(HeadError::Gone),
        };
        let end = head_end(&head, &seen[..n]);
        let wanted = end.map_or(n, |end| end - head.len());
        let start = head.len();
        head.resize(start + wanted, 0);
        // The bytes were peeked, so this read does not wait.
        if (&*client).read_exact(&mut head[start..]).is_err() {
            return Err(HeadError::Gone);
        }
        check_limits(&head, end.is_some())?;
        if end.is_some() {
            return parse_head(&head);
        }
    }
}

/// Where the head ends (just past its blank line) in `head` followed by `more`, if it does.
fn head_end(head: &[u8], more: &[u8]) -> Option<usize> {
    let from = head.len().saturating_sub(3);
    let tail: Vec<u8> = head[from..].iter().chain(more).copied().collect();
    tail.windows(4)
        .position(|w| w == b"\r\n\r\n")
        .map(|at| from + at + 4)
}

/// Refuses a head (`whole`: read to its blank line) or the part read so far, once it breaks a
/// limit.
fn check_limits(head: &[u8], whole: bool) -> Result<(), HeadError> {
    let first_line = head.windows(2).position(|w| w == b"\r\n");
    if first_line.unwrap_or(head.len()) > MAX_REQUEST_LINE {
        return Err(TOO_LONG_LINE);
    }
    if head.len() > MAX_HEAD_BYTES {
        return Err(TOO_LARGE_HEAD);
    }
    // Lines ended so far, less the request line and (when whole) the blank line.
    let lines = head.windows(2).filter(|w| w == b"\r\n").count();
    let headers = lines.saturating_sub(if whole { 2 } else { 1 });
    if headers > MAX_HEADERS {
        return Err(TOO_MANY_HEADERS);
    }
    Ok(())
}

/// Reads a whole head: a request line of three words, then `name: value` lines.
fn parse_head(bytes: &[u8]) -> Result<Head, HeadError> {
    let text = std::str::from_utf8(bytes).map_err(|_| MALFORMED)?;
    let mut lines = text.split("\r\n");
    let mut words = lines.next().unwrap_or("").split(' ');
    let (Some(method), Some(target), Some(version), None) =
        (words.next(), words.next(), words.next(), words.next())
    else {
        return Err(MALFORMED);
    };
    // The target is the routes' to judge (they answer 403/404 for what they do not serve).
    if method.is_empty() || target.is_empty() || !version.starts_with("HTTP/") {
        return Err(MALFORMED);
    }
    let mut headers = Vec::new();
    for line in lines.take_while(|line| !line.is_empty()) {
        let (name, value) = line.split_once(':').ok_or(MALFORMED)?;
        // A name with space around it, or a folded line, is refused (RFC 9112, section 5).
        if name.is_empty() || name.trim() != name || line.starts_with([' ', '\t']) {
            return Err(MALFORMED);
        }
        headers.push((name.to_owned(), value.trim().to_owned()));
    }
    Ok(Head {
        method: method.to_owned(),
        target: target.to_owned(),
        version: version.to_owned(),
        headers,
    })
}

/// A whole plain-text reply that closes the connection.
pub(crate) fn reply(status: u16, why: &str, retry: bool) -> Vec<u8> {
    let reason = respond::reason(status);
    let body = format!("{why}\n");
    let retry = if retry { "Retry-After: 1\r\n" } else { "" };
    format!(
        "HTTP/1.1 {status} {reason}\r\nContent-Type: text/plain; charset=utf-8\r\n\
         Content-Length: {}\r\n{retry}Connection: close\r\n\r\n{body}",
        body.len()
    )
    .into_bytes()
}

/// Answers `status` and closes ([`close`]).
pub(crate) fn refuse(client: &TcpStream, status: u16, why: &str) {
    let mut client = client;
    if client
        .write_all(&reply(status, why, status == 503))
        .is_err()
    {
        return;
    }
    close(client);
}

/// Ends an answered connection: closes this side for writing, then reads what the client
/// still sends (a body, up to 1 MiB, for at most a second) until it closes, so that the
/// kernel does not reset the connection under the answer it has not read yet.
fn close(client: &TcpStream) {
    let mut client = client;
    let _ = client.shutdown(Shutdown::Write);
    let until = Instant::now() + Duration::from_secs(1);
    let mut sink = [0u8; 16 * 1024];
    let mut left_to_read: usize = 1 << 20;
    while let Some(left) = until.checked_duration_since(Instant::now()) {
        if left.is_zero() || left_to_read == 0 || client.set_read_timeout(Some(left)).is_err() {
            break;
        }
        match client.read(&mut sink) {
            Ok(n) if n > 0 => left_to_read = left_to_read.saturating_sub(n),
            _ => break,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(head: &str) -> Result<(), HeadError> {
        check_limits(head.as_bytes(), head.ends_with("\r\n\r\n"))
    }

    #[test]
    fn heads_are_parsed_with_their_target_and_headers() {
        let raw = b"GET /frames/2?x=1 HTTP/1.1\r\nHost: 127.0.0.1:8\r\nConnection: keep-alive\r\nRange:  bytes=0-9 \r\n\r\n";
        let head = parse_head(raw).unwrap();
        assert_eq!(head.path(), "/frames/2");
        assert_eq!(head.header("range"), Some("bytes=0-9"));
        assert_eq!(head.target, "/frames/2?x=1");
        assert_eq!(head.header("Connection"), Some("keep-alive"));
        for bad in [
            "GET /\r\n\r\n",
            "GET / HTTP/1.1 x\r\n\r\n",
            "GET  HTTP/1.1\r\n\r\n",
            "GET / HTTP/1.1\r\nno colon\r\n\r\n",
            "GET / HTTP/1.1\r\nHost : a\r\n\r\n",
            "GET / HTTP/1.1\r\nA: b\r\n folded\r\n\r\n",
        ] {
            assert_eq!(parse_head(bad.as_bytes()), Err(MALFORMED), "{bad:?}");
        }
    }

    #[test]
    fn limits_refuse_long_lines_large_heads_and_many_headers_early() {
        let line = |len: usize| format!("GET /{} HTTP/1.1\r\n", "a".repeat(len - 14));
        assert_eq!(line(MAX_REQUEST_LINE).len(), MAX_REQUEST_LINE + 2);
        assert_eq!(check(&format!("{}\r\n", line(MAX_REQUEST_LINE))), Ok(()));
        assert_eq!(check(&line(MAX_REQUEST_LINE + 1)), Err(TOO_LONG_LINE));
        // Refused before the line ends.
        assert_eq!(check(&"a".repeat(MAX_REQUEST_LINE + 1)), Err(TOO_LONG_LINE));
        let header = format!("X-Pad: {}\r\n", "b".repeat(1000));
        let large = format!("GET / HTTP/1.1\r\n{}", header.repeat(17));
        assert_eq!(check(&large), Err(TOO_LARGE_HEAD));
        let many = |n: usize| format!("GET / HTTP/1.1\r\n{}\r\n", "A: b\r\n".repeat(n));
        assert_eq!(check(&many(MAX_HEADERS)), Ok(()));
        assert_eq!(check(&many(MAX_HEADERS + 1)), Err(TOO_MANY_HEADERS));
    }

    #[test]
    fn the_end_of_a_head_is_found_across_reads() {
        assert_eq!(head_end(b"GET / HTTP/1.1\r\n\r", b"\nbody"), Some(18));
        assert_eq!(head_end(b"", b"GET / HTTP/1.1\r\n\r\n"), Some(18));
        assert_eq!(head_end(b"GET / HTTP/1.1\r\n", b"Host: a\r\n"), None);
    }
}
