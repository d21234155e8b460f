//! `render --renderer raster`: the scan is streamed through the GPU in chunks (decoded on a
//! worker thread while the previous chunk draws) into one frame, so resident memory follows
//! the chunk size and the image size, not the point count.

use std::time::Instant;

use anyhow::{Context, Result};

use crate::Rendered;
use crate::memory;
use crate::prepare::subsample::{self, Subsample};
use crate::raster::{CacheStatus, ChunkedFrame, RasterError, Rasterizer};
use crate::render::RenderSettings;
use crate::scene::Scene;
use crate::stream::{self, ChunkSink, PlanOptions, StreamError};

use super::progress;
use super::render_args::RenderArgs;

/// Draws each streamed chunk, thinned first when `--subsample` asks.
struct RasterSink<'r> {
    frame: ChunkedFrame<'r>,
    subsample: Option<Subsample>,
    settings: RenderSettings,
    offered: u64,
}

impl ChunkSink for RasterSink<'_> {
    fn draw(&mut self, chunk: &Scene) -> Result<(), StreamError> {
        self.offered += chunk.len() as u64;
        match self.subsample {
            // Per chunk: a point hidden by nearer points of its own chunk is hidden in the
            // whole cloud too, so nothing visible is dropped; N counts within each chunk.
            Some(how) => {
                let kept =
                    subsample::apply(chunk, how, &self.settings.camera, self.settings.image.width);
                ChunkSink::draw(&mut self.frame, &kept)
            }
            None => ChunkSink::draw(&mut self.frame, chunk),
        }
    }
}

/// Streams the input files through the GPU rasterizer under `settings` (camera at the origin of
/// the streamed chunks).
pub(super) fn rasterize(
    args: &RenderArgs,
    settings: &RenderSettings,
    say: &impl Fn(String),
) -> Result<Rendered> {
    let eyes = settings.views().len() as u32;
    let (cap, cap_is_default) = match args.max_memory {
        Some(c) => (Some(c), false),
        None => (memory::default_cap(), true),
    };
    let chunk_points = match cap {
        Some(cap) => {
            memory::raster_chunk_points(&args.file, args.render_width(), eyes, cap, cap_is_default)?
        }
        None => stream::DEFAULT_CHUNK_POINTS,
    };

    let started = Instant::now();
    let options = PlanOptions {
        prepare: args.prepare_options(),
        color: args.draw.color,
        ..PlanOptions::default()
    };
    // The GPU device and the pipelines of these settings are set up on another thread while
    // the files are surveyed: neither needs the other.
    let (plan, gpu) = std::thread::scope(|scope| {
        let gpu = scope.spawn(|| {
            let setup = Instant::now();
            let rasterizer = Rasterizer::new()?;
            rasterizer.prepare(settings)?;
            Ok::<_, RasterError>((rasterizer, setup.elapsed()))
        });
        let pb = progress::bar(args.quiet, 0, "surveying");
        let plan = stream::plan_files(&args.inputs(), &options, &pb);
        pb.finish_and_clear();
        (plan, gpu.join())
    });
    let plan = plan?;
    if let Some(lod) = &plan.lod {
        say(format!("{}: {lod}", args.inputs_name()));
    }
    if plan.dropped > 0 {
        say(format!(
            "warning: dropped {} points with NaN/inf or absurd coordinates from {}",
            plan.dropped,
            args.inputs_name()
        ));
    }
    let unit = plan.info.length_symbol();
    say(format!(
        "{}: {} points, radius {}, camera at ({:.3}, {:.3}, {:.3}); planned from {} in {:.2?}",
        args.inputs_name(),
        plan.lod.map_or(plan.declared, |l| l.points_read),
        plan.radii.describe(&unit),
        plan.camera.x,
        plan.camera.y,
        plan.camera.z,
        if plan.whole.is_some() {
            "every point".to_string()
        } else {
            format!("a sample of {} points", plan.surveyed)
        },
        started.elapsed()
    ));

    // GPU buffers no larger than the file needs.
    let to_draw = plan.lod.map_or(plan.declared, |l| l.points_read);
    let chunk_points = chunk_points.min(to_draw.max(1) as usize);
    let waited = Instant::now();
    let (rasterizer, setup) = match gpu {
        Ok(made) => made?,
        Err(panic) => std::panic::resume_unwind(panic),
    };
    let frame = rasterizer.begin_chunked(settings, plan.color, chunk_points as u32)?;
    match rasterizer.pipeline_cache() {
        CacheStatus::Ignored { .. } => say(format!("warning: {}", rasterizer.pipeline_cache())),
        status => say(format!(
            "GPU set up in {setup:.2?} alongside the plan; then {:.2?} waiting for it and \
             allocating the frame: {} ({status})",
            waited.elapsed(),
            rasterizer.adapter_name()
        )),
    }
    let mut sink = RasterSink {
        frame,
        subsample: args.subsample,
        settings: *settings,
        offered: 0,
    };
    let pb = progress::bar(args.quiet, plan.declared, "rasterizing");
    let report = stream::stream_file(&plan, chunk_points, &mut sink, &pb)
        .with_context(|| format!("rendering {}", args.inputs_name()))?;
    pb.finish_and_clear();
    args.say_filtered(&report.filtered, report.drawn, say);
    let drawn = sink.frame.points();
    let (rendered, stats, _) = sink.frame.finish()?;
    say(format!(
        "streamed {} points in chunks of {chunk_points} ({:.2} M points/s); {stats}",
        report.read,
        report.points_per_second() / 1e6,
    ));
    if let Some(how) = args.subsample {
        say(format!(
            "subsample {how:?}: kept {drawn} of {} points ({:.1}%)",
            sink.offered,
            100.0 * drawn as f64 / sink.offered.max(1) as f64
        ));
    }
    Ok(rendered)
}
