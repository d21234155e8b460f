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
    /// every frame; the camera may move).
    pub fn new(
        scene: &'s Scene,
        kind: RendererKind,
        settings: &RenderSettings,
    ) -> Result<Self, ResidentError> {
        match kind {
            RendererKind::Raytrace => Ok(Resident::Raytrace {
                tracer: Tracer::new(scene)?,
                scene,
            }),
            #[cfg(feature = "gpu")]
            RendererKind::Raster => {
                let rasterizer = Box::new(crate::raster::Rasterizer::new()?);
                let at_zero = RenderSettings {
                    camera: crate::projection::Camera::new(glam::DVec3::ZERO, 0.0),
                    ..*settings
                };
                let uploaded = rasterizer.upload(scene, &at_zero)?;
                Ok(Resident::Raster {
                    rasterizer,
                    uploaded,
                })
            }
            #[cfg(not(feature = "gpu"))]
            RendererKind::Raster => {
                let _ = settings;
                Err(ResidentError::NoRasterizer)
            }
        }
    }

    /// What renders, for messages: the GPU adapter's name, or the BVH's size.
    pub fn describe(&self) -> String {
        match self {
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
            Resident::Raytrace { tracer, scene } => Ok(raytrace::render_with_tracer(
                tracer, scene, settings, progress,
            )?),
        }
    }
}
