//! The texture formats of an eye's render targets, which the device must support (the
//! distance channel decides which adapters can render at all).

/// Colour target: sRGB bytes stored as they are.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// Distance target: metres along the ray.
pub const DISTANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// Depth-test buffer (logarithmic depth written by the fragment stage).
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
