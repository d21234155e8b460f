//! H.264 encoding with OpenH264: sRGB frames to YUV 4:2:0 (OpenH264's own converter, BT.601
//! limited range, which the SPS's colour description states), then to NAL units.
//!
//! The stream is Constrained Baseline (OpenH264's profile), which every H.264 decoder plays,
//! at a constant target bit rate with no skipped frames (a 360 video must keep every frame in
//! step with its tour), and a keyframe every two seconds so players and the viewer's slider
//! can seek.

use openh264::encoder::{
    BitRate, Complexity, Encoder, EncoderConfig, FrameRate, IntraFramePeriod, Level,
    MatrixCoefficients, RateControlMode, TransferCharacteristics, UsageType, VuiConfig,
};
use openh264::formats::{RgbSliceU8, YUVBuffer};
use openh264::{OpenH264API, Timestamp};

use super::VideoError;
use super::level::H264Level;

/// Bits per pixel per frame of the automatic bit rate: about what YouTube recommends for 360
/// uploads (35-45 Mbit/s for 3840x2160 at 30 fps is 0.14-0.18).
pub const AUTO_BITS_PER_PIXEL: f64 = 0.15;

/// The lowest automatic bit rate, so that small frames still look clean.
pub const MIN_AUTO_BITRATE: u64 = 1_000_000;

/// Seconds between keyframes.
pub const KEYFRAME_SECONDS: f64 = 2.0;

/// The bit rate used when none is given: [`AUTO_BITS_PER_PIXEL`] at this size and rate, at
/// least [`MIN_AUTO_BITRATE`], at most what `cap` (a level's maximum) allows.
pub fn auto_bitrate(width: u32, height: u32, fps: f64, cap: u64) -> u64 {
    let bits = f64::from(width) * f64::from(height) * fps * AUTO_BITS_PER_PIXEL;
    (bits.round() as u64).max(MIN_AUTO_BITRATE).min(cap)
}

/// What one encoded frame gives the muxer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EncodedFrame {
    /// The frame's NAL units without start codes; parameter sets are kept apart.
    pub nal_units: Vec<Vec<u8>>,
    /// Whether it is an IDR frame (a sync sample).
    pub keyframe: bool,
}

/// The settings of one stream.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StreamSettings {
    /// Frame width in pixels (even).
    pub width: u32,
    /// Frame height in pixels (even).
    pub height: u32,
    /// Frames per second.
    pub fps: f64,
    /// Target bits per second.
    pub bitrate: u64,
    /// The H.264 level written in the stream.
    pub level: H264Level,
}

/// An OpenH264 encoder for frames of one size.
pub struct H264Encoder {
    encoder: Encoder,
    settings: StreamSettings,
    yuv: YUVBuffer,
    frame: usize,
    sps: Option<Vec<u8>>,
    pps: Option<Vec<u8>>,
}

impl H264Encoder {
    /// An encoder for `settings` (checked by [`level_for`](super::level::level_for)).
    pub fn new(settings: StreamSettings) -> Result<Self, VideoError> {
        let codec = |reason: String| VideoError::Codec {
            action: "encoder set-up",
            frame: 0,
            reason,
        };
        let bitrate = u32::try_from(settings.bitrate)
            .map_err(|_| codec(format!("bit rate {} is too high", settings.bitrate)))?;
        let keyframes = (settings.fps * KEYFRAME_SECONDS).round().max(1.0) as u32;
        let vui = VuiConfig::srgb()
            .matrix_coefficients(MatrixCoefficients::Smpte170M)
            .transfer_characteristics(TransferCharacteristics::Srgb)
            .full_range(false);
        let config = EncoderConfig::new()
            // The non-real-time camera mode is refused by this OpenH264 (invalid usage type).
            .usage_type(UsageType::CameraVideoRealTime)
            .rate_control_mode(RateControlMode::Bitrate)
            .bitrate(BitRate::from_bps(bitrate))
            .max_frame_rate(FrameRate::from_hz(settings.fps as f32))
            .skip_frames(false)
            .complexity(Complexity::High)
            .intra_frame_period(IntraFramePeriod::from_num_frames(keyframes))
            .level(openh264_level(settings.level))
            .vui(vui);
        let mut encoder = Encoder::with_api_config(OpenH264API::from_source(), config)
            .map_err(|e| codec(e.to_string()))?;
        quiet_warnings(&mut encoder);
        Ok(Self {
            encoder,
            settings,
            yuv: YUVBuffer::new(settings.width as usize, settings.height as usize),
            frame: 0,
            sps: None,
            pps: None,
        })
    }

    /// Encodes the next frame (`width` x `height` sRGB).
    pub fn encode(&mut self, rgb: &image::RgbImage) -> Result<EncodedFrame, VideoError> {
        let frame = self.frame;
        let codec = |reason: String| VideoError::Codec {
            action: "encoding",
            frame,
            reason,
        };
        let (w, h) = (self.settings.width, self.settings.height);
        if rgb.dimensions() != (w, h) {
            return Err(codec(format!(
                "the frame is {}x{}, the stream {w}x{h}",
                rgb.width(),
                rgb.height()
            )));
        }
        self.yuv
            .read_rgb8(RgbSliceU8::new(rgb.as_raw(), (w as usize, h as usize)));
        let millis = (frame as f64 * 1000.0 / self.settings.fps).round() as u64;
        let stream = self
            .encoder
            .encode_at(&self.yuv, Timestamp::from_millis(millis))
            .map_err(|e| codec(e.to_string()))?;
        let mut out = EncodedFrame {
            nal_units: Vec::new(),
            keyframe: false,
        };
        for l in 0..stream.num_layers() {
            let Some(layer) = stream.layer(l) else {
                continue;
            };
            for n in 0..layer.nal_count() {
                let Some(nal) = layer.nal_unit(n).map(strip_start_code) else {
                    continue;
                };
                match nal.first().map(|b| b & 0x1f) {
                    None => {}
                    Some(7) => keep_parameter_set(&mut self.sps, nal, "sequence", frame)?,
                    Some(8) => keep_parameter_set(&mut self.pps, nal, "picture", frame)?,
                    Some(t) => {
                        out.keyframe |= t == 5;
                        out.nal_units.push(nal.to_vec());
                    }
                }
            }
        }
        if out.nal_units.is_empty() {
            return Err(codec(
                "the encoder gave no picture (a skipped frame)".into(),
            ));
        }
        self.frame += 1;
        Ok(out)
    }

    /// The sequence and picture parameter sets, once the first frame is encoded.
    pub fn parameter_sets(&self) -> Option<(&[u8], &[u8])> {
        Some((self.sps.as_deref()?, self.pps.as_deref()?))
    }
}

/// Lowers OpenH264's log to errors before its set-up, which otherwise warns on stderr that a
/// bit rate "can't be controlled" without skipping frames (it is followed closely all the
/// same: measured within 10 % from 1 to 5 Mbit/s).
fn quiet_warnings(encoder: &mut Encoder) {
    let mut level = openh264_sys2::WELS_LOG_ERROR as std::os::raw::c_int;
    // SAFETY: the encoder is created (its set-up waits for the first frame), OpenH264 takes
    // the trace level before set-up, and reads the option as a C int during the call only.
    unsafe {
        encoder.raw_api().set_option(
            openh264_sys2::ENCODER_OPTION_TRACE_LEVEL,
            (&raw mut level).cast(),
        );
    }
}

/// Keeps the first parameter set of a kind; a later one must repeat it, since an MP4 sample
/// entry holds one set for the whole track.
fn keep_parameter_set(
    slot: &mut Option<Vec<u8>>,
    nal: &[u8],
    kind: &str,
    frame: usize,
) -> Result<(), VideoError> {
    match slot {
        None => *slot = Some(nal.to_vec()),
        Some(kept) if kept.as_slice() == nal => {}
        Some(_) => {
            return Err(VideoError::Codec {
                action: "encoding",
                frame,
                reason: format!("the encoder changed its {kind} parameter set mid-stream"),
            });
        }
    }
    Ok(())
}

/// A NAL unit without its Annex B start code (`00 00 01` or `00 00 00 01`).
pub fn strip_start_code(nal: &[u8]) -> &[u8] {
    let zeros = nal.iter().take_while(|&&b| b == 0).count();
    if zeros >= 2 && nal.get(zeros) == Some(&1) {
        &nal[zeros + 1..]
    } else {
        nal
    }
}

fn openh264_level(level: H264Level) -> Level {
    match level.idc {
        10 => Level::Level_1_0,
        11 => Level::Level_1_1,
        12 => Level::Level_1_2,
        13 => Level::Level_1_3,
        20 => Level::Level_2_0,
        21 => Level::Level_2_1,
        22 => Level::Level_2_2,
        30 => Level::Level_3_0,
        31 => Level::Level_3_1,
        32 => Level::Level_3_2,
        40 => Level::Level_4_0,
        41 => Level::Level_4_1,
        42 => Level::Level_4_2,
        50 => Level::Level_5_0,
        _ => Level::Level_5_1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn start_codes_of_both_lengths_are_stripped() {
        assert_eq!(strip_start_code(&[0, 0, 0, 1, 0x67, 9]), &[0x67, 9]);
        assert_eq!(strip_start_code(&[0, 0, 1, 0x68]), &[0x68]);
        assert_eq!(strip_start_code(&[0x65, 1]), &[0x65, 1]);
    }

    #[test]
    fn the_automatic_bit_rate_follows_the_pixel_rate() {
        assert_eq!(auto_bitrate(2160, 2160, 30.0, u64::MAX), 20_995_200);
        assert_eq!(auto_bitrate(256, 256, 30.0, u64::MAX), MIN_AUTO_BITRATE);
        assert_eq!(auto_bitrate(3840, 1920, 30.0, 10), 10);
    }
}
