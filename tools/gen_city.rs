//! Writes a deterministic generated city as LAS or LAZ, streamed (memory does not grow with
//! the point count): city blocks of 100 m with streets and sidewalks, buildings with façades
//! (windows in rows) and flat or gabled roofs, trees and parked cars, sampled about every
//! 0.1 m like a mobile LiDAR survey (about 100 points a square metre), with classes, colour,
//! intensity, returns and GPS time. Blocks are laid out row by row until the point count is
//! reached; the same seed and count give the same file.
//!
//! `cargo run --example gen_city -- OUT.laz POINTS [--seed N]`

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Parser;
use indicatif::{ProgressBar, ProgressDrawTarget};
use omnicloud::rng::SplitMix64;

/// Writes a generated city.
#[derive(Parser)]
struct Args {
    /// The file to write; `.laz` compresses.
    out: PathBuf,
    /// Points to write (`_` separators allowed: 100_000_000).
    #[arg(value_parser = point_count)]
    points: u64,
    /// Seed of the layout and the sampling jitter.
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

fn point_count(s: &str) -> Result<u64, String> {
    s.replace('_', "")
        .parse()
        .map_err(|_| format!("'{s}' is not a point count"))
}

/// Sampling step, metres.
const STEP: f64 = 0.1;
/// A city block with its half of the streets around it, metres.
const BLOCK: f64 = 100.0;
/// Street width (half on each side of a block).
const STREET: f64 = 16.0;
/// Sidewalk width.
const SIDEWALK: f64 = 4.0;

/// ASPRS classes.
const GROUND: u8 = 2;
const VEGETATION: u8 = 5;
const BUILDING: u8 = 6;
const UNCLASSIFIED: u8 = 1;

/// Where points go: the LAS writer, stopping at the requested count.
struct Sink {
    writer: las::Writer<std::io::BufWriter<std::fs::File>>,
    written: u64,
    wanted: u64,
    rng: SplitMix64,
    progress: ProgressBar,
}

impl Sink {
    fn full(&self) -> bool {
        self.written >= self.wanted
    }

    /// One point, jittered by a third of the step across the surface.
    fn point(&mut self, p: [f64; 3], rgb: [u8; 3], class: u8) -> Result<()> {
        if self.full() {
            return Ok(());
        }
        let j = STEP / 3.0;
        let jitter = [
            self.rng.range(-j, j),
            self.rng.range(-j, j),
            self.rng.range(-j, j) * 0.2,
        ];
        let shade = self.rng.range(0.9, 1.1);
        let c = |v: u8| ((f64::from(v) * shade).clamp(0.0, 255.0) as u16) << 8;
        self.writer.write_point(las::Point {
            x: p[0] + jitter[0],
            y: p[1] + jitter[1],
            z: p[2] + jitter[2],
            intensity: (f64::from(rgb[0]) * 100.0 * shade) as u16,
            return_number: 1,
            number_of_returns: 1,
            classification: las::point::Classification::new(class)?,
            gps_time: Some(self.written as f64 * 1e-5),
            color: Some(las::Color::new(c(rgb[0]), c(rgb[1]), c(rgb[2]))),
            ..Default::default()
        })?;
        self.written += 1;
        if self.written.is_multiple_of(65_536) {
            self.progress.set_position(self.written);
        }
        Ok(())
    }

    /// A rectangle spanned by `u` and `v` from `origin`, sampled every [`STEP`]; `colour`
    /// picks each point's colour and class from its (u, v) in metres.
    fn surface(
        &mut self,
        origin: [f64; 3],
        u: [f64; 3],
        v: [f64; 3],
        colour: &dyn Fn(f64, f64) -> ([u8; 3], u8),
    ) -> Result<()> {
        let len = |a: [f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        let (lu, lv) = (len(u), len(v));
        let (nu, nv) = ((lu / STEP) as u64, (lv / STEP) as u64);
        for i in 0..nv {
            for k in 0..nu {
                if self.full() {
                    return Ok(());
                }
                let (a, b) = ((k as f64 + 0.5) / nu as f64, (i as f64 + 0.5) / nv as f64);
                let p = [0, 1, 2].map(|d| origin[d] + u[d] * a + v[d] * b);
                let (rgb, class) = colour(a * lu, b * lv);
                self.point(p, rgb, class)?;
            }
        }
        Ok(())
    }
}

/// A box's four walls and its roof (flat, or gabled along x when `gable` > 0).
fn building(
    sink: &mut Sink,
    low: [f64; 2],
    size: [f64; 2],
    height: f64,
    gable: f64,
    wall: [u8; 3],
    roof: [u8; 3],
) -> Result<()> {
    let facade = move |u: f64, v: f64| {
        // Windows 1.2 m wide, 1.5 m high, every 3 m along and up, above a 3 m ground floor.
        let window =
            v > 3.0 && (u % 3.0) > 0.9 && (u % 3.0) < 2.1 && (v % 3.0) > 0.8 && (v % 3.0) < 2.3;
        if window {
            ([40, 60, 90], BUILDING)
        } else {
            (wall, BUILDING)
        }
    };
    let [x0, y0] = low;
    let [sx, sy] = size;
    let corners = [[x0, y0], [x0 + sx, y0], [x0 + sx, y0 + sy], [x0, y0 + sy]];
    for i in 0..4 {
        let (a, b) = (corners[i], corners[(i + 1) % 4]);
        sink.surface(
            [a[0], a[1], 0.0],
            [b[0] - a[0], b[1] - a[1], 0.0],
            [0.0, 0.0, height],
            &facade,
        )?;
    }
    let roofing = move |_: f64, _: f64| (roof, BUILDING);
    if gable > 0.0 {
        // Two slopes meeting along the ridge at mid-y, `gable` metres above the walls.
        let half = sy / 2.0;
        sink.surface(
            [x0, y0, height],
            [sx, 0.0, 0.0],
            [0.0, half, gable],
            &roofing,
        )?;
        sink.surface(
            [x0, y0 + sy, height],
            [sx, 0.0, 0.0],
            [0.0, -half, gable],
            &roofing,
        )?;
        // The gable ends, as triangles: rows shortened towards the ridge.
        for x in [x0, x0 + sx] {
            let rows = (gable / STEP) as u64;
            for r in 0..rows {
                let t = (r as f64 + 0.5) / rows as f64;
                let w = sy * (1.0 - t);
                sink.surface(
                    [x, y0 + (sy - w) / 2.0, height + t * gable],
                    [0.0, w, 0.0],
                    [0.0, 0.0, STEP],
                    &roofing,
                )?;
            }
        }
    } else {
        sink.surface([x0, y0, height], [sx, 0.0, 0.0], [0.0, sy, 0.0], &roofing)?;
    }
    Ok(())
}

/// A tree: a trunk and a crown of points on a sphere's surface.
fn tree(sink: &mut Sink, at: [f64; 2], trunk: f64, crown: f64) -> Result<()> {
    let around = (2.0 * std::f64::consts::PI * 0.2 / STEP).ceil() as u64;
    for h in 0..(trunk / STEP) as u64 {
        for a in 0..around {
            let t = a as f64 / around as f64 * std::f64::consts::TAU;
            let p = [
                at[0] + 0.2 * t.cos(),
                at[1] + 0.2 * t.sin(),
                h as f64 * STEP,
            ];
            sink.point(p, [90, 70, 50], VEGETATION)?;
        }
    }
    let area = 4.0 * std::f64::consts::PI * crown * crown;
    let n = (area / (STEP * STEP)) as u64;
    let centre = [at[0], at[1], trunk + crown * 0.8];
    for i in 0..n {
        // Fibonacci sphere: even coverage.
        let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
        let r = (1.0 - z * z).sqrt();
        let t = i as f64 * 2.399_963_229_728_653;
        let p = [
            centre[0] + crown * r * t.cos(),
            centre[1] + crown * r * t.sin(),
            centre[2] + crown * z,
        ];
        sink.point(p, [60, 120, 50], VEGETATION)?;
    }
    Ok(())
}

/// A parked car: a 4.4 x 1.8 m body, 1.5 m tall, with its top and sides.
fn car(sink: &mut Sink, at: [f64; 2], along_x: bool, paint: [u8; 3]) -> Result<()> {
    let (l, w, h) = (4.4, 1.8, 1.5);
    let (sx, sy) = if along_x { (l, w) } else { (w, l) };
    let body = move |_: f64, _: f64| (paint, UNCLASSIFIED);
    let [x0, y0] = at;
    sink.surface([x0, y0, h], [sx, 0.0, 0.0], [0.0, sy, 0.0], &body)?;
    for (o, u) in [
        ([x0, y0, 0.3], [sx, 0.0, 0.0]),
        ([x0, y0 + sy, 0.3], [sx, 0.0, 0.0]),
        ([x0, y0, 0.3], [0.0, sy, 0.0]),
        ([x0 + sx, y0, 0.3], [0.0, sy, 0.0]),
    ] {
        sink.surface(o, u, [0.0, 0.0, h - 0.3], &body)?;
    }
    Ok(())
}

/// One city block with the south-west corner at `(bx, by)`.
fn block(sink: &mut Sink, bx: f64, by: f64) -> Result<()> {
    let half = STREET / 2.0;
    let ground = move |u: f64, v: f64| {
        let edge = u.min(v).min(BLOCK - u).min(BLOCK - v);
        if edge < half {
            // Asphalt with a white centre line... at the block's edge, where streets meet.
            if edge < 0.15 {
                ([230, 230, 220], GROUND)
            } else {
                ([70, 70, 75], GROUND)
            }
        } else if edge < half + SIDEWALK {
            ([170, 165, 160], GROUND)
        } else {
            ([80, 130, 60], GROUND)
        }
    };
    sink.surface([bx, by, 0.0], [BLOCK, 0.0, 0.0], [0.0, BLOCK, 0.0], &ground)?;
    let inner = half + SIDEWALK + 2.0;
    let span = BLOCK - 2.0 * inner;
    // Two to four buildings in a row along x, each a random depth and height.
    let count = 2 + (sink.rng.next_u64() % 3) as usize;
    let width = span / count as f64;
    for i in 0..count {
        let depth = sink.rng.range(15.0, span * 0.6);
        let height = sink.rng.range(6.0, 30.0);
        let gable = if sink.rng.next_f64() < 0.4 {
            sink.rng.range(2.0, 5.0)
        } else {
            0.0
        };
        let wall = [
            sink.rng.range(120.0, 230.0) as u8,
            sink.rng.range(100.0, 200.0) as u8,
            sink.rng.range(80.0, 180.0) as u8,
        ];
        let roof = if gable > 0.0 {
            [150, 60, 50]
        } else {
            [110, 110, 115]
        };
        let low = [bx + inner + i as f64 * width + 1.0, by + inner];
        building(sink, low, [width - 2.0, depth], height, gable, wall, roof)?;
    }
    // Trees along the north sidewalk, cars parked along the south street.
    let mut x = bx + inner;
    while x < bx + BLOCK - inner {
        let trunk = sink.rng.range(2.0, 4.0);
        let crown = sink.rng.range(1.5, 3.0);
        tree(sink, [x, by + BLOCK - half - SIDEWALK / 2.0], trunk, crown)?;
        x += sink.rng.range(8.0, 14.0);
    }
    let mut x = bx + half + 2.0;
    while x < bx + BLOCK - half - 6.0 {
        if sink.rng.next_f64() < 0.7 {
            let paint = [
                (sink.rng.next_u64() % 256) as u8,
                (sink.rng.next_u64() % 256) as u8,
                (sink.rng.next_u64() % 256) as u8,
            ];
            car(sink, [x, by + half - 2.2], true, paint)?;
        }
        x += 6.0;
    }
    Ok(())
}

fn write(path: &Path, points: u64, seed: u64) -> Result<u64> {
    let mut builder = las::Builder::from((1, 4));
    builder.point_format = las::point::Format::new(7)?;
    builder.point_format.is_compressed = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("laz"));
    builder.transforms = las::Vector {
        x: las::Transform {
            scale: 0.001,
            offset: 0.0,
        },
        y: las::Transform {
            scale: 0.001,
            offset: 0.0,
        },
        z: las::Transform {
            scale: 0.001,
            offset: 0.0,
        },
    };
    builder.generating_software = "omnicloud gen_city".into();
    let writer = las::Writer::from_path(path, builder.into_header()?)?;
    let progress = ProgressBar::with_draw_target(Some(points), ProgressDrawTarget::stderr());
    let mut sink = Sink {
        writer,
        written: 0,
        wanted: points,
        rng: SplitMix64::new(seed),
        progress,
    };
    // Blocks row by row on a square city of the size the count needs (~2 M points a block).
    let side = ((points as f64 / 2.0e6).sqrt().ceil() as u64).max(1);
    let mut b = 0u64;
    while !sink.full() {
        block(
            &mut sink,
            (b % side) as f64 * BLOCK,
            (b / side) as f64 * BLOCK,
        )?;
        b += 1;
    }
    sink.writer.close()?;
    sink.progress.finish_and_clear();
    Ok(b)
}

fn main() -> Result<()> {
    let Args { out, points, seed } = Args::parse();
    let blocks = write(&out, points, seed).with_context(|| format!("writing {}", out.display()))?;
    eprintln!(
        "wrote {points} points ({blocks} city blocks, seed {seed}) to {}",
        out.display()
    );
    Ok(())
}
