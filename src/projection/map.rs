//! The top-down map: orthographic from above over the scan's XY extent, north up (DESIGN §8).

use glam::DVec3;

/// The map's extent in the scene's local frame and the height its rays start at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapFrame {
    /// West edge.
    pub x0: f64,
    /// East edge.
    pub x1: f64,
    /// South edge.
    pub y0: f64,
    /// North edge.
    pub y1: f64,
    /// Ray origin height: one metre above the highest sphere top.
    pub z_top: f64,
}

impl MapFrame {
    /// The frame over XY box `[lo, hi]` (sphere extents included), padded in Y or X so its
    /// aspect is that of a `width` x `height` image, `height = round(width * (y1-y0)/(x1-x0))`
    /// before padding. Returns the frame and the height.
    pub fn over(lo: DVec3, hi: DVec3, width: u32) -> (MapFrame, u32) {
        let (dx, dy) = ((hi.x - lo.x).max(1e-6), (hi.y - lo.y).max(1e-6));
        let height = ((f64::from(width) * dy / dx).round() as u32).max(1);
        // Padding keeps the pixels square: one of the two spans grows to the image aspect.
        let aspect = f64::from(height) / f64::from(width);
        let (sx, sy) = if dy / dx > aspect {
            (dy / aspect, dy)
        } else {
            (dx, dx * aspect)
        };
        let (cx, cy) = (0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y));
        let frame = MapFrame {
            x0: cx - 0.5 * sx,
            x1: cx + 0.5 * sx,
            y0: cy - 0.5 * sy,
            y1: cy + 0.5 * sy,
            z_top: hi.z + 1.0,
        };
        (frame, height)
    }

    /// The ray at continuous image position `(u, v)` in `[0, 1]^2`: origin and direction
    /// `(0, 0, -1)`.
    #[inline]
    pub fn ray(&self, u: f64, v: f64) -> (DVec3, DVec3) {
        let origin = DVec3::new(
            self.x0 + u * (self.x1 - self.x0),
            self.y1 - v * (self.y1 - self.y0),
            self.z_top,
        );
        (origin, DVec3::NEG_Z)
    }

    /// Image position `(u, v)` of the XY location of `p`.
    #[inline]
    pub fn position(&self, p: DVec3) -> (f64, f64) {
        (
            (p.x - self.x0) / (self.x1 - self.x0),
            (self.y1 - p.y) / (self.y1 - self.y0),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn north_is_up_and_the_aspect_is_padded() {
        let (f, h) = MapFrame::over(DVec3::new(0.0, 0.0, 0.0), DVec3::new(100.0, 50.0, 9.0), 200);
        assert_eq!(h, 100);
        let (o, d) = f.ray(0.5, 0.0);
        assert!((o - DVec3::new(50.0, 50.0, 10.0)).length() < 1e-12);
        assert_eq!(d, DVec3::NEG_Z);
        let (f, h) = MapFrame::over(DVec3::ZERO, DVec3::new(100.0, 50.2, 0.0), 200);
        assert_eq!(h, 100);
        assert!(((f.y1 - f.y0) / (f.x1 - f.x0) - 0.5).abs() < 1e-12);
        assert!(f.y1 - f.y0 >= 50.2 && f.x1 - f.x0 >= 100.0);
        let (u, v) = f.position(DVec3::new(50.0, 25.1, 0.0));
        assert!((u - 0.5).abs() < 1e-12 && (v - 0.5).abs() < 1e-12);
    }
}
