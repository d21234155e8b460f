//! Rendered images in memory: one equirectangular frame per eye, colour and depth.

/// One equirectangular image (DESIGN §2): sRGB colour with coverage, and ray depth.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Width in pixels (`2 * height`).
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major sRGB-encoded colour; alpha is 255 where a sphere was hit, 0 for background
    /// (the covered fraction after supersampling, colour then not premultiplied).
    pub color: Vec<[u8; 4]>,
    /// Row-major distance along the pixel's ray to the hit, metres; `f32::INFINITY` for background.
    pub depth: Vec<f32>,
}

impl Frame {
    /// A frame from a decoded 8-bit image (alpha is coverage); no depth (`+inf`), as for
    /// PNG and JPEG files.
    pub fn from_rgba8(rgba: image::RgbaImage) -> Self {
        let (width, height) = rgba.dimensions();
        let color: Vec<[u8; 4]> = rgba.pixels().map(|p| p.0).collect();
        Frame {
            width,
            height,
            depth: vec![f32::INFINITY; color.len()],
            color,
        }
    }

    /// An empty (all background) frame; the background colour is transparent black.
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Frame {
            width,
            height,
            color: vec![[0, 0, 0, 0]; n],
            depth: vec![f32::INFINITY; n],
        }
    }

    /// Index of pixel (i, j) in the row-major buffers.
    #[inline]
    pub fn index(&self, i: u32, j: u32) -> usize {
        j as usize * self.width as usize + i as usize
    }

    /// True when pixel (i, j) was hit.
    #[inline]
    pub fn covered(&self, i: u32, j: u32) -> bool {
        self.color[self.index(i, j)][3] != 0
    }

    /// Number of covered pixels.
    pub fn coverage_count(&self) -> usize {
        self.color.iter().filter(|c| c[3] != 0).count()
    }
}

/// What a renderer returns: one frame for mono, left and right for ODS.
#[derive(Debug, Clone, PartialEq)]
pub enum Rendered {
    /// A single equirectangular frame.
    Mono(Frame),
    /// Left and right eye frames.
    Stereo {
        /// Left eye (drawn on top in top-bottom layout).
        left: Frame,
        /// Right eye.
        right: Frame,
    },
}

impl Rendered {
    /// The frames in output order (left first).
    pub fn frames(&self) -> Vec<&Frame> {
        match self {
            Rendered::Mono(f) => vec![f],
            Rendered::Stereo { left, right } => vec![left, right],
        }
    }

    /// Stacks the frames top-bottom (left eye on top, DESIGN §6) into one frame.
    pub fn top_bottom(&self) -> Frame {
        let pixels = self.frames().iter().map(|f| f.color.len()).sum();
        let mut out = Frame {
            width: 0,
            height: 0,
            color: Vec::with_capacity(pixels),
            depth: Vec::with_capacity(pixels),
        };
        self.top_bottom_into(&mut out);
        out
    }

    /// Stacks the frames top-bottom into `out`, whatever it held, in its memory where it
    /// has room: a loop that hands its last frame back writes no fresh pages.
    pub fn top_bottom_into(&self, out: &mut Frame) {
        let frames = self.frames();
        out.width = frames[0].width;
        out.height = frames.iter().map(|f| f.height).sum();
        out.color.clear();
        out.depth.clear();
        for f in frames {
            out.color.extend_from_slice(&f.color);
            out.depth.extend_from_slice(&f.depth);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `width x height` frame whose pixels count up from `first`.
    fn counting(width: u32, height: u32, first: u8) -> Frame {
        let mut f = Frame::new(width, height);
        for (k, (c, d)) in f.color.iter_mut().zip(&mut f.depth).enumerate() {
            *c = [first.wrapping_add(k as u8), 0, 0, 255];
            *d = first as f32 + k as f32;
        }
        f
    }

    #[test]
    fn stacking_into_a_used_frame_gives_the_stacked_pair_in_its_memory() {
        let pair = Rendered::Stereo {
            left: counting(8, 4, 0),
            right: counting(8, 4, 100),
        };
        let stacked = pair.top_bottom();
        assert_eq!((stacked.width, stacked.height), (8, 8));
        assert_eq!(stacked.color[32], [100, 0, 0, 255], "right eye below");
        assert_eq!(stacked.depth[31], 31.0);
        // A larger frame's memory serves, a smaller one's grows.
        let mut larger = counting(16, 8, 7);
        let before = larger.color.as_ptr();
        pair.top_bottom_into(&mut larger);
        assert!(larger == stacked);
        assert_eq!(larger.color.as_ptr(), before, "no new allocation");
        let mut smaller = counting(2, 1, 9);
        pair.top_bottom_into(&mut smaller);
        assert!(smaller == stacked);
        let mono = Rendered::Mono(counting(4, 2, 3));
        mono.top_bottom_into(&mut smaller);
        assert!(smaller == counting(4, 2, 3));
    }
}
