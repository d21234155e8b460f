//! What is done to a render's frames after either renderer drew them, in this order:
//! eye-dome lighting at the render's resolution, supersampling reduced to the output size,
//! then the background. Each eye of an ODS pair is treated alone.

use crate::frame::Rendered;
use crate::projection::{Equirect, Image};

use super::background::Background;
use super::edl::Edl;
use super::supersample::{self, MAX_FACTOR};

/// Why a look cannot be rendered.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum LookError {
    /// The supersampled render would be wider than any renderer accepts.
    #[error(
        "--supersample {factor} at width {width} renders {} pixels wide, above the widest \
         image ({max}): lower --width or --supersample",
        u64::from(*factor) * u64::from(*width)
    )]
    TooWide {
        /// Output width.
        width: u32,
        /// Supersampling factor.
        factor: u32,
        /// Widest render.
        max: u32,
    },
    /// The factor is outside 1..=MAX_FACTOR.
    #[error("--supersample must be within 1..={MAX_FACTOR}, got {0}")]
    BadFactor(u32),
}

/// The passes after rendering. The default does nothing: the renderers' frames are written
/// as they are.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Look {
    /// Eye-dome lighting, when asked for.
    pub edl: Option<Edl>,
    /// Samples per pixel along each axis (1: none).
    pub supersample: u32,
    /// What fills uncovered pixels; `None` leaves them as the renderer gave them.
    pub background: Option<Background>,
}

impl Look {
    /// The image the renderer must draw for an output `output_width` wide: `supersample`
    /// times wider, within the widest image any renderer accepts (a GPU's own texture limit
    /// can be lower; the rasterizer then refuses with its limit).
    pub fn render_image(&self, output: &Image) -> Result<Image, LookError> {
        let factor = self.factor();
        if !(1..=MAX_FACTOR).contains(&factor) {
            return Err(LookError::BadFactor(factor));
        }
        let width = u64::from(output.width) * u64::from(factor);
        if width > u64::from(Equirect::MAX_WIDTH) {
            return Err(LookError::TooWide {
                width: output.width,
                factor,
                max: Equirect::MAX_WIDTH,
            });
        }
        // Both sides scale by the factor, so each output pixel averages whole samples.
        Ok(Image {
            width: width as u32,
            height: output.height * factor,
            projection: output.projection,
        })
    }

    /// The factor, 0 read as 1.
    fn factor(&self) -> u32 {
        self.supersample.max(1)
    }

    /// True when the passes change nothing.
    pub fn is_identity(&self) -> bool {
        self.edl.is_none_or(|e| e.strength == 0.0)
            && self.factor() == 1
            && self.background.is_none_or(|b| b == Background::Transparent)
    }

    /// Applies the passes to a render drawn at [`Look::render_image`]; returns the output
    /// frames.
    pub fn finish(&self, mut rendered: Rendered) -> Rendered {
        if self.is_identity() {
            return rendered;
        }
        let factor = self.factor();
        if let Some(edl) = self.edl {
            let output_height = match &rendered {
                Rendered::Mono(f) | Rendered::Stereo { left: f, .. } => f.height / factor,
            };
            let angle = edl.angle(output_height);
            match &mut rendered {
                Rendered::Mono(f) => edl.apply(f, angle),
                Rendered::Stereo { left, right } => {
                    edl.apply(left, angle);
                    edl.apply(right, angle);
                }
            }
        }
        if factor > 1 {
            rendered = supersample::reduce_rendered(&rendered, factor);
        }
        if let Some(bg) = self.background {
            bg.apply_rendered(&mut rendered);
        }
        rendered
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_render_is_wider_by_the_factor_within_the_limit() {
        let look = Look {
            supersample: 4,
            ..Look::default()
        };
        assert_eq!(
            look.render_image(&Image::equirect(1024)).unwrap(),
            Image::equirect(4096)
        );
        let e = look
            .render_image(&Image::equirect(8192))
            .unwrap_err()
            .to_string();
        assert!(e.contains("32768") && e.contains("16384"), "{e}");
        assert!(Look::default().is_identity());
        assert_eq!(
            Look::default()
                .render_image(&Image::equirect(64))
                .unwrap()
                .width,
            64
        );
    }
}
