//! The angular-disparity image of a rendered stereo frame: the surface each left-eye pixel
//! sees, placed in both eyes ([`crate::projection::disparity_image`] holds the image and its
//! comfort summary).

use crate::frame::Rendered;
use crate::projection::disparity::angular_disparity;
use crate::projection::disparity_image::{DisparityImage, disparity_image, disparity_image_of};
use crate::projection::{Eye, Image, Stereo, View};
use crate::render::RenderSettings;
use crate::render::hit_points::hit_point;

/// The disparity image of `rendered` (drawn under `settings`, its output at `image`): the
/// surface each left-eye pixel sees, placed in both eyes of `model` (default: the settings'
/// own stereo, depth map included). Cube-map eyes see from their parallel cameras, so their
/// model is `parallel`. Under a depth map each surface point stands in for its sphere's
/// centre: its own ODS radius places it (the pixel's ray origin refined once with it).
pub fn left_eye_disparity(
    rendered: &Rendered,
    settings: &RenderSettings,
    image: &Image,
    model: Option<Stereo>,
) -> DisparityImage {
    let frame = rendered.frames()[0];
    let camera = settings.camera;
    let map = settings.depth_map;
    // `View::eye` gives cube-map eyes their parallel cameras.
    let drawn = View::eye(camera, &settings.stereo, Eye::Left).with_depth_map(map);
    let map = if model.is_none() { map } else { None };
    let model = model.unwrap_or(settings.stereo);
    let left = View::eye(camera, &model, Eye::Left).with_depth_map(map);
    let right = View::eye(camera, &model, Eye::Right).with_depth_map(map);
    if drawn.depth_map.is_none() && left.depth_map.is_none() {
        return disparity_image(
            frame.width,
            frame.height,
            |i, j| hit_point(frame, &drawn, image, i, j),
            &left,
            &right,
        );
    }
    disparity_image_of(frame.width, frame.height, |i, j| {
        let first = hit_point(frame, &drawn.with_depth_map(None), image, i, j)?;
        let p = hit_point(frame, &drawn.for_sphere(first), image, i, j)?;
        angular_disparity(&left.for_sphere(p), &right.for_sphere(p), p)
    })
}
