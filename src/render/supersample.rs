//! Supersampling: a frame rendered `N` times wider (and taller) reduced to the output size,
//! each output pixel from its `N × N` samples.
//!
//! - colour: the mean of the covered samples' colours in linear light (straight, not
//!   premultiplied, as the frame stores it), re-encoded as sRGB;
//! - alpha: the fraction of samples covered (`255 · covered / N²`, rounded), so silhouettes
//!   are anti-aliased; written over a background (a JPEG's black, `--background`) the
//!   mix is done in linear light, so a half-covered white pixel on black is sRGB 188, not 128;
//! - depth: the nearest sample's (`+inf` when none is covered).

use rayon::prelude::*;

use super::shading::{linear_to_srgb, srgb_to_linear};
use crate::frame::{Frame, Rendered};

/// Largest supersampling factor accepted (64 samples a pixel).
pub const MAX_FACTOR: u32 = 8;

/// Reduces `frame` by `n` in both directions (see the module doc). `n` must divide both
/// sides; `n = 1` returns the frame unchanged.
///
/// # Panics
/// When `n` is 0 or does not divide the frame's width and height.
pub fn reduce(frame: &Frame, n: u32) -> Frame {
    assert!(
        n > 0 && frame.width.is_multiple_of(n) && frame.height.is_multiple_of(n),
        "supersampling factor {n} does not divide {}x{}",
        frame.width,
        frame.height
    );
    if n == 1 {
        return frame.clone();
    }
    let (w, h) = (frame.width / n, frame.height / n);
    let src_w = frame.width as usize;
    let n = n as usize;
    let samples = (n * n) as f32;
    let mut color = vec![[0u8; 4]; w as usize * h as usize];
    let mut depth = vec![f32::INFINITY; w as usize * h as usize];
    color
        .par_chunks_mut(w as usize)
        .zip(depth.par_chunks_mut(w as usize))
        .enumerate()
        .for_each(|(j, (crow, drow))| {
            for (i, (c, d)) in crow.iter_mut().zip(drow.iter_mut()).enumerate() {
                let mut sum = [0.0f32; 3];
                let mut weight = 0.0f32;
                let mut nearest = f32::INFINITY;
                for sj in j * n..(j + 1) * n {
                    for si in i * n..(i + 1) * n {
                        let k = sj * src_w + si;
                        let s = frame.color[k];
                        if s[3] == 0 {
                            continue;
                        }
                        let a = s[3] as f32 / 255.0;
                        for ch in 0..3 {
                            sum[ch] += srgb_to_linear(s[ch]) * a;
                        }
                        weight += a;
                        nearest = nearest.min(frame.depth[k]);
                    }
                }
                if weight > 0.0 {
                    let alpha = ((weight / samples) * 255.0).round().max(1.0) as u8;
                    *c = [
                        linear_to_srgb(sum[0] / weight),
                        linear_to_srgb(sum[1] / weight),
                        linear_to_srgb(sum[2] / weight),
                        alpha,
                    ];
                    *d = nearest;
                }
            }
        });
    Frame {
        width: w,
        height: h,
        color,
        depth,
    }
}

/// [`reduce`] on every eye.
pub fn reduce_rendered(rendered: &Rendered, n: u32) -> Rendered {
    match rendered {
        Rendered::Mono(f) => Rendered::Mono(reduce(f, n)),
        Rendered::Stereo { left, right } => Rendered::Stereo {
            left: reduce(left, n),
            right: reduce(right, n),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_half_covered_pixel_keeps_its_colour_and_half_alpha() {
        let mut f = Frame::new(4, 2);
        for k in [0, 1] {
            f.color[k] = [255, 255, 255, 255];
            f.depth[k] = 3.0 + k as f32;
        }
        let r = reduce(&f, 2);
        assert_eq!((r.width, r.height), (2, 1));
        assert_eq!(r.color[0], [255, 255, 255, 128]);
        assert_eq!(r.depth[0], 3.0);
        assert_eq!(r.color[1], [0, 0, 0, 0]);
        assert_eq!(r.depth[1], f32::INFINITY);
    }

    #[test]
    fn colours_mix_in_linear_light() {
        let mut f = Frame::new(2, 2);
        f.color = vec![
            [255, 0, 0, 255],
            [0, 0, 0, 255],
            [255, 0, 0, 255],
            [0, 0, 0, 255],
        ];
        f.depth = vec![1.0; 4];
        // Half red, half black, all covered: linear 0.5 is sRGB 188.
        assert_eq!(reduce(&f, 2).color[0], [188, 0, 0, 255]);
    }
}
