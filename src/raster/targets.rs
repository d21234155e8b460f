//! One eye's render targets and their read-back into a [`Frame`].

use rayon::prelude::*;

use crate::frame::Frame;

use super::context::GpuContext;
use super::error::RasterError;
use super::formats::{COLOR_FORMAT, DEPTH_FORMAT, DISTANCE_FORMAT};
use super::read_back::ReadBack;

/// The colour attachments every pipeline drawing into [`EyeTargets`] writes: colour, then
/// distance.
pub const COLOR_TARGETS: [Option<wgpu::ColorTargetState>; 2] = [
    Some(wgpu::ColorTargetState {
        format: COLOR_FORMAT,
        blend: None,
        write_mask: wgpu::ColorWrites::ALL,
    }),
    Some(wgpu::ColorTargetState {
        format: DISTANCE_FORMAT,
        blend: None,
        write_mask: wgpu::ColorWrites::ALL,
    }),
];

/// The one attachment of a keyed draw ([`super::key_targets`]): a pass needs one to
/// rasterize, but its fragments write keys, not colour.
pub const KEYED_TARGETS: [Option<wgpu::ColorTargetState>; 1] = [Some(wgpu::ColorTargetState {
    format: wgpu::TextureFormat::R8Unorm,
    blend: None,
    write_mask: wgpu::ColorWrites::empty(),
})];

/// Nearest fragment wins; every pipeline drawing into [`EyeTargets`] writes the logarithmic
/// depth it tests.
pub fn depth_test() -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::Less),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// Colour, distance and depth-test textures of one eye.
pub struct EyeTargets {
    width: u32,
    height: u32,
    color: wgpu::Texture,
    distance: wgpu::Texture,
    depth: wgpu::Texture,
    /// View of the colour texture.
    pub color_view: wgpu::TextureView,
    /// View of the distance texture.
    pub distance_view: wgpu::TextureView,
    /// View of the depth texture.
    pub depth_view: wgpu::TextureView,
    /// Colour and distance read-back buffers, kept between reads of a reused frame.
    readback: Option<(wgpu::Buffer, wgpu::Buffer)>,
}

/// Refuses a `width x height` image the adapter's textures cannot hold.
pub fn check_size(ctx: &GpuContext, width: u32, height: u32) -> Result<(), RasterError> {
    let max = ctx.limits.max_texture_dimension_2d;
    if width > max || height > max {
        return Err(RasterError::Limit {
            what: format!("a {width}x{height} image"),
            needed: width.max(height) as u64,
            limit: max as u64,
        });
    }
    Ok(())
}

/// A 2D texture of one eye's `(width, height)`.
pub fn eye_texture(
    ctx: &GpuContext,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

fn padded_row(width: u32) -> u32 {
    (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT
}

impl EyeTargets {
    /// Allocates the textures for a `width x height` eye.
    pub fn new(ctx: &GpuContext, width: u32, height: u32) -> Result<Self, RasterError> {
        check_size(ctx, width, height)?;
        ctx.scoped("allocating render targets", || {
            let make =
                |label, format, usage| eye_texture(ctx, label, (width, height), format, usage);
            let rt = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
            let color = make("color", COLOR_FORMAT, rt);
            let distance = make("distance", DISTANCE_FORMAT, rt);
            let depth = make(
                "depth",
                DEPTH_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            );
            EyeTargets {
                width,
                height,
                color_view: color.create_view(&Default::default()),
                distance_view: distance.create_view(&Default::default()),
                depth_view: depth.create_view(&Default::default()),
                color,
                distance,
                depth,
                readback: None,
            }
        })
    }

    /// Records a pass that clears all three targets to background.
    pub fn clear(&self, encoder: &mut wgpu::CommandEncoder) {
        let _ = &self.depth;
        drop(self.begin_pass(encoder, true, None));
    }

    /// Begins a render pass into these targets, clearing them first when `clear`.
    pub fn begin_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        clear: bool,
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) -> wgpu::RenderPass<'e> {
        let color_load = |c| {
            if clear {
                wgpu::LoadOp::Clear(c)
            } else {
                wgpu::LoadOp::Load
            }
        };
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("imposters"),
            color_attachments: &[
                Some(wgpu::RenderPassColorAttachment {
                    view: &self.color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: color_load(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                }),
                Some(wgpu::RenderPassColorAttachment {
                    view: &self.distance_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: color_load(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                }),
            ],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: if clear {
                        wgpu::LoadOp::Clear(1.0)
                    } else {
                        wgpu::LoadOp::Load
                    },
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }

    /// New colour and distance read-back buffers of `size` bytes.
    fn readback_buffers(
        &self,
        ctx: &GpuContext,
        size: u64,
    ) -> Result<(wgpu::Buffer, wgpu::Buffer), RasterError> {
        ctx.scoped("allocating read-back buffers", || {
            let make = |label| {
                ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size,
                    usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                    mapped_at_creation: false,
                })
            };
            (make("color read-back"), make("distance read-back"))
        })
    }

    /// Copies the textures into `(color_buf, dist_buf)` and converts them into a [`Frame`]
    /// (`reuse`'s memory, when it has the size).
    fn read_into(
        &self,
        ctx: &GpuContext,
        (color_buf, dist_buf): &(wgpu::Buffer, wgpu::Buffer),
        reuse: Option<Frame>,
    ) -> Result<Frame, RasterError> {
        let (w, h) = (self.width, self.height);
        let row = padded_row(w);
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        for (tex, buf) in [(&self.color, color_buf), (&self.distance, dist_buf)] {
            encoder.copy_texture_to_buffer(
                tex.as_image_copy(),
                wgpu::TexelCopyBufferInfo {
                    buffer: buf,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(row),
                        rows_per_image: Some(h),
                    },
                },
                wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
            );
        }
        ctx.queue.submit([encoder.finish()]);
        // Straight from the mapped buffers into the frame, row by row on every core: no
        // intermediate copy of the image.
        map_read_with(ctx, color_buf, "reading back colour", |color| {
            map_read_with(ctx, dist_buf, "reading back distances", |dist| {
                let mut frame = match reuse {
                    Some(f) if (f.width, f.height) == (w, h) => f,
                    _ => Frame::new(w, h),
                };
                let (w, row) = (w as usize, row as usize);
                frame
                    .color
                    .par_chunks_mut(w)
                    .zip(frame.depth.par_chunks_mut(w))
                    .zip(color.par_chunks(row).zip(dist.par_chunks(row)))
                    .for_each(|((out_c, out_d), (c_row, d_row))| {
                        let texels = c_row.chunks_exact(4).zip(d_row.chunks_exact(4));
                        for ((oc, od), (c, d)) in out_c.iter_mut().zip(out_d).zip(texels) {
                            (*oc, *od) = if c[3] != 0 {
                                (
                                    [c[0], c[1], c[2], 255],
                                    f32::from_le_bytes([d[0], d[1], d[2], d[3]]),
                                )
                            } else {
                                ([0; 4], f32::INFINITY)
                            };
                        }
                    });
                frame
            })
        })?
    }
}

impl ReadBack for EyeTargets {
    fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Copies the colour and distance textures back and converts them.
    fn read(
        &mut self,
        ctx: &GpuContext,
        keep: bool,
        reuse: Option<Frame>,
    ) -> Result<Frame, RasterError> {
        let (w, h) = (self.width, self.height);
        let row = padded_row(w);
        let size = row as u64 * h as u64;
        let buffers = match self.readback.take() {
            Some(b) => b,
            None => self.readback_buffers(ctx, size)?,
        };
        let frame = self.read_into(ctx, &buffers, reuse);
        if keep {
            self.readback = Some(buffers);
        }
        frame
    }
}

/// Maps `buffer` for reading, waits, and copies its bytes out.
pub fn map_read(
    ctx: &GpuContext,
    buffer: &wgpu::Buffer,
    what: &str,
) -> Result<Vec<u8>, RasterError> {
    map_read_with(ctx, buffer, what, <[u8]>::to_vec)
}

/// Maps `buffer` for reading, waits, and returns what `f` makes of its bytes.
pub fn map_read_with<T>(
    ctx: &GpuContext,
    buffer: &wgpu::Buffer,
    what: &str,
    f: impl FnOnce(&[u8]) -> T,
) -> Result<T, RasterError> {
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = tx.send(r);
    });
    ctx.wait(what)?;
    let gpu_err = |message: String| RasterError::Gpu {
        while_doing: what.to_string(),
        message,
    };
    rx.recv()
        .map_err(|e| gpu_err(e.to_string()))?
        .map_err(|e| gpu_err(e.to_string()))?;
    let out = f(&buffer
        .get_mapped_range(..)
        .map_err(|e| gpu_err(e.to_string()))?);
    buffer.unmap();
    Ok(out)
}
