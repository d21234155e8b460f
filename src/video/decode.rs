//! Decoding an MP4 this module wrote back into frames (OpenH264's decoder), to check a video
//! against the frames it was made from.

use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use openh264::decoder::Decoder;
use openh264::formats::YUVSource;

use super::VideoError;
use super::mux::{VideoInfo, read_sample, read_video_info};

const START_CODE: [u8; 4] = [0, 0, 0, 1];

/// Decodes every frame of `path` in order, handing each to `each` as 8-bit sRGB; returns the
/// file's description.
pub fn decode_frames(
    path: &Path,
    mut each: impl FnMut(usize, image::RgbImage),
) -> Result<VideoInfo, VideoError> {
    let info = read_video_info(path)?;
    let codec = |frame: usize, reason: String| VideoError::Codec {
        action: "decoding",
        frame,
        reason,
    };
    let mut decoder = Decoder::new().map_err(|e| codec(0, e.to_string()))?;
    let (sps, pps) = &info.parameter_sets;
    let mut headers = Vec::new();
    for set in [sps, pps] {
        headers.extend_from_slice(&START_CODE);
        headers.extend_from_slice(set);
    }
    let mut file = BufReader::new(File::open(path).map_err(|source| VideoError::Io {
        path: path.to_path_buf(),
        action: "open",
        source,
    })?);
    let mut decoded = 0;
    for index in 0..info.samples.len() {
        let sample = read_sample(&mut file, &info, index).map_err(|source| VideoError::Io {
            path: path.to_path_buf(),
            action: "read",
            source,
        })?;
        let mut packet = if index == 0 {
            headers.clone()
        } else {
            Vec::new()
        };
        annex_b(&sample, &mut packet).map_err(|reason| codec(index, reason))?;
        if let Some(yuv) = decoder
            .decode(&packet)
            .map_err(|e| codec(index, e.to_string()))?
        {
            each(decoded, to_rgb(&yuv));
            decoded += 1;
        }
    }
    for yuv in decoder
        .flush_remaining()
        .map_err(|e| codec(decoded, e.to_string()))?
    {
        each(decoded, to_rgb(&yuv));
        decoded += 1;
    }
    if decoded != info.frames {
        return Err(codec(
            decoded,
            format!("decoded {decoded} pictures from {} samples", info.frames),
        ));
    }
    Ok(info)
}

/// Appends a sample's length-prefixed NAL units to `out` with start codes instead.
fn annex_b(mut sample: &[u8], out: &mut Vec<u8>) -> Result<(), String> {
    while !sample.is_empty() {
        let Some((len, rest)) = sample.split_first_chunk::<4>() else {
            return Err("a NAL length is cut short".into());
        };
        let len = u32::from_be_bytes(*len) as usize;
        if len > rest.len() {
            return Err(format!("a NAL unit of {len} bytes runs past its sample"));
        }
        out.extend_from_slice(&START_CODE);
        out.extend_from_slice(&rest[..len]);
        sample = &rest[len..];
    }
    Ok(())
}

fn to_rgb(yuv: &openh264::decoder::DecodedYUV<'_>) -> image::RgbImage {
    let (w, h) = yuv.dimensions();
    let mut rgb = vec![0; w * h * 3];
    yuv.write_rgb8(&mut rgb);
    image::RgbImage::from_raw(w as u32, h as u32, rgb).expect("the buffer fits the size")
}
