//! What every renderer shares: render settings, per-point base colours, the shading model,
//! and the passes on finished frames (eye-dome lighting, supersampling, background).

pub mod background;
pub mod color;
pub mod cubemap_stereo;
pub mod edl;
pub mod hit_points;
pub mod look;
pub mod settings;
pub mod shading;
pub mod supersample;

pub use background::Background;
pub use color::{ColorMode, ColorRule, base_colors};
pub use edl::Edl;
pub use look::{Look, LookError};
pub use settings::{Imposter, Proxy, RenderSettings, RendererKind};
pub use shading::Shading;
