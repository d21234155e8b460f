//! The rasterizer's side of a resident scene: the rasterizer with its pipelines, kept for
//! every frame, and the scene's points uploaded relative to an anchor, or streamed through one
//! reused chunk every frame when the GPU has no memory for them.

use indicatif::ProgressBar;

use super::error::ResidentError;
use crate::Rendered;
use crate::raster::{RasterError, Rasterizer, UploadedScene};
use crate::render::{ColorRule, RenderSettings};
use crate::scene::Scene;

/// The rasterizer and where the scene's points are.
pub(super) struct OnGpu {
    rasterizer: Rasterizer,
    points: Points,
}

/// Where the scene's points are for the rasterizer.
enum Points {
    /// On the GPU, relative to the anchor they were uploaded for.
    Uploaded(UploadedScene),
    /// In host memory, drawn through one reused GPU chunk every frame: the fallback when
    /// uploading them whole runs the GPU out of memory.
    Streamed {
        /// Colours fixed for the whole scene.
        color: ColorRule,
        /// Why the scene is not resident on the GPU.
        reason: String,
    },
    /// Nowhere: released, or their upload failed; placing them uploads them again.
    Released,
}

impl OnGpu {
    /// `scene` uploaded by `rasterizer` relative to `settings.camera.center`, or streamed
    /// when the GPU has no memory for it.
    pub(super) fn upload(
        rasterizer: Rasterizer,
        scene: &Scene,
        settings: &RenderSettings,
    ) -> Result<Self, ResidentError> {
        let mut on_gpu = OnGpu {
            rasterizer,
            points: Points::Released,
        };
        on_gpu.place(scene, settings)?;
        Ok(on_gpu)
    }

    /// `scene` kept in host memory and streamed through `rasterizer` every frame, coloured
    /// as `settings` asks; `reason` says why.
    pub(super) fn streamed(
        rasterizer: Rasterizer,
        scene: &Scene,
        settings: &RenderSettings,
        reason: String,
    ) -> Result<Self, ResidentError> {
        Ok(OnGpu {
            rasterizer,
            points: Points::Streamed {
                color: ColorRule::for_scene(scene, settings.color)?,
                reason,
            },
        })
    }

    /// Uploads `scene` again relative to `settings.camera.center`, keeping the rasterizer;
    /// the old upload is freed first. Streamed points stay streamed (they are placed every
    /// frame). On failure the points are left [`Points::Released`].
    pub(super) fn place(
        &mut self,
        scene: &Scene,
        settings: &RenderSettings,
    ) -> Result<(), ResidentError> {
        if self.is_streamed() {
            return Ok(());
        }
        // Free the old upload before the new one claims GPU memory.
        self.points = Points::Released;
        self.points = match self.rasterizer.upload(scene, settings) {
            Ok(uploaded) => Points::Uploaded(uploaded),
            Err(e @ RasterError::OutOfMemory { .. }) => Points::Streamed {
                color: ColorRule::for_scene(scene, settings.color)?,
                reason: e.to_string(),
            },
            Err(e) => return Err(e.into()),
        };
        Ok(())
    }

    /// Frees the points' upload; [`place`](Self::place) uploads them again.
    pub(super) fn release(&mut self) {
        if let Points::Uploaded(_) = self.points {
            self.points = Points::Released;
        }
    }

    /// True unless the points were released (streamed points are always placed).
    pub(super) fn is_placed(&self) -> bool {
        !matches!(self.points, Points::Released)
    }

    /// True when the points are drawn from host memory every frame.
    pub(super) fn is_streamed(&self) -> bool {
        matches!(self.points, Points::Streamed { .. })
    }

    /// The rasterizer.
    pub(super) fn rasterizer(&self) -> &Rasterizer {
        &self.rasterizer
    }

    /// What renders, for messages.
    pub(super) fn describe(&self, scene: &Scene) -> String {
        let adapter = self.rasterizer.adapter_name();
        match &self.points {
            Points::Uploaded(uploaded) => {
                format!("{} points resident on the GPU ({adapter})", uploaded.len())
            }
            Points::Streamed { reason, .. } => format!(
                "warning: {} points streamed through the GPU every frame, slower than resident \
                 ({adapter}; {reason})",
                scene.len(),
            ),
            Points::Released => format!("no points on the GPU ({adapter})"),
        }
    }

    /// Renders one frame of `scene`.
    pub(super) fn render(
        &self,
        scene: &Scene,
        settings: &RenderSettings,
        progress: &ProgressBar,
    ) -> Result<Rendered, ResidentError> {
        match &self.points {
            Points::Uploaded(uploaded) => Ok(self
                .rasterizer
                .render_uploaded(uploaded, settings, progress)?
                .0),
            Points::Streamed { color, .. } => {
                let chunk = crate::stream::DEFAULT_CHUNK_POINTS.min(scene.len().max(1)) as u32;
                let mut frame = self.rasterizer.begin_chunked(settings, *color, chunk)?;
                frame.draw(scene)?;
                Ok(frame.finish()?.0)
            }
            Points::Released => Err(ResidentError::NotPlaced),
        }
    }
}
