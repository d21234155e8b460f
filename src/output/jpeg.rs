//! JPEG: 8-bit sRGB, no alpha (background is black), with Photo Sphere XMP and a minimal
//! EXIF block; and Google's VR Photo (`.vr.jpg`): the left eye as the image, the right eye
//! as a JPEG inside extended XMP.
//!
//! `jpeg-encoder` encodes (with SIMD; four times the `image` crate's speed on a live pair,
//! docs/LIVE.md), the `image` crate decodes; the XMP segments are APP1 segments inserted by
//! hand after the encoder's JFIF and EXIF headers (a JPEG is a list of `FF xx` + length
//! segments, so this is a few lines and needs no further crate).

use std::io::Write;
use std::path::Path;

use base64::Engine;
use jpeg_encoder::{ColorType, Encoder, SamplingFactor};

use super::OutputError;
use super::description::{self, ImageDescription};
use super::xmp::{PhotoSphere, photo_sphere_packet, vr_photo_packets};
use crate::frame::{Frame, Rendered};
use crate::render::shading::{linear_to_srgb, srgb_to_linear};

/// The header of the APP1 segment holding the main XMP packet.
pub const XMP_HEADER: &[u8] = b"http://ns.adobe.com/xap/1.0/\0";
/// The header of each APP1 segment holding a piece of extended XMP.
pub const EXTENDED_XMP_HEADER: &[u8] = b"http://ns.adobe.com/xmp/extension/\0";
/// Extended XMP bytes per segment: a segment holds at most 65,533 bytes after its length,
/// less 75 of headers (namespace, MD5, total length, offset); Adobe's XMP specification
/// suggests about 65,400, this leaves margin.
pub const EXTENDED_CHUNK: usize = 65_000;
/// The default `--quality`.
pub const DEFAULT_QUALITY: u8 = 90;

fn jpeg_error(path: &Path) -> impl FnOnce(image::ImageError) -> OutputError + '_ {
    move |source| OutputError::Jpeg {
        path: path.to_path_buf(),
        source,
    }
}

/// Encodes `frame` as a baseline JPEG at `quality` (1..=100) with the omnicloud EXIF block;
/// coverage is dropped (the colour is laid over black, so the background is black).
fn encode_plain(frame: &Frame, quality: u8, path: &Path) -> Result<Vec<u8>, OutputError> {
    if frame.width == 0 || frame.height == 0 || frame.width > 65_535 || frame.height > 65_535 {
        return Err(OutputError::BadSize {
            path: path.to_path_buf(),
            width: frame.width,
            height: frame.height,
        });
    }
    let rgb: Vec<u8> = frame
        .color
        .iter()
        .flat_map(|&[r, g, b, a]| {
            // Over black in linear light (partial alpha comes from supersampling); alpha 0
            // and 255 give black and the colour exactly.
            let over_black = |c: u8| match a {
                255 => c,
                0 => 0,
                a => linear_to_srgb(srgb_to_linear(c) * (a as f32 / 255.0)),
            };
            [over_black(r), over_black(g), over_black(b)]
        })
        .collect();
    let encode_error = |source| OutputError::JpegEncode {
        path: path.to_path_buf(),
        source,
    };
    let mut out = Vec::new();
    let mut encoder = Encoder::new(&mut out, quality.clamp(1, 100));
    // Full-resolution chroma at every quality: thin coloured detail (class colours, far
    // façades) keeps its colour, as it did with the `image` crate's encoder.
    encoder.set_sampling_factor(SamplingFactor::F_1_1);
    encoder
        .add_exif_metadata(&super::exif::omnicloud_exif())
        .map_err(encode_error)?;
    // The size check above keeps both sides within u16.
    encoder
        .encode(
            &rgb,
            frame.width as u16,
            frame.height as u16,
            ColorType::Rgb,
        )
        .map_err(encode_error)?;
    Ok(out)
}

/// An APP1 segment (`FF E1`, length, `header`, `body`); an error when it exceeds 64 KiB.
fn app1(header: &[u8], body: &[&[u8]], path: &Path) -> Result<Vec<u8>, OutputError> {
    let len = 2 + header.len() + body.iter().map(|b| b.len()).sum::<usize>();
    let len16 = u16::try_from(len).map_err(|_| OutputError::SegmentTooLarge {
        path: path.to_path_buf(),
        bytes: len,
    })?;
    let mut seg = vec![0xFF, 0xE1];
    seg.extend_from_slice(&len16.to_be_bytes());
    seg.extend_from_slice(header);
    for b in body {
        seg.extend_from_slice(b);
    }
    Ok(seg)
}

/// Inserts `segments` after the application segments that follow SOI in `jpeg` (the
/// encoder's JFIF APP0 and EXIF APP1), before the tables and the image data.
fn insert_segments(jpeg: &[u8], segments: &[Vec<u8>]) -> Vec<u8> {
    let mut at = 2; // after SOI
    while at + 4 <= jpeg.len() && jpeg[at] == 0xFF && (0xE0..=0xEF).contains(&jpeg[at + 1]) {
        at += 2 + u16::from_be_bytes([jpeg[at + 2], jpeg[at + 3]]) as usize;
    }
    let mut out = Vec::with_capacity(jpeg.len() + segments.iter().map(Vec::len).sum::<usize>());
    out.extend_from_slice(&jpeg[..at]);
    for s in segments {
        out.extend_from_slice(s);
    }
    out.extend_from_slice(&jpeg[at..]);
    out
}

/// A comment segment (`FF FE`, length, `text`); `text` is far below the 64 KiB limit.
fn comment(text: &str) -> Vec<u8> {
    let mut seg = vec![0xFF, 0xFE];
    seg.extend_from_slice(&((2 + text.len()) as u16).to_be_bytes());
    seg.extend_from_slice(text.as_bytes());
    seg
}

/// The comment segment holding `description`: [`description::KEY`], a space, the text.
fn description_comment(d: &ImageDescription) -> Vec<u8> {
    comment(&format!("{} {d}", description::KEY))
}

/// Encodes a JPEG; `sphere` adds a Photo Sphere XMP packet (only for a full mono
/// equirectangular frame), `description` a comment segment holding it.
pub fn encode_jpeg(
    frame: &Frame,
    quality: u8,
    sphere: Option<&PhotoSphere>,
    description: Option<&ImageDescription>,
    mut out: impl Write,
    path: &Path,
) -> Result<(), OutputError> {
    let jpeg = encode_plain(frame, quality, path)?;
    let mut segments = match sphere {
        Some(s) => vec![app1(
            XMP_HEADER,
            &[photo_sphere_packet(s).as_bytes()],
            path,
        )?],
        None => Vec::new(),
    };
    segments.extend(description.map(description_comment));
    out.write_all(&insert_segments(&jpeg, &segments))
        .map_err(|source| OutputError::Io {
            path: path.to_path_buf(),
            action: "writing",
            source,
        })
}

/// Encodes a VR photo: `left` as the image with GPano (heading `heading_degrees`), `right`
/// as a JPEG in extended XMP.
pub fn encode_vr_jpeg(
    left: &Frame,
    right: &Frame,
    quality: u8,
    heading_degrees: f64,
    mut out: impl Write,
    path: &Path,
) -> Result<(), OutputError> {
    if (left.width, left.height) != (right.width, right.height) {
        return Err(OutputError::EyeSizeMismatch {
            path: path.to_path_buf(),
            left: (left.width, left.height),
            right: (right.width, right.height),
        });
    }
    let sphere = PhotoSphere {
        width: left.width,
        height: left.height,
        heading_degrees,
    };
    let right_jpeg = encode_plain(right, quality, path)?;
    let packets = vr_photo_packets(&sphere, &right_jpeg);
    let ext = packets.extended.as_bytes();
    let total = u32::try_from(ext.len()).map_err(|_| OutputError::SegmentTooLarge {
        path: path.to_path_buf(),
        bytes: ext.len(),
    })?;
    let mut segments = vec![app1(XMP_HEADER, &[packets.main.as_bytes()], path)?];
    for (k, chunk) in ext.chunks(EXTENDED_CHUNK).enumerate() {
        let offset = (k * EXTENDED_CHUNK) as u32;
        segments.push(app1(
            EXTENDED_XMP_HEADER,
            &[
                packets.extended_md5.as_bytes(),
                &total.to_be_bytes(),
                &offset.to_be_bytes(),
                chunk,
            ],
            path,
        )?);
    }
    let jpeg = encode_plain(left, quality, path)?;
    out.write_all(&insert_segments(&jpeg, &segments))
        .map_err(|source| OutputError::Io {
            path: path.to_path_buf(),
            action: "writing",
            source,
        })
}

/// The bodies (after the length) of the APP1 segments of a JPEG, up to the image data.
pub fn app1_segments(jpeg: &[u8]) -> Vec<&[u8]> {
    let mut segments = Vec::new();
    let mut at = 2;
    while at + 4 <= jpeg.len() && jpeg[at] == 0xFF {
        let marker = jpeg[at + 1];
        if marker == 0xDA || marker == 0xD9 {
            break; // start of scan / end of image: no more headers
        }
        let end = at + 2 + u16::from_be_bytes([jpeg[at + 2], jpeg[at + 3]]) as usize;
        if end > jpeg.len() {
            break;
        }
        if marker == 0xE1 {
            segments.push(&jpeg[at + 4..end]);
        }
        at = end;
    }
    segments
}

/// The extended XMP packet of a JPEG whose main packet names it by `md5`, reassembled from
/// its segments; `None` when a piece is missing.
pub fn extended_xmp(jpeg: &[u8], md5: &str) -> Option<Vec<u8>> {
    let mut total = None;
    let mut pieces = Vec::new();
    for body in app1_segments(jpeg) {
        let Some(rest) = body.strip_prefix(EXTENDED_XMP_HEADER) else {
            continue;
        };
        if rest.len() < 40 || &rest[..32] != md5.as_bytes() {
            continue;
        }
        total = Some(u32::from_be_bytes(rest[32..36].try_into().ok()?) as usize);
        let offset = u32::from_be_bytes(rest[36..40].try_into().ok()?) as usize;
        pieces.push((offset, &rest[40..]));
    }
    let total = total?;
    let mut packet = vec![0u8; total];
    let mut filled = 0;
    for (offset, piece) in pieces {
        packet
            .get_mut(offset..offset + piece.len())?
            .copy_from_slice(piece);
        filled += piece.len();
    }
    (filled == total).then_some(packet)
}

/// The value of the XML attribute `name="…"` in `xml`.
fn attribute<'a>(xml: &'a str, name: &str) -> Option<&'a str> {
    let start = xml.find(&format!("{name}=\""))? + name.len() + 2;
    let len = xml[start..].find('"')?;
    Some(&xml[start..start + len])
}

/// Decodes JPEG bytes into a frame (opaque: every pixel counts as hit; depth `+inf`).
fn decode(bytes: &[u8], path: &Path) -> Result<Frame, OutputError> {
    let rgba = image::load_from_memory_with_format(bytes, image::ImageFormat::Jpeg)
        .map_err(jpeg_error(path))?
        .into_rgba8();
    Ok(Frame::from_rgba8(rgba))
}

/// Reads a VR photo written by [`encode_vr_jpeg`] (or any with `GImage:Data` in extended
/// XMP): the main image as the left eye, the embedded JPEG as the right.
pub fn read_vr_jpeg(path: &Path) -> Result<Rendered, OutputError> {
    let bytes = std::fs::read(path).map_err(|source| OutputError::Io {
        path: path.to_path_buf(),
        action: "reading",
        source,
    })?;
    let missing = |what: &'static str| OutputError::NoRightEye {
        path: path.to_path_buf(),
        what,
    };
    let main = app1_segments(&bytes)
        .into_iter()
        .find_map(|b| b.strip_prefix(XMP_HEADER))
        .ok_or_else(|| missing("no XMP packet"))?;
    let main = String::from_utf8_lossy(main);
    let md5 = attribute(&main, "xmpNote:HasExtendedXMP")
        .ok_or_else(|| missing("no xmpNote:HasExtendedXMP"))?;
    let ext = extended_xmp(&bytes, md5).ok_or_else(|| missing("incomplete extended XMP"))?;
    let ext = String::from_utf8_lossy(&ext);
    let data = attribute(&ext, "GImage:Data").ok_or_else(|| missing("no GImage:Data"))?;
    let right = base64::engine::general_purpose::STANDARD
        .decode(data)
        .map_err(|_| missing("GImage:Data is not base64"))?;
    Ok(Rendered::Stereo {
        left: decode(&bytes, path)?,
        right: decode(&right, path)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(w: u32, h: u32, seed: u8) -> Frame {
        let mut f = Frame::new(w, h);
        for (k, c) in f.color.iter_mut().enumerate() {
            let v = (k as u32 * 37 + seed as u32) as u8;
            *c = [v, v / 2 + seed, 255 - v, 255];
        }
        f
    }

    #[test]
    fn vr_jpeg_splits_a_large_right_eye_and_reads_back() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.vr.jpg");
        // Noise-like content compresses badly, so the right eye needs several segments.
        let (left, right) = (frame(512, 256, 3), frame(512, 256, 90));
        let mut bytes = Vec::new();
        encode_vr_jpeg(&left, &right, 95, 12.5, &mut bytes, &path).unwrap();
        let pieces = app1_segments(&bytes)
            .iter()
            .filter(|b| b.starts_with(EXTENDED_XMP_HEADER))
            .count();
        assert!(pieces >= 2, "{pieces} extended segments");
        std::fs::write(&path, &bytes).unwrap();
        let Rendered::Stereo { left: l, right: r } = read_vr_jpeg(&path).unwrap() else {
            panic!("not stereo")
        };
        assert_eq!((l.width, l.height, r.width, r.height), (512, 256, 512, 256));
        let err = |a: &Frame, b: &Frame| {
            a.color
                .iter()
                .zip(&b.color)
                .map(|(x, y)| (x[1] as i32 - y[1] as i32).abs())
                .sum::<i32>() as f64
                / a.color.len() as f64
        };
        // Each eye decodes near its own source and far from the other.
        assert!(err(&l, &left) < 8.0 && err(&r, &right) < 8.0);
        assert!(err(&r, &left) > 20.0, "{}", err(&r, &left));
    }

    #[test]
    fn plain_jpeg_without_sphere_has_exif_but_no_xmp() {
        let mut bytes = Vec::new();
        encode_jpeg(
            &frame(8, 4, 1),
            90,
            None,
            None,
            &mut bytes,
            Path::new("a.jpg"),
        )
        .unwrap();
        let app1 = app1_segments(&bytes);
        assert!(app1.iter().any(|b| b.starts_with(b"Exif\0\0")));
        assert!(!app1.iter().any(|b| b.starts_with(XMP_HEADER)));
    }
}
