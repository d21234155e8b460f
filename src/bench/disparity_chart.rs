//! Angular disparity error of a stereo method against exact ODS, binned by longitude and by
//! latitude: statistics, charts (PNG and SVG) and a markdown table.
//!
//! Both disparity images are full equirectangular left-eye images of the same size: pixel
//! `(i, j)` lies at longitude `(i + 0.5)/W * 360 - 180` and latitude `90 - (j + 0.5)/H * 180`
//! degrees. The error of a pixel is `other.dh - reference.dh` (arcminutes) where both are
//! finite; other pixels are left out.

use std::ops::Range;
use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::chart::{ChartError, palette, write_both};
use crate::font::FONT;
use crate::projection::disparity_image::DisparityImage;

/// Errors below this many arcminutes are drawn at it on the log axis, so exact methods stay
/// visible.
pub const ERROR_FLOOR_ARCMIN: f64 = 1e-4;

/// The absolute error of the pixels of one bin, arcminutes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BinStat {
    /// Centre of the bin, degrees.
    pub center_deg: f64,
    /// Mean absolute error; NaN when the bin holds no pixel.
    pub mean_abs_arcmin: f64,
    /// Largest absolute error; NaN when the bin holds no pixel.
    pub max_abs_arcmin: f64,
    /// Pixels in the bin.
    pub count: usize,
}

/// One method's disparity error against the reference.
#[derive(Debug, Clone, PartialEq)]
pub struct DisparityErrorSeries {
    /// The method, e.g. `parallel`.
    pub method: String,
    /// Equal longitude bins, west (-180°) to east.
    pub by_longitude: Vec<BinStat>,
    /// Equal latitude bins, south (-90°) to north.
    pub by_latitude: Vec<BinStat>,
    /// Every compared pixel.
    pub overall: BinStat,
    /// The pixel columns straight ahead: centres within half a pixel of 0°.
    pub ahead: BinStat,
    /// The pixel columns to the sides: centres within half a pixel of -90° or +90°.
    pub sideways: BinStat,
}

/// Why two disparity images cannot be compared.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DisparityErrorSeriesError {
    /// The images differ in size, or a buffer does not match its image's size.
    #[error("{method}: disparity image is {other:?} pixels, the reference {reference:?}")]
    SizeMismatch {
        /// The method compared.
        method: String,
        /// Reference (width, height).
        reference: (u32, u32),
        /// The method's (width, height).
        other: (u32, u32),
    },
    /// No bins were asked for.
    #[error("{method}: at least one longitude bin is needed")]
    NoBins {
        /// The method compared.
        method: String,
    },
}

/// Running sums of one bin.
#[derive(Debug, Clone, Copy, Default)]
struct Acc {
    sum: f64,
    max: f64,
    count: usize,
}

impl Acc {
    fn add(&mut self, abs_error: f64) {
        self.sum += abs_error;
        self.max = self.max.max(abs_error);
        self.count += 1;
    }

    fn stat(&self, center_deg: f64) -> BinStat {
        let (mean, max) = if self.count == 0 {
            (f64::NAN, f64::NAN)
        } else {
            (self.sum / self.count as f64, self.max)
        };
        BinStat {
            center_deg,
            mean_abs_arcmin: mean,
            max_abs_arcmin: max,
            count: self.count,
        }
    }
}

fn consistent(img: &DisparityImage) -> bool {
    let n = img.width as usize * img.height as usize;
    img.dh.len() == n && img.dv.len() == n
}

/// The error of `other` against `reference` in `bins` longitude bins over 360° and
/// `max(bins / 2, 1)` latitude bins over 180° (bins of equal angle when `bins` is even).
///
/// # Errors
/// Images of different sizes, or `bins == 0`.
pub fn disparity_error_series(
    method: impl Into<String>,
    reference: &DisparityImage,
    other: &DisparityImage,
    bins: usize,
) -> Result<DisparityErrorSeries, DisparityErrorSeriesError> {
    let method = method.into();
    let size = |img: &DisparityImage| (img.width, img.height);
    if size(reference) != size(other) || !consistent(reference) || !consistent(other) {
        return Err(DisparityErrorSeriesError::SizeMismatch {
            method,
            reference: size(reference),
            other: size(other),
        });
    }
    if bins == 0 {
        return Err(DisparityErrorSeriesError::NoBins { method });
    }
    let lat_bins = (bins / 2).max(1);
    let (w, h) = (reference.width as usize, reference.height as usize);
    // Pixel columns (in pixel units) whose centres lie within half a pixel of `lon_deg`.
    let near = |i: usize, lon_deg: f64| {
        let at = (lon_deg + 180.0) / 360.0 * w as f64;
        ((i as f64 + 0.5) - at).abs() <= 0.5 + 1e-9
    };
    let column_bin: Vec<usize> = (0..w).map(|i| (i * 2 + 1) * bins / (2 * w)).collect();
    let ahead_cols: Vec<bool> = (0..w).map(|i| near(i, 0.0)).collect();
    let side_cols: Vec<bool> = (0..w).map(|i| near(i, -90.0) || near(i, 90.0)).collect();

    let mut by_lon = vec![Acc::default(); bins];
    let mut by_lat = vec![Acc::default(); lat_bins];
    let (mut overall, mut ahead, mut sideways) = (Acc::default(), Acc::default(), Acc::default());
    for j in 0..h {
        // Bins run south to north: row j's latitude (90 - (j + 0.5)/H * 180) from -90.
        let lat_bin = ((2 * (h - j) - 1) * lat_bins) / (2 * h);
        for i in 0..w {
            let k = j * w + i;
            let (r, o) = (reference.dh[k], other.dh[k]);
            if !(r.is_finite() && o.is_finite()) {
                continue;
            }
            let e = (o as f64 - r as f64).abs();
            by_lon[column_bin[i]].add(e);
            by_lat[lat_bin].add(e);
            overall.add(e);
            if ahead_cols[i] {
                ahead.add(e);
            }
            if side_cols[i] {
                sideways.add(e);
            }
        }
    }
    let center = |k: usize, n: usize, span: f64| (k as f64 + 0.5) / n as f64 * span - 0.5 * span;
    Ok(DisparityErrorSeries {
        method,
        by_longitude: (by_lon.iter().enumerate())
            .map(|(k, a)| a.stat(center(k, bins, 360.0)))
            .collect(),
        by_latitude: (by_lat.iter().enumerate())
            .map(|(k, a)| a.stat(center(k, lat_bins, 180.0)))
            .collect(),
        overall: overall.stat(0.0),
        ahead: ahead.stat(0.0),
        sideways: sideways.stat(90.0),
    })
}

/// Which binning a chart shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Axis {
    Longitude,
    Latitude,
}

impl Axis {
    fn bins(self, s: &DisparityErrorSeries) -> &[BinStat] {
        match self {
            Axis::Longitude => &s.by_longitude,
            Axis::Latitude => &s.by_latitude,
        }
    }

    fn range(self) -> Range<f64> {
        match self {
            Axis::Longitude => -180.0..180.0,
            Axis::Latitude => -90.0..90.0,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Axis::Longitude => "longitude",
            Axis::Latitude => "latitude",
        }
    }
}

fn floored(v: f64) -> f64 {
    v.max(ERROR_FLOOR_ARCMIN)
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    axis: Axis,
    series: &[DisparityErrorSeries],
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let hi = series
        .iter()
        .flat_map(|s| axis.bins(s).iter().map(|b| b.mean_abs_arcmin))
        .filter(|v| v.is_finite())
        .fold(ERROR_FLOOR_ARCMIN, f64::max);
    // Headroom above the largest error keeps the legend (upper right) off the lines.
    let y = (ERROR_FLOOR_ARCMIN * 0.5)..(hi * 8.0).max(ERROR_FLOOR_ARCMIN * 10.0);
    let title = format!(
        "Angular disparity error against exact ODS by {}",
        axis.name()
    );
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT, 22))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(80)
        .build_cartesian_2d(axis.range(), y.log_scale())?;
    chart
        .configure_mesh()
        .x_desc(format!("{}, degrees (bin centres)", axis.name()))
        .y_desc(format!(
            "mean |disparity error|, arcmin (log; 0 drawn at {ERROR_FLOOR_ARCMIN:e})"
        ))
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 15))
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()?;
    for (k, s) in series.iter().enumerate() {
        let color = palette(k);
        let style = ShapeStyle::from(&color).stroke_width(2);
        let points: Vec<(f64, f64)> = axis
            .bins(s)
            .iter()
            .filter(|b| b.count > 0)
            .map(|b| (b.center_deg, floored(b.mean_abs_arcmin)))
            .collect();
        chart
            .draw_series(LineSeries::new(points.iter().copied(), style))?
            .label(s.method.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
        chart.draw_series(points.iter().map(|&p| Circle::new(p, 3, color.filled())))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.3))
        .label_font((FONT, 13))
        .draw()?;
    root.present()
}

/// Writes `disparity_error_longitude.{png,svg}` and `disparity_error_latitude.{png,svg}`
/// into `dir` (one line per method, mean absolute error per bin on a log axis); returns the
/// files written.
pub fn write_disparity_charts(
    dir: &Path,
    series: &[DisparityErrorSeries],
) -> Result<Vec<PathBuf>, ChartError> {
    let mut written = Vec::with_capacity(4);
    for axis in [Axis::Longitude, Axis::Latitude] {
        let stem = format!("disparity_error_{}", axis.name());
        let (png, svg) = (
            dir.join(format!("{stem}.png")),
            dir.join(format!("{stem}.svg")),
        );
        write_both(
            &png,
            &svg,
            |root| draw(root, axis, series).map_err(|e| e.to_string()),
            |root| draw(root, axis, series).map_err(|e| e.to_string()),
        )?;
        written.extend([png, svg]);
    }
    Ok(written)
}

/// An error in arcminutes for the table: 4 significant digits, `–` for none.
fn cell(v: f64) -> String {
    if v.is_nan() {
        "–".to_owned()
    } else if v == 0.0 || (1e-2..1e4).contains(&v.abs()) {
        format!("{v:.4}")
    } else {
        format!("{v:.3e}")
    }
}

/// A markdown table: per method, the mean absolute error overall, straight ahead (0°) and to
/// the sides (±90° longitude), and the largest, arcminutes.
pub fn disparity_error_table(series: &[DisparityErrorSeries]) -> String {
    let mut out = String::from(
        "| method | mean abs error (arcmin) | at 0° | at ±90° | max abs error (arcmin) |\n\
         |---|---:|---:|---:|---:|\n",
    );
    for s in series {
        out.push_str(&format!(
            "| {} | {} | {} | {} | {} |\n",
            s.method,
            cell(s.overall.mean_abs_arcmin),
            cell(s.ahead.mean_abs_arcmin),
            cell(s.sideways.mean_abs_arcmin),
            cell(s.overall.max_abs_arcmin)
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: u32 = 64;
    const H: u32 = 32;

    fn lon_deg(i: u32) -> f64 {
        (i as f64 + 0.5) / W as f64 * 360.0 - 180.0
    }

    fn lat_deg(j: u32) -> f64 {
        90.0 - (j as f64 + 0.5) / H as f64 * 180.0
    }

    /// A full `W x H` image with `dh(lon, lat)` in arcminutes.
    fn image(dh: impl Fn(u32, u32) -> f32) -> DisparityImage {
        let dh: Vec<f32> = (0..H)
            .flat_map(|j| (0..W).map(move |i| (i, j)))
            .map(|(i, j)| dh(i, j))
            .collect();
        DisparityImage {
            width: W,
            height: H,
            dv: vec![0.0; dh.len()],
            dh,
        }
    }

    fn cos_error() -> (DisparityImage, DisparityImage) {
        // Row 0 of the reference and pixel (5, 3) of the method have no disparity.
        let reference = image(|_, j| if j == 0 { f32::NAN } else { 0.0 });
        let other = image(|i, j| {
            if (i, j) == (5, 3) {
                f32::NAN
            } else {
                lon_deg(i).to_radians().cos() as f32
            }
        });
        (reference, other)
    }

    #[test]
    fn cosine_of_longitude_lands_in_the_right_bins() {
        let (reference, other) = cos_error();
        let s = disparity_error_series("parallel", &reference, &other, W as usize).unwrap();
        assert_eq!(s.by_longitude.len(), 64);
        assert_eq!(s.by_latitude.len(), 32);
        // One column a bin: its |cos(lon)|.
        for (i, b) in s.by_longitude.iter().enumerate() {
            let want = lon_deg(i as u32).to_radians().cos().abs();
            assert!((b.center_deg - lon_deg(i as u32)).abs() < 1e-12);
            assert!((b.mean_abs_arcmin - want).abs() < 1e-7, "bin {i}");
            assert_eq!(b.count, if i == 5 { 30 } else { 31 });
        }
        // One row a bin, south first; the top row has no reference.
        let north = s.by_latitude.last().unwrap();
        assert_eq!((north.count, north.center_deg), (0, lat_deg(0)));
        assert!(north.mean_abs_arcmin.is_nan());
        // The mean of |cos| over 64 column centres d/2 + k d, d = 5.625°, is
        // 1 / (32 sin(d/2)) = 0.63683 (2/pi = 0.63662 in the limit).
        let full_row = 1.0 / (32.0 * (180.0 / W as f64).to_radians().sin());
        // Row 3 (bin 28) lacks column 5.
        let row_3 = (64.0 * full_row - lon_deg(5).to_radians().cos().abs()) / 63.0;
        for (k, b) in s.by_latitude[..31].iter().enumerate() {
            let want = if k == 28 { row_3 } else { full_row };
            assert!((b.mean_abs_arcmin - want).abs() < 1e-7, "bin {k}");
        }
        assert_eq!(s.by_latitude[0].center_deg, lat_deg(H - 1));
        assert_eq!(s.by_latitude[28].count, 63); // row 3
        // Straight ahead: columns at ±2.8125°; to the sides: columns at ±90° ± 2.8125°.
        let half_pixel = (180.0 / W as f64).to_radians();
        assert_eq!((s.ahead.count, s.sideways.count), (62, 124));
        assert!((s.ahead.mean_abs_arcmin - half_pixel.cos()).abs() < 1e-7);
        assert!((s.sideways.mean_abs_arcmin - half_pixel.sin()).abs() < 1e-7);
        assert!((s.overall.max_abs_arcmin - half_pixel.cos()).abs() < 1e-7);
        assert_eq!(s.overall.count, 64 * 31 - 1);
    }

    #[test]
    fn wide_bins_average_their_columns() {
        let (reference, other) = cos_error();
        let s = disparity_error_series("parallel", &reference, &other, 8).unwrap();
        let centres: Vec<f64> = s.by_longitude.iter().map(|b| b.center_deg).collect();
        assert_eq!(
            centres,
            [-157.5, -112.5, -67.5, -22.5, 22.5, 67.5, 112.5, 157.5]
        );
        // Bin [0°, 45°): the mean of cos over 8 column centres d/2 + k d, d = 5.625°, is
        // sin(45°) / (16 sin(d/2)) = 0.9007 (the integral mean is 0.9003).
        let b = s.by_longitude[4];
        assert_eq!(b.count, 8 * 31);
        let half_pixel = 2.8125f64.to_radians();
        let want = 45f64.to_radians().sin() / (16.0 * half_pixel.sin());
        assert!(
            (b.mean_abs_arcmin - want).abs() < 1e-7,
            "{} vs {want}",
            b.mean_abs_arcmin
        );
        assert!((b.max_abs_arcmin - (2.8125f64).to_radians().cos()).abs() < 1e-7);
        assert_eq!(s.by_latitude.len(), 4);
        assert_eq!(s.by_latitude[3].count, 7 * 64 - 1); // rows 0..8: row 0 empty, row 3 short
    }

    #[test]
    fn latitude_error_lands_in_latitude_bins() {
        let reference = image(|_, _| 10.0);
        let other = image(|_, j| 10.0 - (lat_deg(j) / 90.0) as f32);
        let s = disparity_error_series("cubemap:64", &reference, &other, 4).unwrap();
        // Two latitude bins: south [-90, 0) and north [0, 90), each 16 rows.
        assert_eq!(s.by_latitude.len(), 2);
        for b in &s.by_latitude {
            assert_eq!(b.count, 16 * 64);
            // Mean |lat|/90 over 16 row centres 2.8125° + k 5.625°: 0.5.
            assert!(
                (b.mean_abs_arcmin - 0.5).abs() < 2e-6,
                "{}",
                b.mean_abs_arcmin
            );
            assert!((b.max_abs_arcmin - lat_deg(0) / 90.0).abs() < 2e-6);
        }
        assert_eq!(
            (s.by_latitude[0].center_deg, s.by_latitude[1].center_deg),
            (-45.0, 45.0)
        );
        for b in &s.by_longitude {
            assert!((b.mean_abs_arcmin - 0.5).abs() < 2e-6);
        }
    }

    #[test]
    fn mismatched_images_and_zero_bins_are_errors() {
        let (reference, other) = cos_error();
        let mut small = other.clone();
        small.width = 32;
        small.dh.truncate(32 * 32);
        small.dv.truncate(32 * 32);
        let e = disparity_error_series("x", &reference, &small, 8).unwrap_err();
        assert!(
            e.to_string()
                .contains("x: disparity image is (32, 32) pixels, the reference (64, 32)"),
            "{e}"
        );
        let e = disparity_error_series("y", &reference, &other, 0).unwrap_err();
        assert!(e.to_string().contains("at least one longitude bin"), "{e}");
    }

    #[test]
    fn table_lists_each_method() {
        let (reference, other) = cos_error();
        let exact = disparity_error_series("ods exact", &reference, &reference, 8).unwrap();
        let parallel = disparity_error_series("parallel", &reference, &other, 8).unwrap();
        let table = disparity_error_table(&[exact, parallel]);
        let lines: Vec<&str> = table.lines().collect();
        assert_eq!(lines.len(), 4, "{table}");
        assert!(lines[0].starts_with("| method | mean abs error"));
        assert_eq!(
            lines[2],
            "| ods exact | 0.0000 | 0.0000 | 0.0000 | 0.0000 |"
        );
        // 0.9988 = cos(2.8125°), 0.04907 = sin(2.8125°).
        assert!(lines[3].starts_with("| parallel | 0.63"), "{}", lines[3]);
        assert!(
            lines[3].ends_with("| 0.9988 | 0.0491 | 0.9988 |"),
            "{}",
            lines[3]
        );
    }

    #[test]
    fn charts_are_written_as_png_and_svg() {
        let (reference, other) = cos_error();
        let exact = disparity_error_series("ods exact", &reference, &reference, 16).unwrap();
        let parallel = disparity_error_series("parallel", &reference, &other, 16).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let files = write_disparity_charts(dir.path(), &[exact, parallel]).unwrap();
        let names: Vec<String> = files
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(
            names,
            [
                "disparity_error_longitude.png",
                "disparity_error_longitude.svg",
                "disparity_error_latitude.png",
                "disparity_error_latitude.svg"
            ]
        );
        for f in &files {
            let bytes = std::fs::metadata(f).unwrap().len();
            if f.extension().unwrap() == "png" {
                // Measured 92 and 95 kB.
                assert!(bytes > 60_000, "{} is {bytes} bytes", f.display());
                let img = image::open(f).unwrap().to_rgb8();
                assert_eq!(img.dimensions(), super::super::chart::CHART_SIZE);
            } else {
                // Measured 19 and 20 kB.
                assert!(bytes > 15_000, "{} is {bytes} bytes", f.display());
                let svg = std::fs::read_to_string(f).unwrap();
                assert!(svg.contains("ods exact") && svg.contains("parallel"));
            }
        }
    }
}
