//! One live frame taken apart: the rasterizer renders `serve`'s ODS pair at the start camera
//! (as `/api/live` does), timed per step, under each compute-splat limit asked for.
//!
//! `cargo run --release --example live_frame -- [FILE] [--width 1440] [--frames 5]
//! [--splat 64,32,16,0] [--east M]` (FILE defaults to the sample, data/autzen_trim.laz).

use std::path::PathBuf;
use std::time::Instant;

use clap::Parser;
use glam::DVec3;
use indicatif::ProgressBar;
use omnicloud::prepare::{LengthScale, PrepareOptions, Units, prepare};
use omnicloud::projection::Image;
use omnicloud::raster::Rasterizer;
use omnicloud::web::serve::live::jpeg::encode_jpeg;
use omnicloud::web::serve::render_thread::live_settings;
use omnicloud::web::serve::{LiveOptions, LiveScan, RenderRequest};

#[derive(Parser)]
struct Args {
    /// The scan.
    #[arg(default_value = "data/autzen_trim.laz")]
    file: PathBuf,
    /// Panorama width per eye.
    #[arg(long, default_value = "1440")]
    width: u32,
    /// Frames timed per splat limit (after one warm-up frame).
    #[arg(long, default_value = "5")]
    frames: usize,
    /// Camera this many metres east of the start camera (the live bench's walk starts a fifth
    /// of the scan's width west of it).
    #[arg(long, default_value = "0", allow_hyphen_values = true)]
    east: f64,
    /// Compute-splat limits to try, pixels (0: every sphere drawn); none: the default.
    #[arg(long, value_delimiter = ',')]
    splat: Vec<u32>,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let info = omnicloud::io::read_info(&args.file)?;
    let scale = LengthScale::for_info(&info, Units::Metres, omnicloud::io::Up::Z);
    let prepared = prepare(
        &args.file,
        &PrepareOptions::default(),
        &ProgressBar::hidden(),
    )?;
    let options = LiveOptions {
        width: args.width,
        height: scale.height(1.7),
        per_metre: scale.length(1.0),
        metres_per_unit: scale.metres_per_unit,
        map_size: 256,
        ..LiveOptions::default()
    };
    let scan = LiveScan::new(&args.file, prepared.scene, options)?;
    let camera = DVec3::from_array(scan.info.camera) - scan.scene.origin
        + DVec3::X * scale.length(args.east);
    let mut settings = live_settings(&scan, camera, &RenderRequest::default_at(&scan.limits));
    settings.image = Image::equirect(args.width);
    let hidden = ProgressBar::hidden();
    let limits: Vec<Option<u32>> = if args.splat.is_empty() {
        vec![None]
    } else {
        args.splat.iter().map(|&l| Some(l)).collect()
    };
    println!(
        "{}: {} points, ODS {} per eye",
        args.file.display(),
        scan.scene.len(),
        args.width
    );
    for limit in limits {
        let mut raster = Rasterizer::new()?;
        if let Some(l) = limit {
            raster.set_splat_limit(l);
        }
        let uploaded = raster.upload(&scan.scene, &settings)?;
        let (mut gpu, mut wall, mut read, mut pair, mut reused, mut jpeg) =
            (vec![], vec![], vec![], vec![], vec![], vec![]);
        // The live stream stacks each pair into the one its client encoded last.
        let mut spent = omnicloud::Frame::new(0, 0);
        let mut last = None;
        for k in 0..=args.frames {
            let t = Instant::now();
            let (rendered, stats, timing) =
                raster.render_uploaded(&uploaded, &settings, &hidden)?;
            let total = t.elapsed().as_secs_f64() * 1e3;
            let t = Instant::now();
            let frame = rendered.top_bottom();
            let top_bottom = t.elapsed().as_secs_f64() * 1e3;
            let t = Instant::now();
            rendered.top_bottom_into(&mut spent);
            let into_spent = t.elapsed().as_secs_f64() * 1e3;
            raster.recycle(rendered);
            let t = Instant::now();
            let bytes = encode_jpeg(&frame, 80)?.len();
            let encode = t.elapsed().as_secs_f64() * 1e3;
            if k > 0 {
                gpu.push(timing.seconds * 1e3);
                wall.push(timing.wall_seconds * 1e3);
                read.push(total - timing.wall_seconds * 1e3);
                pair.push(top_bottom);
                reused.push(into_spent);
                jpeg.push(encode);
            }
            last = Some((stats, bytes));
        }
        let (stats, bytes) = last.expect("one frame");
        println!(
            "splat limit {}: render (GPU stamps) {:.1} ms, wall to end of GPU work {:.1} ms, \
             then stats + read-back {:.1} ms, top-bottom pair {:.1} ms fresh / {:.1} ms into the last, JPEG q80 {:.1} ms ({} KiB); \
             {} drawn, {} splatted, {} vertices, {} special, {} occluded",
            limit.map_or("default".into(), |l| l.to_string()),
            median(gpu),
            median(wall),
            median(read),
            median(pair),
            median(reused),
            median(jpeg),
            bytes / 1024,
            stats.drawn,
            stats.splatted,
            stats.vertices,
            stats.special,
            stats.occluded
        );
    }
    Ok(())
}
