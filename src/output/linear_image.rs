//! An image in linear light with coverage and depth: what EXR files hold and what
//! [`crate::compare`] measures.

use crate::frame::Frame;
use crate::render::shading::{linear_to_srgb, srgb_to_linear};

/// Linear-light colour, coverage and ray depth of one image (row-major, `width * height`).
#[derive(Debug, Clone, PartialEq)]
pub struct LinearImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Linear RGB, premultiplied by coverage (the OpenEXR convention).
    pub color: Vec<[f32; 3]>,
    /// Fraction of the pixel covered by geometry: 1 hit, 0 background.
    pub coverage: Vec<f32>,
    /// Distance along the pixel's ray to the hit, metres; `f32::INFINITY` for background.
    pub depth: Vec<f32>,
}

/// One sRGB pixel with alpha as premultiplied linear RGB and coverage.
#[inline]
pub fn linear_pixel(c: [u8; 4]) -> ([f32; 3], f32) {
    let a = c[3] as f32 / 255.0;
    (
        [
            srgb_to_linear(c[0]) * a,
            srgb_to_linear(c[1]) * a,
            srgb_to_linear(c[2]) * a,
        ],
        a,
    )
}

impl LinearImage {
    /// Number of pixels.
    pub fn len(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// True when the image has no pixels.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// True when pixel `index` counts as hit: coverage of at least one half.
    #[inline]
    pub fn hit(&self, index: usize) -> bool {
        self.coverage[index] >= 0.5
    }

    /// Converts a rendered frame: sRGB bytes to linear light, alpha to coverage.
    pub fn from_frame(frame: &Frame) -> LinearImage {
        let (color, coverage) = frame.color.iter().map(|&c| linear_pixel(c)).unzip();
        LinearImage {
            width: frame.width,
            height: frame.height,
            color,
            coverage,
            depth: frame.depth.clone(),
        }
    }

    /// Converts back to an 8-bit frame (un-premultiplied, sRGB); the inverse of
    /// [`LinearImage::from_frame`] for frames whose alpha is 0 or 255.
    pub fn to_frame(&self) -> Frame {
        let color = self
            .color
            .iter()
            .zip(&self.coverage)
            .map(|(c, &a)| {
                let a = a.clamp(0.0, 1.0);
                let un = |v: f32| if a > 0.0 { linear_to_srgb(v / a) } else { 0 };
                [un(c[0]), un(c[1]), un(c[2]), (a * 255.0 + 0.5) as u8]
            })
            .collect();
        Frame {
            width: self.width,
            height: self.height,
            color,
            depth: self.depth.clone(),
        }
    }
}

impl From<&Frame> for LinearImage {
    fn from(frame: &Frame) -> Self {
        LinearImage::from_frame(frame)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_bytes_survive_linear_round_trip() {
        for c in 0..=255u8 {
            assert_eq!(linear_to_srgb(srgb_to_linear(c)), c, "byte {c}");
        }
    }

    #[test]
    fn frame_round_trips_through_linear() {
        let mut f = Frame::new(4, 2);
        f.color[3] = [10, 128, 250, 255];
        f.depth[3] = 2.5;
        let lin = LinearImage::from_frame(&f);
        assert!(lin.hit(3) && !lin.hit(0));
        assert_eq!(lin.to_frame(), f);
    }
}
