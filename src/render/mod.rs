//! What every renderer shares: render settings, per-point base colours and the shading model.

pub mod color;
pub mod settings;
pub mod shading;

pub use color::{ColorMode, ColorRule, base_colors};
pub use settings::{Imposter, Proxy, RenderSettings, RendererKind};
pub use shading::Shading;
