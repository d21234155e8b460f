//! The one font of every drawn picture (benchmark charts, the heatmap legend): DejaVu Sans,
//! embedded by the `dejavu` crate and drawn by plotters' `ab_glyph` backend, so no system
//! font is needed.

use std::sync::Once;

use plotters::style::FontStyle;

/// The family name to ask plotters for, e.g. `(FONT, 14)`.
pub const FONT: &str = "sans-serif";

/// Registers the embedded DejaVu Sans as [`FONT`]; call before drawing text (cheap after the
/// first call).
pub fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The embedded DejaVu Sans is a valid TrueType font; a failure would only lose text.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
    });
}
