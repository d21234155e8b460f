//! Several files rendered as one scene: tiles of a survey equal the merged file, bit for bit;
//! the stream plan covers every input.

mod data_common;
#[path = "raster_common/gpu.rs"]
mod gpu;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use glam::DVec3;
use indicatif::ProgressBar;
use omnicloud::Scene;
use omnicloud::prepare::{PrepareOptions, prepare, prepare_files};
use omnicloud::stream::{self, ChunkSink, PlanOptions, StreamError};

fn autzen() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/autzen_trim.laz")
}

/// Writes `points` as an uncompressed LAS with the header layout of `like`.
fn write_las(path: &Path, like: &las::Header, points: &[las::Point]) {
    let mut builder = las::Builder::from(like.version());
    builder.point_format = *like.point_format();
    builder.point_format.is_compressed = false;
    builder.transforms = *like.transforms();
    let mut writer = las::Writer::from_path(path, builder.into_header().unwrap()).unwrap();
    for p in points {
        writer.write_point(p.clone()).unwrap();
    }
    writer.close().unwrap();
}

/// The sample split at its middle X into two tiles (west, east) and the merged file (west's
/// points, then east's), in `dir`.
fn tiles(dir: &Path) -> (PathBuf, PathBuf, PathBuf) {
    let mut reader = las::Reader::from_path(autzen()).unwrap();
    let header = reader.header().clone();
    let points: Vec<las::Point> = reader
        .read_all()
        .unwrap()
        .points()
        .map(Result::unwrap)
        .collect();
    let b = header.bounds();
    let mid = (b.min.x + b.max.x) / 2.0;
    let (west, east): (Vec<las::Point>, Vec<las::Point>) =
        points.into_iter().partition(|p| p.x < mid);
    assert!(west.len() > 10_000 && east.len() > 10_000);
    let paths = (
        dir.join("west.las"),
        dir.join("east.las"),
        dir.join("merged.las"),
    );
    write_las(&paths.0, &header, &west);
    write_las(&paths.1, &header, &east);
    let merged: Vec<las::Point> = west.into_iter().chain(east).collect();
    write_las(&paths.2, &header, &merged);
    (paths.0, paths.1, paths.2)
}

fn omnicloud(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(args)
        .output()
        .unwrap()
}

fn assert_same_scene(a: &Scene, b: &Scene) {
    assert_eq!(a.origin, b.origin);
    assert_eq!(a.positions, b.positions);
    assert_eq!(a.radii, b.radii);
    assert_eq!(a.attributes, b.attributes);
}

#[test]
fn two_tiles_render_as_the_merged_file_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let (west, east, merged) = tiles(dir.path());
    let hidden = ProgressBar::hidden();

    // The prepared scenes are identical: one origin, one camera, one radius.
    for options in [
        PrepareOptions::default(),
        PrepareOptions {
            filter: omnicloud::prepare::PointFilter {
                crop: Some("636400,848950,636900,849300".parse().unwrap()),
                max_distance: Some(150.0),
                ..Default::default()
            },
            ..PrepareOptions::default()
        },
    ] {
        let together = prepare_files(&[west.clone(), east.clone()], &options, &hidden).unwrap();
        let alone = prepare(&merged, &options, &hidden).unwrap();
        assert_eq!(together.camera_world, alone.camera_world);
        assert_eq!(together.filtered, alone.filtered);
        assert_same_scene(&together.scene, &alone.scene);
        assert_eq!(together.report.points_read, 110_000);
    }

    // A crop inside the west tile: the east tile is not read, its points count as cropped.
    let west_only = PrepareOptions {
        filter: omnicloud::prepare::PointFilter {
            crop: Some("636100,849000,636400,849300".parse().unwrap()),
            ..Default::default()
        },
        ..PrepareOptions::default()
    };
    let together = prepare_files(&[west.clone(), east.clone()], &west_only, &hidden).unwrap();
    let alone = prepare(&merged, &west_only, &hidden).unwrap();
    assert_eq!(together.filtered.files_skipped, 1);
    assert_eq!(together.filtered.crop, alone.filtered.crop);
    assert_eq!(together.scene.len(), alone.scene.len());
    let west_points = las::Reader::from_path(&west)
        .unwrap()
        .header()
        .number_of_points();
    assert!(west_points < 110_000);
    assert_eq!(together.report.points_read, west_points);
    let plan_options = PlanOptions {
        prepare: west_only,
        survey_points: 20_000,
        ..PlanOptions::default()
    };
    let plan = stream::plan_files(&[west.clone(), east.clone()], &plan_options, &hidden).unwrap();
    assert_eq!(plan.paths, std::slice::from_ref(&west));
    let mut sink = Count(0, DVec3::INFINITY, DVec3::NEG_INFINITY);
    let report = stream::stream_file(&plan, 30_000, &mut sink, &hidden).unwrap();
    assert_eq!(report.filtered.crop, alone.filtered.crop);
    assert_eq!(sink.0, alone.scene.len() as u64);

    // Rendered through the binary: the same bytes, from the ray tracer and the rasterizer.
    let (w, e, m) = (
        west.to_str().unwrap(),
        east.to_str().unwrap(),
        merged.to_str().unwrap(),
    );
    for renderer in ["raytrace", "raster"] {
        let out_tiles = dir.path().join(format!("tiles_{renderer}.png"));
        let out_merged = dir.path().join(format!("merged_{renderer}.png"));
        let run = |inputs: &[&str], out: &Path| {
            let mut args = vec!["render"];
            args.extend(inputs);
            args.extend(["-o", out.to_str().unwrap(), "--width", "256"]);
            args.extend(["--renderer", renderer]);
            omnicloud(&args)
        };
        let a = run(&[w, e], &out_tiles);
        let stderr = String::from_utf8_lossy(&a.stderr);
        if renderer == "raster" && !a.status.success() && stderr.contains("no GPU adapter") {
            gpu::require_or_skip(&format!("no adapter: {}", stderr.trim()));
            continue;
        }
        assert!(a.status.success(), "{stderr}");
        assert!(stderr.contains("(+1 more file)"), "{stderr}");
        let b = run(&[m], &out_merged);
        assert!(b.status.success(), "{}", String::from_utf8_lossy(&b.stderr));
        let (ta, tb) = (
            std::fs::read(&out_tiles).unwrap(),
            std::fs::read(&out_merged).unwrap(),
        );
        assert!(
            ta == tb,
            "{renderer}: the tiles' image differs from the merged file's"
        );
    }
}

/// Counts the streamed points.
#[derive(Default)]
struct Count(u64, DVec3, DVec3);

impl ChunkSink for Count {
    fn draw(&mut self, chunk: &Scene) -> Result<(), StreamError> {
        self.0 += chunk.len() as u64;
        for p in &chunk.positions {
            let w = chunk.origin + p.as_dvec3();
            self.1 = self.1.min(w);
            self.2 = self.2.max(w);
        }
        Ok(())
    }
}

#[test]
fn a_surveyed_plan_covers_every_tile() {
    let dir = tempfile::tempdir().unwrap();
    let (west, east, _) = tiles(dir.path());
    let options = PlanOptions {
        survey_points: 20_000,
        ..PlanOptions::default()
    };
    let inputs = [west.clone(), east.clone()];
    let plan = stream::plan_files(&inputs, &options, &ProgressBar::hidden()).unwrap();
    assert!(
        plan.whole.is_none(),
        "110,000 points over a 20,000 budget are surveyed"
    );
    assert_eq!(plan.declared, 110_000);
    // The survey read from both tiles, close to the budget.
    assert!(
        (19_000..=20_000).contains(&plan.surveyed),
        "{}",
        plan.surveyed
    );
    let header = las::Reader::from_path(autzen()).unwrap().header().bounds();
    let c = plan.camera;
    assert!(c.x > header.min.x && c.x < header.max.x && c.y > header.min.y && c.y < header.max.y);
    let mut sink = Count(0, DVec3::INFINITY, DVec3::NEG_INFINITY);
    let report = stream::stream_file(&plan, 30_000, &mut sink, &ProgressBar::hidden()).unwrap();
    assert_eq!(
        (report.read, report.drawn, sink.0),
        (110_000, 110_000, 110_000)
    );
    // Both tiles were drawn: the streamed extent is the sample's (to the centimetre).
    assert!((sink.1.x - header.min.x).abs() < 0.01 && (sink.2.x - header.max.x).abs() < 0.01);
}

#[test]
fn files_in_different_coordinate_systems_are_flagged() {
    let dir = tempfile::tempdir().unwrap();
    let simple = data_common::laspy("simple.las");
    let out = omnicloud(&[
        "render",
        autzen().to_str().unwrap(),
        simple.to_str().unwrap(),
        "-o",
        dir.path().join("m.png").to_str().unwrap(),
        "--width",
        "64",
        "--renderer",
        "raytrace",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("warning: the files declare different coordinate systems")
            && err.contains("NAD_1983_HARN_Lambert_Conformal_Conic")
            && err.contains("simple.las (none declared)"),
        "{err}"
    );
    assert!(err.contains("111065 points"), "{err}");
}
