//! Writes a route's [`Reply`] to the client as an HTTP/1.1 response, one per connection: the
//! status line, the headers every reply has, its own, and the body (a file straight from the
//! file to the socket, in the byte range the request asks for).

use std::io::{Read, Seek, SeekFrom, Write};
use std::net::TcpStream;
use std::path::Path;

use super::door::Head;
use super::routes::{Body, Reply};

/// The reason phrase of `status`.
pub(crate) fn reason(status: u16) -> &'static str {
    match status {
        200 => "OK",
        206 => "Partial Content",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        408 => "Request Timeout",
        409 => "Conflict",
        414 => "URI Too Long",
        416 => "Range Not Satisfiable",
        431 => "Request Header Fields Too Large",
        500 => "Internal Server Error",
        503 => "Service Unavailable",
        _ => "Status",
    }
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

/// Sends `reply` to the request `head` on `client`; a client that goes away meanwhile is no
/// concern of the server's.
pub(crate) fn send(client: &TcpStream, head: &Head, reply: Reply) {
    let mut out = client;
    let body_too = head.method != "HEAD";
    let extra = &reply.headers;
    let _ = match reply.body {
        Body::Static(text) => send_bytes(out, &reply, text.as_bytes(), body_too),
        Body::Text(ref text) => send_bytes(out, &reply, text.as_bytes(), body_too),
        Body::Bytes(ref bytes) => send_bytes(out, &reply, bytes, body_too),
        Body::File(ref path) => match open_range(path, head.header("Range")) {
            Ok((file, FileRange::Whole(len))) => {
                let mut headers = extra.clone();
                headers.push(("Accept-Ranges", "bytes".into()));
                send_file(
                    &mut out,
                    (reply.status, reply.content_type),
                    &headers,
                    file,
                    len,
                    body_too,
                )
            }
            Ok((file, FileRange::Part { start, end, len })) => {
                let mut headers = extra.clone();
                headers.push(("Accept-Ranges", "bytes".into()));
                headers.push(("Content-Range", format!("bytes {start}-{end}/{len}")));
                let part = end - start + 1;
                send_file(
                    &mut out,
                    (206, reply.content_type),
                    &headers,
                    file,
                    part,
                    body_too,
                )
            }
            Ok((_, FileRange::Unsatisfiable(len))) => {
                let mut unsatisfiable = Reply::error(416, format!("the file has {len} bytes"));
                unsatisfiable
                    .headers
                    .push(("Content-Range", format!("bytes */{len}")));
                let Body::Text(text) = &unsatisfiable.body else {
                    unreachable!("an error reply is text")
                };
                send_bytes(out, &unsatisfiable, text.as_bytes(), body_too)
            }
            Err(e) => {
                let failed = Reply::error(500, format!("cannot read {}: {e}", path.display()));
                let Body::Text(text) = &failed.body else {
                    unreachable!("an error reply is text")
                };
                send_bytes(out, &failed, text.as_bytes(), body_too)
            }
        },
    };
}

fn send_bytes(
    mut out: &TcpStream,
    reply: &Reply,
    body: &[u8],
    body_too: bool,
) -> std::io::Result<()> {
    let mut bytes = response_head(
        (reply.status, reply.content_type),
        &reply.headers,
        body.len() as u64,
    );
    if body_too {
        bytes.extend_from_slice(body);
    }
    out.write_all(&bytes)
}

/// The head, then `len` bytes of `file` from where it stands: `std::io::copy` moves them from
/// the file to the socket in the kernel (sendfile) where it can.
fn send_file(
    out: &mut &TcpStream,
    (status, content_type): (u16, &str),
    headers: &[(&'static str, String)],
    file: std::fs::File,
    len: u64,
    body_too: bool,
) -> std::io::Result<()> {
    out.write_all(&response_head((status, content_type), headers, len))?;
    if body_too {
        let sent = std::io::copy(&mut file.take(len), out)?;
        if sent < len {
            return Err(std::io::Error::new(
                std::io::ErrorKind::UnexpectedEof,
                "the file shrank while it was sent",
            ));
        }
    }
    Ok(())
}

/// Status line and headers, ended by the blank line. Every body's length is known and sent
/// as `Content-Length`, never chunked, so clients see the size up front.
fn response_head(
    (status, content_type): (u16, &str),
    extra: &[(&'static str, String)],
    len: u64,
) -> Vec<u8> {
    let mut head = format!(
        "HTTP/1.1 {status} {}\r\nContent-Type: {content_type}\r\nContent-Length: {len}\r\n",
        reason(status)
    );
    for (name, value) in extra {
        head.push_str(&format!("{name}: {value}\r\n"));
    }
    head.push_str(
        "Cache-Control: no-cache\r\nX-Content-Type-Options: nosniff\r\n\
         Referrer-Policy: no-referrer\r\nContent-Security-Policy: default-src 'self'; \
         img-src 'self' blob:; style-src 'self' 'unsafe-inline'\r\nConnection: close\r\n\r\n",
    );
    head.into_bytes()
}

/// Opens `path` positioned at the start of the part `range` (a `Range` header) asks for.
fn open_range(path: &Path, range: Option<&str>) -> std::io::Result<(std::fs::File, FileRange)> {
    let mut file = std::fs::File::open(path)?;
    let len = file.metadata()?.len();
    let part = range.map_or(FileRange::Whole(len), |r| byte_range(r, len));
    if let FileRange::Part { start, .. } = part {
        file.seek(SeekFrom::Start(start))?;
    }
    Ok((file, part))
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

    #[test]
    fn a_head_names_its_status_length_and_every_reply_header() {
        let head = response_head((206, "video/mp4"), &[("Accept-Ranges", "bytes".into())], 42);
        let text = String::from_utf8(head).unwrap();
        assert!(
            text.starts_with("HTTP/1.1 206 Partial Content\r\n"),
            "{text}"
        );
        for line in [
            "Content-Type: video/mp4\r\n",
            "Content-Length: 42\r\n",
            "Accept-Ranges: bytes\r\n",
            "X-Content-Type-Options: nosniff\r\n",
            "Connection: close\r\n",
        ] {
            assert!(text.contains(line), "{line:?} missing from {text}");
        }
        assert!(text.ends_with("\r\n\r\n"));
    }
}
