//! One eye's image on the keyed path ([`super::splat`]): a key per pixel, which the splat and
//! the keyed draws write and which holds the pixel's distance and colour, and the attachment
//! the keyed draws rasterize into.

use rayon::prelude::*;

use crate::frame::Frame;

use super::context::GpuContext;
use super::error::RasterError;
use super::read_back::ReadBack;
use super::sizing::key_bytes;
use super::splat::{key_buffer, tile_bytes};
use super::targets::{KEYED_TARGETS, check_size, eye_texture, map_read_with};

/// The keys of one eye, row by row: `!distance bits << 32 | RGBA8` once shaded, 0 where
/// nothing shows (`shaders/splat_key.wgsl`).
pub struct KeyedTargets {
    width: u32,
    height: u32,
    /// The keys.
    pub keys: wgpu::Buffer,
    /// The occlusion tiles (`shaders/occlusion.wgsl`).
    pub tiles: wgpu::Buffer,
    /// Their read-back buffer, kept between reads of a reused frame.
    readback: Option<wgpu::Buffer>,
}

impl KeyedTargets {
    /// Allocates the keys and occlusion tiles of a `width x height` eye.
    pub fn new(ctx: &GpuContext, width: u32, height: u32) -> Result<Self, RasterError> {
        ctx.scoped("allocating splat keys", || KeyedTargets {
            width,
            height,
            keys: key_buffer(&ctx.device, "splat keys", key_bytes(width, height)),
            tiles: key_buffer(&ctx.device, "occlusion tiles", tile_bytes(width, height)),
            readback: None,
        })
    }

    /// Records the clear of the image to nothing shown.
    pub fn clear(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.clear_buffer(&self.keys, 0, None);
        encoder.clear_buffer(&self.tiles, 0, None);
    }
}

impl ReadBack for KeyedTargets {
    fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Copies the keys back and decodes them.
    fn read(
        &mut self,
        ctx: &GpuContext,
        keep: bool,
        reuse: Option<Frame>,
    ) -> Result<Frame, RasterError> {
        let readback = match self.readback.take() {
            Some(b) => b,
            None => ctx.scoped("allocating the read-back buffer", || {
                ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("key read-back"),
                    size: self.keys.size(),
                    usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                    mapped_at_creation: false,
                })
            })?,
        };
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&self.keys, 0, &readback, 0, None);
        ctx.queue.submit([encoder.finish()]);
        let (w, h) = (self.width, self.height);
        let frame = map_read_with(ctx, &readback, "reading back the image", |keys| {
            // Straight from the mapped keys into the frame, on every core; into a handed-back
            // frame's memory when there is one, since fresh pages cost more than the decode.
            let n = keys.len() / 8;
            let (mut color, mut depth) = match reuse {
                Some(f) if (f.width, f.height) == (w, h) => (f.color, f.depth),
                _ => (vec![[0u8; 4]; n], vec![0f32; n]),
            };
            color
                .par_chunks_mut(DECODE_CHUNK)
                .zip(depth.par_chunks_mut(DECODE_CHUNK))
                .zip(keys.par_chunks(DECODE_CHUNK * 8))
                .for_each(|((color, depth), keys)| {
                    for ((c, d), key) in color.iter_mut().zip(depth).zip(keys.chunks_exact(8)) {
                        let key = u64::from_le_bytes(key.try_into().expect("8 bytes"));
                        (*c, *d) = decode_key(key).unwrap_or(([0; 4], f32::INFINITY));
                    }
                });
            Frame {
                width: w,
                height: h,
                color,
                depth,
            }
        });
        if keep {
            self.readback = Some(readback);
        }
        frame
    }
}

/// Pixels a task of the read-back's decode takes.
const DECODE_CHUNK: usize = 1 << 16;

/// The colour and distance a key holds (`shaders/splat_key.wgsl`); `None` for no hit.
fn decode_key(key: u64) -> Option<([u8; 4], f32)> {
    (key != 0).then(|| {
        let [r, g, b, _] = (key as u32).to_le_bytes();
        ([r, g, b, 255], f32::from_bits(!((key >> 32) as u32)))
    })
}

/// What a keyed draw rasterizes into: one attachment of the image's size that no fragment
/// writes (its fragments keep keys instead), shared by the eyes of a frame.
pub struct KeyedAttachment {
    _texture: wgpu::Texture,
    view: wgpu::TextureView,
}

impl KeyedAttachment {
    /// Allocates the attachment of a `width x height` eye.
    pub fn new(ctx: &GpuContext, width: u32, height: u32) -> Result<Self, RasterError> {
        check_size(ctx, width, height)?;
        let format = KEYED_TARGETS[0].as_ref().expect("one target").format;
        ctx.scoped("allocating the draw attachment", || {
            let usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
            let texture = eye_texture(ctx, "keyed draw attachment", (width, height), format, usage);
            let view = texture.create_view(&Default::default());
            KeyedAttachment {
                _texture: texture,
                view,
            }
        })
    }

    /// Begins a render pass of keyed draws.
    pub fn begin_pass<'e>(&self, encoder: &'e mut wgpu::CommandEncoder) -> wgpu::RenderPass<'e> {
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("keyed imposters"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Discard,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_decode_as_the_shaders_encode_them() {
        assert_eq!(decode_key(0), None);
        // hit_key(2.5, (10, 20, 30, 255) / 255)
        let key = ((!2.5f32.to_bits() as u64) << 32) | u32::from_le_bytes([10, 20, 30, 255]) as u64;
        assert_eq!(decode_key(key), Some(([10, 20, 30, 255], 2.5)));
        // The nearer hit has the larger key.
        let far = ((!3.0f32.to_bits() as u64) << 32) | 0xff00_0000;
        assert!(key > far);
    }
}
