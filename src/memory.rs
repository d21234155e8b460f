//! Memory budgets: parsing sizes (`2G`, `800M`), the machine's available memory, and the
//! estimate of what the ray tracer will need for a file, from its header alone, so that a
//! cloud too large for the cap is refused before anything is loaded.
//!
//! The per-point figures are measured (see [`RAYTRACE_BYTES_PER_POINT`]); the estimate is the
//! peak, which comes while the BVH is built, not what stays resident while tracing.

use bytesize::ByteSize;
use sysinfo::{MemoryRefreshKind, RefreshKind, System};

use crate::io::FileInfo;

/// Peak bytes per point of `render --renderer raytrace`, reached while the BVH is built.
///
/// Measured (VmHWM of `omnicloud render --renderer raytrace --width 512`, minus the 9 MB of a
/// 1,065-point run): 291 bytes per point on autzen_trim (110,000 points), 294 on the lion
/// (341,989). Where it goes:
///
/// - scene, kept throughout: position 12, rgb 3, intensity 2, classification 1 = 18 (+4 for a
///   per-point radius); while loading, 16-bit colour is held unscaled (6) next to it;
/// - base colours 3;
/// - tracer, resident while tracing (`Tracer::memory()`): sphere records 16, primitive
///   indices 4, CWBVH nodes ~14 (80-byte nodes, ~0.18 per point) = ~34;
/// - transient during the build (obvhs PLOC): boxes 32, BVH2 nodes (2 per point), Morton
///   codes and index arrays, and the BVH2 and CWBVH alive together during conversion: the
///   remaining ~230.
///
/// 320 keeps ~9% margin over the measurements.
pub const RAYTRACE_BYTES_PER_POINT: u64 = 320;

/// Fixed overhead of a process that loads and renders (code, thread stacks, the decoder's
/// buffers, rayon): measured ~40 MB.
pub const BASE_BYTES: u64 = 64 << 20;

/// Fraction of the available memory ([`mem_available`]) used when no `--max-memory` is given.
pub const DEFAULT_FRACTION: f64 = 0.8;

/// What a render is expected to need, bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MemoryEstimate {
    /// Points the file declares.
    pub points: u64,
    /// Bytes for the points (scene, colours, BVH build).
    pub points_bytes: u64,
    /// Bytes for the frames (colour + depth per pixel per eye, plus the output image).
    pub image_bytes: u64,
    /// Fixed process overhead.
    pub base_bytes: u64,
}

impl MemoryEstimate {
    /// Total bytes.
    pub fn total(&self) -> u64 {
        self.points_bytes
            .saturating_add(self.image_bytes)
            .saturating_add(self.base_bytes)
    }
}

/// Bytes per point of a loaded scene before any renderer runs: position 12, rgb 3,
/// intensity 2, classification 1, a per-point radius 4, and 2 of Vec slack.
pub const LOADED_BYTES_PER_POINT: u64 = 24;

/// Estimates the ray tracer's peak for `loaded` points read from the file, of which `traced`
/// remain after subsampling, rendered at `width x width/2` per eye for `eyes` eyes.
pub fn raytrace_estimate(loaded: u64, traced: u64, width: u32, eyes: u32) -> MemoryEstimate {
    let pixels = u64::from(width) * u64::from(width / 2) * u64::from(eyes);
    let loaded_bytes = loaded.saturating_mul(LOADED_BYTES_PER_POINT);
    let traced_bytes = traced.saturating_mul(RAYTRACE_BYTES_PER_POINT - LOADED_BYTES_PER_POINT);
    MemoryEstimate {
        points: loaded,
        points_bytes: loaded_bytes.saturating_add(traced_bytes),
        // Frame: 4 colour + 4 depth bytes; the output writer converts to RGBA/EXR (up to 20
        // bytes per pixel for RGBA f32 + Z).
        image_bytes: pixels * (8 + 20),
        base_bytes: BASE_BYTES,
    }
}

/// Points the ray tracer holds within `cap` at `width x width/2` per eye for `eyes` eyes,
/// every point traced: the inverse of [`raytrace_estimate`].
pub fn raytrace_points_within(cap: u64, width: u32, eyes: u32) -> u64 {
    let fixed = raytrace_estimate(0, 0, width, eyes).total();
    cap.saturating_sub(fixed) / RAYTRACE_BYTES_PER_POINT
}

/// Estimate for a file from its header's point count, keeping one point in `keep_every`.
pub fn raytrace_estimate_for(
    info: &FileInfo,
    keep_every: u64,
    width: u32,
    eyes: u32,
) -> MemoryEstimate {
    let kept = info.point_count.div_ceil(keep_every.max(1));
    raytrace_estimate(info.point_count, kept, width, eyes)
}

/// Resident bytes per pixel and eye of a streamed raster render. On a software adapter the
/// GPU's textures and buffers are host memory, so they count: on the keyed path the keys 8
/// (the image; without 64-bit atomics colour 4 + distance 4 + depth 4 textures instead), the
/// frame read back 8, and transient read-back staging 8 and output encoding. Measured on the
/// keyed path: 24.5 bytes (mono) and 8.7 more for the second eye at 3840×1920 (Autzen,
/// `/usr/bin/time -v`, against the same render 256 wide); 32 keeps a margin.
pub const RASTER_BYTES_PER_PIXEL: u64 = 32;

/// Resident bytes per point of the stream's chunk size, while streaming: decoded chunks (raw
/// and converted, ~40 bytes a point each as f64 positions and attributes) waiting in the
/// channel and being decoded, the chunk as a scene, its colours, the packed GPU upload and its
/// staging copy, and what the allocator keeps between chunks. Measured 360 (VmHWM growth
/// while streaming 20 M points in chunks of 512 Ki, `tests/stream_raster_big.rs`).
pub const RASTER_BYTES_PER_CHUNK_POINT: u64 = 384;

/// Fixed overhead of a rasterizing process: the Vulkan driver (llvmpipe measured ~160 MB with
/// its compiled pipelines), code and thread stacks.
pub const RASTER_BASE_BYTES: u64 = 192 << 20;

/// Bytes of the rasterizer's work buffers for chunks of `chunk_points` (bounds proxies): the
/// vertex buffer, and the list of points the splat leaves to draw.
fn vertex_buffer_bytes(chunk_points: u64) -> u64 {
    (chunk_points * 12 * 16).min(128 << 20) + chunk_points * 4
}

/// Estimated peak of `render --renderer raster` streaming in chunks of `chunk_points` at
/// `width x width/2` per eye for `eyes` eyes. It does not depend on the file's size.
pub fn raster_stream_estimate(width: u32, eyes: u32, chunk_points: u64) -> MemoryEstimate {
    let pixels = u64::from(width) * u64::from(width / 2) * u64::from(eyes);
    MemoryEstimate {
        points: chunk_points,
        points_bytes: chunk_points * RASTER_BYTES_PER_CHUNK_POINT
            + vertex_buffer_bytes(chunk_points),
        image_bytes: pixels * RASTER_BYTES_PER_PIXEL,
        base_bytes: RASTER_BASE_BYTES,
    }
}

/// Smallest chunk worth streaming: below it, per-batch GPU overhead dominates.
pub const MIN_CHUNK_POINTS: usize = 1 << 14;

/// Why a streamed raster render cannot fit the memory cap whatever the chunk size.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "{file}: a {width}-pixel-wide {eyes_word} frame needs an estimated {need} while streaming, over the memory cap of {cap}{source_of_cap}; use a smaller --width or raise --max-memory"
)]
pub struct FrameOverBudget {
    /// The file.
    pub file: String,
    /// Image width per eye.
    pub width: u32,
    /// "mono" or "stereo".
    pub eyes_word: &'static str,
    /// The estimate at the smallest chunk, formatted.
    pub need: String,
    /// The cap, formatted.
    pub cap: String,
    /// Where the cap comes from (empty when given on the command line).
    pub source_of_cap: String,
}

/// The largest chunk (at most [`crate::stream::DEFAULT_CHUNK_POINTS`], at least
/// [`MIN_CHUNK_POINTS`]) whose streamed raster render fits `cap`.
///
/// # Errors
/// [`FrameOverBudget`] when even the smallest chunk does not fit.
pub fn raster_chunk_points(
    file: &std::path::Path,
    width: u32,
    eyes: u32,
    cap: u64,
    cap_is_default: bool,
) -> Result<usize, FrameOverBudget> {
    let mut chunk = crate::stream::DEFAULT_CHUNK_POINTS;
    while raster_stream_estimate(width, eyes, chunk as u64).total() > cap {
        if chunk <= MIN_CHUNK_POINTS {
            return Err(FrameOverBudget {
                file: file.display().to_string(),
                width,
                eyes_word: if eyes > 1 { "stereo" } else { "mono" },
                need: format_size(raster_stream_estimate(width, eyes, chunk as u64).total()),
                cap: format_size(cap),
                source_of_cap: cap_source(cap_is_default),
            });
        }
        chunk /= 2;
    }
    Ok(chunk)
}

fn cap_source(cap_is_default: bool) -> String {
    if cap_is_default {
        format!(
            " ({:.0}% of the available memory)",
            DEFAULT_FRACTION * 100.0
        )
    } else {
        String::new()
    }
}

/// Parses a size: a number with an optional binary unit `K`, `M`, `G`, `T`, `P`, `E` (powers
/// of 1024, optionally followed by `B` or `iB`, case-insensitive), e.g. `2G`, `800M`,
/// `1.5GiB`, `4096`.
///
/// # Errors
/// A message naming the value and saying what is wrong with it.
pub fn parse_size(s: &str) -> Result<u64, String> {
    let lower = s.trim().to_ascii_lowercase();
    let body = lower
        .strip_suffix("ib")
        .or_else(|| lower.strip_suffix('b'))
        .unwrap_or(&lower);
    // bytesize reads `K`, `M`, `G` as powers of 1000 and `Ki`, `Mi`, `Gi` as powers of 1024;
    // a memory cap has always meant the binary units, so every unit letter is made binary.
    let binary = if body.ends_with(|c: char| c.is_ascii_alphabetic()) {
        format!("{body}iB")
    } else {
        format!("{body}B")
    };
    let bytes = binary
        .parse::<ByteSize>()
        .map_err(|_| format!("'{s}' is not a size (e.g. 2G, 800M, 1.5GiB)"))?
        .as_u64();
    match bytes {
        0 => Err(format!("'{s}': a memory size must be at least one byte")),
        // bytesize saturates what does not fit.
        u64::MAX => Err(format!("'{s}' is too large")),
        _ => Ok(bytes),
    }
}

/// `bytes` as a short human size: `1.5 GiB`, `800.0 MiB`, `512 B`.
pub fn format_size(bytes: u64) -> String {
    ByteSize::b(bytes).display().iec().to_string()
}

/// The memory available to new allocations (`MemAvailable` on Linux), bytes; `None` where the
/// platform does not report it.
pub fn mem_available() -> Option<u64> {
    // Only the RAM figures: no process, CPU or disk scan.
    let refresh = RefreshKind::nothing().with_memory(MemoryRefreshKind::nothing().with_ram());
    let system = System::new_with_specifics(refresh).ok()?;
    Some(system.available_memory()).filter(|&b| b > 0)
}

/// The default cap: [`DEFAULT_FRACTION`] of the available memory, or no cap when it is
/// unknown.
pub fn default_cap() -> Option<u64> {
    mem_available().map(|b| (b as f64 * DEFAULT_FRACTION) as u64)
}

/// Peak resident memory of this process (`VmHWM` of `/proc/self/status`), bytes; `None` where
/// unavailable (not Linux). Read by hand because sysinfo reports only the current resident
/// size, and a peak is what bounds a render.
pub fn peak_resident() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/status").ok()?;
    status_kb(&text, "VmHWM:").map(|kb| kb * 1024)
}

/// A `NAME:   1234 kB` line of `/proc/self/status`, in kB.
fn status_kb(text: &str, name: &str) -> Option<u64> {
    text.lines()
        .find_map(|l| l.strip_prefix(name))
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|v| v.parse().ok())
}

/// Why a render was refused before loading.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "{file}: {points} points need an estimated {need} with the ray tracer, over the memory cap of {cap}{source_of_cap}; use --renderer raster (GPU), --subsample N|auto, or raise --max-memory"
)]
pub struct OverBudget {
    /// The file.
    pub file: String,
    /// Points the estimate is for.
    pub points: u64,
    /// The estimate, formatted.
    pub need: String,
    /// The cap, formatted.
    pub cap: String,
    /// Where the cap comes from (empty when given on the command line).
    pub source_of_cap: String,
}

/// Checks `estimate` against `cap`; `cap_is_default` words the error.
///
/// # Errors
/// [`OverBudget`] when the estimate exceeds the cap.
pub fn check_budget(
    file: &std::path::Path,
    estimate: &MemoryEstimate,
    cap: u64,
    cap_is_default: bool,
) -> Result<(), OverBudget> {
    if estimate.total() <= cap {
        return Ok(());
    }
    Err(OverBudget {
        file: file.display().to_string(),
        points: estimate.points,
        need: format_size(estimate.total()),
        cap: format_size(cap),
        source_of_cap: cap_source(cap_is_default),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_within_a_cap_are_the_estimates_inverse() {
        for (cap, width, eyes) in [(120 << 20, 128, 1), (2 << 30, 3840, 2), (1 << 20, 512, 2)] {
            let n = raytrace_points_within(cap, width, eyes);
            let fits = |n: u64| raytrace_estimate(n, n, width, eyes).total() <= cap;
            assert!(n == 0 || fits(n), "{cap} {width} {eyes}: {n}");
            assert!(!fits(n + 1), "{cap} {width} {eyes}: {n}");
        }
    }

    #[test]
    fn sizes_parse_with_binary_units() {
        assert_eq!(parse_size("2G"), Ok(2 << 30));
        assert_eq!(parse_size("800M"), Ok(800 << 20));
        assert_eq!(parse_size("800m"), Ok(800 << 20));
        assert_eq!(parse_size("1.5GiB"), Ok(3 << 29));
        assert_eq!(parse_size("64KB"), Ok(64 << 10));
        assert_eq!(parse_size("4096"), Ok(4096));
        assert_eq!(parse_size(" 1T "), Ok(1 << 40));
        assert_eq!(parse_size("1.5 g"), Ok(3 << 29));
        assert_eq!(parse_size("2gb"), Ok(2 << 30));
        assert_eq!(parse_size("1.5"), Ok(1));
        assert_eq!(parse_size("1P"), Ok(1 << 50));
        assert_eq!(
            parse_size("2X"),
            Err("'2X' is not a size (e.g. 2G, 800M, 1.5GiB)".into())
        );
        assert!(parse_size("0.5").unwrap_err().contains("at least one byte"));
        assert!(parse_size("99999999E").unwrap_err().contains("too large"));
        for bad in [
            "", "G", "-1G", "0", "2X", "nanG", "infG", "1e30T", "2 G B B",
        ] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn sizes_format_readably() {
        assert_eq!(format_size(512), "512 B");
        assert_eq!(format_size(3 << 29), "1.5 GiB");
        assert_eq!(format_size(800 << 20), "800.0 MiB");
        assert_eq!(format_size(2 << 30), "2.0 GiB");
    }

    #[test]
    fn status_lines_parse() {
        let text = "VmPeak:   24000000 kB\nVmHWM:   21000000 kB\n";
        assert_eq!(status_kb(text, "VmHWM:"), Some(21_000_000));
        assert_eq!(status_kb(text, "VmRSS:"), None);
        assert!(peak_resident().is_some_and(|b| b > 0));
    }

    #[test]
    fn available_memory_is_known_and_capped_at_the_default_fraction() {
        let available = mem_available().expect("sysinfo reports available memory here");
        let cap = default_cap().expect("a default cap");
        assert!(available > 64 << 20, "{available}");
        // Both read the same figure a moment apart; allow for other processes in between.
        let expected = DEFAULT_FRACTION * available as f64;
        assert!(
            (cap as f64 - expected).abs() < 0.05 * expected,
            "{cap} vs {expected}"
        );
    }

    #[test]
    fn the_stream_chunk_shrinks_to_fit_the_cap_and_the_frame_must_fit() {
        let file = std::path::Path::new("big.laz");
        let full = crate::stream::DEFAULT_CHUNK_POINTS;
        assert_eq!(raster_chunk_points(file, 3840, 2, 8 << 30, false), Ok(full));
        let roomy = raster_stream_estimate(3840, 2, full as u64).total();
        let tight = raster_chunk_points(file, 3840, 2, roomy - 1, false).unwrap();
        assert_eq!(tight, full / 2);
        assert!(raster_stream_estimate(3840, 2, tight as u64).total() < roomy);
        // The target: under 1 GB at 3840×1920 whatever the file's size (no point
        // count goes in), ODS included.
        assert!(raster_stream_estimate(3840, 2, full as u64).total() < 1 << 30);
        let e = raster_chunk_points(file, 3840, 2, 300 << 20, true).unwrap_err();
        let text = e.to_string();
        for needle in [
            "big.laz",
            "3840",
            "stereo",
            "300.0 MiB",
            "--width",
            "available",
        ] {
            assert!(text.contains(needle), "{needle}: {text}");
        }
    }

    #[test]
    fn the_budget_names_estimate_and_cap() {
        let est = raytrace_estimate(100_000_000, 100_000_000, 3840, 1);
        assert!(est.total() > 100_000_000 * RAYTRACE_BYTES_PER_POINT);
        let e = check_budget(std::path::Path::new("big.laz"), &est, 2 << 30, false).unwrap_err();
        let text = e.to_string();
        for needle in [
            "big.laz",
            "100000000 points",
            "2.0 GiB",
            "--renderer raster",
            "--subsample",
        ] {
            assert!(text.contains(needle), "{needle}: {text}");
        }
        assert!(
            check_budget(
                std::path::Path::new("a"),
                &raytrace_estimate(10, 10, 64, 1),
                1 << 30,
                true
            )
            .is_ok()
        );
    }
}
