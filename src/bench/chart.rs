//! Charts with `plotters`: speed against accuracy per mode, and error by latitude band.
//!
//! Pure-Rust backends only: bitmap (encoded to PNG by `image`) and SVG; text in the embedded
//! font of [`crate::font`].

use std::ops::Range;
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::font::{FONT, register_font};
use crate::render::Imposter;

use super::report::{BenchReport, TimingKind};

/// Chart size in pixels (PNG) and user units (SVG).
pub const CHART_SIZE: (u32, u32) = (960, 640);

/// Errors are clamped up to this fraction on log axes, so exact results (0) stay visible.
pub const ERROR_FLOOR: f64 = 1e-6;

/// One marker of the speed/accuracy chart.
#[derive(Debug, Clone, PartialEq)]
pub struct ChartPoint {
    /// Mode label, e.g. `static:4+sprite`.
    pub label: String,
    /// Fragment model (marker shape).
    pub imposter: Imposter,
    /// Median frame time, milliseconds.
    pub frame_ms: f64,
    /// Coverage mismatch as a fraction of the pixels.
    pub error: f64,
}

/// The markers of the speed/accuracy chart, one per measured mode.
pub fn speed_accuracy_points(report: &BenchReport) -> Vec<ChartPoint> {
    report
        .modes
        .iter()
        .map(|m| ChartPoint {
            label: m.mode.label(),
            imposter: m.mode.imposter,
            frame_ms: m.frame_ms,
            error: m.accuracy.coverage_mismatch,
        })
        .collect()
}

/// Indices of the Pareto-optimal points (no other point is both faster and more accurate),
/// ordered by frame time.
pub fn pareto_front(points: &[ChartPoint]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| {
        points[a]
            .frame_ms
            .total_cmp(&points[b].frame_ms)
            .then(points[a].error.total_cmp(&points[b].error))
    });
    let mut front = Vec::new();
    let mut best = f64::INFINITY;
    for i in order {
        if points[i].error < best {
            best = points[i].error;
            front.push(i);
        }
    }
    front
}

/// What a chart drew, for callers and tests.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChartSummary {
    /// Markers drawn (one per mode).
    pub markers: usize,
    /// Points on the Pareto front.
    pub pareto: usize,
}

/// A chart could not be drawn or written.
#[derive(Debug, thiserror::Error)]
#[error("cannot write chart {path}: {message}")]
pub struct ChartError {
    /// The output file.
    pub path: std::path::PathBuf,
    /// What failed.
    pub message: String,
}

fn log_range(values: impl Iterator<Item = f64>) -> Range<f64> {
    let hi = values.fold(ERROR_FLOOR, f64::max);
    (ERROR_FLOOR * 100.0 * 0.5)..(hi * 100.0 * 2.0).max(ERROR_FLOOR * 100.0 * 10.0)
}

fn pct(fraction: f64) -> f64 {
    100.0 * fraction.max(ERROR_FLOOR)
}

fn color_of(imposter: Imposter) -> RGBColor {
    match imposter {
        Imposter::Sprite => RGBColor(214, 96, 77),
        Imposter::Raycast => RGBColor(33, 102, 172),
    }
}

fn draw_speed_accuracy<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    timing: TimingKind,
    points: &[ChartPoint],
) -> Result<ChartSummary, DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    // Log time axis: frame times span orders of magnitude between proxies.
    let x_hi = points.iter().map(|p| p.frame_ms).fold(1e-3, f64::max) * 1.6;
    let x_lo = points
        .iter()
        .map(|p| p.frame_ms)
        .filter(|&t| t > 0.0)
        .fold(x_hi, f64::min)
        / 1.4;
    let y = log_range(points.iter().map(|p| p.error));
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT, 22))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(80)
        .build_cartesian_2d((x_lo..x_hi).log_scale(), y.log_scale())?;
    chart
        .configure_mesh()
        .x_desc(format!("frame time, ms, log ({})", timing.describe()))
        .y_desc("coverage mismatch, % of pixels (log; 0 drawn at 1e-4)")
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 15))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()?;

    let front = pareto_front(points);
    chart
        .draw_series(LineSeries::new(
            front
                .iter()
                .map(|&i| (points[i].frame_ms, pct(points[i].error))),
            ShapeStyle::from(&BLACK.mix(0.45)).stroke_width(2),
        ))?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.mix(0.45)));

    let at = |p: &ChartPoint| (p.frame_ms, pct(p.error));
    let short = |p: &ChartPoint| p.label.split('+').next().unwrap_or(&p.label).to_string();
    let of = |imposter| -> Vec<&ChartPoint> {
        points.iter().filter(|p| p.imposter == imposter).collect()
    };
    // Two series with concrete marker types: circles for sprites, triangles for ray casts.
    let sprites = of(Imposter::Sprite);
    if !sprites.is_empty() {
        let c = color_of(Imposter::Sprite);
        chart
            .draw_series(sprites.iter().map(|p| {
                EmptyElement::at(at(p))
                    + Circle::new((0, 0), 6, c.filled())
                    + Text::new(short(p), (8, -16), (FONT, 13))
            }))?
            .label("sprite (billboard shading)")
            .legend(move |(x, y)| Circle::new((x + 10, y), 6, c.filled()));
    }
    let casts = of(Imposter::Raycast);
    if !casts.is_empty() {
        let c = color_of(Imposter::Raycast);
        chart
            .draw_series(casts.iter().map(|p| {
                EmptyElement::at(at(p))
                    + TriangleMarker::new((0, 0), 7, c.filled())
                    + Text::new(short(p), (8, 4), (FONT, 13))
            }))?
            .label("raycast (exact per pixel)")
            .legend(move |(x, y)| TriangleMarker::new((x + 10, y), 7, c.filled()));
    }
    let markers = sprites.len() + casts.len();
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.3))
        .label_font((FONT, 14))
        .draw()?;
    root.present()?;
    Ok(ChartSummary {
        markers,
        pareto: front.len(),
    })
}

/// One line of the latitude chart: a mode's mismatch per band.
#[derive(Debug, Clone, PartialEq)]
pub struct BandSeries {
    /// Mode label.
    pub label: String,
    /// (band centre latitude in degrees, mismatched fraction) north to south.
    pub values: Vec<(f64, f64)>,
}

pub(super) fn palette(k: usize) -> RGBColor {
    const COLORS: [RGBColor; 10] = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
        RGBColor(188, 189, 34),
        RGBColor(23, 190, 207),
    ];
    COLORS[k % COLORS.len()]
}

fn draw_bands<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    series: &[BandSeries],
) -> Result<usize, DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let y = log_range(series.iter().flat_map(|s| s.values.iter().map(|v| v.1)));
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT, 22))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(80)
        .build_cartesian_2d(-90.0..90.0, y.log_scale())?;
    chart
        .configure_mesh()
        .x_desc("latitude, degrees (band centres, 10° bands)")
        .y_desc("coverage mismatch, % of band pixels (log; 0 drawn at 1e-4)")
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 15))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()?;
    for (k, s) in series.iter().enumerate() {
        let color = palette(k);
        let dashed = k >= 5;
        let style = ShapeStyle::from(&color).stroke_width(if dashed { 1 } else { 2 });
        chart
            .draw_series(LineSeries::new(
                s.values.iter().map(|&(lat, e)| (lat, pct(e))),
                style,
            ))?
            .label(s.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
        chart.draw_series(
            s.values
                .iter()
                .map(|&(lat, e)| Circle::new((lat, pct(e)), 3, color.filled())),
        )?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerMiddle)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.3))
        .label_font((FONT, 12))
        .draw()?;
    root.present()?;
    Ok(series.len())
}

/// Renders `draw` into a PNG at `png` and an SVG at `svg`.
pub(super) fn write_both<T>(
    png: &Path,
    svg: &Path,
    draw_png: impl FnOnce(&DrawingArea<BitMapBackend, Shift>) -> Result<T, String>,
    draw_svg: impl FnOnce(&DrawingArea<SVGBackend, Shift>) -> Result<T, String>,
) -> Result<T, ChartError> {
    register_font();
    let (w, h) = CHART_SIZE;
    let mut buf = vec![0u8; w as usize * h as usize * 3];
    let err = |path: &Path| {
        let path = path.to_path_buf();
        move |message: String| ChartError { path, message }
    };
    let result = {
        let root = BitMapBackend::with_buffer(&mut buf, CHART_SIZE).into_drawing_area();
        draw_png(&root).map_err(err(png))?
    };
    image::save_buffer(png, &buf, w, h, image::ExtendedColorType::Rgb8)
        .map_err(|e| err(png)(e.to_string()))?;
    let root = SVGBackend::new(svg, CHART_SIZE).into_drawing_area();
    draw_svg(&root).map_err(err(svg))?;
    Ok(result)
}

/// Writes the speed/accuracy chart of `report` (one marker per mode, labelled, Pareto front
/// drawn) as PNG and SVG.
pub fn write_speed_accuracy_chart(
    report: &BenchReport,
    png: &Path,
    svg: &Path,
) -> Result<ChartSummary, ChartError> {
    let points = speed_accuracy_points(report);
    let title = format!(
        "{}: speed vs accuracy ({} pts, {}×{} {}, {})",
        report.scene,
        report.points,
        report.width,
        report.height,
        report.stereo,
        report.adapter.split(" (").next().unwrap_or(&report.adapter)
    );
    let timing = report.timing();
    write_both(
        png,
        svg,
        |root| draw_speed_accuracy(root, &title, timing, &points).map_err(|e| e.to_string()),
        |root| draw_speed_accuracy(root, &title, timing, &points).map_err(|e| e.to_string()),
    )
}

/// Writes the error-by-latitude chart (one line per series) as PNG and SVG; returns the
/// number of lines drawn.
pub fn write_band_chart(
    title: &str,
    series: &[BandSeries],
    png: &Path,
    svg: &Path,
) -> Result<usize, ChartError> {
    write_both(
        png,
        svg,
        |root| draw_bands(root, title, series).map_err(|e| e.to_string()),
        |root| draw_bands(root, title, series).map_err(|e| e.to_string()),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(frame_ms: f64, error: f64) -> ChartPoint {
        ChartPoint {
            label: String::new(),
            imposter: Imposter::Sprite,
            frame_ms,
            error,
        }
    }

    #[test]
    fn pareto_front_keeps_only_undominated_points_in_time_order() {
        let pts = [
            p(1.0, 0.5),
            p(2.0, 0.6),
            p(3.0, 0.1),
            p(4.0, 0.1),
            p(5.0, 0.0),
        ];
        assert_eq!(pareto_front(&pts), vec![0, 2, 4]);
    }

    #[test]
    fn zero_errors_sit_at_the_floor_inside_the_axis() {
        let r = log_range([0.0, 0.0].into_iter());
        assert!(r.contains(&pct(0.0)));
    }

    #[test]
    fn sample_charts_are_written_as_png_and_svg() {
        let report = crate::bench::report::tests::sample_report();
        let dir = std::env::temp_dir().join("omnicloud_chart_test");
        std::fs::create_dir_all(&dir).unwrap();
        let (png, svg) = (dir.join("speed.png"), dir.join("speed.svg"));
        let s = write_speed_accuracy_chart(&report, &png, &svg).unwrap();
        assert_eq!(s.markers, 10);
        let img = image::open(&png).unwrap().to_rgb8();
        assert_eq!(img.dimensions(), CHART_SIZE);
        let series = vec![BandSeries {
            label: "quad+sprite".into(),
            values: report.modes[0]
                .accuracy
                .bands
                .iter()
                .map(|b| (0.5 * (b.lat_lo_deg + b.lat_hi_deg), b.fraction()))
                .collect(),
        }];
        let n = write_band_chart("bands", &series, &dir.join("b.png"), &dir.join("b.svg")).unwrap();
        assert_eq!(n, 1);
        assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
    }
}
