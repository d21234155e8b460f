//! Runs one benchmark: the ray-traced reference, then every rasterizer mode, timed and
//! compared.

use std::time::Instant;

use indicatif::ProgressBar;

use crate::projection::Stereo;
use crate::raster::{FrameTiming, Rasterizer, TimingSource};
use crate::raytrace;
use crate::render::RenderSettings;
use crate::scene::Scene;

use super::BenchError;
use super::accuracy::measure;
use super::config::BenchConfig;
use super::report::{BenchReport, ModeResult, ModeStats, ReferenceRun, TimingKind};

/// The settings a benchmark renders with: `base` with the config's width, stereo and depth-map
/// overrides.
pub fn bench_settings(base: &RenderSettings, config: &BenchConfig) -> RenderSettings {
    let mut s = *base;
    if let Some(w) = config.width {
        s.image = crate::projection::Image::new(s.image.projection, w).unwrap_or(s.image);
    }
    if let Some(stereo) = config.stereo {
        s.stereo = stereo;
    }
    if config.depth_map.is_some() {
        s.depth_map = config.depth_map;
    }
    s
}

fn stereo_name(s: &Stereo) -> &'static str {
    match s {
        Stereo::Mono => "mono",
        Stereo::Ods { .. } => "ods",
        Stereo::Parallel { .. } => "parallel",
        Stereo::Cubemap { .. } => "cubemap",
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        0.0
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn timing_kind(t: &FrameTiming) -> TimingKind {
    match t.source {
        TimingSource::GpuTimestamps => TimingKind::GpuTimestamps,
        TimingSource::WallClock => TimingKind::WallClock,
    }
}

/// Benchmarks `scene` (named `name` in the outputs) with a new rasterizer; see
/// [`run_bench_with`].
pub fn run_bench(
    name: &str,
    scene: &Scene,
    base: &RenderSettings,
    config: &BenchConfig,
    progress: &ProgressBar,
) -> Result<BenchReport, BenchError> {
    let rasterizer = Rasterizer::new()?;
    run_bench_with(&rasterizer, name, scene, base, config, progress)
}

/// Benchmarks `scene` on `rasterizer`: one timed ray-traced reference render, then for each
/// mode of `config` the warm-up frames and the timed frames (scene uploaded once), the median
/// frame time, and the accuracy of the first timed frame against the reference. A stereo
/// frame is followed by a mono one when `config.mono_baseline` is set.
///
/// `progress` advances once for the reference and once per rasterizer frame.
pub fn run_bench_with(
    rasterizer: &Rasterizer,
    name: &str,
    scene: &Scene,
    base: &RenderSettings,
    config: &BenchConfig,
    progress: &ProgressBar,
) -> Result<BenchReport, BenchError> {
    if config.timed_frames == 0 {
        return Err(BenchError::Config(
            "at least one timed frame is needed".into(),
        ));
    }
    let settings = bench_settings(base, config);
    // The stereo / mono ratio is measured in one run: each stereo frame is followed by a
    // mono frame of the same camera and mode.
    let mono = (config.mono_baseline && !matches!(settings.stereo, Stereo::Mono)).then(|| {
        let mut m = settings;
        m.stereo = Stereo::Mono;
        m.depth_map = None;
        m
    });
    let renders_per_frame = if mono.is_some() { 2 } else { 1 };
    let frames_per_mode = (config.warmup_frames + config.timed_frames) * renders_per_frame;
    progress.set_length(1 + (config.modes.len() * frames_per_mode) as u64);
    progress.set_position(0);
    progress.set_message(format!("{name}: ray-traced reference"));
    let hidden = ProgressBar::hidden();

    let start = Instant::now();
    let reference = raytrace::render(scene, &settings, &hidden)?;
    let reference_run = ReferenceRun {
        seconds: start.elapsed().as_secs_f64(),
        threads: rayon::current_num_threads(),
    };
    progress.inc(1);

    let uploaded = rasterizer.upload(scene, &settings)?;
    // Alternating shapes would otherwise allocate (and page in) fresh images every frame.
    let kept_shapes = rasterizer.keep_frame_shapes(renders_per_frame);
    // Timed in a closure so that the allowance is restored on error too.
    let timed = || -> Result<Vec<ModeResult>, BenchError> {
        let mut modes = Vec::with_capacity(config.modes.len());
        for &mode in &config.modes {
            progress.set_message(format!("{name}: {}", mode.label()));
            let in_mode = |mut r: RenderSettings| {
                r.proxy = mode.proxy;
                r.imposter = mode.imposter;
                r
            };
            let s = in_mode(settings);
            let mono = mono.map(in_mode);
            // One frame under `r`, drawn, read back and counted.
            let frame = |r: &RenderSettings| {
                let drawn = rasterizer.render_uploaded(&uploaded, r, &hidden);
                progress.inc(1);
                drawn
            };
            for _ in 0..config.warmup_frames {
                rasterizer.recycle(frame(&s)?.0);
                if let Some(m) = &mono {
                    rasterizer.recycle(frame(m)?.0);
                }
            }
            let mut times = Vec::with_capacity(config.timed_frames);
            let mut mono_times = Vec::with_capacity(config.timed_frames);
            let mut first = None;
            let mut kind = TimingKind::GpuTimestamps;
            let mut record = |timing: &FrameTiming, times: &mut Vec<f64>| {
                times.push(timing.seconds * 1e3);
                if timing_kind(timing) == TimingKind::WallClock {
                    kind = TimingKind::WallClock;
                }
            };
            // Wall clock of the timed frames themselves (each drawn and read back), not of the
            // mono frames between them.
            let mut run_seconds = 0.0;
            for _ in 0..config.timed_frames {
                let frame_start = Instant::now();
                let (rendered, stats, timing) = frame(&s)?;
                run_seconds += frame_start.elapsed().as_secs_f64();
                record(&timing, &mut times);
                // Frames after the first are read back into the memory of the ones before.
                match first {
                    None => first = Some((rendered, stats)),
                    Some(_) => rasterizer.recycle(rendered),
                }
                if let Some(m) = &mono {
                    let (rendered, _, timing) = frame(m)?;
                    record(&timing, &mut mono_times);
                    rasterizer.recycle(rendered);
                }
            }
            let (rendered, stats) = first.expect("timed_frames > 0");
            let frame_ms = median(times.clone());
            modes.push(ModeResult {
                mode,
                frame_ms,
                frame_ms_min: times.iter().copied().fold(f64::INFINITY, f64::min),
                frame_ms_max: times.iter().copied().fold(0.0, f64::max),
                fps: if frame_ms > 0.0 { 1e3 / frame_ms } else { 0.0 },
                sustained_fps: config.timed_frames as f64 / run_seconds.max(1e-9),
                mono_frame_ms: mono.is_some().then(|| median(mono_times)),
                timing: kind,
                accuracy: measure(
                    &reference,
                    &rendered,
                    settings.image.projection.is_full_equirect(),
                )?,
                stats: ModeStats {
                    culled: stats.culled,
                    drawn: stats.drawn,
                    special: stats.special,
                    seam_copies: stats.seam_copies,
                    vertices: stats.vertices,
                    splatted: stats.splatted,
                    hidden: stats.occluded,
                },
            });
        }
        Ok(modes)
    };
    let modes = timed();
    rasterizer.keep_frame_shapes(kept_shapes);
    let modes = modes?;
    Ok(BenchReport {
        scene: name.to_string(),
        points: scene.len(),
        width: settings.image.width,
        height: settings.image.height,
        projection: settings.image.projection.to_string(),
        stereo: stereo_name(&settings.stereo).to_string(),
        metres_per_unit: None,
        level_of_detail: None,
        adapter: rasterizer.adapter_name().to_string(),
        warmup_frames: config.warmup_frames,
        timed_frames: config.timed_frames,
        reference: reference_run,
        modes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(vec![3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(vec![4.0, 1.0, 2.0, 3.0]), 2.5);
    }
}
