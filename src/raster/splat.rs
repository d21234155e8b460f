//! The keyed path, taken where the device has 64-bit atomics: small spheres are ray cast by
//! the expand module's splat (`shaders/splat.wgsl`), and the fragments of drawn ones by the
//! keyed fragment stage (`shaders/imposter_key.wgsl`), into one key per pixel holding the
//! nearest hit's distance and its colour (unlit) or point (lit, shaded by
//! [`super::splat_shade`]; `shaders/splat_key.wgsl`), which is the image
//! ([`super::key_targets`]). Without 64-bit atomics every sphere is drawn into render targets.

use super::constants::TILE_SIDE;

/// `shaders/splat_key.wgsl`: the per-pixel key.
pub const SPLAT_KEY: &str = include_str!("../../shaders/splat_key.wgsl");
/// `shaders/splat.wgsl`: the splat (64-bit atomics).
const SPLAT: &str = include_str!("../../shaders/splat.wgsl");
/// `shaders/tiles.wgsl`: the occlusion tiles' buffer.
pub const TILES: &str = include_str!("../../shaders/tiles.wgsl");
/// `shaders/occlusion.wgsl`: the tiles that let hidden spheres be skipped whole.
const OCCLUSION: &str = include_str!("../../shaders/occlusion.wgsl");

/// Default largest sphere the compute splat ray casts, in pixels per side of its bounds;
/// larger ones are drawn.
pub const DEFAULT_SPLAT_LIMIT: u32 = 16;

/// The same for an ODS pair's splat (`expand_splat_pair`), which serves both eyes: a sphere
/// it leaves is drawn once per eye, so it takes larger ones.
pub const DEFAULT_PAIR_SPLAT_LIMIT: u32 = 64;

/// The expand module's splat part: the key and the splat's entry points when the device has
/// 64-bit atomics, else nothing.
pub fn expand_part(int64_atomics: bool) -> String {
    if int64_atomics {
        [SPLAT_KEY, SPLAT, TILES, OCCLUSION].join("\n")
    } else {
        String::new()
    }
}

/// Bytes of the list of points the splat leaves to draw or to cast wide (WGSL
/// `ListedPoints`) for batches of up to `batch_points` points: the two counts, then an index
/// each (the listed from the start, the wide from the end: a point is one or the other).
pub fn listed_bytes(batch_points: u32) -> u64 {
    (2 + batch_points as u64) * size_of::<u32>() as u64
}

/// The two counts of WGSL `ListedPoints`, as they are cleared before each batch.
pub const NO_LISTED: [u32; 2] = [0, 0];

/// The indirect dispatches' arguments after a pair splat (WGSL `ListedGroups`): the listed
/// points' workgroups, then the wide spheres'.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ListedGroups {
    /// `expand_listed`'s workgroups (x, y, z).
    pub listed: [u32; 3],
    /// `splat_wide_pair`'s workgroups (x, y, z).
    pub wide: [u32; 3],
}

/// What [`ListedGroups`] holds before each batch: no workgroups yet, of one row and layer.
pub const NO_GROUPS: ListedGroups = ListedGroups {
    listed: [0, 1, 1],
    wide: [0, 1, 1],
};

/// Byte offset of [`ListedGroups::wide`], the wide spheres' dispatch arguments.
pub const WIDE_GROUPS_OFFSET: u64 = std::mem::offset_of!(ListedGroups, wide) as u64;

/// Bytes of the occlusion tiles of a `width x height` eye (`shaders/occlusion.wgsl`): a `u32`
/// per tile of `TILE_SIDE` pixels a side.
pub fn tile_bytes(width: u32, height: u32) -> u64 {
    tiles_along(width) as u64 * tiles_along(height) as u64 * size_of::<u32>() as u64
}

/// Occlusion tiles along an image side of `pixels` (the last one may be partial).
pub fn tiles_along(pixels: u32) -> u32 {
    pixels.div_ceil(TILE_SIDE)
}

/// Allocates `bytes` of one eye's keyed image, `label`led: its keys (one `u64` per pixel) or
/// its occlusion tiles.
pub fn key_buffer(device: &wgpu::Device, label: &str, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}
