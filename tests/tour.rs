//! `omnicloud tour` as a user runs it on the bundled sample: frames at equal arc length with
//! headings along the path, each frame the same file as `omnicloud render` at its pose,
//! resuming, sharding across processes, GeoJSON paths and bad paths. The ray tracer renders
//! (fast and deterministic on any machine); `tour_raster.rs` checks the rasterizer.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

use serde_json::Value;

const SCAN: &str = "data/autzen_trim.laz";
const WALK: &str = "data/tours/autzen_walk.csv";

/// The scheduler variables `--shard auto` reads: removed from every child so that a test run
/// inside a Slurm job or GNU parallel does not pick them up.
const SCHEDULER_VARS: [&str; 6] = [
    "SLURM_ARRAY_TASK_ID",
    "SLURM_ARRAY_TASK_MIN",
    "SLURM_ARRAY_TASK_COUNT",
    "SLURM_ARRAY_TASK_STEP",
    "JOB_COMPLETION_INDEX",
    "PARALLEL_SEQ",
];

fn command(args: &[&str], env: &[(&str, &str)]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_omnicloud"));
    c.args(args);
    for v in SCHEDULER_VARS {
        c.env_remove(v);
    }
    c.env_remove("OMNICLOUD_PROGRESS");
    c.envs(env.iter().copied());
    c
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// `omnicloud tour` of the walk: 12 frames, 256 wide, ODS, ray traced, into `dir`; `extra`
/// adds options or replaces these.
fn tour(dir: &Path, extra: &[&str], env: &[(&str, &str)]) -> Output {
    let mut args = vec!["tour", SCAN, "--path", WALK, "-o", dir.to_str().unwrap()];
    for (option, value) in [
        ("--frames", "12"),
        ("--width", "256"),
        ("--stereo", "ods"),
        ("--renderer", "raytrace"),
    ] {
        if !extra.contains(&option) {
            args.extend([option, value]);
        }
    }
    args.extend(extra);
    command(&args, env).output().unwrap()
}

fn manifest(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("tour.json")).unwrap()).unwrap()
}

/// Every frame file of `dir`, by name.
fn frames(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("frame_")
        })
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&p).unwrap())
        })
        .collect()
}

/// One unsharded run of the walk, shared by the tests that only read it.
fn baseline() -> &'static Path {
    static DIR: OnceLock<tempfile::TempDir> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let out = tour(dir.path(), &[], &[]);
        assert!(out.status.success(), "{}", stderr(&out));
        dir
    })
    .path()
}

fn positions(m: &Value) -> Vec<[f64; 3]> {
    m["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| {
            let p = f["position"].as_array().unwrap();
            [0, 1, 2].map(|i| p[i].as_f64().unwrap())
        })
        .collect()
}

fn horizontal(a: [f64; 3], b: [f64; 3]) -> f64 {
    (b[0] - a[0]).hypot(b[1] - a[1])
}

/// The words of a POSIX command line as `tour.json` quotes them.
fn shell_words(line: &str) -> Vec<String> {
    let mut words = Vec::new();
    let mut word = String::new();
    let (mut quoted, mut any) = (false, false);
    for c in line.chars() {
        match c {
            '\'' => {
                quoted = !quoted;
                any = true;
            }
            ' ' if !quoted => {
                if any || !word.is_empty() {
                    words.push(std::mem::take(&mut word));
                }
                any = false;
            }
            _ => word.push(c),
        }
    }
    if any || !word.is_empty() {
        words.push(word);
    }
    words
}

#[test]
fn twelve_frames_stand_at_equal_arc_length_with_headings_along_the_path() {
    let dir = baseline();
    let m = manifest(dir);
    let frames_found = frames(dir);
    assert_eq!(frames_found.len(), 12);
    assert_eq!(
        (m["width"].as_u64(), m["height"].as_u64()),
        (Some(256), Some(256))
    );
    assert_eq!(m["stereo_layout"], "top-bottom");
    let sparse = positions(&m);
    assert_eq!(sparse.len(), 12);
    // The path has no heights: the walk is measured over the ground plan and starts and ends
    // on the first and last keyframes.
    assert_eq!((sparse[0][0], sparse[0][1]), (636400.0, 849100.0));
    assert_eq!((sparse[11][0], sparse[11][1]), (636800.0, 849200.0));

    // The same curve ten times denser: every tenth of its frames is one of the twelve, and its
    // short chords measure the arc between them.
    let dense_dir = tempfile::tempdir().unwrap();
    let out = tour(dense_dir.path(), &["--frames", "111", "--width", "16"], &[]);
    assert!(out.status.success(), "{}", stderr(&out));
    let dense = positions(&manifest(dense_dir.path()));
    // The curve passes through the middle keyframe: a dense frame (4.2 m apart) stands
    // within half a spacing of it.
    let nearest = dense
        .iter()
        .map(|&p| horizontal(p, [636600.0, 849250.0, 0.0]))
        .fold(f64::INFINITY, f64::min);
    assert!(nearest < 2.2, "{nearest}");
    let mut arcs = Vec::new();
    for k in 0..12 {
        let (a, b) = (sparse[k], dense[10 * k]);
        assert!(
            horizontal(a, b) < 1e-6 && (a[2] - b[2]).abs() < 1e-6,
            "frame {k}"
        );
        if k > 0 {
            let arc: f64 = (10 * k - 10..10 * k)
                .map(|i| horizontal(dense[i], dense[i + 1]))
                .sum();
            arcs.push(arc);
        }
    }
    let mean = arcs.iter().sum::<f64>() / arcs.len() as f64;
    let worst = arcs
        .iter()
        .map(|a| (a / mean - 1.0).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "arc between frames: mean {mean:.3} m, worst deviation {:.4} %",
        100.0 * worst
    );
    assert!(worst < 0.01, "{arcs:?}");
    let length = m["length"].as_f64().unwrap();
    assert!(
        (mean * 11.0 / length - 1.0).abs() < 0.002,
        "{mean} vs {length}"
    );

    // Headings: yaw = atan2(dx, dy) of the path's direction at each frame (dense neighbours).
    let mut worst_heading: f64 = 0.0;
    for (k, f) in m["frames"].as_array().unwrap().iter().enumerate() {
        let (i0, i1) = ((10 * k).saturating_sub(1), (10 * k + 1).min(110));
        let (a, b) = (dense[i0], dense[i1]);
        let tangent = (b[0] - a[0]).atan2(b[1] - a[1]).to_degrees();
        let yaw = f["yaw"].as_f64().unwrap();
        let d = (yaw - tangent + 540.0).rem_euclid(360.0) - 180.0;
        worst_heading = worst_heading.max(d.abs());
    }
    eprintln!("worst heading off the tangent: {worst_heading:.3} degrees");
    assert!(worst_heading < 1.0, "{worst_heading}");
}

#[test]
fn each_frame_is_the_file_render_writes_at_its_pose() {
    let dir = baseline();
    let m = manifest(dir);
    let check = tempfile::tempdir().unwrap();
    for k in [0usize, 5, 11] {
        let f = &m["frames"][k];
        let mut words = shell_words(f["command"].as_str().unwrap());
        assert_eq!(&words[..2], ["omnicloud", "render"]);
        let o = words.iter().position(|w| w == "-o").unwrap();
        assert_eq!(
            PathBuf::from(&words[o + 1]),
            dir.join(f["file"].as_str().unwrap())
        );
        let again = check.path().join(format!("again_{k}.png"));
        words[o + 1] = again.display().to_string();
        let args: Vec<&str> = words[1..].iter().map(String::as_str).collect();
        let out = command(&args, &[]).output().unwrap();
        assert!(out.status.success(), "{}", stderr(&out));
        assert!(
            std::fs::read(&again).unwrap()
                == std::fs::read(dir.join(f["file"].as_str().unwrap())).unwrap(),
            "frame {k} differs from `omnicloud render` at its pose"
        );
    }
}

#[test]
fn pitch_and_roll_columns_tilt_the_frames_and_render_reproduces_them() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("tilt.csv");
    std::fs::write(
        &path,
        "x,y,pitch,roll\n636400,849100,0,0\n636600,849250,20,-10\n636800,849200,40,-20\n",
    )
    .unwrap();
    let out_dir = dir.path().join("frames");
    let out = command(
        &[
            "tour",
            SCAN,
            "--path",
            path.to_str().unwrap(),
            "-o",
            out_dir.to_str().unwrap(),
            "--frames",
            "5",
            "--width",
            "64",
            "--renderer",
            "raytrace",
        ],
        &[],
    )
    .output()
    .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let m = manifest(&out_dir);
    let pose = |k: usize, what: &str| m["frames"][k][what].as_f64().unwrap();
    assert!(pose(0, "pitch").abs() < 1e-9 && (pose(4, "pitch") - 40.0).abs() < 1e-9);
    assert!((pose(4, "roll") + 20.0).abs() < 1e-9);
    let mid = pose(2, "pitch");
    assert!(mid > 5.0 && mid < 35.0, "pitch halfway along: {mid}");
    // Frame 2 is the file its recorded command writes, and that command tilts the camera.
    let f = &m["frames"][2];
    let mut words = shell_words(f["command"].as_str().unwrap());
    assert!(
        words
            .iter()
            .any(|w| w.starts_with("--pitch=") && w != "--pitch=0")
    );
    let o = words.iter().position(|w| w == "-o").unwrap();
    let again = dir.path().join("again.png");
    words[o + 1] = again.display().to_string();
    let args: Vec<&str> = words[1..].iter().map(String::as_str).collect();
    let out = command(&args, &[]).output().unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let frame = std::fs::read(out_dir.join(f["file"].as_str().unwrap())).unwrap();
    assert_eq!(std::fs::read(&again).unwrap(), frame);
    // Without the columns the same pose looks elsewhere.
    let level = words
        .iter()
        .map(|w| {
            if w.starts_with("--pitch=") || w.starts_with("--roll=") {
                format!("{}=0", &w[..w.find('=').unwrap()])
            } else {
                w.clone()
            }
        })
        .collect::<Vec<_>>();
    let args: Vec<&str> = level[1..].iter().map(String::as_str).collect();
    let out = command(&args, &[]).output().unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    assert_ne!(
        std::fs::read(&again).unwrap(),
        frame,
        "pitch and roll changed nothing"
    );
}

#[test]
fn a_rerun_renders_exactly_the_missing_frames() {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in frames(baseline()) {
        std::fs::write(dir.path().join(name), bytes).unwrap();
    }
    std::fs::remove_file(dir.path().join("frame_000003.png")).unwrap();
    std::fs::remove_file(dir.path().join("frame_000007.png")).unwrap();
    let out = tour(dir.path(), &[], &[]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("skipping 10 frame(s) already rendered (0-2, 4-6, 8-11)"),
        "{err}"
    );
    assert!(err.contains("rendered 2 frame(s) (3, 7)"), "{err}");
    let log = std::fs::read_to_string(dir.path().join("tour.log")).unwrap();
    let logged: Vec<&str> = log.lines().collect();
    assert_eq!(logged.len(), 2, "{log}");
    assert!(
        logged[0].contains("rendered frame 3 (frame_000003.png)"),
        "{log}"
    );
    assert!(
        logged[1].contains("rendered frame 7 (frame_000007.png)"),
        "{log}"
    );
    assert_eq!(frames(dir.path()), frames(baseline()));

    // --overwrite renders all of them again, to the same bytes.
    let out = tour(dir.path(), &["--overwrite", "--quiet"], &[]);
    assert!(
        out.status.success() && out.stderr.is_empty(),
        "{}",
        stderr(&out)
    );
    let log = std::fs::read_to_string(dir.path().join("tour.log")).unwrap();
    assert_eq!(log.lines().count(), 14);
    assert_eq!(frames(dir.path()), frames(baseline()));
}

#[test]
fn three_shard_processes_write_the_unsharded_files() {
    let dir = tempfile::tempdir().unwrap();
    let children: Vec<_> = ["0/3", "1/3", "2/3"]
        .iter()
        .map(|s| {
            let mut c = command(
                &[
                    "tour",
                    SCAN,
                    "--path",
                    WALK,
                    "-o",
                    dir.path().to_str().unwrap(),
                    "--frames",
                    "12",
                    "--width",
                    "256",
                    "--stereo",
                    "ods",
                    "--renderer",
                    "raytrace",
                    "--shard",
                    s,
                ],
                &[],
            );
            c.stderr(std::process::Stdio::piped());
            c.spawn().unwrap()
        })
        .collect();
    let errs: Vec<String> = children
        .into_iter()
        .map(|c| {
            let out = c.wait_with_output().unwrap();
            assert!(out.status.success(), "{}", stderr(&out));
            stderr(&out)
        })
        .collect();
    for (err, range) in errs.iter().zip(["0..=3", "4..=7", "8..=11"]) {
        assert!(err.contains(&format!("frames {range}")), "{err}");
    }
    assert_eq!(frames(dir.path()), frames(baseline()));
    // Every shard wrote the same manifest (the output folder's name aside).
    let here = std::fs::read_to_string(dir.path().join("tour.json")).unwrap();
    let there = std::fs::read_to_string(baseline().join("tour.json")).unwrap();
    assert_eq!(
        here.replace(dir.path().to_str().unwrap(), "DIR"),
        there.replace(baseline().to_str().unwrap(), "DIR")
    );
}

#[test]
fn shard_auto_reads_each_schedulers_variables() {
    /// A scheduler's variables, the options it needs and its name in the tour's message.
    type Case<'a> = (&'a [(&'a str, &'a str)], &'a [&'a str], &'a str);
    let cases: [Case; 3] = [
        (
            &[
                ("SLURM_ARRAY_TASK_ID", "2"),
                ("SLURM_ARRAY_TASK_MIN", "1"),
                ("SLURM_ARRAY_TASK_COUNT", "3"),
            ],
            &[],
            "Slurm job array",
        ),
        (
            &[("JOB_COMPLETION_INDEX", "1")],
            &["--shards", "3"],
            "Kubernetes Indexed Job",
        ),
        (&[("PARALLEL_SEQ", "2")], &["--shards", "3"], "GNU parallel"),
    ];
    for (env, extra, name) in cases {
        let dir = tempfile::tempdir().unwrap();
        let mut args = vec!["--shard", "auto", "--width", "16"];
        args.extend(extra);
        let out = tour(dir.path(), &args, env);
        let err = stderr(&out);
        assert!(out.status.success(), "{name}: {err}");
        assert!(err.contains(&format!("shard 1/3 from {name}")), "{err}");
        let names: Vec<String> = frames(dir.path()).into_keys().collect();
        assert_eq!(
            names,
            (4..8)
                .map(|i| format!("frame_{i:06}.png"))
                .collect::<Vec<_>>(),
            "{name}"
        );
    }
    let out = tour(
        tempfile::tempdir().unwrap().path(),
        &["--shard", "auto"],
        &[],
    );
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("found no scheduler"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn geojson_paths_in_two_and_three_dimensions() {
    // The 2D GeoJSON holds the CSV walk's keyframes: the same poses.
    let dir = tempfile::tempdir().unwrap();
    let out = command(
        &[
            "tour",
            SCAN,
            "--path",
            "data/tours/autzen_walk.geojson",
            "-o",
            dir.path().to_str().unwrap(),
            "--frames",
            "12",
            "--width",
            "16",
            "--renderer",
            "raytrace",
        ],
        &[],
    )
    .output()
    .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let poses = |m: &Value| -> Vec<Value> {
        m["frames"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| serde_json::json!([f["position"], f["yaw"]]))
            .collect()
    };
    assert_eq!(poses(&manifest(dir.path())), poses(&manifest(baseline())));

    // The 3D flight keeps its heights and its four vertices (two lines) in order; at the
    // --speed 30 (m/s) and 1 fps the frames stand 30 m apart along the 3D curve.
    let dir = tempfile::tempdir().unwrap();
    let out = command(
        &[
            "tour",
            SCAN,
            "--path",
            "data/tours/autzen_flight.geojson",
            "-o",
            dir.path().to_str().unwrap(),
            "--speed",
            "30",
            "--fps",
            "1",
            "--width",
            "16",
            "--renderer",
            "raytrace",
        ],
        &[],
    )
    .output()
    .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let m = manifest(dir.path());
    // 30 m/s in the sample's feet, a frame a second.
    let step = 30.0 / 0.3048;
    let p = positions(&m);
    assert_eq!(p[0], [636400.0, 849100.0, 470.0]);
    let length = m["length"].as_f64().unwrap();
    assert_eq!(p.len(), (length / step).floor() as usize + 1);
    let arc = |k: usize| m["frames"][k]["arc_length"].as_f64().unwrap();
    assert!((arc(3) - 3.0 * step).abs() < 1e-9);
    assert_eq!(
        (m["speed"].as_f64(), m["fps"].as_f64()),
        (Some(step), Some(1.0))
    );
    assert_eq!(m["metres_per_unit"].as_f64(), Some(0.3048));
    let chord = |a: [f64; 3], b: [f64; 3]| {
        ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt()
    };
    // Straight-ish 30 m (98.4 ft) steps: chords within 2 % of the arc (a step across one of the
    // flight's vertices cuts its corner by 1.7 %).
    for w in p.windows(2) {
        assert!((chord(w[0], w[1]) / step - 1.0).abs() < 0.02, "{w:?}");
    }
    assert!(p.iter().all(|q| (469.0..=481.0).contains(&q[2])), "{p:?}");
}

#[test]
fn bad_paths_are_refused_naming_the_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "one.csv",
            "x,y\n636400,849100\n",
            "one.csv: a path needs at least two distinct points; found one (line 2)",
        ),
        (
            "nan.csv",
            "x,y,z\n636400,849100,440\n636500,NaN,440\n",
            "nan.csv: line 3: `NaN` is not a finite number (y)",
        ),
        (
            "column.csv",
            "x,y,heading\n636400,849100,0\n",
            "column.csv: line 1: unknown column `heading`",
        ),
        (
            "outside.csv",
            "x,y\n636400,849100\n# far east\n640000,849100\n",
            "outside.csv: line 4: (640000, 849100) lies outside the scan's bounds x 636001.760 .. 637179.220",
        ),
        (
            "lonlat.geojson",
            r#"{"type":"LineString","coordinates":[[-123.07,44.06],[-123.06,44.06]]}"#,
            "the path looks like longitude/latitude",
        ),
        (
            "point.geojson",
            r#"{"type":"FeatureCollection","features":[{"type":"Feature","geometry":{"type":"Point","coordinates":[636400,849100]}}]}"#,
            "point.geojson: feature 0: geometry is Point; a path is a LineString or MultiLineString",
        ),
        (
            "broken.geojson",
            "{\"type\": \"LineString\",\n\"coordinates\": [[636400, 849100], [636500 849100]]}",
            "broken.geojson: line 2, column",
        ),
    ];
    for (name, text, want) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        let out = command(
            &[
                "tour",
                SCAN,
                "--path",
                path.to_str().unwrap(),
                "-o",
                dir.path().join("out").to_str().unwrap(),
                "--width",
                "16",
                "--renderer",
                "raytrace",
            ],
            &[],
        )
        .output()
        .unwrap();
        let err = stderr(&out);
        assert!(!out.status.success(), "{name} was accepted");
        assert!(err.contains(want), "{name}: {err}");
        assert_eq!(err.lines().count(), 1, "{name}: one line, no panic: {err}");
    }
    assert!(!dir.path().join("out").exists(), "nothing was written");
}

#[test]
fn options_that_cannot_apply_are_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let out = tour(dir.path(), &["--camera", "636400,849100,440"], &[]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("drop --camera"), "{}", stderr(&out));
    let out = tour(dir.path(), &["--shard", "3/3"], &[]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("out of range for 3 shards"),
        "{}",
        stderr(&out)
    );
    let png = dir.path().join("x.png");
    let out = command(
        &[
            "render",
            SCAN,
            "-o",
            png.to_str().unwrap(),
            "--origin=636600,849175,463",
            "--subsample=2",
        ],
        &[],
    )
    .output()
    .unwrap();
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("--subsample is not available with --origin"),
        "{}",
        stderr(&out)
    );
}
