//! Large synthetic scans for out-of-core tests and measurements: a 2 km × 2 km ground grid
//! with gentle relief and a 50 m checkerboard of two earth tones (16-bit RGB), points in row
//! order (spatially coherent, as survey files are), written point by point with flat memory.

use std::path::Path;

use glam::DVec3;
use indicatif::ProgressBar;

/// Side of the square the grid covers, metres.
pub const GROUND_SIDE: f64 = 2000.0;

/// World position of the grid's corner (x, y minimum, z of the reference level).
pub const GROUND_CORNER: DVec3 = DVec3::new(500_000.0, 4_000_000.0, 0.0);

/// Height of the ground `(x, y)` metres from the corner.
pub fn ground_height(x: f64, y: f64) -> f64 {
    0.5 * (x * 0.01).sin() + 0.3 * (y * 0.013).cos()
}

/// Sphere radius that closes the gaps of a `points`-point grid (half the diagonal spacing).
pub fn ground_radius(points: u64) -> f32 {
    let side = (points as f64).sqrt().ceil();
    (GROUND_SIDE / side * std::f64::consts::FRAC_1_SQRT_2) as f32
}

/// Writes `points` grid points to `path` (LAS 1.2 format 2; LAZ when the name ends in `.laz`);
/// `progress` counts points written.
///
/// # Errors
/// What the las crate reports creating or writing the file.
pub fn write_ground_las(path: &Path, points: u64, progress: &ProgressBar) -> las::Result<()> {
    let mut builder = las::Builder::from((1, 2));
    builder.point_format = las::point::Format::new(2)?;
    builder.point_format.is_compressed = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("laz"));
    let transform = |offset| las::Transform {
        scale: 0.001,
        offset,
    };
    builder.transforms = las::Vector {
        x: transform(GROUND_CORNER.x),
        y: transform(GROUND_CORNER.y),
        z: transform(GROUND_CORNER.z),
    };
    let mut writer = las::Writer::from_path(path, builder.into_header()?)?;
    progress.set_length(points);
    let side = (points as f64).sqrt().ceil() as u64;
    let step = GROUND_SIDE / side as f64;
    for i in 0..points {
        let (x, y) = ((i % side) as f64 * step, (i / side) as f64 * step);
        let dark = ((x / 50.0) as u64 + (y / 50.0) as u64).is_multiple_of(2);
        let (r, g, b) = if dark { (90, 110, 60) } else { (170, 150, 110) };
        writer.write_point(las::Point {
            x: GROUND_CORNER.x + x,
            y: GROUND_CORNER.y + y,
            z: GROUND_CORNER.z + ground_height(x, y),
            color: Some(las::Color::new(r << 8, g << 8, b << 8)),
            ..Default::default()
        })?;
        if i.is_multiple_of(65_536) {
            progress.set_position(i);
        }
    }
    writer.close()?;
    progress.finish_and_clear();
    Ok(())
}
