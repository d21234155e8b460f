//! A scan held resident for many camera positions: on the GPU for the rasterizer (uploaded
//! once, relative to the scene's local zero), or as the ray tracer's BVH. `omnicloud render
//! --origin` renders through this same path, so a tour's frame and the single render of its
//! pose are the same computation.

use indicatif::ProgressBar;

use crate::Rendered;
use crate::raytrace::{self, RaytraceError, Tracer};
use crate::render::{RenderSettings, RendererKind};
use crate::scene::Scene;

/// Why a resident scene could not be built or rendered.
#[derive(Debug, thiserror::Error)]
pub enum ResidentError {
    /// The ray tracer failed.
    #[error(transparent)]
    Raytrace(#[from] RaytraceError),
    /// The rasterizer failed (no adapter, or the scan does not fit the GPU).
    #[cfg(feature = "gpu")]
    #[error(transparent)]
    Raster(#[from] crate::raster::RasterError),
    /// The colour mode needs an attribute the scene lacks.
    #[error(transparent)]
    Color(#[from] crate::render::color::MissingAttribute),
    /// This build has no rasterizer.
    #[error("this build has no GPU rasterizer (feature `gpu`); use --renderer raytrace")]
    NoRasterizer,
}

/// The renderer with its scene resident.
pub enum Resident<'s> {
    /// Points and colours on the GPU.
    #[cfg(feature = "gpu")]
    Raster {
        /// The device and pipelines (boxed: far larger than the other variant).
        rasterizer: Box<crate::raster::Rasterizer>,
        /// The scene, uploaded relative to its local zero.
        uploaded: crate::raster::UploadedScene,
    },
    /// The scene stays in host memory and is drawn through one reused GPU chunk every frame:
    /// the fallback when uploading it whole runs the GPU out of memory.
    #[cfg(feature = "gpu")]
    Streamed {
        /// The device and pipelines.
        rasterizer: Box<crate::raster::Rasterizer>,
        /// The scene, relative to its local zero.
        scene: &'s Scene,
        /// Colours fixed for the whole scene.
        color: crate::render::ColorRule,
        /// Why the scene is not resident on the GPU.
        reason: String,
    },
    /// The BVH over the scene's spheres.
    Raytrace {
        /// The BVH.
        tracer: Tracer,
        /// The scene it was built over.
        scene: &'s Scene,
    },
}

impl<'s> Resident<'s> {
    /// Makes `scene` resident for `kind` under `settings` (its colour mode is fixed for
    /// every frame; the camera may move). A scene the GPU has no memory for is kept in host
    /// memory and streamed through the GPU every frame instead ([`Resident::Streamed`]).
    pub fn new(
        scene: &'s Scene,
        kind: RendererKind,
        settings: &RenderSettings,
    ) -> Result<Self, ResidentError> {
        match kind {
            RendererKind::Raytrace => Ok(Resident::Raytrace {
                tracer: Tracer::padded(scene, raytrace::padding_for(settings))?,
                scene,
            }),
            #[cfg(feature = "gpu")]
            RendererKind::Raster => {
                let rasterizer = Box::new(crate::raster::Rasterizer::new()?);
                let at_zero = RenderSettings {
                    camera: crate::projection::Camera::new(glam::DVec3::ZERO, 0.0),
                    ..*settings
                };
                match rasterizer.upload(scene, &at_zero) {
                    Ok(uploaded) => Ok(Resident::Raster {
                        rasterizer,
                        uploaded,
                    }),
                    Err(e @ crate::raster::RasterError::OutOfMemory { .. }) => {
                        Resident::streamed(rasterizer, scene, settings, e.to_string())
                    }
                    Err(e) => Err(e.into()),
                }
            }
            #[cfg(not(feature = "gpu"))]
            RendererKind::Raster => {
                let _ = settings;
                Err(ResidentError::NoRasterizer)
            }
        }
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
        Ok(Resident::Streamed {
            color: crate::render::ColorRule::for_scene(scene, settings.color)?,
            rasterizer,
            scene,
            reason,
        })
    }

    /// True when the scene is drawn from host memory every frame (a warning for the caller).
    pub fn is_streamed(&self) -> bool {
        #[cfg(feature = "gpu")]
        if let Resident::Streamed { .. } = self {
            return true;
        }
        false
    }

    /// What renders, for messages: the GPU adapter's name, or the BVH's size.
    pub fn describe(&self) -> String {
        match self {
            #[cfg(feature = "gpu")]
            Resident::Streamed {
                rasterizer,
                scene,
                reason,
                ..
            } => format!(
                "warning: {} points streamed through the GPU every frame, slower than resident \
                 ({}; {reason})",
                scene.len(),
                rasterizer.adapter_name()
            ),
            #[cfg(feature = "gpu")]
            Resident::Raster {
                rasterizer,
                uploaded,
            } => format!(
                "{} points resident on the GPU ({})",
                uploaded.len(),
                rasterizer.adapter_name()
            ),
            Resident::Raytrace { tracer, .. } => format!(
                "BVH over {} spheres resident ({}, built in {:.2?})",
                tracer.len(),
                crate::memory::format_size(tracer.memory().total() as u64),
                tracer.build_time()
            ),
        }
    }

    /// Hands a frame this resident rendered back once it is written, for the next frame's
    /// read-back to reuse its memory (rasterizers only).
    pub fn recycle(&self, rendered: Rendered) {
        match self {
            #[cfg(feature = "gpu")]
            Resident::Raster { rasterizer, .. } | Resident::Streamed { rasterizer, .. } => {
                rasterizer.recycle(rendered)
            }
            Resident::Raytrace { .. } => drop(rendered),
        }
    }

    /// Renders one frame; `settings.camera.center` is in the scene's local frame.
    pub fn render(
        &self,
        settings: &RenderSettings,
        progress: &ProgressBar,
    ) -> Result<Rendered, ResidentError> {
        match self {
            #[cfg(feature = "gpu")]
            Resident::Raster {
                rasterizer,
                uploaded,
            } => Ok(rasterizer.render_uploaded(uploaded, settings, progress)?.0),
            #[cfg(feature = "gpu")]
            Resident::Streamed {
                rasterizer,
                scene,
                color,
                ..
            } => {
                let chunk = crate::stream::DEFAULT_CHUNK_POINTS.min(scene.len().max(1)) as u32;
                let mut frame = rasterizer.begin_chunked(settings, *color, chunk)?;
                frame.draw(scene)?;
                Ok(frame.finish()?.0)
            }
            Resident::Raytrace { tracer, scene } => Ok(raytrace::render_with_tracer(
                tracer, scene, settings, progress,
            )?),
        }
    }
}
