//! What compare reads from an image, pixel by pixel: a linear-light image (EXR, or a PNG read
//! back) and an in-memory 8-bit frame feed the same statistics.

use crate::frame::Frame;
use crate::output::LinearImage;

/// An image as compare measures it; pixels are indexed row-major.
pub trait Samples {
    /// Width and height in pixels.
    fn size(&self) -> (u32, u32);
    /// True when pixel `k` counts as hit: coverage of at least one half.
    fn hit(&self, k: usize) -> bool;
    /// Distance along pixel `k`'s ray to the hit, metres (`f32::INFINITY` for background).
    fn depth(&self, k: usize) -> f32;
    /// Colour of pixel `k`, sRGB-encoded, each channel in [0, 1] (not quantised).
    fn srgb(&self, k: usize) -> [f64; 3];
}

/// sRGB encoding of linear light as a float in [0, 1] (not quantised).
fn srgb_encode(l: f32) -> f64 {
    let l = (l as f64).clamp(0.0, 1.0);
    if l <= 0.003_130_8 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

impl Samples for LinearImage {
    fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    fn hit(&self, k: usize) -> bool {
        LinearImage::hit(self, k)
    }

    fn depth(&self, k: usize) -> f32 {
        self.depth[k]
    }

    fn srgb(&self, k: usize) -> [f64; 3] {
        self.color[k].map(srgb_encode)
    }
}

/// A frame's bytes are sRGB already; alpha is the coverage, as
/// [`LinearImage::from_frame`] reads it.
impl Samples for Frame {
    fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    fn hit(&self, k: usize) -> bool {
        self.color[k][3] >= 128
    }

    fn depth(&self, k: usize) -> f32 {
        self.depth[k]
    }

    fn srgb(&self, k: usize) -> [f64; 3] {
        let c = self.color[k];
        [c[0], c[1], c[2]].map(|v| v as f64 / 255.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_and_its_linear_image_read_alike() {
        let mut f = Frame::new(4, 2);
        f.color[1] = [10, 128, 250, 255];
        f.depth[1] = 2.5;
        f.color[2] = [200, 1, 2, 127];
        let lin = LinearImage::from_frame(&f);
        for k in 0..f.color.len() {
            assert_eq!(Samples::hit(&f, k), Samples::hit(&lin, k), "pixel {k}");
            assert_eq!(Samples::depth(&f, k), Samples::depth(&lin, k));
        }
        let (a, b) = (f.srgb(1), lin.srgb(1));
        for c in 0..3 {
            assert!((a[c] - b[c]).abs() < 1e-6, "{a:?} vs {b:?}");
        }
    }
}
