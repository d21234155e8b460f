//! One client's live stream: read its poses as they come, keep only the newest, render it
//! as soon as the previous render is done (the previous frame is encoded and sent meanwhile),
//! and once the client rests send one high-quality pair of where it stands.

use std::io::ErrorKind;
use std::net::TcpStream;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError};
use std::time::{Duration, Instant};

use tungstenite::protocol::CloseFrame;
use tungstenite::protocol::frame::coding::CloseCode;
use tungstenite::{Error as WsError, Message, WebSocket};

use super::super::render_thread::{RawFrame, RenderFailure, RenderQueue};
use super::super::scan::LiveScan;
use super::jpeg::encode_jpeg;
use super::message::{FrameHeader, frame_message};
use super::pace::{LiveScale, Pace};
use super::pose::{MAX_POSE_BYTES, Pose, PoseLimits, parse_pose};

/// How long a read waits for a pose before the session looks at its render again: the
/// most a finished render waits to be encoded.
const POLL: Duration = Duration::from_millis(2);

/// Send buffer asked for on a live connection (Linux keeps twice this). Left to itself the
/// kernel grows it to megabytes (4 MiB on loopback): dozens of small frames a client that
/// falls behind would see late, and a stalled client dropped only after they drain into it.
/// This holds about one full-quality pair at 1440 per eye and still moves 10 MB/s at a 50 ms
/// round trip.
const SEND_BUFFER: usize = 256 * 1024;

/// Quality of the pair sent at rest.
const STILL_QUALITY: u8 = 95;

/// How the live stream runs; fixed when the server starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StreamOptions {
    /// Whether moving frames may render narrower.
    pub scale: LiveScale,
    /// Frames a second moving frames aim at.
    pub fps: f64,
    /// No pose for this long after a moving frame: the client rests; send the still pair.
    pub rest_after: Duration,
    /// A frame the client has not taken within this long drops the client.
    pub write_timeout: Duration,
}

impl Default for StreamOptions {
    fn default() -> Self {
        StreamOptions {
            scale: LiveScale::Auto,
            fps: 10.0,
            rest_after: Duration::from_millis(300),
            write_timeout: Duration::from_secs(5),
        }
    }
}

/// What a session needs from the server.
pub(in crate::web::serve) struct Shared {
    pub scan: Arc<LiveScan>,
    pub queue: RenderQueue,
    pub options: StreamOptions,
    pub stop: Arc<AtomicBool>,
}

/// The render of one pose, under way.
struct InFlight {
    answer: Receiver<Result<RawFrame, RenderFailure>>,
    pose: Pose,
    quality: u8,
    still: bool,
}

/// Why a session ends early: a close code and its reason, and whether the client can still
/// be told (not when it stopped reading).
struct Close(CloseCode, String, bool);

impl Close {
    fn tell(code: CloseCode, reason: impl Into<String>) -> Self {
        Close(code, reason.into(), true)
    }
}

/// Serves one upgraded connection (`name` keeps its renders apart from other clients')
/// until the client leaves, breaks the protocol, stops reading or the server stops.
pub(in crate::web::serve) fn run(mut ws: WebSocket<TcpStream>, name: String, shared: &Shared) {
    let stream = ws.get_ref();
    let timeouts = stream
        .set_read_timeout(Some(POLL))
        .and(stream.set_write_timeout(Some(shared.options.write_timeout)))
        .and(stream.set_nodelay(true));
    if timeouts.is_err() {
        return;
    }
    // Without it the stream still works, only with the kernel's larger buffer.
    let _ = socket2::SockRef::from(stream).set_send_buffer_size(SEND_BUFFER);
    let mut session = Session::new(name, shared);
    match session.serve(&mut ws) {
        Ok(()) => {}
        Err(Close(_, _, false)) => {
            let _ = ws.get_ref().shutdown(std::net::Shutdown::Both);
        }
        Err(Close(code, reason, true)) => {
            let frame = CloseFrame {
                code,
                reason: close_reason(&reason).into(),
            };
            // The client may be gone already; then there is no one to tell.
            let _ = ws.close(Some(frame));
            let deadline = Instant::now() + Duration::from_millis(500);
            while Instant::now() < deadline {
                match ws.read() {
                    Ok(_) => {}
                    Err(WsError::Io(e)) if would_block(&e) => {}
                    Err(_) => break,
                }
            }
        }
    }
}

/// The stream's WebSocket settings: a pose message is small.
pub(super) fn ws_config() -> tungstenite::protocol::WebSocketConfig {
    tungstenite::protocol::WebSocketConfig::default()
        .max_message_size(Some(MAX_POSE_BYTES))
        .max_frame_size(Some(MAX_POSE_BYTES))
}

/// A close reason fits a control frame: at most 123 bytes, cut at a character boundary.
fn close_reason(reason: &str) -> &str {
    let mut end = reason.len().min(123);
    while !reason.is_char_boundary(end) {
        end -= 1;
    }
    &reason[..end]
}

fn would_block(e: &std::io::Error) -> bool {
    matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut)
}

struct Session<'a> {
    name: String,
    shared: &'a Shared,
    limits: PoseLimits,
    pace: Pace,
    /// The newest pose not yet rendered.
    pending: Option<Pose>,
    in_flight: Option<InFlight>,
    /// The last pose rendered while moving, until its still pair is asked for.
    resting: Option<Pose>,
    /// When the newest pose arrived or, if later, the last moving frame was sent: the client
    /// rests once this lies `rest_after` back.
    quiet_since: Instant,
    /// The newest seq seen: an older pose arriving late is ignored.
    newest_seq: u64,
}

impl<'a> Session<'a> {
    fn new(name: String, shared: &'a Shared) -> Self {
        let scan = &shared.scan;
        let pad = (scan.limits.hi - scan.limits.lo).max_element();
        Session {
            name,
            limits: PoseLimits {
                xy: scan.limits,
                z: (scan.info.min[2] - pad, scan.info.max[2] + pad),
                per_metre: scan.options.per_metre,
            },
            pace: Pace::new(shared.options.scale, shared.options.fps),
            shared,
            pending: None,
            in_flight: None,
            resting: None,
            quiet_since: Instant::now(),
            newest_seq: 0,
        }
    }

    fn serve(&mut self, ws: &mut WebSocket<TcpStream>) -> Result<(), Close> {
        loop {
            if self.shared.stop.load(Ordering::SeqCst) {
                return Err(Close::tell(CloseCode::Away, "the server is stopping"));
            }
            match ws.read() {
                Ok(message) => {
                    if !self.take(message)? {
                        return Ok(());
                    }
                    // Read every pose that has arrived before rendering: only the newest counts.
                    continue;
                }
                Err(WsError::Io(e)) if would_block(&e) => {}
                Err(WsError::Capacity(e)) => {
                    return Err(Close::tell(
                        CloseCode::Size,
                        format!("{e}: a pose is at most {MAX_POSE_BYTES} bytes"),
                    ));
                }
                Err(_) => return Ok(()),
            }
            self.work(ws)?;
        }
    }

    /// Takes in one message; false when the client closed.
    fn take(&mut self, message: Message) -> Result<bool, Close> {
        match message {
            Message::Text(text) => {
                let pose = parse_pose(text.as_str(), &self.limits).map_err(|e| {
                    let code = CloseCode::from(e.close_code());
                    Close::tell(code, e.to_string())
                })?;
                if pose.request.seq >= self.newest_seq {
                    self.newest_seq = pose.request.seq;
                    self.pending = Some(pose);
                    self.quiet_since = Instant::now();
                }
                Ok(true)
            }
            Message::Binary(_) => Err(Close::tell(
                CloseCode::Unsupported,
                "binary messages are not poses: send JSON text",
            )),
            Message::Close(_) => Ok(false),
            Message::Ping(_) | Message::Pong(_) | Message::Frame(_) => Ok(true),
        }
    }

    /// Sends a finished frame and starts the next render.
    fn work(&mut self, ws: &mut WebSocket<TcpStream>) -> Result<(), Close> {
        if let Some(flight) = &self.in_flight {
            let done = match flight.answer.try_recv() {
                Ok(done) => done,
                Err(TryRecvError::Empty) => return Ok(()),
                Err(TryRecvError::Disconnected) => Err(RenderFailure::Stopped),
            };
            let flight = self.in_flight.take().expect("checked above");
            // The next pose renders while this frame is encoded and sent.
            self.start_next(false);
            match done {
                Ok(raw) => self.send(ws, &flight, raw)?,
                Err(RenderFailure::Stopped) => {
                    return Err(Close::tell(CloseCode::Away, "the renderer has stopped"));
                }
                // Only this session queues under its name, one render at a time.
                Err(RenderFailure::Superseded) => {}
                Err(e) => {
                    let note = serde_json::json!({ "seq": flight.pose.request.seq, "error": e.to_string() });
                    self.deliver(ws, Message::text(note.to_string()))?;
                }
            }
        }
        if self.in_flight.is_none() {
            self.start_next(true);
        }
        Ok(())
    }

    /// Renders the newest pose if one waits, else (with `rested`, once every frame asked for
    /// is sent) the still pair once the client rests.
    fn start_next(&mut self, rested: bool) {
        let full = self.shared.scan.options.width;
        let (pose, width, quality, still) = if let Some(pose) = self.pending.take() {
            self.resting = Some(pose.clone());
            (pose, self.pace.width(full), self.pace.quality(), false)
        } else if rested
            && self.quiet_since.elapsed() >= self.shared.options.rest_after
            && let Some(pose) = self.resting.take()
        {
            (pose, full, STILL_QUALITY, true)
        } else {
            return;
        };
        let mut request = pose.request.clone();
        request.client.clone_from(&self.name);
        self.in_flight = Some(InFlight {
            answer: self.shared.queue.submit(request, width),
            pose,
            quality,
            still,
        });
    }

    fn send(
        &mut self,
        ws: &mut WebSocket<TcpStream>,
        flight: &InFlight,
        raw: RawFrame,
    ) -> Result<(), Close> {
        let started = Instant::now();
        let image = encode_jpeg(&raw.frame, flight.quality)
            .map_err(|e| Close::tell(CloseCode::Error, e.to_string()))?;
        let encode_ms = started.elapsed().as_secs_f64() * 1e3;
        let render_ms = raw.elapsed.as_secs_f64() * 1e3;
        if !flight.still {
            self.pace.after(render_ms, encode_ms);
        }
        let header = FrameHeader {
            seq: raw.seq,
            camera: raw.camera.to_array(),
            yaw: flight.pose.yaw,
            pitch: flight.pose.pitch,
            width: raw.frame.width,
            height: raw.frame.height,
            format: "jpeg".into(),
            quality: flight.quality,
            still: flight.still,
            render_ms,
            encode_ms,
        };
        self.shared.queue.give_back(raw.frame);
        self.deliver(ws, Message::binary(frame_message(&header, &image)))?;
        if !flight.still {
            self.quiet_since = Instant::now();
        }
        Ok(())
    }

    /// Sends a message; a client that does not take it within the write timeout is dropped.
    fn deliver(&mut self, ws: &mut WebSocket<TcpStream>, message: Message) -> Result<(), Close> {
        match ws.send(message) {
            Ok(()) => Ok(()),
            Err(WsError::Io(e)) if would_block(&e) => Err(Close(
                CloseCode::Policy,
                "the client stopped taking frames".into(),
                false,
            )),
            Err(e) => Err(Close::tell(CloseCode::Away, e.to_string())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_close_reason_fits_a_control_frame() {
        let long = "é".repeat(100);
        let cut = close_reason(&long);
        assert_eq!(cut.len(), 122, "61 two-byte characters");
        assert_eq!(close_reason("short"), "short");
    }
}
