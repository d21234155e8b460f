//! The colour behind the scene. Renderers leave uncovered pixels transparent (alpha 0);
//! writing a colour there makes the image opaque.

use std::str::FromStr;

use super::shading::{linear_to_srgb, srgb_to_linear};
use crate::frame::{Frame, Rendered};

/// What fills the pixels no sphere covers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Background {
    /// Alpha 0 (PNG and EXR keep it; a JPEG, which has no alpha, cannot).
    Transparent,
    /// An opaque sRGB colour; partly covered (supersampled) pixels are mixed with it in
    /// linear light.
    Color([u8; 3]),
}

impl Background {
    /// Fills `frame`'s background: with a colour every pixel becomes opaque (alpha 255),
    /// colour `c·a + bg·(1 − a)` in linear light; depth stays `+inf` where nothing was hit.
    /// Transparent leaves the frame as it is.
    pub fn apply(&self, frame: &mut Frame) {
        let Background::Color(bg) = *self else {
            return;
        };
        let bg_linear = bg.map(srgb_to_linear);
        for c in &mut frame.color {
            match c[3] {
                255 => {}
                0 => *c = [bg[0], bg[1], bg[2], 255],
                a => {
                    let a = a as f32 / 255.0;
                    for ch in 0..3 {
                        c[ch] =
                            linear_to_srgb(srgb_to_linear(c[ch]) * a + bg_linear[ch] * (1.0 - a));
                    }
                    c[3] = 255;
                }
            }
        }
    }

    /// [`Background::apply`] on every eye.
    pub fn apply_rendered(&self, rendered: &mut Rendered) {
        match rendered {
            Rendered::Mono(f) => self.apply(f),
            Rendered::Stereo { left, right } => {
                self.apply(left);
                self.apply(right);
            }
        }
    }
}

/// `transparent`, a name (`black`, `white`, `grey`/`gray`), `#rrggbb` or `r,g,b` (0–255).
impl FromStr for Background {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let t = s.trim().to_ascii_lowercase();
        let bad = || {
            format!(
                "unknown background `{s}`: use transparent, black, white, grey, #rrggbb or r,g,b \
                 (0-255)"
            )
        };
        Ok(match t.as_str() {
            "transparent" | "none" => Background::Transparent,
            "black" => Background::Color([0, 0, 0]),
            "white" => Background::Color([255, 255, 255]),
            "grey" | "gray" => Background::Color([128, 128, 128]),
            _ if t.starts_with('#') => {
                let hex = &t[1..];
                if hex.len() != 6 || !hex.chars().all(|c| c.is_ascii_hexdigit()) {
                    return Err(bad());
                }
                let byte =
                    |k: usize| u8::from_str_radix(&hex[2 * k..2 * k + 2], 16).map_err(|_| bad());
                Background::Color([byte(0)?, byte(1)?, byte(2)?])
            }
            _ if t.contains(',') => {
                let parts: Vec<&str> = t.split(',').map(str::trim).collect();
                if parts.len() != 3 {
                    return Err(bad());
                }
                let byte = |p: &str| {
                    p.parse::<u8>().map_err(|_| {
                        format!("`{p}` in background `{s}` is not a whole number 0-255")
                    })
                };
                Background::Color([byte(parts[0])?, byte(parts[1])?, byte(parts[2])?])
            }
            _ => return Err(bad()),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_parse_in_every_spelling() {
        let c = |s: &str| s.parse::<Background>();
        assert_eq!(c("#FF8000"), Ok(Background::Color([255, 128, 0])));
        assert_eq!(c(" 10, 20,30"), Ok(Background::Color([10, 20, 30])));
        assert_eq!(c("Grey"), c("gray"));
        assert_eq!(c("transparent"), Ok(Background::Transparent));
        for bad in ["#12345", "#gg0000", "1,2", "1,2,256", "blue", ""] {
            assert!(c(bad).is_err(), "{bad}");
        }
        assert!(c("1,2,300").unwrap_err().contains("0-255"));
    }

    #[test]
    fn a_colour_fills_the_background_and_mixes_partial_pixels_in_linear_light() {
        let mut f = Frame::new(4, 2);
        f.color[0] = [10, 20, 30, 255];
        f.color[1] = [255, 255, 255, 128];
        Background::Color([0, 0, 0]).apply(&mut f);
        assert_eq!(f.color[0], [10, 20, 30, 255]);
        // Half-covered white over black: linear 0.502 is sRGB 188.
        assert_eq!(f.color[1], [188, 188, 188, 255]);
        assert_eq!(f.color[2], [0, 0, 0, 255]);
        assert_eq!(f.depth[2], f32::INFINITY);
        let before = f.clone();
        Background::Transparent.apply(&mut f);
        assert_eq!(f, before);
    }
}
