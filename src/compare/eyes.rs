//! Splitting an image into the eyes it holds.

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
