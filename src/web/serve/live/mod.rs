//! The live stream (`/api/live`): a WebSocket on which a client sends its pose as it moves
//! and the server answers with ODS pairs of the newest pose, one frame in flight per client,
//! JPEG while moving and one high-quality pair once the client rests. The protocol
//! ([`pose`], [`message`]) is public: docs/LIVE.md describes it for other clients.

pub(super) mod front;
pub mod jpeg;
pub mod message;
pub mod pace;
pub mod pose;
pub(super) mod session;

pub use message::{FrameHeader, frame_message, split_frame};
pub use pace::{LiveScale, Pace};
pub use pose::{PoseError, PoseLimits, parse_pose};
pub use session::StreamOptions;
