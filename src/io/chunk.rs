//! Chunks of points as the readers produce them, and the 16-bit colour scaling.

use crate::scene::Returns;
use glam::DVec3;

/// A run of consecutive points from a file, in file coordinates (f64, not yet re-originated).
///
/// Every `Some` attribute has one entry per position.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PointChunk {
    /// Point coordinates as stored in the file (scale and offset applied), including any
    /// NaN/inf the file holds: filtering is [`crate::io::load_scene`]'s job.
    pub positions: Vec<DVec3>,
    /// Colour scaled to 8 bits per channel (see [`ColorScale`]).
    pub rgb: Option<Vec<[u8; 3]>>,
    /// Raw intensity.
    pub intensity: Option<Vec<u16>>,
    /// ASPRS classification code.
    pub classification: Option<Vec<u8>>,
    /// Return number and number of returns.
    pub returns: Option<Vec<Returns>>,
    /// Per-point sphere radius (PLY `radius`).
    pub radius: Option<Vec<f32>>,
}

impl PointChunk {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// True when the chunk holds no point.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }
}

/// How stored colour values become 8-bit sRGB.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColorScale {
    /// 8-bit storage: values are taken as they are.
    Direct8,
    /// 16-bit fields that only hold 0–255 (Autzen does this): taken as they are.
    Low8In16,
    /// 16-bit fields using 0–65535: the high byte is kept (`v >> 8`, i.e. scaled by 256).
    Full16,
}

impl ColorScale {
    /// The scale for 16-bit fields whose largest channel value is `max`.
    pub fn detect_16(max: u16) -> Self {
        if max <= 255 {
            ColorScale::Low8In16
        } else {
            ColorScale::Full16
        }
    }

    /// One 16-bit stored channel as 8 bits. Under `Low8In16` values above 255 (possible
    /// when the scale was decided from a first chunk only) saturate at 255.
    #[inline]
    pub fn to_u8(self, v: u16) -> u8 {
        match self {
            ColorScale::Direct8 | ColorScale::Low8In16 => v.min(255) as u8,
            ColorScale::Full16 => (v >> 8) as u8,
        }
    }
}

/// Colour as the reader found it, before scaling.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum RawRgb {
    /// 8 bits per channel.
    Bits8(Vec<[u8; 3]>),
    /// 16-bit fields (LAS, PLY `ushort`).
    Bits16(Vec<[u16; 3]>),
}

impl RawRgb {
    /// Largest channel value of a 16-bit colour run, `None` for 8-bit runs.
    pub(crate) fn max_16(&self) -> Option<u16> {
        match self {
            RawRgb::Bits8(_) => None,
            RawRgb::Bits16(v) => Some(v.iter().flatten().copied().max().unwrap_or(0)),
        }
    }

    /// Scales to 8 bits; `scale` is used for 16-bit runs only.
    pub(crate) fn into_u8(self, scale: ColorScale) -> Vec<[u8; 3]> {
        match self {
            RawRgb::Bits8(v) => v,
            RawRgb::Bits16(v) => v.into_iter().map(|c| c.map(|x| scale.to_u8(x))).collect(),
        }
    }

    fn split_off(&mut self, at: usize) -> RawRgb {
        match self {
            RawRgb::Bits8(v) => RawRgb::Bits8(v.split_off(at)),
            RawRgb::Bits16(v) => RawRgb::Bits16(v.split_off(at)),
        }
    }
}

/// A chunk before colour scaling: what the format readers return.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct RawChunk {
    pub(crate) positions: Vec<DVec3>,
    pub(crate) rgb: Option<RawRgb>,
    pub(crate) intensity: Option<Vec<u16>>,
    pub(crate) classification: Option<Vec<u8>>,
    pub(crate) returns: Option<Vec<Returns>>,
    pub(crate) radius: Option<Vec<f32>>,
    /// GPS time (LAS point formats with a time field).
    pub(crate) gps_time: Option<Vec<f64>>,
}

impl RawChunk {
    /// Splits into pieces of at most `size` points, in order.
    pub(crate) fn split_into(mut self, size: usize) -> Vec<RawChunk> {
        let size = size.max(1);
        let mut pieces = Vec::new();
        // Split from the back so each split copies only the piece it cuts off.
        while self.positions.len() > size {
            let at = (self.positions.len() - 1) / size * size;
            pieces.push(self.split_off(at));
        }
        pieces.push(self);
        pieces.reverse();
        pieces
    }

    fn split_off(&mut self, at: usize) -> RawChunk {
        RawChunk {
            positions: self.positions.split_off(at),
            rgb: self.rgb.as_mut().map(|c| c.split_off(at)),
            intensity: self.intensity.as_mut().map(|v| v.split_off(at)),
            classification: self.classification.as_mut().map(|v| v.split_off(at)),
            returns: self.returns.as_mut().map(|v| v.split_off(at)),
            radius: self.radius.as_mut().map(|v| v.split_off(at)),
            gps_time: self.gps_time.as_mut().map(|v| v.split_off(at)),
        }
    }

    /// Applies the colour scale, giving the public chunk.
    pub(crate) fn into_chunk(self, scale: ColorScale) -> PointChunk {
        PointChunk {
            positions: self.positions,
            rgb: self.rgb.map(|c| c.into_u8(scale)),
            intensity: self.intensity,
            classification: self.classification,
            returns: self.returns,
            radius: self.radius,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn numbered(n: usize) -> RawChunk {
        RawChunk {
            positions: (0..n).map(|i| DVec3::splat(i as f64)).collect(),
            rgb: Some(RawRgb::Bits16((0..n).map(|i| [i as u16; 3]).collect())),
            intensity: Some((0..n).map(|i| i as u16).collect()),
            classification: None,
            returns: None,
            radius: None,
            gps_time: None,
        }
    }

    #[test]
    fn split_keeps_order_and_sizes() {
        for (n, size) in [(10, 3), (9, 3), (2, 5), (1, 1), (100, 7)] {
            let pieces = numbered(n).split_into(size);
            let lens: Vec<usize> = pieces.iter().map(|p| p.positions.len()).collect();
            assert!(lens.iter().all(|&l| l <= size && l > 0), "{lens:?}");
            assert!(
                lens[..lens.len() - 1].iter().all(|&l| l == size),
                "{lens:?}"
            );
            let xs: Vec<f64> = pieces
                .iter()
                .flat_map(|p| p.positions.iter().map(|q| q.x))
                .collect();
            assert_eq!(xs, (0..n).map(|i| i as f64).collect::<Vec<_>>());
            let is: Vec<u16> = pieces
                .iter()
                .flat_map(|p| p.intensity.clone().unwrap())
                .collect();
            assert_eq!(is, (0..n).map(|i| i as u16).collect::<Vec<_>>());
        }
    }

    #[test]
    fn colour_scale_detection_and_values() {
        assert_eq!(ColorScale::detect_16(236), ColorScale::Low8In16);
        assert_eq!(ColorScale::detect_16(255), ColorScale::Low8In16);
        assert_eq!(ColorScale::detect_16(256), ColorScale::Full16);
        assert_eq!(ColorScale::Low8In16.to_u8(236), 236);
        assert_eq!(ColorScale::Low8In16.to_u8(300), 255);
        assert_eq!(ColorScale::Full16.to_u8(65535), 255);
        assert_eq!(ColorScale::Full16.to_u8(256 * 17 + 200), 17);
        let rgb = RawRgb::Bits16(vec![[0, 65535, 4096]]);
        assert_eq!(rgb.max_16(), Some(65535));
        assert_eq!(rgb.into_u8(ColorScale::Full16), vec![[0, 255, 16]]);
    }
}
