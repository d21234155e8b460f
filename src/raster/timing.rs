//! How long a frame's GPU work took: timestamp queries where the device has them, else the
//! wall clock.

use std::time::Instant;

use super::context::GpuContext;
use super::error::RasterError;
use super::targets::map_read;

/// How a frame time was measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimingSource {
    /// GPU timestamp queries around the work.
    GpuTimestamps,
    /// Wall clock from the first submission to the end of the GPU work.
    WallClock,
}

/// A frame time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameTiming {
    /// Seconds from the frame's clears to the end of its last draw (read-back excluded; for
    /// a streamed frame, the waits for its chunks included).
    pub seconds: f64,
    /// How it was measured.
    pub source: TimingSource,
    /// Wall clock from the frame's first submission to the end of its GPU work, whatever
    /// `source` is: on a software adapter, where the GPU is the CPU, the two agree.
    pub wall_seconds: f64,
}

/// Times one frame: a timestamp before its clears and one after its last draw, and the wall
/// clock from its first submission.
pub(crate) struct FrameClock {
    query: Option<wgpu::QuerySet>,
    started: Instant,
}

/// Records an empty compute pass that only writes `writes`.
fn stamp(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    writes: wgpu::ComputePassTimestampWrites<'_>,
) {
    drop(encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes: Some(writes),
    }));
}

impl FrameClock {
    /// Starts the clock of a frame: records its start stamp (when the device has timestamps)
    /// into `encoder`, ahead of the frame's clears, and starts the wall clock. Call just
    /// before submitting `encoder`.
    pub fn start(ctx: &GpuContext, encoder: &mut wgpu::CommandEncoder) -> Self {
        let query = ctx.timestamps.then(|| {
            ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("frame time"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            })
        });
        if let Some(q) = &query {
            stamp(
                encoder,
                "frame start",
                wgpu::ComputePassTimestampWrites {
                    query_set: q,
                    beginning_of_pass_write_index: Some(0),
                    end_of_pass_write_index: None,
                },
            );
        }
        FrameClock {
            query,
            started: Instant::now(),
        }
    }

    /// Stamps the end of the frame (after `batches` batches), waits for the GPU, and reads the
    /// time.
    pub fn finish(self, ctx: &GpuContext, batches: u64) -> Result<FrameTiming, RasterError> {
        let query = self.query.as_ref().filter(|_| batches > 0);
        if let Some(q) = query {
            // An empty pass after the last draw stamps the end of the frame.
            let mut encoder = ctx.device.create_command_encoder(&Default::default());
            stamp(
                &mut encoder,
                "frame end",
                wgpu::ComputePassTimestampWrites {
                    query_set: q,
                    beginning_of_pass_write_index: None,
                    end_of_pass_write_index: Some(1),
                },
            );
            ctx.queue.submit([encoder.finish()]);
        }
        ctx.wait("drawing imposters")?;
        let wall = self.started.elapsed().as_secs_f64();
        let gpu = match query {
            Some(q) => read_timestamps(ctx, q)?,
            None => None,
        };
        Ok(match gpu {
            Some(seconds) => FrameTiming {
                seconds,
                source: TimingSource::GpuTimestamps,
                wall_seconds: wall,
            },
            None => FrameTiming {
                seconds: wall,
                source: TimingSource::WallClock,
                wall_seconds: wall,
            },
        })
    }
}

/// Seconds between the two timestamps of `query`, or `None` when they make no sense.
fn read_timestamps(ctx: &GpuContext, query: &wgpu::QuerySet) -> Result<Option<f64>, RasterError> {
    let device = &ctx.device;
    let (resolve, read) = ctx.scoped("reading timestamps", || {
        let make = |label, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: 2 * size_of::<u64>() as u64,
                usage,
                mapped_at_creation: false,
            })
        };
        (
            make(
                "timestamps",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            make(
                "timestamps read-back",
                wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            ),
        )
    })?;
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.resolve_query_set(query, 0..2, &resolve, 0);
    encoder.copy_buffer_to_buffer(&resolve, 0, &read, 0, None);
    ctx.queue.submit([encoder.finish()]);
    let raw = map_read(ctx, &read, "reading timestamps")?;
    let t: Vec<u64> = bytemuck::pod_collect_to_vec(&raw);
    let period_ns = ctx.queue.get_timestamp_period() as f64;
    Ok((t[1] > t[0]).then(|| (t[1] - t[0]) as f64 * period_ns * 1e-9))
}
