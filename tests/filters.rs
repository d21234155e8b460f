//! Class, return, crop and distance filters on the real sample, counted against an
//! independent read of the file (the `las` crate); the same counts in the streamed path; clear
//! errors when a file lacks what a filter needs.

mod data_common;

use std::path::{Path, PathBuf};
use std::process::Command;

use glam::DVec3;
use indicatif::ProgressBar;
use omnicloud::Scene;
use omnicloud::prepare::filter::{ClassSet, ReturnFilter};
use omnicloud::prepare::{FilterCounts, PointFilter, PrepareOptions, prepare};
use omnicloud::stream::{self, ChunkSink, PlanOptions, StreamError, StreamPlan};

fn autzen() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/autzen_trim.laz")
}

fn sample_points() -> Vec<las::Point> {
    let mut reader = las::Reader::from_path(autzen()).unwrap();
    reader
        .read_all()
        .unwrap()
        .points()
        .map(Result::unwrap)
        .collect()
}

fn with(filter: PointFilter, camera: Option<DVec3>) -> PrepareOptions {
    PrepareOptions {
        // The old centre rule, which the distance counts below were measured from.
        camera: camera.map_or(
            omnicloud::prepare::CameraChoice::Center,
            omnicloud::prepare::CameraChoice::At,
        ),
        filter,
        ..PrepareOptions::default()
    }
}

fn counts(filter: PointFilter) -> (usize, FilterCounts) {
    let p = prepare(&autzen(), &with(filter, None), &ProgressBar::hidden()).unwrap();
    (p.scene.len(), p.filtered)
}

#[test]
fn class_and_return_filters_remove_the_points_the_file_says() {
    let points = sample_points();
    let class = |c: u8| {
        points
            .iter()
            .filter(|p| u8::from(p.classification) == c)
            .count()
    };
    let (ground, unclassified) = (class(2), class(1));
    assert_eq!((ground, unclassified), (26_107, 83_893));

    let (kept, c) = counts(PointFilter {
        classes: Some(ClassSet::of(&[2])),
        ..Default::default()
    });
    assert_eq!((kept, c.classes, c.total()), (ground, 83_893, 83_893));

    let (kept, c) = counts(PointFilter {
        drop_classes: Some("1,7,18".parse().unwrap()),
        ..Default::default()
    });
    assert_eq!((kept, c.drop_classes, c.total()), (ground, 83_893, 83_893));

    let first = points.iter().filter(|p| p.return_number <= 1).count();
    let last = points
        .iter()
        .filter(|p| p.return_number >= p.number_of_returns)
        .count();
    assert_eq!(first, 99_257);
    let (kept, c) = counts(PointFilter {
        returns: ReturnFilter::First,
        ..Default::default()
    });
    assert_eq!((kept, c.returns), (first, 110_000 - first as u64));
    let (kept, c) = counts(PointFilter {
        returns: ReturnFilter::Last,
        ..Default::default()
    });
    assert_eq!((kept, c.returns), (last, 110_000 - last as u64));
    assert!(last < 110_000 && last > 90_000, "{last}");

    // Together: each point counts against the first filter that rejects it.
    let both = points
        .iter()
        .filter(|p| u8::from(p.classification) == 2 && p.return_number <= 1)
        .count();
    let (kept, c) = counts(PointFilter {
        classes: Some(ClassSet::of(&[2])),
        returns: ReturnFilter::First,
        ..Default::default()
    });
    assert_eq!(kept, both);
    assert_eq!(c.classes, 83_893);
    assert_eq!(c.returns, (ground - both) as u64);
}

#[test]
fn crop_and_max_distance_keep_what_the_view_needs() {
    let points = sample_points();
    let (x0, y0, x1, y1) = (636_300.0, 849_000.0, 636_900.0, 849_400.0);
    let camera = DVec3::new(636_600.0, 849_200.0, 430.0);
    let m = 120.0;
    let inside = |p: &las::Point| p.x >= x0 && p.x <= x1 && p.y >= y0 && p.y <= y1;
    let near = |p: &las::Point| (p.x - camera.x).hypot(p.y - camera.y) <= m;
    let cropped = points.iter().filter(|p| inside(p)).count();
    let both = points.iter().filter(|p| inside(p) && near(p)).count();
    assert!(
        cropped > 20_000 && both > 5_000 && both < cropped,
        "{cropped} {both}"
    );

    let filter = PointFilter {
        crop: Some(format!("{x1},{y1},{x0},{y0}").parse().unwrap()),
        max_distance: Some(m),
        ..Default::default()
    };
    let p = prepare(
        &autzen(),
        &with(filter, Some(camera)),
        &ProgressBar::hidden(),
    )
    .unwrap();
    assert_eq!(p.scene.len(), both);
    assert_eq!(p.filtered.crop, (110_000 - cropped) as u64);
    assert_eq!(p.filtered.max_distance, (cropped - both) as u64);
    // Every kept point is within the distance (f32 positions around the camera).
    let far = p
        .scene
        .positions
        .iter()
        .map(|q| q.truncate().length())
        .fold(0.0f32, f32::max);
    assert!(far <= m as f32 + 1e-3, "{far}");

    // An automatic camera stands inside the crop.
    let crop_only = PointFilter {
        crop: filter.crop,
        ..Default::default()
    };
    let p = prepare(&autzen(), &with(crop_only, None), &ProgressBar::hidden()).unwrap();
    let c = p.camera_world;
    assert!(c.x > x0 && c.x < x1 && c.y > y0 && c.y < y1, "{c}");
    assert_eq!(p.scene.len(), cropped);

    // A crop beside the scan leaves nothing: a clear error.
    let away = PointFilter {
        crop: Some("0,0,10,10".parse().unwrap()),
        ..Default::default()
    };
    let e = prepare(&autzen(), &with(away, None), &ProgressBar::hidden())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("removed every point") && e.contains("--crop removed 110000"),
        "{e}"
    );
}

/// Counts what reaches the renderer.
struct Count(u64);

impl ChunkSink for Count {
    fn draw(&mut self, chunk: &Scene) -> Result<(), StreamError> {
        self.0 += chunk.len() as u64;
        Ok(())
    }
}

#[test]
fn streamed_chunks_are_filtered_as_in_core() {
    let filter = PointFilter {
        classes: Some(ClassSet::of(&[1, 2])),
        drop_classes: Some(ClassSet::of(&[1])),
        returns: ReturnFilter::Last,
        crop: Some("636100,848950,637100,849450".parse().unwrap()),
        max_distance: Some(250.0),
    };
    let options = PlanOptions {
        prepare: with(filter, None),
        ..PlanOptions::default()
    };
    let plan = stream::plan(&autzen(), &options, &ProgressBar::hidden()).unwrap();
    let whole = plan.whole.as_ref().unwrap().len() as u64;
    assert!(plan.filtered.total() > 0 && whole > 1_000);
    // Decoded from the file chunk by chunk instead of drawn from the survey's copy.
    let decoded = StreamPlan {
        whole: None,
        ..plan.clone()
    };
    let mut sink = Count(0);
    let report = stream::stream_file(&decoded, 7_000, &mut sink, &ProgressBar::hidden()).unwrap();
    assert_eq!(report.filtered, plan.filtered);
    assert_eq!((report.drawn, sink.0), (whole, whole));
}

/// An ascii PLY with CloudCompare's classification and return properties.
fn write_ply(path: &Path, with_returns: bool) {
    let mut text = String::from("ply\nformat ascii 1.0\nelement vertex 6\n");
    text += "property float x\nproperty float y\nproperty float z\n";
    text += "property float scalar_Classification\n";
    if with_returns {
        text += "property float scalar_Return_Number\nproperty float scalar_Number_Of_Returns\n";
    }
    text += "end_header\n";
    for i in 0..6 {
        let class = if i < 4 { 2 } else { 6 };
        let returns = if with_returns {
            format!(" {} 2", i % 2 + 1)
        } else {
            String::new()
        };
        text += &format!("{} {} 0 {class}{returns}\n", i, i % 3);
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn ply_classes_are_read_and_a_missing_attribute_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let ply = dir.path().join("classes.ply");
    write_ply(&ply, true);
    let filter = PointFilter {
        classes: Some(ClassSet::of(&[6])),
        returns: ReturnFilter::Last,
        ..Default::default()
    };
    let camera = Some(DVec3::new(2.0, 1.0, 1.0));
    let p = prepare(&ply, &with(filter, camera), &ProgressBar::hidden()).unwrap();
    // Points 4 and 5 are class 6; of them, 5 is its pulse's last (second) return.
    assert_eq!(p.scene.len(), 1);
    assert_eq!((p.filtered.classes, p.filtered.returns), (4, 1));

    let no_returns = dir.path().join("no_returns.ply");
    write_ply(&no_returns, false);
    let e = prepare(&no_returns, &with(filter, camera), &ProgressBar::hidden())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("no_returns.ply") && e.contains("--returns needs return numbers"),
        "{e}"
    );

    let building = data_common::building_ply();
    let out = Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(["render", building.path().to_str().unwrap(), "-o"])
        .arg(dir.path().join("b.png"))
        .args(["--drop-classes", "7", "--width", "64"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("building.ply: --drop-classes needs a classification, and this file has none"),
        "{err}"
    );
}

#[test]
fn render_says_what_each_filter_removed() {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(["render", autzen().to_str().unwrap(), "-o"])
        .arg(dir.path().join("g.png"))
        .args(["--classes", "2", "--returns", "first", "--width", "64"])
        .args(["--renderer", "raytrace"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let line = err
        .lines()
        .find(|l| l.starts_with("filters:"))
        .unwrap_or("");
    assert!(
        line.starts_with("filters: --classes removed 83893, --returns removed ")
            && line.ends_with(" of 110000 points kept"),
        "{err}"
    );
}

#[test]
fn a_small_crop_of_a_surveyed_file_is_planned_from_its_own_points() {
    // 100 m x 100 m of the sample: about 1 % of its points, which evenly spaced survey blocks
    // of a large file would mostly miss.
    let filter = PointFilter {
        crop: Some("636550,849150,636650,849250".parse().unwrap()),
        ..Default::default()
    };
    let in_core = prepare(&autzen(), &with(filter, None), &ProgressBar::hidden()).unwrap();
    let n = in_core.scene.len() as u64;
    assert!(n > 300 && n < 4_096, "{n}");
    let options = PlanOptions {
        prepare: with(filter, None),
        survey_points: 8_192,
        ..PlanOptions::default()
    };
    let plan = stream::plan(&autzen(), &options, &ProgressBar::hidden()).unwrap();
    assert!(plan.whole.is_none());
    // The camera stands in the crop, at the in-core camera's height within a metre.
    let (c, core) = (plan.camera, in_core.camera_world);
    assert!(c.x > 636_550.0 && c.x < 636_650.0 && c.y > 849_150.0 && c.y < 849_250.0);
    assert!((c.z - core.z).abs() < 1.0, "{c} vs {core}");
    let mut sink = Count(0);
    let report = stream::stream_file(&plan, 20_000, &mut sink, &ProgressBar::hidden()).unwrap();
    assert_eq!((sink.0, report.filtered.crop), (n, 110_000 - n));
}
