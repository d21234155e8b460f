//! A scene held resident for many camera positions, by the renderer chosen at run time: on the
//! GPU for the rasterizer (uploaded relative to an [`Anchor`], or streamed through a reused
//! chunk when it does not fit), or as the ray tracer's BVH.

use indicatif::ProgressBar;

use super::anchor::Anchor;
use super::error::ResidentError;
use crate::Rendered;
use crate::projection::Camera;
use crate::raytrace::{self, Tracer};
use crate::render::{RenderSettings, RendererKind};
use crate::scene::Scene;

/// The renderer with its scene resident.
pub struct Resident<'s> {
    scene: &'s Scene,
    /// The settings it was made resident under: their colour mode holds for every frame.
    settings: RenderSettings,
    anchor: Anchor,
    kept: Kept,
}

/// What each renderer keeps between frames.
enum Kept {
    /// The rasterizer and the points (boxed: far larger than the other variant).
    #[cfg(feature = "gpu")]
    Raster(Box<super::on_gpu::OnGpu>),
    /// The BVH over the scene's spheres.
    Raytrace(Tracer),
}

impl<'s> Resident<'s> {
    /// Makes `scene` resident for `kind` under `settings`, anchored at the scene's local zero
    /// ([`Resident::anchored`]).
    pub fn new(
        scene: &'s Scene,
        kind: RendererKind,
        settings: &RenderSettings,
    ) -> Result<Self, ResidentError> {
        Self::anchored(scene, kind, settings, Anchor::SceneZero)
    }

    /// Makes `scene` resident for `kind` under `settings` (its colour mode is fixed for every
    /// frame; the camera may move), the rasterizer's points relative to `anchor`. A scene the
    /// GPU has no memory for is kept in host memory and streamed through the GPU every frame
    /// instead ([`Resident::is_streamed`]).
    pub fn anchored(
        scene: &'s Scene,
        kind: RendererKind,
        settings: &RenderSettings,
        anchor: Anchor,
    ) -> Result<Self, ResidentError> {
        let kept = match kind {
            RendererKind::Raytrace => {
                Kept::Raytrace(Tracer::padded(scene, raytrace::padding_for(settings))?)
            }
            #[cfg(feature = "gpu")]
            RendererKind::Raster => Kept::Raster(Box::new(super::on_gpu::OnGpu::upload(
                crate::raster::Rasterizer::new()?,
                scene,
                &at_anchor(settings, anchor),
            )?)),
            #[cfg(not(feature = "gpu"))]
            RendererKind::Raster => return Err(ResidentError::NoRasterizer),
        };
        Ok(Resident {
            scene,
            settings: at_anchor(settings, anchor),
            anchor,
            kept,
        })
    }

    /// `scene` kept in host memory and streamed through `rasterizer` every frame; `reason`
    /// says why (for [`Resident::describe`]). Public for tests, which compare it with the
    /// resident upload.
    #[cfg(feature = "gpu")]
    pub fn streamed(
        rasterizer: Box<crate::raster::Rasterizer>,
        scene: &'s Scene,
        settings: &RenderSettings,
        reason: String,
    ) -> Result<Self, ResidentError> {
        let on_gpu = super::on_gpu::OnGpu::streamed(*rasterizer, scene, settings, reason)?;
        Ok(Resident {
            scene,
            settings: at_anchor(settings, Anchor::SceneZero),
            anchor: Anchor::SceneZero,
            kept: Kept::Raster(Box::new(on_gpu)),
        })
    }

    /// Where the rasterizer's points are measured from.
    pub fn anchor(&self) -> Anchor {
        self.anchor
    }

    /// Places the points relative to `anchor` for the frames to come, keeping the renderer
    /// (the rasterizer and its pipelines, or the BVH): the rasterizer uploads them again unless
    /// they are already there (streamed points and the BVH need nothing).
    ///
    /// # Errors
    /// The upload failed (the points are then released, and the next `place` tries again).
    pub fn place(&mut self, anchor: Anchor) -> Result<(), ResidentError> {
        #[cfg(feature = "gpu")]
        if let Kept::Raster(on_gpu) = &mut self.kept {
            if anchor == self.anchor && on_gpu.is_placed() {
                return Ok(());
            }
            self.settings = at_anchor(&self.settings, anchor);
            self.anchor = anchor;
            return on_gpu.place(self.scene, &self.settings);
        }
        self.settings = at_anchor(&self.settings, anchor);
        self.anchor = anchor;
        Ok(())
    }

    /// Frees the rasterizer's upload of the points (keeping the rasterizer), so that the next
    /// [`place`](Self::place) uploads them afresh; the BVH and streamed points stay.
    pub fn release(&mut self) {
        #[cfg(feature = "gpu")]
        if let Kept::Raster(on_gpu) = &mut self.kept {
            on_gpu.release();
        }
    }

    /// True when the scene is drawn from host memory every frame (a warning for the caller).
    pub fn is_streamed(&self) -> bool {
        match &self.kept {
            #[cfg(feature = "gpu")]
            Kept::Raster(on_gpu) => on_gpu.is_streamed(),
            Kept::Raytrace(_) => false,
        }
    }

    /// What renders, for messages: the points on the GPU with its adapter's name, or the
    /// BVH's size.
    pub fn describe(&self) -> String {
        match &self.kept {
            #[cfg(feature = "gpu")]
            Kept::Raster(on_gpu) => on_gpu.describe(self.scene),
            Kept::Raytrace(tracer) => format!(
                "BVH over {} spheres resident ({}, built in {:.2?})",
                tracer.len(),
                crate::memory::format_size(tracer.memory().total() as u64),
                tracer.build_time()
            ),
        }
    }

    /// The device that renders: the GPU adapter's name and backend, or the CPU.
    pub fn device(&self) -> &str {
        match &self.kept {
            #[cfg(feature = "gpu")]
            Kept::Raster(on_gpu) => on_gpu.rasterizer().adapter_name(),
            Kept::Raytrace(_) => "CPU ray tracer",
        }
    }

    /// Widest panorama (pixels per eye) the renderer can render; `None` when no device limits
    /// it (the ray tracer).
    pub fn max_image_width(&self) -> Option<u32> {
        match &self.kept {
            #[cfg(feature = "gpu")]
            Kept::Raster(on_gpu) => Some(on_gpu.rasterizer().max_image_width()),
            Kept::Raytrace(_) => None,
        }
    }

    /// Hands a frame this resident rendered back once it is written, for the next frame's
    /// read-back to reuse its memory (rasterizers only).
    pub fn recycle(&self, rendered: Rendered) {
        match &self.kept {
            #[cfg(feature = "gpu")]
            Kept::Raster(on_gpu) => on_gpu.rasterizer().recycle(rendered),
            Kept::Raytrace(_) => drop(rendered),
        }
    }

    /// Renders one frame; `settings.camera.center` is in the scene's local frame.
    pub fn render(
        &self,
        settings: &RenderSettings,
        progress: &ProgressBar,
    ) -> Result<Rendered, ResidentError> {
        match &self.kept {
            #[cfg(feature = "gpu")]
            Kept::Raster(on_gpu) => on_gpu.render(self.scene, settings, progress),
            Kept::Raytrace(tracer) => Ok(raytrace::render_with_tracer(
                tracer, self.scene, settings, progress,
            )?),
        }
    }
}

/// `settings` with the camera standing at `anchor`, heading north: what an upload relative
/// to the anchor reads.
fn at_anchor(settings: &RenderSettings, anchor: Anchor) -> RenderSettings {
    RenderSettings {
        camera: Camera::new(anchor.position(), 0.0),
        ..*settings
    }
}

#[cfg(test)]
mod tests {
    use glam::{DVec3, Vec3};

    use super::*;
    use crate::projection::{OdsOffset, PoleMerge, PoleMerging, Stereo};
    use crate::render::ColorMode;

    /// A 10 m x 10 m floor 1.5 m below the local zero, points every 0.25 m.
    fn floor() -> Scene {
        let pts = (0..41 * 41)
            .map(|k| {
                Vec3::new(
                    (k % 41) as f32 * 0.25 - 5.0,
                    (k / 41) as f32 * 0.25 - 5.0,
                    -1.5,
                )
            })
            .collect();
        Scene::new(DVec3::new(500_000.0, 4_000_000.0, 80.0), pts, 0.15)
    }

    fn settings_at(center: DVec3, yaw: f64) -> RenderSettings {
        RenderSettings {
            color: ColorMode::Elevation,
            stereo: Stereo::Ods {
                ipd: 0.064,
                merging: PoleMerging::both(PoleMerge::COMFORTABLE),
                offset: OdsOffset::Exact,
            },
            ..RenderSettings::new(64, Camera::new(center, yaw))
        }
    }

    #[test]
    fn the_ray_tracer_kept_resident_renders_as_a_single_trace_wherever_it_is_placed() {
        let scene = floor();
        let first = settings_at(DVec3::new(0.5, -1.0, 0.2), 20.0);
        let mut resident = Resident::anchored(
            &scene,
            RendererKind::Raytrace,
            &first,
            Anchor::Camera(first.camera.center),
        )
        .unwrap();
        assert_eq!(resident.device(), "CPU ray tracer");
        assert_eq!(resident.max_image_width(), None);
        assert!(!resident.is_streamed());
        assert!(
            resident
                .describe()
                .starts_with(&format!("BVH over {} spheres", scene.len()))
        );
        let hidden = ProgressBar::hidden();
        let got = resident.render(&first, &hidden).unwrap();
        let want = raytrace::render(&scene, &first, &hidden).unwrap();
        assert!(got == want, "the resident BVH renders another image");
        assert!(got.frames()[0].coverage_count() > 64 * 32 / 4);

        let moved = settings_at(DVec3::new(-2.0, 3.0, 0.0), -75.0);
        resident.place(Anchor::Camera(moved.camera.center)).unwrap();
        assert_eq!(resident.anchor(), Anchor::Camera(moved.camera.center));
        resident.release();
        let got = resident.render(&moved, &hidden).unwrap();
        assert!(got == raytrace::render(&scene, &moved, &hidden).unwrap());
    }

    #[cfg(not(feature = "gpu"))]
    #[test]
    fn a_build_without_the_gpu_feature_has_no_rasterizer() {
        let scene = floor();
        let settings = settings_at(DVec3::ZERO, 0.0);
        assert!(matches!(
            Resident::new(&scene, RendererKind::Raster, &settings),
            Err(ResidentError::NoRasterizer)
        ));
    }
}
