//! What a benchmark measured, and its CSV and Markdown forms.

use std::fmt::Write as _;

use serde::{Deserialize, Serialize, Serializer};

use crate::render::{Imposter, Proxy};

use super::mode::{BenchMode, TABLE_IMPOSTERS, TABLE_PROXIES, imposter_name, proxy_heading};

/// How frame times were measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TimingKind {
    /// GPU timestamp queries around the expand and draw passes.
    GpuTimestamps,
    /// Wall clock from the first submission to the end of the GPU work (the adapter has no
    /// timestamp queries).
    WallClock,
}

impl TimingKind {
    /// Words for tables and chart captions.
    pub fn describe(self) -> &'static str {
        match self {
            TimingKind::GpuTimestamps => "GPU timestamp queries",
            TimingKind::WallClock => "wall clock (no GPU timestamps on this adapter)",
        }
    }
}

/// Coverage mismatch in one 10° latitude band.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BandAccuracy {
    /// Southern edge of the band, degrees.
    pub lat_lo_deg: f64,
    /// Northern edge of the band, degrees.
    pub lat_hi_deg: f64,
    /// Pixels in the band (all eyes).
    pub pixels: u64,
    /// Pixels in the band covered by exactly one of reference and test.
    pub mismatched: u64,
}

impl BandAccuracy {
    /// Mismatched fraction of the band's pixels.
    pub fn fraction(&self) -> f64 {
        if self.pixels == 0 {
            0.0
        } else {
            self.mismatched as f64 / self.pixels as f64
        }
    }
}

/// Coverage mismatch in one image region (all eyes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct RegionCount {
    /// Pixels in the region.
    pub pixels: u64,
    /// Pixels in the region covered by exactly one of reference and test.
    pub mismatched: u64,
}

impl RegionCount {
    /// Mismatched fraction of the region's pixels.
    pub fn fraction(&self) -> f64 {
        if self.pixels == 0 {
            0.0
        } else {
            self.mismatched as f64 / self.pixels as f64
        }
    }
}

/// Accuracy of one render against the ray-traced reference, over all eyes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Accuracy {
    /// Fraction of all pixels covered by exactly one of reference and test.
    pub coverage_mismatch: f64,
    /// Intersection over union of the covered pixel sets (1 when both are empty).
    pub iou: f64,
    /// Median relative depth error `|d - d_ref| / d_ref` where both hit.
    pub depth_rel_p50: f64,
    /// 99th percentile of the relative depth error where both hit.
    pub depth_rel_p99: f64,
    /// Largest relative depth error where both hit.
    pub depth_rel_max: f64,
    /// Fraction of pixels hit by both whose RGB differs.
    pub color_mismatch: f64,
    /// Colour PSNR (peak 1, sRGB) over the pixels both hit, dB (`None` when their colours are
    /// identical or no pixel is hit by both).
    pub psnr_db: Option<f64>,
    /// Coverage mismatch per 10° latitude band, north to south (as `compare` orders them).
    pub bands: Vec<BandAccuracy>,
    /// Coverage mismatch in the seam columns (as `compare` defines them: the 1 % of columns
    /// nearest each edge, at least one each side); only in full equirect panoramas, as are
    /// the bands.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seam: Option<RegionCount>,
}

impl Accuracy {
    /// Coverage mismatch in the worse of the two polar bands (|latitude| ≥ 80°).
    pub fn polar_mismatch(&self) -> f64 {
        let first = self.bands.first().map_or(0.0, BandAccuracy::fraction);
        let last = self.bands.last().map_or(0.0, BandAccuracy::fraction);
        first.max(last)
    }
}

/// Counts the rasterizer reported for one frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct ModeStats {
    /// Points whose centre has no projection.
    pub culled: u64,
    /// Points that produced a proxy.
    pub drawn: u64,
    /// Proxies drawn as analytic bounds with forced ray casting.
    pub special: u64,
    /// Proxies drawn twice across the seam.
    pub seam_copies: u64,
    /// Vertices written.
    pub vertices: u64,
    /// Spheres the compute splat ray cast instead of drawing (counted in `drawn`; in the JSON
    /// only, as the CSV keeps the columns of the committed benchmark files).
    #[serde(default)]
    pub splatted: u64,
    /// Spheres skipped whole, hidden by nearer ones (counted in `drawn`).
    #[serde(default)]
    pub hidden: u64,
}

/// One rasterizer mode's speed and accuracy.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeResult {
    /// The mode.
    pub mode: BenchMode,
    /// Median frame time over the timed frames, milliseconds.
    pub frame_ms: f64,
    /// Fastest timed frame, milliseconds.
    pub frame_ms_min: f64,
    /// Slowest timed frame, milliseconds.
    pub frame_ms_max: f64,
    /// `1000 / frame_ms`.
    pub fps: f64,
    /// Timed frames per second of wall-clock time over the whole timed run, each frame
    /// drawn and read back into host memory (scene resident on the GPU): what a tour or a
    /// live viewer gets.
    #[serde(default)]
    pub sustained_fps: f64,
    /// Median frame time of the mono frames of the same camera and mode timed between the
    /// stereo ones, milliseconds (a stereo benchmark with the mono baseline only; in the
    /// JSON only, as the CSV keeps the columns of the committed benchmark files).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mono_frame_ms: Option<f64>,
    /// How the frame times were measured.
    pub timing: TimingKind,
    /// Accuracy of the first timed frame against the reference.
    pub accuracy: Accuracy,
    /// Rasterizer counts.
    pub stats: ModeStats,
}

impl ModeResult {
    /// Median stereo frame over median mono frame, when mono frames were timed beside it.
    pub fn stereo_over_mono(&self) -> Option<f64> {
        self.mono_frame_ms
            .filter(|&m| m > 0.0)
            .map(|m| self.frame_ms / m)
    }
}

/// The ray-traced reference render.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ReferenceRun {
    /// Wall-clock seconds for one render, BVH build included.
    pub seconds: f64,
    /// Rayon threads it ran on.
    pub threads: usize,
}

/// Everything one `bench` run measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BenchReport {
    /// Scene name (file stem or suite entry).
    pub scene: String,
    /// Points in the scene.
    pub points: usize,
    /// Image width per eye.
    pub width: u32,
    /// Image height per eye.
    pub height: u32,
    /// The projection, as `--projection` writes it (`equirect` in reports that predate it).
    #[serde(default = "equirect")]
    pub projection: String,
    /// `mono` or `ods`.
    pub stereo: String,
    /// Metres per unit of the scene's coordinates (its IPD and radii are in that unit);
    /// `None` when the scan declares no unit of length.
    #[serde(default)]
    pub metres_per_unit: Option<f64>,
    /// What a COPC file's level of detail read for the camera (`None`: every point).
    #[serde(default)]
    pub level_of_detail: Option<crate::prepare::LodReport>,
    /// The GPU adapter (name and backend).
    pub adapter: String,
    /// Frames rendered before timing, per mode.
    pub warmup_frames: usize,
    /// Frames timed per mode (the report gives their median).
    pub timed_frames: usize,
    /// The reference render.
    pub reference: ReferenceRun,
    /// One result per mode, in the configured order.
    pub modes: Vec<ModeResult>,
}

impl BenchReport {
    /// The result of `mode`, if it was measured.
    pub fn mode(&self, mode: BenchMode) -> Option<&ModeResult> {
        self.modes.iter().find(|m| m.mode == mode)
    }

    /// How this report's frame times were measured: GPU timestamps only when every mode had
    /// them.
    pub fn timing(&self) -> TimingKind {
        if !self.modes.is_empty()
            && self
                .modes
                .iter()
                .all(|m| m.timing == TimingKind::GpuTimestamps)
        {
            TimingKind::GpuTimestamps
        } else {
            TimingKind::WallClock
        }
    }
}

/// One CSV line: a mode of one report. The field names are the column names, in order.
#[derive(Serialize)]
struct CsvRow<'a> {
    scene: &'a str,
    points: usize,
    width: u32,
    height: u32,
    stereo: &'a str,
    mode: String,
    proxy: String,
    imposter: &'static str,
    #[serde(serialize_with = "fixed::<4, _>")]
    frame_ms_median: f64,
    #[serde(serialize_with = "fixed::<4, _>")]
    frame_ms_min: f64,
    #[serde(serialize_with = "fixed::<4, _>")]
    frame_ms_max: f64,
    #[serde(serialize_with = "fixed::<2, _>")]
    fps: f64,
    #[serde(serialize_with = "fixed::<2, _>")]
    sustained_fps: f64,
    timing: TimingKind,
    frames: usize,
    #[serde(serialize_with = "scientific::<6, _>")]
    coverage_mismatch: f64,
    #[serde(serialize_with = "fixed::<6, _>")]
    iou: f64,
    #[serde(serialize_with = "scientific::<3, _>")]
    depth_rel_p50: f64,
    #[serde(serialize_with = "scientific::<3, _>")]
    depth_rel_p99: f64,
    #[serde(serialize_with = "scientific::<3, _>")]
    depth_rel_max: f64,
    #[serde(serialize_with = "scientific::<6, _>")]
    color_mismatch: f64,
    /// `inf` when the images are identical.
    #[serde(serialize_with = "psnr")]
    psnr_db: Option<f64>,
    culled: u64,
    drawn: u64,
    special: u64,
    seam_copies: u64,
    vertices: u64,
}

impl<'a> CsvRow<'a> {
    fn new(report: &'a BenchReport, m: &ModeResult) -> CsvRow<'a> {
        let a = &m.accuracy;
        CsvRow {
            scene: &report.scene,
            points: report.points,
            width: report.width,
            height: report.height,
            stereo: &report.stereo,
            mode: m.mode.label(),
            proxy: m.mode.proxy_name(),
            imposter: m.mode.imposter_name(),
            frame_ms_median: m.frame_ms,
            frame_ms_min: m.frame_ms_min,
            frame_ms_max: m.frame_ms_max,
            fps: m.fps,
            sustained_fps: m.sustained_fps,
            timing: m.timing,
            frames: report.timed_frames,
            coverage_mismatch: a.coverage_mismatch,
            iou: a.iou,
            depth_rel_p50: a.depth_rel_p50,
            depth_rel_p99: a.depth_rel_p99,
            depth_rel_max: a.depth_rel_max,
            color_mismatch: a.color_mismatch,
            psnr_db: a.psnr_db,
            culled: m.stats.culled,
            drawn: m.stats.drawn,
            special: m.stats.special,
            seam_copies: m.stats.seam_copies,
            vertices: m.stats.vertices,
        }
    }
}

/// `v` with `DIGITS` decimals.
fn fixed<const DIGITS: usize, S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{v:.DIGITS$}"))
}

/// `v` in scientific notation with `DIGITS` decimals (`4.468918e-3`).
fn scientific<const DIGITS: usize, S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{v:.DIGITS$e}"))
}

fn psnr<S: Serializer>(v: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
    match v {
        Some(p) => fixed::<2, S>(p, s),
        None => s.serialize_str("inf"),
    }
}

/// Writes the CSV table of `reports` to `out`: a header, then one row per mode of each report
/// in order (nothing at all when there is no row).
///
/// # Errors
/// The error of writing to `out`.
pub fn write_csv<'a>(
    out: impl std::io::Write,
    reports: impl IntoIterator<Item = &'a BenchReport>,
) -> std::io::Result<()> {
    let mut writer = csv::Writer::from_writer(out);
    for report in reports {
        for m in &report.modes {
            writer.serialize(CsvRow::new(report, m))?;
        }
    }
    writer.flush()
}

/// Percent with enough digits to tell small errors apart.
pub fn percent(fraction: f64) -> String {
    let p = 100.0 * fraction;
    if p == 0.0 {
        "0 %".to_string()
    } else if p >= 1.0 {
        format!("{p:.2} %")
    } else {
        format!("{p:.2e} %")
    }
}

fn cell(report: &BenchReport, proxy: Proxy, imposter: Imposter) -> Option<&ModeResult> {
    report.mode(BenchMode { proxy, imposter })
}

fn equirect() -> String {
    "equirect".into()
}

/// The report as Markdown: a header with the setup, then a table in the shape of the paper's
/// Table 1 (columns: proxies; rows: per imposter, frame time, coverage error, depth error).
pub fn markdown(report: &BenchReport) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "## Benchmark: {}\n", report.scene);
    let _ = writeln!(
        out,
        "- {} points, {}×{} per eye{}, {}\n- adapter: {}\n- frame time: median of {} frames after {} warm-up frames, measured by {}\n- reference: CPU ray tracer, {:.3} s on {} threads",
        report.points,
        report.width,
        report.height,
        if report.projection == "equirect" {
            String::new()
        } else {
            format!(" ({})", report.projection)
        },
        report.stereo,
        report.adapter,
        report.timed_frames,
        report.warmup_frames,
        report.timing().describe(),
        report.reference.seconds,
        report.reference.threads,
    );
    if let Some(lod) = &report.level_of_detail {
        let _ = writeln!(out, "- {lod}");
    }
    let _ = writeln!(out);
    let proxies: Vec<Proxy> = TABLE_PROXIES
        .iter()
        .copied()
        .filter(|&p| {
            TABLE_IMPOSTERS
                .iter()
                .any(|&i| cell(report, p, i).is_some())
        })
        .collect();
    out.push_str("| imposter | metric |");
    for &p in &proxies {
        let _ = write!(out, " {} |", proxy_heading(p));
    }
    out.push_str("\n|---|---|");
    for _ in &proxies {
        out.push_str("---:|");
    }
    out.push('\n');
    type Metric = (&'static str, fn(&ModeResult) -> String);
    let mut metrics: Vec<Metric> = vec![
        ("frame time (fps)", |m| {
            format!("{:.2} ms ({:.0} fps)", m.frame_ms, m.fps)
        }),
        ("sustained fps", |m| format!("{:.1}", m.sustained_fps)),
        ("coverage mismatch", |m| {
            percent(m.accuracy.coverage_mismatch)
        }),
        ("depth rel. err. p99", |m| {
            format!("{:.1e}", m.accuracy.depth_rel_p99)
        }),
        ("colour mismatch", |m| percent(m.accuracy.color_mismatch)),
    ];
    let baseline = report.modes.iter().any(|m| m.mono_frame_ms.is_some());
    if baseline {
        metrics.insert(
            1,
            ("stereo / mono", |m| {
                match (m.stereo_over_mono(), m.mono_frame_ms) {
                    (Some(r), Some(mono)) => format!("{r:.2} (mono {mono:.2} ms)"),
                    _ => "–".into(),
                }
            }),
        );
    }
    for &imposter in &TABLE_IMPOSTERS {
        if !proxies.iter().any(|&p| cell(report, p, imposter).is_some()) {
            continue;
        }
        for (name, f) in &metrics {
            let _ = write!(out, "| {} | {name} |", imposter_name(imposter));
            for &p in &proxies {
                let text = cell(report, p, imposter)
                    .map(f)
                    .unwrap_or_else(|| "–".into());
                let _ = write!(out, " {text} |");
            }
            out.push('\n');
        }
    }
    if baseline {
        out.push_str(
            "\nStereo / mono: median stereo frame over the median of the mono frames of the same \
             camera and mode, each timed right after a stereo frame.",
        );
    }
    out.push_str(
        "\nSustained fps: timed frames per wall-clock second, each drawn and read back to host \
         memory. Coverage mismatch: share of pixels that exactly one of reference and test covers. \
         Depth error: |d − d_ref| / d_ref where both hit. Colour mismatch: share of pixels hit \
         by both whose unlit colour differs.\n",
    );
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A report with made-up numbers for every mode, for output tests.
    pub(crate) fn sample_report() -> BenchReport {
        let modes = BenchMode::all()
            .into_iter()
            .enumerate()
            .map(|(k, mode)| ModeResult {
                mode,
                frame_ms: 2.0 + k as f64,
                frame_ms_min: 1.5 + k as f64,
                frame_ms_max: 3.0 + k as f64,
                fps: 1000.0 / (2.0 + k as f64),
                sustained_fps: 400.0 / (2.0 + k as f64),
                mono_frame_ms: None,
                timing: TimingKind::WallClock,
                accuracy: Accuracy {
                    coverage_mismatch: 0.05 / (k as f64 + 1.0).powi(2),
                    iou: 0.9,
                    depth_rel_p50: 1e-5,
                    depth_rel_p99: 1e-3,
                    depth_rel_max: 1e-2,
                    color_mismatch: 0.0,
                    psnr_db: Some(30.0),
                    bands: (0..18)
                        .map(|b| BandAccuracy {
                            lat_lo_deg: 80.0 - 10.0 * b as f64,
                            lat_hi_deg: 90.0 - 10.0 * b as f64,
                            pixels: 1000,
                            mismatched: if b == 0 || b == 17 {
                                50 / (k as u64 + 1)
                            } else {
                                1
                            },
                        })
                        .collect(),
                    seam: Some(RegionCount {
                        pixels: 100,
                        mismatched: 10 - k as u64,
                    }),
                },
                stats: ModeStats::default(),
            })
            .collect();
        BenchReport {
            scene: "sample".into(),
            points: 100,
            width: 64,
            height: 32,
            projection: "equirect".into(),
            stereo: "mono".into(),
            metres_per_unit: Some(0.3048),
            level_of_detail: None,
            adapter: "test adapter".into(),
            warmup_frames: 1,
            timed_frames: 3,
            reference: ReferenceRun {
                seconds: 0.5,
                threads: 2,
            },
            modes,
        }
    }

    /// `bench.json` is read back by scripts and tests: every f64 must survive it bit for bit,
    /// including values whose shortest decimal serde_json's default parser rounds wrongly.
    #[test]
    fn json_round_trips_every_f64_exactly() {
        let mut report = sample_report();
        report.modes[0].frame_ms = 0.473_516_000_000_000_05;
        report.modes[0].mono_frame_ms = Some(0.473_516_000_000_000_1);
        report.modes[1].accuracy.depth_rel_p99 = f64::from_bits(5); // subnormal
        let text = serde_json::to_string(&report).unwrap();
        let back: BenchReport = serde_json::from_str(&text).unwrap();
        for (a, b) in report.modes.iter().zip(&back.modes) {
            assert_eq!(a.frame_ms.to_bits(), b.frame_ms.to_bits());
            assert_eq!(
                a.mono_frame_ms.map(f64::to_bits),
                b.mono_frame_ms.map(f64::to_bits)
            );
            assert_eq!(
                a.accuracy.depth_rel_p99.to_bits(),
                b.accuracy.depth_rel_p99.to_bits()
            );
        }
    }

    #[test]
    fn csv_has_a_row_per_mode_with_every_column() {
        let mut bytes = Vec::new();
        write_csv(&mut bytes, [&sample_report()]).unwrap();
        let text = String::from_utf8(bytes).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 11);
        // The columns of the committed benchmark files, in their order.
        let committed = include_str!("../../docs/bench/suite.csv");
        assert_eq!(lines[0], committed.lines().next().unwrap());
        for l in &lines {
            assert_eq!(l.split(',').count(), 27, "{l}");
        }
        assert_eq!(
            lines[1],
            "sample,100,64,32,mono,quad+sprite,quad,sprite,2.0000,1.5000,3.0000,500.00,200.00,\
             wall-clock,3,5.000000e-2,0.900000,1.000e-5,1.000e-3,1.000e-2,0.000000e0,30.00,\
             0,0,0,0,0"
        );
    }

    #[test]
    fn markdown_table_has_paper_columns_and_a_row_per_metric() {
        let md = markdown(&sample_report());
        assert!(md.contains(
            "| imposter | metric | No Tess. | Static (4) | Static (16) | Dynamic | Bounds (ours) |"
        ));
        let rows = md
            .lines()
            .filter(|l| l.starts_with("| sprite") || l.starts_with("| raycast"));
        assert_eq!(rows.count(), 10);
        assert!(md.contains("| sprite | frame time (fps) | 2.00 ms (500 fps) |"));
        assert!(md.contains("| sprite | sustained fps | 200.0 |"));
        assert!(md.contains("wall clock"));
    }
}
