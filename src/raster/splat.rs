//! The keyed path, taken where the device has 64-bit atomics: small spheres are ray cast by
//! the expand pass (`shaders/splat.wgsl`), and the fragments of drawn ones by the keyed
//! fragment stage (`shaders/imposter_key.wgsl`), into one key per pixel holding the nearest
//! hit's distance and its colour (unlit) or point (lit, shaded by [`super::splat_shade`];
//! `shaders/splat_key.wgsl`), which is the image ([`super::key_targets`]). Without 64-bit atomics the expand pass splats nothing
//! (`splat_off.wgsl`) and every sphere is drawn into render targets.

/// `shaders/splat_key.wgsl`: the per-pixel key.
pub const SPLAT_KEY: &str = include_str!("../../shaders/splat_key.wgsl");
/// `shaders/splat.wgsl`: the splat (64-bit atomics).
const SPLAT: &str = include_str!("../../shaders/splat.wgsl");
/// `shaders/splat_off.wgsl`: its stand-in without 64-bit atomics.
const SPLAT_OFF: &str = include_str!("../../shaders/splat_off.wgsl");

/// Default largest sphere the compute splat ray casts, in pixels per side of its bounds;
/// larger ones are drawn.
pub const DEFAULT_SPLAT_LIMIT: u32 = 16;

/// The expand module's splat part: the key and the splat when the device has 64-bit atomics,
/// else a stand-in that splats nothing.
pub fn expand_part(int64_atomics: bool) -> String {
    if int64_atomics {
        [SPLAT_KEY, SPLAT].join("\n")
    } else {
        SPLAT_OFF.to_string()
    }
}

/// Allocates a key buffer of `bytes` (one `u64` per pixel of one eye).
pub fn key_buffer(device: &wgpu::Device, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("splat keys"),
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}
