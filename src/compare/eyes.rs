//! Splitting an image into the eyes it holds: as its file describes it, or guessed from its
//! shape.

use crate::output::ImageDescription;
use crate::projection::Projection;

/// One eye's rows in an image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EyeRows {
    /// `mono`, `left` or `right`.
    pub name: &'static str,
    /// First row of the eye in the image.
    pub first_row: u32,
    /// Number of rows (the eye's equirect height).
    pub height: u32,
}

/// The eyes of a `width x height` image: a square image of even height is a top-bottom ODS
/// pair (left on top, DESIGN §6); anything else is one mono image.
pub fn split_eyes(width: u32, height: u32) -> Vec<EyeRows> {
    if width == height && height.is_multiple_of(2) && height > 0 {
        let h = height / 2;
        vec![
            EyeRows {
                name: "left",
                first_row: 0,
                height: h,
            },
            EyeRows {
                name: "right",
                first_row: h,
                height: h,
            },
        ]
    } else {
        vec![EyeRows {
            name: "mono",
            first_row: 0,
            height,
        }]
    }
}

/// How a compared image is laid out.
#[derive(Debug, Clone, PartialEq)]
pub struct ImageLayout {
    /// The eyes, top first.
    pub eyes: Vec<EyeRows>,
    /// The projection each eye is in; `None` when guessed from the image's shape.
    pub projection: Option<Projection>,
}

impl ImageLayout {
    /// The layout of a `width x height` image without a description: a full equirect, a
    /// top-bottom pair when square ([`split_eyes`]).
    pub fn from_shape(width: u32, height: u32) -> Self {
        ImageLayout {
            eyes: split_eyes(width, height),
            projection: None,
        }
    }

    /// The layout `description` gives an image `height` rows tall; `None` when the rows do
    /// not split into its eyes.
    pub fn described(description: &ImageDescription, height: u32) -> Option<Self> {
        let count = description.eyes.count();
        if height == 0 || !height.is_multiple_of(count) {
            return None;
        }
        let h = height / count;
        let names: &[&'static str] = match count {
            2 => &["left", "right"],
            _ => &[description.eyes.name()],
        };
        let eyes = names
            .iter()
            .zip(0..)
            .map(|(&name, k)| EyeRows {
                name,
                first_row: k * h,
                height: h,
            })
            .collect();
        Some(ImageLayout {
            eyes,
            projection: Some(description.projection),
        })
    }

    /// True when each eye is a full 360° x 180° equirect (assumed for a guessed layout):
    /// only then are latitude bands and the seam measured.
    pub fn is_panorama(&self) -> bool {
        self.projection.is_none_or(|p| p.is_full_equirect())
    }

    /// `mono` or `top-bottom`.
    pub fn name(&self) -> &'static str {
        if self.eyes.len() == 2 {
            "top-bottom"
        } else {
            "mono"
        }
    }
}

/// Number of 10° latitude bands.
pub const LATITUDE_BANDS: usize = 18;

/// The 10° latitude band (0 = +90°..+80° at the top, 17 = -80°..-90°) of row `j` of an eye
/// `height` rows tall, by the latitude of the row's pixel centres (DESIGN §2).
pub fn latitude_band(j: u32, height: u32) -> usize {
    let t = (j as f64 + 0.5) / height as f64; // = (90° - latitude) / 180°
    ((t * LATITUDE_BANDS as f64) as usize).min(LATITUDE_BANDS - 1)
}

/// Name of band `b`, e.g. `+90..+80`.
pub fn band_name(b: usize) -> String {
    let top = 90 - 10 * b as i32;
    format!("{top:+}..{:+}", top - 10)
}

/// Columns on each side of the seam (longitude ±180°) counted as seam columns: 1% of the
/// width, at least one.
pub fn seam_columns(width: u32) -> u32 {
    width.div_ceil(100).max(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_follow_latitude() {
        assert_eq!(latitude_band(0, 180), 0);
        assert_eq!(latitude_band(9, 180), 0);
        assert_eq!(latitude_band(10, 180), 1);
        assert_eq!(latitude_band(179, 180), 17);
        assert_eq!(latitude_band(0, 4), 2); // centre at +67.5°
        assert_eq!(latitude_band(3, 4), 15);
        assert_eq!(band_name(0), "+90..+80");
        assert_eq!(band_name(9), "+0..-10");
        assert_eq!(band_name(17), "-80..-90");
    }

    #[test]
    fn square_images_are_top_bottom() {
        assert_eq!(split_eyes(8, 8).len(), 2);
        assert_eq!(split_eyes(8, 8)[1].first_row, 4);
        assert_eq!(split_eyes(8, 4)[0].name, "mono");
        assert_eq!(seam_columns(8192), 82);
        assert_eq!(seam_columns(64), 1);
    }
}
