//! `omnicloud video`: encodes a folder of frames into a 360 MP4 and prints what it wrote.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};

use crate::frames::{StereoChoice, StereoSource};
use crate::video::{self, VideoOptions};

use super::progress;

/// Options of `omnicloud video`.
#[derive(Debug, Args)]
pub struct VideoArgs {
    /// A folder of frames: frame_000000.png, frame_000001.png, ... (or .jpg, .exr), as
    /// `omnicloud tour` writes them, with its tour.json if there is one.
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// The MP4 file to write.
    #[arg(short, long, value_name = "OUT.mp4")]
    pub output: PathBuf,
    /// Frames per second [default: tour.json's, else 30].
    #[arg(long, value_parser = fps)]
    pub fps: Option<f64>,
    /// How the frames hold the eyes: auto reads tour.json, else takes 1:1 frames as
    /// top-bottom ODS pairs (left eye on top) and 2:1 frames as mono.
    #[arg(long, value_enum, default_value_t = StereoArg::Auto)]
    pub stereo: StereoArg,
    /// Target bit rate in bits per second, with an optional k or M (e.g. 20M) [default: 0.15
    /// bits per pixel per frame, at least 1M: 21M for 2160x2160 at 30 fps].
    #[arg(long, value_parser = bitrate)]
    pub bitrate: Option<u64>,
    /// No progress bar.
    #[arg(short, long)]
    pub quiet: bool,
}

/// `--stereo` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum StereoArg {
    /// From tour.json or the frame shape.
    Auto,
    /// Mono equirectangular frames (2:1).
    Mono,
    /// ODS pairs, left eye on top (1:1).
    TopBottom,
}

/// Encodes `args.dir` into `args.output`.
pub fn run(args: &VideoArgs) -> Result<()> {
    let options = VideoOptions {
        fps: args.fps,
        stereo: match args.stereo {
            StereoArg::Auto => StereoChoice::Auto,
            StereoArg::Mono => StereoChoice::Mono,
            StereoArg::TopBottom => StereoChoice::TopBottom,
        },
        bitrate: args.bitrate,
    };
    let plan = video::plan(&args.dir, &options)?;
    let folder = &plan.folder;
    let bar = progress::bar(args.quiet, folder.frames.len() as u64, "encoding");
    let report = video::encode_plan(&plan, &args.output, &bar).with_context(|| {
        format!(
            "encoding {} into {}",
            args.dir.display(),
            args.output.display()
        )
    })?;
    let how = match report.stereo_source {
        StereoSource::Given => "as given",
        StereoSource::Tour => "from tour.json",
        StereoSource::Aspect => "from the frame shape",
    };
    println!(
        "{}: {} frames {}x{} at {} fps ({:.1} s), {} ({how}), H.264 level {}, {:.1} Mbit/s \
         target, {} in {:.1} s",
        report.output.display(),
        report.frames,
        report.width,
        report.height,
        report.fps,
        report.duration_seconds,
        report.stereo.name(),
        report.level.name,
        report.bitrate as f64 / 1e6,
        bytesize::ByteSize(report.bytes),
        report.elapsed_seconds,
    );
    println!(
        "360 metadata: sv3d equirectangular, st3d {}; look at it with: omnicloud view {}",
        report.stereo.name(),
        report.output.display()
    );
    Ok(())
}

fn fps(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(f) if f.is_finite() && (1.0..=240.0).contains(&f) => Ok(f),
        _ => Err(format!("`{s}`: expected frames per second from 1 to 240")),
    }
}

/// Bits per second: a number with an optional `k` (1000) or `M` (1,000,000).
fn bitrate(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let (number, scale) = match t.char_indices().last() {
        Some((i, 'k' | 'K')) => (&t[..i], 1e3),
        Some((i, 'm' | 'M')) => (&t[..i], 1e6),
        _ => (t, 1.0),
    };
    match number.trim().parse::<f64>() {
        Ok(n) if n.is_finite() && n > 0.0 && n * scale >= 1.0 => Ok((n * scale).round() as u64),
        _ => Err(format!(
            "`{s}`: expected a positive bit rate in bits per second, e.g. 20M or 8000k"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bit_rates_and_frame_rates_parse() {
        assert_eq!(bitrate("20M").unwrap(), 20_000_000);
        assert_eq!(bitrate("1.5m").unwrap(), 1_500_000);
        assert_eq!(bitrate("8000k").unwrap(), 8_000_000);
        assert_eq!(bitrate("64000").unwrap(), 64_000);
        for bad in ["", "M", "-1M", "NaNM", "fast", "0"] {
            assert!(bitrate(bad).is_err(), "{bad}");
        }
        assert_eq!(fps("29.97").unwrap(), 29.97);
        assert!(fps("0").is_err() && fps("inf").is_err() && fps("1000").is_err());
    }
}
