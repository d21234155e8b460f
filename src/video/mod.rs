//! 360 videos: a folder of equirectangular frames (mono, or ODS top-bottom with the left eye
//! on top) encoded to an H.264 MP4 with the Spherical Video V2 metadata (`st3d`, `sv3d`) that
//! YouTube, headset players and other 360 players read to show it as a sphere, in stereo.
//!
//! [`crate::frames`] lists and checks the frames, [`level`] keeps the stream within what players
//! decode, [`encode`] runs OpenH264, [`mux`] writes and reads the MP4, [`decode`] decodes it
//! back. No external program is involved.

pub mod decode;
pub mod encode;
mod error;
pub mod level;
pub mod mux;

use std::path::{Path, PathBuf};
use std::time::Instant;

use indicatif::ProgressBar;
use rayon::prelude::*;

use crate::frames::{FrameFolder, FramesError, StereoChoice, StereoSource, read_rgb};
use crate::output::StereoLayout;

pub use error::VideoError;
pub use level::{H264Level, check_frame_size};
pub use mux::{Projection, VideoInfo, read_video_info};

/// The frame rate when neither the caller nor `tour.json` gives one.
pub const DEFAULT_FPS: f64 = 30.0;

/// How to encode a folder of frames.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct VideoOptions {
    /// Frames per second; `None`: `tour.json`'s, else [`DEFAULT_FPS`].
    pub fps: Option<f64>,
    /// The stereo layout; `Auto` reads `tour.json` or the frame shape.
    pub stereo: StereoChoice,
    /// Target bits per second; `None`: [`encode::auto_bitrate`].
    pub bitrate: Option<u64>,
}

/// A checked plan: which frames, at which rate, size, level and bit rate.
#[derive(Debug, Clone)]
pub struct VideoPlan {
    /// The frames.
    pub folder: FrameFolder,
    /// Frames per second.
    pub fps: f64,
    /// Target bits per second.
    pub bitrate: u64,
    /// The H.264 level of the stream.
    pub level: H264Level,
}

/// What an encode wrote.
#[derive(Debug, Clone)]
pub struct VideoReport {
    /// The MP4 file.
    pub output: PathBuf,
    /// Frames written.
    pub frames: usize,
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// Frames per second.
    pub fps: f64,
    /// Stereo layout written in `st3d`.
    pub stereo: StereoLayout,
    /// Where the layout came from.
    pub stereo_source: StereoSource,
    /// The H.264 level.
    pub level: H264Level,
    /// Target bits per second.
    pub bitrate: u64,
    /// File size in bytes.
    pub bytes: u64,
    /// Seconds of video.
    pub duration_seconds: f64,
    /// Seconds the encode took.
    pub elapsed_seconds: f64,
}

/// Checks a frame folder and the options without encoding anything.
pub fn plan(dir: &Path, options: &VideoOptions) -> Result<VideoPlan, VideoError> {
    let folder = FrameFolder::open(dir, options.stereo)?;
    let fps = options
        .fps
        .or_else(|| folder.tour.as_ref().and_then(|t| t.fps))
        .unwrap_or(DEFAULT_FPS);
    if options.bitrate == Some(0) {
        return Err(VideoError::Option(
            "--bitrate 0: expected a positive number of bits per second".into(),
        ));
    }
    let (w, h) = (folder.width, folder.height);
    // Size and rate first, so their error comes before any about the bit rate.
    level::level_for(w, h, fps, 0)?;
    let bitrate = options
        .bitrate
        .unwrap_or_else(|| encode::auto_bitrate(w, h, fps, level::MAX_LEVEL.max_bitrate));
    let level = level::level_for(w, h, fps, bitrate)?;
    Ok(VideoPlan {
        folder,
        fps,
        bitrate,
        level,
    })
}

/// Encodes a planned folder to `output` (`.mp4`), stepping `progress` once per frame.
pub fn encode_plan(
    plan: &VideoPlan,
    output: &Path,
    progress: &ProgressBar,
) -> Result<VideoReport, VideoError> {
    let is_mp4 = output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("mp4"));
    if !is_mp4 {
        return Err(VideoError::Option(format!(
            "{}: the video is an MP4 file; name it .mp4",
            output.display()
        )));
    }
    let started = Instant::now();
    let folder = &plan.folder;
    let settings = encode::StreamSettings {
        width: folder.width,
        height: folder.height,
        fps: plan.fps,
        bitrate: plan.bitrate,
        level: plan.level,
    };
    let mut encoder = encode::H264Encoder::new(settings)?;
    let mut writer = mux::Mp4Writer::create(
        output,
        mux::TrackInfo {
            width: folder.width,
            height: folder.height,
            fps: plan.fps,
            stereo: folder.stereo,
        },
    )?;
    progress.set_length(folder.frames.len() as u64);
    // Decode a batch of frames in parallel while the encoder, which is sequential, waits.
    let batch = rayon::current_num_threads().max(1);
    for chunk in folder.frames.chunks(batch) {
        let images: Vec<image::RgbImage> = chunk
            .par_iter()
            .map(|path| read_rgb(path))
            .collect::<Result<_, _>>()?;
        for (path, image) in chunk.iter().zip(&images) {
            if image.dimensions() != (folder.width, folder.height) {
                return Err(FramesError::FrameSize {
                    path: path.clone(),
                    width: image.width(),
                    height: image.height(),
                    first: folder.frames[0].clone(),
                    first_width: folder.width,
                    first_height: folder.height,
                }
                .into());
            }
            writer.write_frame(&encoder.encode(image)?)?;
            progress.inc(1);
        }
    }
    let Some((sps, pps)) = encoder.parameter_sets() else {
        return Err(VideoError::Codec {
            action: "encoding",
            frame: 0,
            reason: "the encoder gave no parameter sets".into(),
        });
    };
    let bytes = writer.finish(sps, pps, plan.level)?;
    progress.finish_and_clear();
    let frames = folder.frames.len();
    Ok(VideoReport {
        output: output.to_path_buf(),
        frames,
        width: folder.width,
        height: folder.height,
        fps: plan.fps,
        stereo: folder.stereo,
        stereo_source: folder.stereo_source,
        level: plan.level,
        bitrate: plan.bitrate,
        bytes,
        duration_seconds: frames as f64 / plan.fps,
        elapsed_seconds: started.elapsed().as_secs_f64(),
    })
}

/// Encodes the frames of `dir` (see [`crate::frames`]) into the MP4 `output`.
pub fn encode_folder(
    dir: &Path,
    output: &Path,
    options: &VideoOptions,
    progress: &ProgressBar,
) -> Result<VideoReport, VideoError> {
    encode_plan(&plan(dir, options)?, output, progress)
}
