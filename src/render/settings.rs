//! Render settings shared by the ray tracer and the rasterizer.

use crate::projection::{Camera, Equirect, Stereo, View};

use super::color::ColorMode;
use super::shading::Shading;

/// Which renderer draws the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RendererKind {
    /// GPU imposter-sphere rasterizer (wgpu).
    #[default]
    Raster,
    /// CPU ray tracer (the accuracy reference).
    Raytrace,
}

/// Rasterizer proxy geometry per sphere (DESIGN §7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Proxy {
    /// Projected billboard corners, no tessellation.
    Quad,
    /// An N x N tessellated billboard.
    Static(u32),
    /// Tessellation per imposter from its projected size and latitude.
    Dynamic,
    /// The analytic bounding rectangle of the sphere's projection.
    #[default]
    Bounds,
}

/// Rasterizer fragment model (DESIGN §7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Imposter {
    /// Shaded from interpolated billboard coordinates, as in the paper.
    Sprite,
    /// Exact per-pixel ODS ray / sphere intersection.
    #[default]
    Raycast,
}

/// Everything a renderer needs besides the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    /// Image size per eye.
    pub image: Equirect,
    /// Camera in the scene's local frame.
    pub camera: Camera,
    /// Mono or ODS.
    pub stereo: Stereo,
    /// Base colour per point.
    pub color: ColorMode,
    /// Shading model.
    pub shading: Shading,
    /// Rasterizer proxy (ignored by the ray tracer).
    pub proxy: Proxy,
    /// Rasterizer fragment model (ignored by the ray tracer).
    pub imposter: Imposter,
}

impl RenderSettings {
    /// Mono, unlit, flat-coloured settings at `width`, camera at `camera`: the accuracy setup.
    pub fn new(width: u32, camera: Camera) -> Self {
        RenderSettings {
            image: Equirect::from_width(width),
            camera,
            stereo: Stereo::Mono,
            color: ColorMode::Flat,
            shading: Shading::Unlit,
            proxy: Proxy::default(),
            imposter: Imposter::default(),
        }
    }

    /// The views to render, left eye first.
    pub fn views(&self) -> Vec<View> {
        self.stereo.views(self.camera)
    }
}
