//! A frame's GPU memory: each eye's targets, the splat keys and the expand/draw work
//! buffers. A rasterizer that draws frame after frame of one shape keeps them (see
//! [`Spare`]): fresh buffers cost a page fault and a zero-fill per page on every frame, which
//! on a software adapter took longer than the expand pass.

use std::sync::Mutex;

use super::context::GpuContext;
use super::error::RasterError;
use super::expand::ExpandedVertex;
use super::params::Params;
use super::sizing::FrameSizing;
use super::splat;
use super::stats::EyeStats;
use super::targets::EyeTargets;

/// Eyes a frame can have (ODS: left and right).
pub const MAX_EYES: usize = 2;

/// What a frame's buffers must hold: frames of equal shape can share them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameShape {
    /// Image width and height, pixels.
    pub size: (u32, u32),
    /// Views drawn.
    pub eyes: usize,
    /// Vertices per batch.
    pub vertex_capacity: u32,
    /// Bytes of the splat key buffer.
    pub splat_key_bytes: u64,
}

impl FrameShape {
    /// The shape of a frame of `eyes` views of `size` sized by `sizing`.
    pub fn new(size: (u32, u32), eyes: usize, sizing: &FrameSizing) -> Self {
        FrameShape {
            size,
            eyes,
            vertex_capacity: sizing.vertex_capacity,
            splat_key_bytes: sizing.splat_key_bytes,
        }
    }
}

/// The targets and buffers of one frame.
pub struct FrameBuffers {
    /// What they hold.
    pub shape: FrameShape,
    /// Each eye's targets (and read-back buffers once read).
    pub targets: Vec<EyeTargets>,
    /// One key buffer, eye after eye (zero between eyes); a placeholder when the splat is
    /// off.
    pub splat_keys: wgpu::Buffer,
    /// `Params` uniform.
    pub params: wgpu::Buffer,
    /// Expanded proxy vertices.
    pub vertices: wgpu::Buffer,
    /// Indirect draw arguments.
    pub draw_args: wgpu::Buffer,
    /// Per-eye statistics.
    pub stats: wgpu::Buffer,
}

impl FrameBuffers {
    /// Allocates the buffers of `shape` (zeroed by wgpu before first use).
    pub fn new(ctx: &GpuContext, shape: FrameShape) -> Result<Self, RasterError> {
        let device = &ctx.device;
        let (w, h) = shape.size;
        let targets = (0..shape.eyes)
            .map(|_| EyeTargets::new(ctx, w, h))
            .collect::<Result<Vec<_>, _>>()?;
        let splat_keys = ctx.scoped("allocating splat buffers", || {
            splat::key_buffer(device, shape.splat_key_bytes)
        })?;
        ctx.scoped("allocating work buffers", || {
            let make = |label, size: usize, usage| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: size as u64,
                    usage,
                    mapped_at_creation: false,
                })
            };
            use wgpu::BufferUsages as U;
            FrameBuffers {
                shape,
                targets,
                splat_keys,
                params: make("params", size_of::<Params>(), U::UNIFORM | U::COPY_DST),
                vertices: make(
                    "vertices",
                    shape.vertex_capacity as usize * size_of::<ExpandedVertex>(),
                    U::STORAGE | U::VERTEX,
                ),
                draw_args: make(
                    "draw args",
                    size_of::<wgpu::util::DrawIndirectArgs>(),
                    U::STORAGE | U::INDIRECT | U::COPY_DST,
                ),
                stats: make(
                    "stats",
                    MAX_EYES * size_of::<EyeStats>(),
                    U::STORAGE | U::COPY_SRC | U::COPY_DST,
                ),
            }
        })
    }
}

/// The buffers of the last finished frame, kept for the next frame of the same shape once a
/// rasterizer has begun a second frame (a single render frees its buffers as it reads back,
/// which keeps its peak memory at one eye's read-back).
#[derive(Default)]
pub struct Spare {
    frames_begun: u64,
    kept: Option<FrameBuffers>,
}

impl Spare {
    /// The buffers for a frame of `shape`: the kept ones when they fit, else new ones; and
    /// whether this frame should keep its buffers when it finishes.
    pub fn take(
        spare: &Mutex<Spare>,
        ctx: &GpuContext,
        shape: FrameShape,
    ) -> Result<(FrameBuffers, bool), RasterError> {
        let (kept, keep) = {
            let mut s = spare.lock().unwrap_or_else(|e| e.into_inner());
            s.frames_begun += 1;
            // A kept set of another shape is freed before the new one is allocated.
            (
                s.kept.take().filter(|b| b.shape == shape),
                s.frames_begun > 1,
            )
        };
        let buffers = match kept {
            Some(b) => b,
            None => FrameBuffers::new(ctx, shape)?,
        };
        Ok((buffers, keep))
    }

    /// Keeps `buffers` for the next frame.
    pub fn put(spare: &Mutex<Spare>, buffers: FrameBuffers) {
        spare.lock().unwrap_or_else(|e| e.into_inner()).kept = Some(buffers);
    }
}
