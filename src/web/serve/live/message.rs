//! A frame message: what the server sends for each pair, a 4-byte little-endian length `L`,
//! `L` bytes of JSON header ([`FrameHeader`]), then the image.

use serde::{Deserialize, Serialize};

/// What a frame message says about its image.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameHeader {
    /// The `seq` of the pose it shows.
    pub seq: u64,
    /// The camera, file coordinates.
    pub camera: [f64; 3],
    /// The pose's heading, degrees clockwise from north, echoed (the pair itself always has
    /// north at its centre column).
    pub yaw: f64,
    /// The pose's pitch, degrees, echoed.
    pub pitch: f64,
    /// Image width, pixels (per eye).
    pub width: u32,
    /// Image height, pixels: both eyes, top-bottom, left eye on top.
    pub height: u32,
    /// `"jpeg"` or `"png"`.
    pub format: String,
    /// JPEG quality, 1 to 100 (100 for PNG).
    pub quality: u8,
    /// True for the full-quality pair sent once the client rests.
    pub still: bool,
    /// Milliseconds the render took (with the upload of a new camera position).
    pub render_ms: f64,
    /// Milliseconds the encoding took.
    pub encode_ms: f64,
}

/// The binary message for `header` and `image`.
pub fn frame_message(header: &FrameHeader, image: &[u8]) -> Vec<u8> {
    let json = serde_json::to_vec(header).expect("a header serialises");
    let mut out = Vec::with_capacity(4 + json.len() + image.len());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(&json);
    out.extend_from_slice(image);
    out
}

/// Splits a frame message into its header and image (for clients).
///
/// # Errors
/// The message is shorter than its length prefix says, or its header is not a frame
/// header.
pub fn split_frame(message: &[u8]) -> Result<(FrameHeader, &[u8]), String> {
    let Some((len, rest)) = message.split_first_chunk::<4>() else {
        return Err(format!("a frame message of {} bytes", message.len()));
    };
    let len = u32::from_le_bytes(*len) as usize;
    if rest.len() < len {
        return Err(format!(
            "the header is {len} bytes but only {} follow",
            rest.len()
        ));
    }
    let (json, image) = rest.split_at(len);
    let header = serde_json::from_slice(json).map_err(|e| format!("frame header: {e}"))?;
    Ok((header, image))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_message_splits_back_into_its_header_and_image() {
        let header = FrameHeader {
            seq: 7,
            camera: [636_000.5, 849_000.25, 420.0],
            yaw: 90.0,
            pitch: 0.0,
            width: 64,
            height: 64,
            format: "jpeg".into(),
            quality: 80,
            still: false,
            render_ms: 12.5,
            encode_ms: 3.25,
        };
        let message = frame_message(&header, b"\xff\xd8image");
        let len = u32::from_le_bytes(message[..4].try_into().unwrap()) as usize;
        let json: serde_json::Value = serde_json::from_slice(&message[4..4 + len]).unwrap();
        assert_eq!(json["camera"][1], 849_000.25);
        assert_eq!(json["format"], "jpeg");
        let (back, image) = split_frame(&message).unwrap();
        assert_eq!((back, image), (header, &b"\xff\xd8image"[..]));
        assert!(
            split_frame(&message[..10])
                .unwrap_err()
                .contains("only 6 follow")
        );
        assert!(split_frame(b"ab").is_err());
    }
}
