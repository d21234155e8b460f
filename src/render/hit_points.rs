//! The surface point each pixel of a rendered frame sees: its ray and its depth.

use glam::DVec3;

use crate::frame::Frame;
use crate::projection::{Image, View};

/// The world point pixel `(i, j)` of `frame` (rendered in `view` at `image`) sees:
/// `origin + depth * dir` of its ray; `None` for background.
#[inline]
pub fn hit_point(frame: &Frame, view: &View, image: &Image, i: u32, j: u32) -> Option<DVec3> {
    let t = frame.depth[frame.index(i, j)];
    if !t.is_finite() || frame.color[frame.index(i, j)][3] == 0 {
        return None;
    }
    let (origin, dir) = view.image_ray(image, i, j)?;
    Some(origin + f64::from(t) * dir)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projection::Camera;

    #[test]
    fn a_hit_lies_along_its_pixels_ray() {
        let image = Image::equirect(8);
        let view = View::mono(Camera::new(DVec3::new(1.0, 2.0, 3.0), 0.0));
        let mut frame = Frame::new(8, 4);
        let k = frame.index(4, 2);
        frame.depth[k] = 2.5;
        frame.color[k] = [1, 2, 3, 255];
        let p = hit_point(&frame, &view, &image, 4, 2).unwrap();
        let (o, d) = view.image_ray(&image, 4, 2).unwrap();
        assert!((p - (o + 2.5 * d)).length() < 1e-12);
        assert!(hit_point(&frame, &view, &image, 0, 0).is_none());
    }
}
