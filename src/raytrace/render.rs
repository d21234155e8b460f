//! Whole-image rendering: one exact ray per pixel centre, rows in parallel.

use glam::DVec3;
use indicatif::ProgressBar;
use rayon::prelude::*;

use super::RaytraceError;
use super::bvh::{Hit, Tracer};
use crate::frame::{Frame, Rendered};
use crate::projection::sphere;
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
    let tracer = Tracer::padded(scene, padding_for(settings))?;
    render_with_tracer(&tracer, scene, settings, progress)
}

/// The box padding ([`Tracer::padded`]) a tracer needs to render `settings`: the largest
/// sphere half-ipd of a depth map ([`View::max_sphere_half_ipd`]), 0 without one.
pub fn padding_for(settings: &RenderSettings) -> f64 {
    settings
        .views()
        .iter()
        .filter(|v| v.depth_map.is_some())
        .map(View::max_sphere_half_ipd)
        .fold(0.0, f64::max)
}

/// Renders with a prebuilt [`Tracer`] (built from this `scene`), so that several frames
/// share one BVH; one padded too little for a depth map ([`padding_for`]) is rebuilt for
/// this frame.
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
    let padding = padding_for(settings);
    if tracer.padding() < padding {
        let padded = Tracer::padded(scene, padding)?;
        return render_with_tracer(&padded, scene, settings, progress);
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
                    let shaded = if view.depth_map.is_some() {
                        self.shade_mapped(view, image, i as u32, j as u32)
                    } else {
                        view.image_ray(image, i as u32, j as u32)
                            .and_then(|(origin, dir)| self.shade_ray(origin, dir))
                    };
                    if let Some((rgb, t)) = shaded {
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
        Some(self.shade_hit(origin, dir, hit))
    }

    /// Pixel `(i, j)` of a view with a depth map: each sphere is met by its own ODS ray,
    /// `C + e r_s merge(phi) side(lam)` along `d(lam, phi)` (DESIGN §9), the nearest wins.
    fn shade_mapped(&self, view: &View, image: &Image, i: u32, j: u32) -> Option<([u8; 3], f64)> {
        let (lam, phi) = image.pixel_angles(i, j)?;
        let (center, dir) = View::mono(view.camera).ray(lam, phi);
        let side = view.side(lam);
        let merge = view.merging.factor(phi);
        let origin_of = |c: DVec3| view.circle_origin(view.sphere_half_ipd(c) * merge, side);
        let hit = self.tracer.trace_own_rays(center, dir, origin_of)?;
        let c = self.scene.positions[hit.index].as_dvec3();
        Some(self.shade_hit(origin_of(c), dir, hit))
    }

    /// Shaded colour and depth of `hit` on the unit ray from `origin` along `dir`.
    #[inline]
    fn shade_hit(&self, origin: DVec3, dir: DVec3, hit: Hit) -> ([u8; 3], f64) {
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
        (rgb, hit.t)
    }
}
