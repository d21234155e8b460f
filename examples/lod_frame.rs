//! One ODS pair of a COPC file through its level of detail, taken apart: the points the
//! selection reads by horizontal distance from the camera, and what the rasterizer did with
//! them (spheres splatted, skipped whole as hidden by nearer ones) with the GPU time.
//!
//! `cargo run --release --example lod_frame -- FILE --camera X,Y,Z [--width 2160]
//! [--lod 1] [--frames 3]` (X,Y,Z in file coordinates).

use std::path::PathBuf;

use clap::Parser;
use glam::{DVec3, Vec3};
use indicatif::ProgressBar;
use omnicloud::Rendered;
use omnicloud::prepare::lod::NodeRadii;
use omnicloud::prepare::{CameraChoice, LodChoice, PrepareOptions, prepare};
use omnicloud::projection::{Camera, Image, Stereo};
use omnicloud::raster::{FrameTiming, RasterError, RasterStats, Rasterizer};
use omnicloud::render::{ColorRule, RenderSettings};
use omnicloud::renderer::{NodeRules, NodeStream};
use std::time::Instant;

#[derive(Parser)]
struct Args {
    /// The COPC file.
    file: PathBuf,
    /// Camera, file coordinates.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    camera: Vec<f64>,
    /// Panorama width per eye.
    #[arg(long, default_value = "2160")]
    width: u32,
    /// Level of detail: on, off or a threshold in pixels.
    #[arg(long, default_value = "on")]
    lod: LodChoice,
    /// Frames timed (after one warm-up frame).
    #[arg(long, default_value = "3")]
    frames: usize,
}

/// Horizontal distance bands, file units.
const BANDS: [f64; 5] = [25.0, 50.0, 100.0, 200.0, 400.0];

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let camera = DVec3::from_slice(&args.camera);
    let options = PrepareOptions {
        camera: CameraChoice::At(camera),
        lod: args.lod.at_width(args.width),
        ..PrepareOptions::default()
    };
    let prepared = prepare(&args.file, &options, &ProgressBar::hidden())?;
    let scene = &prepared.scene;
    if let Some(lod) = &prepared.lod {
        println!("{}: {lod}", args.file.display());
    }
    let band: Vec<usize> = scene.positions.iter().map(band_of).collect();
    let mut counts = [0u64; BANDS.len() + 1];
    for &k in &band {
        counts[k] += 1;
    }
    let mut from = 0.0;
    for (k, n) in counts.iter().enumerate() {
        let to = BANDS
            .get(k)
            .map_or("beyond".to_string(), |b| format!("{b}"));
        println!("  {from:>5}-{to:<6}: {n:>10} points");
        from = BANDS.get(k).copied().unwrap_or(0.0);
    }
    let mut settings = RenderSettings::new(args.width, Camera::new(DVec3::ZERO, 0.0));
    settings.image = Image::equirect(args.width);
    settings.stereo = Stereo::DEFAULT_ODS;
    let raster = Rasterizer::new()?;
    let uploaded = raster.upload(scene, &settings)?;
    let hidden = ProgressBar::hidden();
    // The same points gathered as one piece in the file's order, then as distance bands
    // nearest first (GPU time, read-back excluded).
    let bands: Vec<_> = (0..=BANDS.len())
        .map(|k| {
            let mask: Vec<bool> = band.iter().map(|&b| b == k).collect();
            raster.upload(&scene.select(&mask), &settings)
        })
        .collect::<Result<_, _>>()?;
    for (name, pieces) in [
        ("file order", vec![&uploaded]),
        ("nearest band first", bands.iter().collect::<Vec<_>>()),
    ] {
        let (ms, stats) = median_frame(&raster, args.frames, || {
            raster.render_gathered_timed(&pieces, &settings, &hidden)
        })?;
        println!("gathered, {name}: GPU {ms:.1} ms; {stats}");
    }
    let (ms, stats) = median_frame(&raster, args.frames, || {
        raster.render_uploaded(&uploaded, &settings, &hidden)
    })?;
    println!(
        "ODS {} per eye: GPU {ms:.1} ms (median of {}); {stats}",
        args.width,
        args.frames.max(1)
    );
    drop((uploaded, bands, raster));
    // The tour's own path: the selected nodes, each uploaded once, gathered per frame, with
    // hidden nodes skipped and without.
    let mut frames = Vec::new();
    for skip in [true, false] {
        let mut raster = Rasterizer::new()?;
        raster.set_skip_hidden_pieces(skip);
        let origin = scene.origin;
        let mut stream = NodeStream::new(
            raster,
            &args.file,
            &PrepareOptions {
                origin: Some(origin),
                ..options
            },
            NodeRules {
                radii: NodeRadii::File,
                color: ColorRule::for_scene(scene, settings.color)?,
                pixels: match args.lod {
                    LodChoice::Pixels(p) => p,
                    LodChoice::Off => 0.0,
                },
                floor: omnicloud::prepare::lod::LOD_FLOOR_POINTS,
                budget: 4 << 30,
            },
            &settings,
        )?;
        let at = RenderSettings {
            camera: Camera::new(camera - origin, 0.0),
            ..settings
        };
        let mut wall = Vec::new();
        let mut last = None;
        for k in 0..=args.frames.max(1) {
            let t = Instant::now();
            let rendered = stream.render(&at, &hidden)?;
            if k > 0 {
                wall.push(t.elapsed().as_secs_f64() * 1e3);
            }
            if let Some(old) = last.replace(rendered) {
                stream.rasterizer().recycle(old);
            }
        }
        wall.sort_by(f64::total_cmp);
        let f = stream.last_frame();
        println!(
            "node stream, hidden nodes {}: {:.1} ms a cached frame (median, wall); {} nodes, {} \
             ({} points) skipped as hidden",
            if skip { "skipped" } else { "drawn" },
            wall[wall.len() / 2],
            f.nodes,
            f.hidden,
            f.hidden_points
        );
        frames.push(last.expect("one frame"));
    }
    let same = match (&frames[0], &frames[1]) {
        (Rendered::Stereo { left: a, right: b }, Rendered::Stereo { left: c, right: d }) => {
            a.color == c.color && b.color == d.color
        }
        _ => false,
    };
    println!(
        "the two node-stream pairs are {}",
        if same { "identical" } else { "DIFFERENT" }
    );
    Ok(())
}

/// The distance band (index into `BANDS`, or past them) of a point, horizontally from the
/// camera.
fn band_of(p: &Vec3) -> usize {
    let d = f64::from(p.x.hypot(p.y));
    BANDS.iter().take_while(|&&b| d >= b).count()
}

/// Median GPU milliseconds of `frames` renders after one warm-up, with the last one's counters.
fn median_frame(
    raster: &Rasterizer,
    frames: usize,
    mut render: impl FnMut() -> Result<(Rendered, RasterStats, FrameTiming), RasterError>,
) -> anyhow::Result<(f64, RasterStats)> {
    let mut gpu = Vec::new();
    let mut stats = None;
    for k in 0..=frames.max(1) {
        let (rendered, s, timing) = render()?;
        raster.recycle(rendered);
        if k > 0 {
            gpu.push(timing.seconds * 1e3);
        }
        stats = Some(s);
    }
    gpu.sort_by(f64::total_cmp);
    Ok((gpu[gpu.len() / 2], stats.expect("one frame")))
}
