//! Seeking readers and the survey that plans a streamed render: seeks read the same points as
//! sequential reading, bad seeks are errors, a surveyed plan agrees with the in-core path,
//! and streamed chunks are coloured as the in-core path colours them.

mod data_common;

use data_common::{autzen, building_ply, laspy, lion_ply};
use glam::DVec3;
use indicatif::ProgressBar;
use omnicloud::io::{self, ColorScale, LoadError, LoadOptions, PointChunk, load_scene};
use omnicloud::prepare::radius::RadiusChoice;
use omnicloud::prepare::{PrepareOptions, placement};
use omnicloud::render::{ColorMode, base_colors};
use omnicloud::rng::SplitMix64;
use omnicloud::scene::{Radii, Scene};
use omnicloud::stream::{ChunkSink, PlanOptions, StreamError, StreamPlan, plan, stream_file};
use std::path::Path;

/// Colour scale used on both sides of a comparison, so detection plays no part.
const SCALE: ColorScale = ColorScale::Full16;

/// Every point of the file, read sequentially, as one chunk.
fn read_all(path: &Path) -> PointChunk {
    let mut all = PointChunk::default();
    for chunk in io::open(path).unwrap().chunks_with_scale(50_000, SCALE) {
        append(&mut all, chunk.unwrap());
    }
    all
}

fn append(all: &mut PointChunk, c: PointChunk) {
    fn add<T: Clone>(a: &mut Option<Vec<T>>, b: Option<Vec<T>>) {
        if let Some(b) = b {
            a.get_or_insert_with(Vec::new).extend(b);
        }
    }
    all.positions.extend(c.positions);
    add(&mut all.rgb, c.rgb);
    add(&mut all.intensity, c.intensity);
    add(&mut all.classification, c.classification);
    add(&mut all.returns, c.returns);
    add(&mut all.radius, c.radius);
}

fn slice(all: &PointChunk, from: usize, n: usize) -> PointChunk {
    let end = (from + n).min(all.len());
    fn part<T: Clone>(v: &Option<Vec<T>>, r: std::ops::Range<usize>) -> Option<Vec<T>> {
        v.as_ref().map(|v| v[r].to_vec())
    }
    PointChunk {
        positions: all.positions[from..end].to_vec(),
        rgb: part(&all.rgb, from..end),
        intensity: part(&all.intensity, from..end),
        classification: part(&all.classification, from..end),
        returns: part(&all.returns, from..end),
        radius: part(&all.radius, from..end),
    }
}

#[test]
fn seeks_read_the_same_points_as_sequential_reading() {
    const N: usize = 777;
    let (lion_ply, building) = (lion_ply(), building_ply());
    for path in [
        laspy("simple.las"),
        laspy("simple1_4.las"),
        laspy("simple.laz"),
        laspy("1_4_w_evlr.laz"),
        autzen(),
        lion_ply.path().to_owned(),
        building.path().to_owned(),
    ] {
        let all = read_all(&path);
        let n = all.len();
        // Forward seeks, a seek back after a forward one, and the last points.
        let plans: [&[usize]; 5] = [&[0], &[n / 3], &[7, n / 2], &[n - 5], &[n / 2, n / 5]];
        for seeks in plans {
            let mut reader = io::open(&path).unwrap();
            for &s in seeks {
                reader.seek(s as u64).unwrap();
            }
            let at = *seeks.last().unwrap();
            let got = reader.chunks_with_scale(N, SCALE).next().unwrap().unwrap();
            assert_eq!(
                got,
                slice(&all, at, N),
                "{} after seeks {seeks:?}",
                path.display()
            );
        }
        // Reading goes on in order past the first chunk after a seek.
        let mut reader = io::open(&path).unwrap();
        reader.seek(n as u64 / 4).unwrap();
        let mut chunks = reader.chunks_with_scale(n / 4, SCALE);
        chunks.next().unwrap().unwrap();
        let next = chunks.next().unwrap().unwrap();
        assert_eq!(next, slice(&all, n / 2, n / 4), "{}", path.display());
    }
}

#[test]
fn seeking_past_the_end_is_an_error_naming_the_file() {
    let (lion_ply, building) = (lion_ply(), building_ply());
    for path in [
        laspy("simple.las"),
        laspy("simple.laz"),
        lion_ply.path().to_owned(),
        building.path().to_owned(),
    ] {
        let mut reader = io::open(&path).unwrap();
        let declared = reader.info().point_count;
        let e = reader.seek(declared + 1).unwrap_err();
        assert!(
            matches!(e, LoadError::SeekPastEnd { point, .. } if point == declared + 1),
            "{e}"
        );
        assert!(e.to_string().contains(path.to_str().unwrap()), "{e}");
        // The end itself is a valid position with nothing left to read.
        let mut reader = io::open(&path).unwrap();
        reader.seek(declared).unwrap();
        assert!(reader.chunks_with_scale(10, SCALE).next().is_none());
    }
}

#[test]
fn seeking_into_a_truncated_ascii_ply_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("short.ply");
    let mut text = String::from(
        "ply\nformat ascii 1.0\nelement vertex 10\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
    );
    for i in 0..4 {
        text.push_str(&format!("{i} 0 0\n"));
    }
    std::fs::write(&path, text).unwrap();
    let mut reader = io::open(&path).unwrap();
    let e = reader.seek(8).unwrap_err();
    assert!(matches!(e, LoadError::CorruptPoints { .. }), "{e}");
    assert!(e.to_string().contains("short.ply"), "{e}");
    // Within the lines present, seeking works.
    let mut reader = io::open(&path).unwrap();
    reader.seek(3).unwrap();
    let c = reader.chunks(10).next().unwrap();
    assert!(c.is_err(), "the file still ends early after point 3");
}

#[test]
fn seeking_past_the_data_of_a_truncated_binary_ply_is_an_error() {
    // A list element before the vertices keeps `open` from checking the vertex count against
    // the file size: the seek must.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cut.ply");
    let mut bytes = b"ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list uchar int vertex_indices\nelement vertex 10\nproperty float x\nproperty float y\nproperty float z\nend_header\n".to_vec();
    bytes.push(1);
    bytes.extend(0i32.to_le_bytes());
    for i in 0..4 {
        for v in [i as f32, 0.0, 0.0] {
            bytes.extend(v.to_le_bytes());
        }
    }
    std::fs::write(&path, bytes).unwrap();
    let mut reader = io::open(&path).unwrap();
    let e = reader.seek(8).unwrap_err();
    assert!(matches!(e, LoadError::SeekFailed { point: 8, .. }), "{e}");
    assert!(e.to_string().contains("cut.ply"), "{e}");
    let mut reader = io::open(&path).unwrap();
    reader.seek(2).unwrap();
    let c = reader.chunks_with_scale(2, SCALE).next().unwrap().unwrap();
    assert_eq!(
        c.positions,
        vec![DVec3::new(2.0, 0.0, 0.0), DVec3::new(3.0, 0.0, 0.0)]
    );
}

/// Side of the generated grid: 448² = 200,704 points.
const SIDE: usize = 448;
/// Points per tile side: files store points in spatially coherent runs, as real scans do.
const TILE: usize = 32;
const SPACING: f64 = 0.5;
const X0: f64 = 637_000.0;
const Y0: f64 = 851_000.0;

/// A jittered 0.5 m ground grid over a gently sloping, rolling terrain, stored tile by tile,
/// with full-range 16-bit colour and intensity; `laz` compresses it.
fn write_terrain(path: &Path, laz: bool) {
    let mut builder = las::Builder::from((1, 2));
    builder.point_format = las::point::Format::new(2).unwrap();
    builder.point_format.is_compressed = laz;
    let t = |offset| las::Transform {
        scale: 0.001,
        offset,
    };
    builder.transforms = las::Vector {
        x: t(X0),
        y: t(Y0),
        z: t(0.0),
    };
    let mut writer = las::Writer::from_path(path, builder.into_header().unwrap()).unwrap();
    let mut rng = SplitMix64::new(11);
    let tiles = SIDE / TILE;
    for ty in 0..tiles {
        for tx in 0..tiles {
            for j in 0..TILE {
                for i in 0..TILE {
                    let x = ((tx * TILE + i) as f64 + 0.6 * (rng.next_f64() - 0.5)) * SPACING;
                    let y = ((ty * TILE + j) as f64 + 0.6 * (rng.next_f64() - 0.5)) * SPACING;
                    let z = 10.0 + 0.02 * x + 0.5 * (y / 20.0).sin();
                    let v = (z * 4000.0) as u16;
                    writer
                        .write_point(las::Point {
                            x: X0 + x,
                            y: Y0 + y,
                            z,
                            intensity: (x * 100.0) as u16,
                            color: Some(las::Color::new(v, 65_535 - v, 30_000)),
                            ..Default::default()
                        })
                        .unwrap();
                }
            }
        }
    }
    writer.close().unwrap();
}

/// The in-core decisions, through the public pieces `prepare::prepare` uses.
fn in_core(path: &Path) -> (Scene, DVec3, f32) {
    let (mut scene, _) = load_scene(path, &LoadOptions::default()).unwrap();
    let camera = placement::center_on_camera(
        &mut scene,
        omnicloud::prepare::CameraChoice::Auto,
        Default::default(),
    )
    .unwrap();
    let radius = omnicloud::prepare::radius::apply_choice(&mut scene, None).radius;
    (scene, camera, radius)
}

#[test]
fn a_surveyed_plan_agrees_with_the_in_core_path() {
    let dir = tempfile::tempdir().unwrap();
    let (las_path, laz_path) = (dir.path().join("t.las"), dir.path().join("t.laz"));
    write_terrain(&las_path, false);
    write_terrain(&laz_path, true);
    let (scene, core_camera, core_radius) = in_core(&las_path);
    let extent = (SIDE as f64) * SPACING;

    let options = PlanOptions {
        survey_points: 20_000,
        color: ColorMode::Elevation,
        ..PlanOptions::default()
    };
    let planned = plan(&las_path, &options, &ProgressBar::hidden()).unwrap();
    assert!(planned.whole.is_none());
    assert_eq!(planned.declared, (SIDE * SIDE) as u64);
    assert!(
        (19_000..=20_000).contains(&planned.surveyed),
        "{}",
        planned.surveyed
    );
    let off = planned.camera - core_camera;
    eprintln!(
        "camera off by {off:?} (extent {extent} m); radius {} vs in-core {core_radius}; elevation range {:?}",
        planned.radii.radius, planned.color.range
    );
    // XY from the header bounds: the same centre; the ground from the surveyed blocks only.
    assert!(off.truncate().length() < 0.01 * extent, "{off}");
    assert!(off.z.abs() < 0.02 * extent, "{off}");
    assert!(
        (planned.radii.radius / core_radius - 1.0).abs() < 0.1,
        "{} vs {core_radius}",
        planned.radii.radius
    );
    assert_eq!(planned.color_scale, ColorScale::Full16);
    // Heights relative to each path's own camera: the ranges differ by the camera's height.
    let core_rule = omnicloud::render::ColorRule::for_scene(&scene, ColorMode::Elevation).unwrap();
    let shift = off.z as f32;
    for (a, b) in [
        (planned.color.range.0 + shift, core_rule.range.0),
        (planned.color.range.1 + shift, core_rule.range.1),
    ] {
        assert!(
            (a - b).abs() < 0.1 * (core_rule.range.1 - core_rule.range.0),
            "{a} vs {b}"
        );
    }

    // The LAZ copy seeks through its chunk table to the same blocks: the same plan.
    let laz = plan(&laz_path, &options, &ProgressBar::hidden()).unwrap();
    assert_eq!(
        (laz.camera, laz.radii.radius, laz.color, laz.surveyed),
        (
            planned.camera,
            planned.radii.radius,
            planned.color,
            planned.surveyed
        )
    );

    // A fixed radius is kept; the stream reads every point once.
    let fixed = PlanOptions {
        prepare: PrepareOptions {
            radius: Some(RadiusChoice::Fixed(0.07)),
            ..options.prepare
        },
        ..options
    };
    let planned = plan(&laz_path, &fixed, &ProgressBar::hidden()).unwrap();
    assert_eq!(
        (planned.radii.radius, planned.radii.keep_file_radii),
        (0.07, false)
    );
    let mut sink = Collect::default();
    let report = stream_file(&planned, 30_000, &mut sink, &ProgressBar::hidden()).unwrap();
    assert_eq!(
        (report.read, report.drawn),
        (planned.declared, planned.declared)
    );
    assert_eq!(sink.positions.len() as u64, planned.declared);
    assert!(sink.radii_ok);
}

/// Collects what a stream draws: positions (world, f64), colours by a rule, and whether
/// every chunk had the expected radius rule.
#[derive(Default)]
struct Collect {
    rule: Option<omnicloud::render::ColorRule>,
    positions: Vec<DVec3>,
    colors: Vec<[u8; 3]>,
    radii_ok: bool,
    chunks: usize,
}

impl ChunkSink for Collect {
    fn draw(&mut self, chunk: &Scene) -> Result<(), StreamError> {
        self.radii_ok = (self.chunks == 0 || self.radii_ok)
            && matches!(chunk.radii, Radii::Uniform(r) if r > 0.0);
        self.chunks += 1;
        self.positions
            .extend(chunk.positions.iter().map(|p| chunk.origin + p.as_dvec3()));
        if let Some(rule) = &self.rule {
            self.colors.extend(rule.colors(chunk)?);
        }
        Ok(())
    }
}

/// A plan that makes the stream decode the file instead of drawing the survey's copy.
fn decoded(plan: &StreamPlan) -> StreamPlan {
    StreamPlan {
        whole: None,
        ..plan.clone()
    }
}

#[test]
fn streamed_chunks_are_coloured_as_in_core() {
    let building = building_ply();
    for (path, mode) in [
        (autzen(), ColorMode::Auto),
        (autzen(), ColorMode::Intensity),
        (laspy("vegetation_1_3.las"), ColorMode::Auto),
        (building.path().to_owned(), ColorMode::Elevation),
    ] {
        let options = PlanOptions {
            color: mode,
            ..PlanOptions::default()
        };
        let planned = plan(&path, &options, &ProgressBar::hidden()).unwrap();
        let (scene, camera, _) = in_core(&path);
        let expected = base_colors(&scene, mode).unwrap();
        let name = path.display();
        assert_eq!(planned.camera, camera, "{name}");

        // From the survey's copy: exactly the in-core colours.
        let mut sink = Collect {
            rule: Some(planned.color),
            ..Collect::default()
        };
        stream_file(&planned, 25_000, &mut sink, &ProgressBar::hidden()).unwrap();
        assert!(sink.chunks > 1 || scene.len() <= 25_000);
        assert_eq!(sink.colors, expected, "{name}");

        // Decoded again in chunks: each point re-originated once in f64 instead of twice
        // through f32, so a height may differ by an f32 rounding step and a colour channel
        // by one step of rounding.
        let mut sink = Collect {
            rule: Some(planned.color),
            ..Collect::default()
        };
        let report = stream_file(
            &decoded(&planned),
            25_000,
            &mut sink,
            &ProgressBar::hidden(),
        )
        .unwrap();
        assert_eq!(report.drawn as usize, scene.len(), "{name}");
        assert!(sink.chunks >= report.drawn.div_ceil(25_000) as usize);
        let worst = sink
            .colors
            .iter()
            .zip(&expected)
            .flat_map(|(a, b)| (0..3).map(move |k| a[k].abs_diff(b[k])))
            .max()
            .unwrap();
        assert!(worst <= 1, "{name}: colours differ by {worst}");
        let far = sink
            .positions
            .iter()
            .zip(&scene.positions)
            .map(|(a, b)| (*a - (scene.origin + b.as_dvec3())).length())
            .fold(0.0, f64::max);
        assert!(far < 1e-3, "{name}: positions differ by {far} m");
    }
}

#[test]
fn a_failing_sink_stops_the_stream_with_its_error() {
    struct Fail(usize);
    impl ChunkSink for Fail {
        fn draw(&mut self, _: &Scene) -> Result<(), StreamError> {
            self.0 += 1;
            if self.0 == 2 {
                return Err(StreamError::sink("out of GPU memory"));
            }
            Ok(())
        }
    }
    let planned = plan(&autzen(), &PlanOptions::default(), &ProgressBar::hidden()).unwrap();
    for p in [planned.clone(), decoded(&planned)] {
        let e = stream_file(&p, 10_000, &mut Fail(0), &ProgressBar::hidden()).unwrap_err();
        assert!(matches!(e, StreamError::Sink(_)), "{e}");
        assert_eq!(e.to_string(), "rendering failed: out of GPU memory");
    }
    // A colour mode the file cannot serve is refused at planning.
    let options = PlanOptions {
        color: ColorMode::Classification,
        ..PlanOptions::default()
    };
    let e = plan(building_ply().path(), &options, &ProgressBar::hidden()).unwrap_err();
    assert!(matches!(e, StreamError::Color(_)), "{e}");
}
