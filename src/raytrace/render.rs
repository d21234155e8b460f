//! Whole-image rendering: one exact ray per pixel centre, rows in parallel.

use glam::DVec3;
use indicatif::ProgressBar;
use rayon::prelude::*;

use super::RaytraceError;
use super::bvh::Tracer;
use super::sphere;
use crate::frame::{Frame, Rendered};
use crate::projection::{Image, View};
use crate::render::RenderSettings;
use crate::render::color::base_colors;
use crate::render::cubemap_stereo;
use crate::render::shading::{Light, Shading, lights, shade};
use crate::scene::Scene;

/// Builds the BVH over `scene` and renders every view of `settings` (mono: one frame; ODS:
/// left and right). The progress bar's length is set to the number of rows over all views
/// and it advances by one per row.
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    progress: &ProgressBar,
) -> Result<Rendered, RaytraceError> {
    check_image(&settings.image)?;
    let tracer = Tracer::new(scene)?;
    render_with_tracer(&tracer, scene, settings, progress)
}

/// Renders with a prebuilt [`Tracer`] (built from this `scene`), so that several frames
/// share one BVH.
pub fn render_with_tracer(
    tracer: &Tracer,
    scene: &Scene,
    settings: &RenderSettings,
    progress: &ProgressBar,
) -> Result<Rendered, RaytraceError> {
    check_image(&settings.image)?;
    if tracer.len() != scene.len() {
        return Err(RaytraceError::SceneMismatch {
            tracer: tracer.len(),
            scene: scene.len(),
        });
    }
    if let Some(faces) = cubemap_stereo::face_settings(settings) {
        let strips = render_with_tracer(tracer, scene, &faces, progress)?;
        return Ok(cubemap_stereo::resample(&strips, settings));
    }
    let colors = base_colors(scene, settings.color)?;
    let views = settings.views();
    progress.set_length(settings.image.height as u64 * views.len() as u64);
    progress.set_position(0);
    let target = Target {
        tracer,
        scene,
        colors: &colors,
        shading: settings.shading,
        lights: lights(&settings.camera),
    };
    let mut frames: Vec<Frame> = views
        .iter()
        .map(|view| target.render_view(view, &settings.image, progress))
        .collect();
    Ok(if frames.len() == 2 {
        let right = frames.pop().expect("two frames");
        let left = frames.pop().expect("two frames");
        Rendered::Stereo { left, right }
    } else {
        Rendered::Mono(frames.pop().expect("one frame"))
    })
}

fn check_image(image: &Image) -> Result<(), RaytraceError> {
    if image.width == 0 || image.height == 0 {
        return Err(RaytraceError::EmptyImage {
            width: image.width,
            height: image.height,
        });
    }
    Ok(())
}

/// What every pixel of a render needs besides its ray.
struct Target<'a> {
    tracer: &'a Tracer,
    scene: &'a Scene,
    colors: &'a [[u8; 3]],
    shading: Shading,
    lights: [Light; 2],
}

impl Target<'_> {
    fn render_view(&self, view: &View, image: &Image, progress: &ProgressBar) -> Frame {
        let mut frame = Frame::new(image.width, image.height);
        let w = image.width as usize;
        frame
            .color
            .par_chunks_mut(w)
            .zip(frame.depth.par_chunks_mut(w))
            .enumerate()
            .for_each(|(j, (colors, depths))| {
                for (i, (color, depth)) in colors.iter_mut().zip(depths.iter_mut()).enumerate() {
                    let Some((origin, dir)) = view.image_ray(image, i as u32, j as u32) else {
                        continue;
                    };
                    if let Some((rgb, t)) = self.shade_ray(origin, dir) {
                        *color = [rgb[0], rgb[1], rgb[2], 255];
                        *depth = t as f32;
                    }
                }
                progress.inc(1);
            });
        frame
    }

    /// Shaded colour and depth of the closest hit along a unit ray.
    #[inline]
    fn shade_ray(&self, origin: DVec3, dir: DVec3) -> Option<([u8; 3], f64)> {
        let hit = self.tracer.trace(origin, dir)?;
        let center = self.scene.positions[hit.index].as_dvec3();
        let normal = sphere::facing_normal(origin, dir, hit.t, center);
        let point = origin + hit.t * dir;
        let rgb = shade(
            self.shading,
            self.colors[hit.index],
            normal.as_vec3(),
            point.as_vec3(),
            origin.as_vec3(),
            &self.lights,
        );
        Some((rgb, hit.t))
    }
}
