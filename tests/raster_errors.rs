//! GPU requests the adapter cannot meet become clear errors, not panics or hangs.

mod raster_common;

use glam::{DVec3, Vec3};
use indicatif::ProgressBar;
use omnicloud::Scene;
use omnicloud::projection::{Camera, Image, Projection};
use omnicloud::raster::RasterError;
use omnicloud::render::{ColorMode, ColorRule, RenderSettings};
use raster_common::rasterizer;

fn one_point() -> Scene {
    Scene::new(DVec3::ZERO, vec![Vec3::new(0.0, 5.0, 0.0)], 0.5)
}

#[test]
fn an_image_over_the_texture_limit_is_refused_with_the_limit() {
    let Some(raster) = rasterizer() else { return };
    let max = raster.max_image_width();
    let width = (max + 2).next_multiple_of(2);
    let mut s = RenderSettings::new(16, Camera::new(DVec3::ZERO, 0.0));
    s.image = Image::equirect(width);
    let Err(e) = raster.render(&one_point(), &s, &ProgressBar::hidden()) else {
        panic!("an image wider than the adapter allows must fail")
    };
    assert!(matches!(e, RasterError::Limit { .. }), "{e:?}");
    let text = e.to_string();
    assert!(
        text.contains(&width.to_string()) && text.contains(&max.to_string()),
        "{text}"
    );
}

#[test]
fn settings_the_rasterizer_cannot_draw_are_refused() {
    let Some(raster) = rasterizer() else { return };
    let mut s = RenderSettings::new(64, Camera::new(DVec3::ZERO, 0.0));
    s.image = Image {
        width: 64,
        height: 40,
        projection: Projection::EQUIRECT,
    };
    let Err(e) = raster.begin_frame(&s, 1) else {
        panic!("not 2:1")
    };
    assert!(e.to_string().contains("64x40"), "{e}");
}

#[test]
fn a_chunk_lacking_the_colour_attribute_is_an_error() {
    let Some(raster) = rasterizer() else { return };
    let s = RenderSettings::new(64, Camera::new(DVec3::ZERO, 0.0));
    // The rule was decided on a cloud with RGB; a chunk without it cannot be coloured.
    let mut coloured = one_point();
    coloured.attributes.rgb = Some(vec![[1, 2, 3]]);
    let rule = ColorRule::for_scene(&coloured, ColorMode::Rgb).unwrap();
    let mut frame = raster.begin_chunked(&s, rule, 16).unwrap();
    let Err(e) = frame.draw(&one_point()) else {
        panic!("no RGB in the chunk")
    };
    assert!(e.to_string().contains("RGB"), "{e}");
    frame.draw(&coloured).unwrap();
    let (_, stats, _) = frame.finish().unwrap();
    assert_eq!(stats.drawn, 1);
}
