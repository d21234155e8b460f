//! A frame's GPU memory: each eye's image (keys or render targets) and the expand/draw work
//! buffers. A rasterizer that draws frame after frame of one shape keeps them (see
//! [`Spare`]): fresh buffers cost a page fault and a zero-fill per page on every frame, which
//! on a software adapter took longer than the expand pass.

use std::sync::Mutex;

use crate::frame::Frame;

use super::context::GpuContext;
use super::error::RasterError;
use super::expand::ExpandedVertex;
use super::key_targets::{KeyedAttachment, KeyedTargets};
use super::lock::lock;
use super::params::Params;
use super::read_back::ReadBack;
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
    /// Points per batch.
    pub batch_points: u32,
    /// Whether the images are keyed (see [`super::splat`]) rather than drawn.
    pub keyed: bool,
}

impl FrameShape {
    /// The shape of a frame of `eyes` views of `size` sized by `sizing`.
    pub fn new(size: (u32, u32), eyes: usize, sizing: &FrameSizing) -> Self {
        FrameShape {
            size,
            eyes,
            vertex_capacity: sizing.vertex_capacity,
            batch_points: sizing.batch_points,
            keyed: sizing.splat(),
        }
    }
}

/// The targets and buffers of one frame.
pub struct FrameBuffers {
    /// What they hold.
    pub shape: FrameShape,
    /// Each eye's image (and read-back buffers once read).
    pub images: Images,
    /// On the keyed path, the points the splat leaves to draw and the dispatch that draws
    /// them (see [`super::expand::KeyedBuffers`]).
    pub listed: Option<(wgpu::Buffer, wgpu::Buffer)>,
    /// `Params` buffer.
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
        let images = Images::new(ctx, shape)?;
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
            let listed = shape.keyed.then(|| {
                (
                    make(
                        "listed points",
                        splat::listed_bytes(shape.batch_points) as usize,
                        U::STORAGE | U::COPY_DST,
                    ),
                    make(
                        "listed points' dispatch",
                        size_of::<splat::ListedGroups>(),
                        U::STORAGE | U::INDIRECT | U::COPY_DST,
                    ),
                )
            });
            FrameBuffers {
                shape,
                images,
                listed,
                params: make("params", size_of::<Params>(), U::STORAGE | U::COPY_DST),
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

/// Each eye's image: render targets that the imposters are drawn and shaded into, or on the
/// keyed path the keys that the splat and the keyed draws write.
pub enum Images {
    /// Drawn and shaded into render targets.
    Drawn(Vec<EyeTargets>),
    /// Keys.
    Keyed {
        /// Each eye's image.
        eyes: Vec<KeyedTargets>,
        /// What the keyed draws of every eye rasterize into.
        attachment: KeyedAttachment,
    },
}

impl Images {
    /// Allocates the images of `shape`.
    fn new(ctx: &GpuContext, shape: FrameShape) -> Result<Self, RasterError> {
        let (w, h) = shape.size;
        Ok(if shape.keyed {
            Images::Keyed {
                eyes: (0..shape.eyes)
                    .map(|_| KeyedTargets::new(ctx, w, h))
                    .collect::<Result<_, _>>()?,
                attachment: KeyedAttachment::new(ctx, w, h)?,
            }
        } else {
            Images::Drawn(
                (0..shape.eyes)
                    .map(|_| EyeTargets::new(ctx, w, h))
                    .collect::<Result<_, _>>()?,
            )
        })
    }

    /// The keys (and occlusion tiles) of eye `eye` on the keyed path.
    pub fn keys(&self, eye: usize) -> Option<&KeyedTargets> {
        match self {
            Images::Drawn(_) => None,
            Images::Keyed { eyes, .. } => Some(&eyes[eye]),
        }
    }

    /// Begins the render pass that draws eye `eye`'s proxies.
    pub fn begin_draw<'e>(
        &self,
        eye: usize,
        encoder: &'e mut wgpu::CommandEncoder,
    ) -> wgpu::RenderPass<'e> {
        match self {
            Images::Drawn(eyes) => eyes[eye].begin_pass(encoder, false, None),
            Images::Keyed { attachment, .. } => attachment.begin_pass(encoder),
        }
    }

    /// Records the clear of every eye's image.
    pub fn clear(&self, encoder: &mut wgpu::CommandEncoder) {
        match self {
            Images::Drawn(eyes) => eyes.iter().for_each(|t| t.clear(encoder)),
            Images::Keyed { eyes, .. } => eyes.iter().for_each(|t| t.clear(encoder)),
        }
    }

    /// Reads every eye back, keeping the read-back buffers for the next frame; each eye is
    /// decoded into a frame taken from `spare` where it holds one of the eye's size.
    pub fn read_kept(
        &mut self,
        ctx: &GpuContext,
        spare: &Mutex<Spare>,
    ) -> Result<Vec<Frame>, RasterError> {
        let reuse = |(w, h)| Spare::take_frame(spare, w, h);
        match self {
            Images::Drawn(eyes) => read_each(eyes, ctx, reuse),
            Images::Keyed { eyes, .. } => read_each(eyes, ctx, reuse),
        }
    }

    /// Reads every eye back, freeing each eye's memory as soon as it is read: the peak while
    /// reading stays near one eye's read-back.
    pub fn read_freed(self, ctx: &GpuContext) -> Result<Vec<Frame>, RasterError> {
        // Each eye is dropped as soon as it is read.
        match self {
            Images::Drawn(eyes) => eyes
                .into_iter()
                .map(|mut t| t.read(ctx, false, None))
                .collect(),
            Images::Keyed { eyes, attachment } => {
                drop(attachment);
                eyes.into_iter()
                    .map(|mut t| t.read(ctx, false, None))
                    .collect()
            }
        }
    }
}

/// Reads `eyes` back in order, keeping their read-back buffers, each into the frame `reuse`
/// gives for its size, if any.
fn read_each<E: ReadBack>(
    eyes: &mut [E],
    ctx: &GpuContext,
    reuse: impl Fn((u32, u32)) -> Option<Frame>,
) -> Result<Vec<Frame>, RasterError> {
    eyes.iter_mut()
        .map(|t| t.read(ctx, true, reuse(t.size())))
        .collect()
}

/// The buffers of the last finished frames, kept for the next frame of the same shape once a
/// rasterizer has begun a second frame (a single render frees its buffers as it reads back,
/// which keeps its peak memory at one eye's read-back). One shape is kept unless a caller
/// that alternates shapes (a benchmark timing stereo against mono) asks for more.
pub struct Spare {
    frames_begun: u64,
    /// Buffer sets allocated so far.
    allocated: u64,
    /// Most recently finished last.
    kept: Vec<FrameBuffers>,
    /// Most shapes kept at once.
    shapes: usize,
    /// Frames handed back by the caller ([`super::Rasterizer::recycle`]): a frame read back
    /// into one of these fills memory already paged in instead of fresh pages (whose first
    /// writes cost as much as the decode at 3840x1920 on a CPU adapter).
    frames: Vec<Frame>,
}

impl Default for Spare {
    fn default() -> Self {
        Spare {
            frames_begun: 0,
            allocated: 0,
            kept: Vec::new(),
            shapes: 1,
            frames: Vec::new(),
        }
    }
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
            let mut s = lock(spare);
            s.frames_begun += 1;
            let found = s.kept.iter().position(|b| b.shape == shape);
            let kept = match found {
                Some(i) => Some(s.kept.remove(i)),
                None => {
                    s.allocated += 1;
                    // Sets of other shapes beyond the allowance are freed before the new one
                    // is allocated.
                    let room = s.shapes - 1;
                    s.keep_at_most(room);
                    None
                }
            };
            (kept, s.frames_begun > 1)
        };
        let buffers = match kept {
            Some(b) => b,
            None => FrameBuffers::new(ctx, shape)?,
        };
        Ok((buffers, keep))
    }

    /// Keeps `buffers` for the next frame of their shape, freeing the oldest kept set beyond
    /// the allowance.
    pub fn put(spare: &Mutex<Spare>, buffers: FrameBuffers) {
        let mut s = lock(spare);
        s.kept.push(buffers);
        let shapes = s.shapes;
        s.keep_at_most(shapes);
    }

    /// Buffer sets allocated so far.
    pub fn allocated(spare: &Mutex<Spare>) -> u64 {
        lock(spare).allocated
    }

    /// Keeps the buffers of up to `shapes` frame shapes (at least one); returns the previous
    /// allowance.
    pub fn set_shapes(spare: &Mutex<Spare>, shapes: usize) -> usize {
        let mut s = lock(spare);
        let previous = s.shapes;
        let shapes = shapes.max(1);
        s.shapes = shapes;
        s.keep_at_most(shapes);
        previous
    }

    /// Keeps `frames` for the next read-backs, up to [`MAX_EYES`] per kept shape.
    pub fn recycle(spare: &Mutex<Spare>, frames: impl IntoIterator<Item = Frame>) {
        let mut s = lock(spare);
        s.frames.extend(frames);
        let excess = s.frames.len().saturating_sub(MAX_EYES * s.shapes);
        s.frames.drain(..excess);
    }

    /// A handed-back frame of `width x height`, if one is kept.
    pub fn take_frame(spare: &Mutex<Spare>, width: u32, height: u32) -> Option<Frame> {
        let mut s = lock(spare);
        let i = s
            .frames
            .iter()
            .rposition(|f| (f.width, f.height) == (width, height))?;
        Some(s.frames.swap_remove(i))
    }

    /// Frees the oldest kept sets beyond the `n` most recent.
    fn keep_at_most(&mut self, n: usize) {
        let excess = self.kept.len().saturating_sub(n);
        self.kept.drain(..excess);
    }
}
