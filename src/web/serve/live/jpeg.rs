//! JPEG encoding of a rendered pair for the live stream: `jpeg-encoder` (SIMD), and the
//! `image` crate's encoder it was measured against (`examples/live_bench.rs --encoders`).

use crate::frame::Frame;

/// Why a frame could not be encoded.
#[derive(Debug, thiserror::Error)]
#[error("JPEG encoding of a {width}x{height} image failed: {reason}")]
pub struct JpegError {
    width: u32,
    height: u32,
    reason: String,
}

/// `frame` as a baseline JPEG of `quality` (1 to 100), with `jpeg-encoder`.
///
/// # Errors
/// The frame is wider or taller than JPEG allows (65,535 pixels).
pub fn encode_jpeg(frame: &Frame, quality: u8) -> Result<Vec<u8>, JpegError> {
    let fail = |reason: String| JpegError {
        width: frame.width,
        height: frame.height,
        reason,
    };
    let side = |v: u32| u16::try_from(v).map_err(|_| fail("JPEG sides stop at 65535".into()));
    let (w, h) = (side(frame.width)?, side(frame.height)?);
    let mut out = Vec::new();
    jpeg_encoder::Encoder::new(&mut out, quality.clamp(1, 100))
        .encode(
            bytemuck::cast_slice(&frame.color),
            w,
            h,
            jpeg_encoder::ColorType::Rgba,
        )
        .map_err(|e| fail(e.to_string()))?;
    Ok(out)
}

/// `frame` as a JPEG of `quality` with the `image` crate's encoder (for comparison).
///
/// # Errors
/// The encoder refused the frame.
pub fn encode_jpeg_image_crate(frame: &Frame, quality: u8) -> Result<Vec<u8>, JpegError> {
    let rgb: Vec<u8> = frame
        .color
        .iter()
        .flat_map(|c| [c[0], c[1], c[2]])
        .collect();
    let mut out = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut out, quality.clamp(1, 100))
        .encode(
            &rgb,
            frame.width,
            frame.height,
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| JpegError {
            width: frame.width,
            height: frame.height,
            reason: e.to_string(),
        })?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 64x64 gradient.
    fn gradient() -> Frame {
        let mut f = Frame::new(64, 64);
        for (k, c) in f.color.iter_mut().enumerate() {
            let (i, j) = ((k % 64) as u8, (k / 64) as u8);
            *c = [i * 4, j * 4, 128, 255];
        }
        f
    }

    #[test]
    fn both_encoders_give_a_jpeg_that_decodes_close_to_the_frame() {
        let frame = gradient();
        for (name, bytes) in [
            ("jpeg-encoder", encode_jpeg(&frame, 90).unwrap()),
            ("image", encode_jpeg_image_crate(&frame, 90).unwrap()),
        ] {
            let back = image::load_from_memory(&bytes).unwrap().to_rgb8();
            assert_eq!(back.dimensions(), (64, 64), "{name}");
            let worst = back
                .pixels()
                .zip(&frame.color)
                .flat_map(|(a, b)| (0..3).map(move |k| a.0[k].abs_diff(b[k])))
                .max()
                .unwrap();
            // Measured: 3 for both at quality 90 on this smooth gradient.
            assert!(worst <= 5, "{name}: worst channel error {worst}");
        }
        let low = encode_jpeg(&frame, 30).unwrap().len();
        assert!(low < encode_jpeg(&frame, 95).unwrap().len());
    }
}
