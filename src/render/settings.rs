//! Render settings shared by the ray tracer and the rasterizer.

use std::str::FromStr;

use crate::projection::depth_map::DepthMap;
use crate::projection::{Camera, Image, Stereo, View};
use crate::value::choice;

use super::color::ColorMode;
use super::shading::Shading;

/// Which renderer draws the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
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
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Imposter {
    /// Shaded from interpolated billboard coordinates, as in the paper.
    Sprite,
    /// Exact per-pixel ODS ray / sphere intersection.
    #[default]
    Raycast,
}

/// `raster` or `raytrace`.
impl FromStr for RendererKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        choice(s, "renderer")
    }
}

/// `sprite` or `raycast`.
impl FromStr for Imposter {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        choice(s, "imposter")
    }
}

/// `quad`, `static:N` (N in 1..=64; `static` alone is `static:4`), `dynamic` or `bounds`.
impl FromStr for Proxy {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let s = s.trim().to_ascii_lowercase();
        match s.split_once(':') {
            Some(("static", n)) => {
                let n: u32 = n
                    .parse()
                    .map_err(|_| format!("expected static:N with N a whole number, got `{s}`"))?;
                if (1..=64).contains(&n) {
                    Ok(Proxy::Static(n))
                } else {
                    Err(format!("static:N needs 1 <= N <= 64, got {n}"))
                }
            }
            None if s == "quad" => Ok(Proxy::Quad),
            None if s == "dynamic" => Ok(Proxy::Dynamic),
            None if s == "bounds" => Ok(Proxy::Bounds),
            None if s == "static" => Ok(Proxy::Static(4)),
            _ => Err(format!(
                "unknown proxy `{s}`: use quad, static:N, dynamic or bounds"
            )),
        }
    }
}

/// Everything a renderer needs besides the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    /// Image per eye: projection and size.
    pub image: Image,
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
    /// `--depth-map` (DESIGN §9): each sphere's own ODS radius; ODS only (the other stereo
    /// modes, and identity maps, ignore it).
    pub depth_map: Option<DepthMap>,
}

impl RenderSettings {
    /// Mono, unlit, flat-coloured settings at `width`, camera at `camera`: the accuracy setup.
    pub fn new(width: u32, camera: Camera) -> Self {
        RenderSettings {
            image: Image::equirect(width),
            camera,
            stereo: Stereo::Mono,
            color: ColorMode::Flat,
            shading: Shading::Unlit,
            proxy: Proxy::default(),
            imposter: Imposter::default(),
            depth_map: None,
        }
    }

    /// The views to render, left eye first, with the depth map where it applies.
    pub fn views(&self) -> Vec<View> {
        let mut views = self.stereo.views(self.camera);
        for v in &mut views {
            *v = v.with_depth_map(self.depth_map);
        }
        views
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_enums_parse_by_their_help_names() {
        assert_eq!("raytrace".parse(), Ok(RendererKind::Raytrace));
        assert_eq!(" Sprite".parse(), Ok(Imposter::Sprite));
        assert_eq!("classification".parse(), Ok(ColorMode::Classification));
        let e = "toon".parse::<Shading>().unwrap_err();
        assert!(
            e.contains("unknown shading `toon`: use unlit, phong, normal"),
            "{e}"
        );
    }

    #[test]
    fn proxies_parse_with_their_bounds_checked() {
        assert_eq!("static:16".parse(), Ok(Proxy::Static(16)));
        assert_eq!(" Bounds".parse(), Ok(Proxy::Bounds));
        assert_eq!("static".parse(), Ok(Proxy::Static(4)));
        for bad in ["static:0", "static:65", "static:x", "hull"] {
            assert!(bad.parse::<Proxy>().is_err(), "{bad}");
        }
    }
}
