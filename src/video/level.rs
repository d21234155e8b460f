//! Which H.264 level a frame size and rate need, and the largest frames we accept.
//!
//! Two limits apply. The OpenH264 encoder refuses frames whose longer side exceeds 3840 or
//! whose shorter side exceeds 2160 pixels, so the largest frames are 3840x1920 for a mono
//! panorama and 2160x2160 for a top-bottom ODS pair (1080 rows per eye). And the video must
//! stay within H.264 level 5.1 (ITU-T H.264 Table A-1), the highest level that 360 players
//! and headsets (Quest's player, phone and desktop browsers, YouTube's uploads) decode
//! everywhere; level 5.1 bounds the macroblock rate, which caps the frame rate for large
//! frames (3840x1920 plays at up to 34 fps). H.264's 4:2:0 colour needs even dimensions.

use super::VideoError;

/// One level of ITU-T H.264 Table A-1 (the limits that matter for one video track).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct H264Level {
    /// The level's name, e.g. `"5.1"`.
    pub name: &'static str,
    /// `level_idc` as written in the SPS and `avcC` (ten times the level).
    pub idc: u8,
    /// Maximum macroblocks per second (MaxMBPS).
    pub max_mb_per_second: u64,
    /// Maximum frame size in macroblocks (MaxFS).
    pub max_frame_macroblocks: u64,
    /// Maximum bit rate in bits per second for Baseline/Main profiles (MaxBR).
    pub max_bitrate: u64,
}

const fn level(
    name: &'static str,
    idc: u8,
    max_mb_per_second: u64,
    max_frame_macroblocks: u64,
    max_kbps: u64,
) -> H264Level {
    H264Level {
        name,
        idc,
        max_mb_per_second,
        max_frame_macroblocks,
        max_bitrate: max_kbps * 1000,
    }
}

/// The levels up to the highest we write, in increasing order (Table A-1; level 1b left out).
pub const LEVELS: [H264Level; 15] = [
    level("1", 10, 1_485, 99, 64),
    level("1.1", 11, 3_000, 396, 192),
    level("1.2", 12, 6_000, 396, 384),
    level("1.3", 13, 11_880, 396, 768),
    level("2", 20, 11_880, 396, 2_000),
    level("2.1", 21, 19_800, 792, 4_000),
    level("2.2", 22, 20_250, 1_620, 4_000),
    level("3", 30, 40_500, 1_620, 10_000),
    level("3.1", 31, 108_000, 3_600, 14_000),
    level("3.2", 32, 216_000, 5_120, 20_000),
    level("4", 40, 245_760, 8_192, 20_000),
    level("4.1", 41, 245_760, 8_192, 50_000),
    level("4.2", 42, 522_240, 8_704, 50_000),
    level("5", 50, 589_824, 22_080, 135_000),
    level("5.1", 51, 983_040, 36_864, 240_000),
];

/// The highest level we write: 5.1.
pub const MAX_LEVEL: H264Level = LEVELS[LEVELS.len() - 1];

/// The OpenH264 encoder's limit on the longer side of a frame.
pub const ENCODER_MAX_LONG_SIDE: u32 = 3840;

/// The OpenH264 encoder's limit on the shorter side of a frame.
pub const ENCODER_MAX_SHORT_SIDE: u32 = 2160;

/// Macroblocks (16x16 pixels) that cover a frame, across and down.
fn macroblocks(width: u32, height: u32) -> (u64, u64) {
    (
        u64::from(width).div_ceil(16),
        u64::from(height).div_ceil(16),
    )
}

/// Whether frames of `width` x `height` can be encoded and played: even dimensions, within
/// the encoder's 3840x2160 (either way round) and level 5.1's frame size. The error says why
/// and which sizes fit; `omnicloud tour --video` calls this before rendering anything.
pub fn check_frame_size(width: u32, height: u32) -> Result<(), VideoError> {
    let refuse = |reason: String| VideoError::FrameTooLarge {
        width,
        height,
        reason,
    };
    if width == 0 || height == 0 {
        return Err(refuse("a frame needs at least one pixel".into()));
    }
    if !width.is_multiple_of(2) || !height.is_multiple_of(2) {
        let fix = |n: u32| format!("{} or {}", n - n % 4, n - n % 4 + 4);
        return Err(refuse(format!(
            "H.264's 4:2:0 colour needs even width and height; render at a width that is a \
             multiple of 4 ({} for this one)",
            fix(width.max(height))
        )));
    }
    let (long, short) = (width.max(height), width.min(height));
    if long > ENCODER_MAX_LONG_SIDE || short > ENCODER_MAX_SHORT_SIDE {
        return Err(refuse(format!(
            "the OpenH264 encoder takes frames up to {ENCODER_MAX_LONG_SIDE}x\
             {ENCODER_MAX_SHORT_SIDE} (either way round): at most --width 3840 for a mono \
             panorama (3840x1920) and --width 2160 for an ODS pair (2160x2160, top-bottom)"
        )));
    }
    let (across, down) = macroblocks(width, height);
    let side_limit = ((8 * MAX_LEVEL.max_frame_macroblocks) as f64).sqrt() as u64;
    if across * down > MAX_LEVEL.max_frame_macroblocks || across > side_limit || down > side_limit {
        return Err(refuse(format!(
            "H.264 level {} (what 360 players and headsets decode) allows {} macroblocks per \
             frame and {} across or down; this frame has {} ({across}x{down})",
            MAX_LEVEL.name,
            MAX_LEVEL.max_frame_macroblocks,
            side_limit,
            across * down
        )));
    }
    Ok(())
}

/// The lowest level that plays `width` x `height` frames at `fps` and `bitrate` bits per
/// second, at most [`MAX_LEVEL`].
pub fn level_for(width: u32, height: u32, fps: f64, bitrate: u64) -> Result<H264Level, VideoError> {
    check_frame_size(width, height)?;
    if !(fps.is_finite() && fps > 0.0) {
        return Err(VideoError::Option(format!(
            "--fps {fps}: expected a positive number of frames per second"
        )));
    }
    if bitrate > MAX_LEVEL.max_bitrate {
        return Err(VideoError::Option(format!(
            "--bitrate {bitrate}: H.264 level {} allows at most {} bits per second",
            MAX_LEVEL.name, MAX_LEVEL.max_bitrate
        )));
    }
    let (across, down) = macroblocks(width, height);
    let frame = across * down;
    let rate = (frame as f64 * fps).ceil() as u64;
    LEVELS
        .iter()
        .find(|l| {
            let side = ((8 * l.max_frame_macroblocks) as f64).sqrt() as u64;
            frame <= l.max_frame_macroblocks
                && across <= side
                && down <= side
                && rate <= l.max_mb_per_second
                && bitrate <= l.max_bitrate
        })
        .copied()
        .ok_or(VideoError::RateTooHigh {
            width,
            height,
            fps,
            needed: rate,
            level: MAX_LEVEL.name,
            allowed: MAX_LEVEL.max_mb_per_second,
            max_fps: (MAX_LEVEL.max_mb_per_second as f64 / frame as f64).floor(),
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_largest_accepted_frames_fit_level_5_1_at_30_fps() {
        let mbps = 1_000_000;
        assert_eq!(level_for(2160, 2160, 30.0, 20 * mbps).unwrap().name, "5");
        assert_eq!(level_for(3840, 1920, 30.0, 40 * mbps).unwrap().name, "5.1");
        assert_eq!(level_for(1920, 1920, 30.0, 16 * mbps).unwrap().name, "5");
        assert_eq!(level_for(1920, 960, 30.0, 8 * mbps).unwrap().name, "4");
        // 256 macroblocks at 30 fps fit level 1.3; the bit rate asks for more.
        assert_eq!(level_for(256, 256, 30.0, 700_000).unwrap().name, "1.3");
        assert_eq!(level_for(256, 256, 30.0, mbps).unwrap().name, "2");
    }

    #[test]
    fn too_large_frames_are_refused_with_the_reason() {
        let e = check_frame_size(2880, 2880).unwrap_err().to_string();
        assert!(e.contains("2880x2880 frames cannot be encoded"), "{e}");
        assert!(e.contains("--width 2160 for an ODS pair"), "{e}");
        let e = check_frame_size(4096, 2048).unwrap_err().to_string();
        assert!(e.contains("--width 3840 for a mono"), "{e}");
        check_frame_size(2160, 3840).unwrap();
    }

    #[test]
    fn odd_sizes_are_refused_with_a_width_that_works() {
        let e = check_frame_size(250, 125).unwrap_err().to_string();
        assert!(e.contains("even width and height"), "{e}");
        assert!(e.contains("248 or 252"), "{e}");
    }

    #[test]
    fn a_rate_above_level_5_1_is_refused_with_the_highest_fps() {
        let e = level_for(3840, 1920, 60.0, 1_000_000)
            .unwrap_err()
            .to_string();
        assert!(e.contains("at most 34"), "{e}");
        assert!(level_for(64, 64, f64::NAN, 1_000).is_err());
        assert!(level_for(64, 64, 0.0, 1_000).is_err());
        let e = level_for(64, 64, 30.0, 300_000_000)
            .unwrap_err()
            .to_string();
        assert!(e.contains("at most 240000000 bits per second"), "{e}");
    }
}
