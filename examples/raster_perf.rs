//! Frame times of the rasterizer per proxy/imposter mode on a generated cloud.
//!
//! `cargo run --release --example raster_perf -- [points] [width] [frames] [modes] [splat] [rt]`
//! (defaults: 1000000 points, 1920 wide, 3 frames, every mode; `modes` is a comma list
//! of `proxy-imposter` names such as `bounds-raycast,quad-sprite,static4-sprite`; `splat` is
//! the compute splat's limit in pixels, 0 off; `rt` also times the CPU ray tracer on the same
//! cloud; `--shading unlit|phong|normal`, default phong; `--seed N`, the cloud's seed;
//! `--batch N`, a cap on the points per batch). Prints the adapter, the timing source (GPU
//! timestamps or wall clock) and, per mode, mono and ODS frame times.

use clap::{Parser, ValueEnum};
use glam::{DVec3, Vec3};
use indicatif::ProgressBar;
use omnicloud::projection::{Camera, OdsOffset, PoleMerge, PoleMerging, Stereo};
use omnicloud::raster::Rasterizer;
use omnicloud::render::{ColorMode, Imposter, Proxy, RenderSettings, Shading};
use omnicloud::rng::SplitMix64;
use omnicloud::{Radii, Scene};

/// A terrain-like cloud: a ground plane with bumps, walls and a few trees around the camera,
/// drawn from `seed`. One wall passes through the camera, so the few spheres nearest it cover
/// much of the image and a frame's time depends on where the seed puts them.
fn cloud(n: usize, seed: u64) -> Scene {
    let mut rng = SplitMix64::new(seed);
    let mut next = move || rng.next_f64() as f32;
    let positions = (0..n)
        .map(|k| {
            let (x, y) = (next() * 200.0 - 100.0, next() * 200.0 - 100.0);
            match k % 10 {
                0..=6 => Vec3::new(x, y, -1.7 + 0.3 * (0.1 * x).sin() * (0.13 * y).cos()),
                7 | 8 => Vec3::new(
                    x,
                    30.0 * (k % 3) as f32 - 30.0 + 0.1 * next(),
                    next() * 12.0 - 1.7,
                ),
                _ => Vec3::new(x * 0.2, y * 0.2, next() * 15.0 + 1.0),
            }
        })
        .collect();
    Scene {
        origin: DVec3::ZERO,
        positions,
        radii: Radii::Uniform(0.06),
        attributes: Default::default(),
    }
}

/// Frame times of the rasterizer per proxy/imposter mode on a generated cloud.
#[derive(Parser)]
struct Args {
    /// Points in the generated cloud.
    #[arg(default_value_t = 1_000_000)]
    points: usize,
    /// Image width per eye.
    #[arg(default_value_t = 1920)]
    width: u32,
    /// Frames per mode (the best is printed).
    #[arg(default_value_t = 3)]
    frames: usize,
    /// Modes to time, comma-separated `proxy-imposter` names (e.g. bounds-raycast,quad-sprite)
    /// [every mode].
    modes: Option<String>,
    /// The compute splat's limit in pixels (0: off) [the rasterizer's default].
    splat: Option<u32>,
    /// `rt`: also time the CPU ray tracer on the same cloud.
    rt: Option<RayTracer>,
    /// Shading of both renderers.
    #[arg(long, default_value = "phong")]
    shading: Shading,
    /// Cap on the points per expand/draw batch [as many as the vertex buffer holds].
    #[arg(long)]
    batch: Option<u32>,
    /// Seed of the generated cloud.
    #[arg(long, default_value_t = 0x9e37_79b9_7f4a_7c15)]
    seed: u64,
}

/// The one value of the last argument.
#[derive(Clone, Copy, ValueEnum)]
enum RayTracer {
    Rt,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let Args {
        points,
        width,
        frames,
        modes,
        splat,
        rt,
        shading,
        batch,
        seed,
    } = Args::parse();
    let modes: Option<Vec<String>> =
        modes.map(|m| m.split(',').map(|s| s.to_lowercase()).collect());
    let t0 = std::time::Instant::now();
    let mut raster = Rasterizer::new()?;
    let setup_ms = t0.elapsed().as_secs_f64() * 1e3;
    raster.set_batch_limit(batch);
    if let Some(limit) = splat {
        raster.set_splat_limit(limit);
    }
    let with_ray_tracer = rt.is_some();
    println!(
        "adapter: {} (device and pipelines: {setup_ms:.0} ms)",
        raster.adapter_name()
    );
    let scene = cloud(points, seed);
    let mut base = RenderSettings::new(width, Camera::new(DVec3::ZERO, 0.0));
    base.color = ColorMode::Elevation;
    base.shading = shading;
    let uploaded = raster.upload(&scene, &base)?;
    println!(
        "{points} points, {width}x{} per eye, best of {frames} frames",
        width / 2
    );
    let ods = Stereo::Ods {
        ipd: 0.064,
        merging: PoleMerging::both(PoleMerge::COMFORTABLE),
        offset: OdsOffset::Exact,
    };
    if with_ray_tracer {
        let t0 = std::time::Instant::now();
        let tracer = omnicloud::raytrace::Tracer::new(&scene)?;
        println!("ray tracer: BVH {:.1} ms", t0.elapsed().as_secs_f64() * 1e3);
        for stereo in [Stereo::Mono, ods] {
            let mut s = base;
            s.stereo = stereo;
            let t0 = std::time::Instant::now();
            omnicloud::raytrace::render_with_tracer(&tracer, &scene, &s, &ProgressBar::hidden())?;
            println!(
                "{:5} ray tracer: {:8.1} ms ({} threads)",
                if matches!(stereo, Stereo::Mono) {
                    "mono"
                } else {
                    "ods"
                },
                t0.elapsed().as_secs_f64() * 1e3,
                rayon::current_num_threads()
            );
        }
    }
    for stereo in [Stereo::Mono, ods] {
        for (proxy, imposter) in [
            (Proxy::Bounds, Imposter::Raycast),
            (Proxy::Quad, Imposter::Raycast),
            (Proxy::Quad, Imposter::Sprite),
            (Proxy::Static(4), Imposter::Sprite),
            (Proxy::Dynamic, Imposter::Sprite),
            (Proxy::Dynamic, Imposter::Raycast),
        ] {
            let name = format!("{proxy:?}-{imposter:?}")
                .to_lowercase()
                .replace(['(', ')'], "");
            if modes.as_ref().is_some_and(|m| !m.contains(&name)) {
                continue;
            }
            let mut s = base;
            s.stereo = stereo;
            s.proxy = proxy;
            s.imposter = imposter;
            let mut best = f64::INFINITY;
            let mut best_wall = f64::INFINITY;
            let mut source = None;
            let mut stats = None;
            for _ in 0..frames {
                let t0 = std::time::Instant::now();
                let (_, st, t) = raster.render_uploaded(&uploaded, &s, &ProgressBar::hidden())?;
                best_wall = best_wall.min(t0.elapsed().as_secs_f64());
                best = best.min(t.seconds);
                source = Some(t.source);
                stats = Some(st);
            }
            let st = stats.expect("one frame");
            println!(
                "{:5} {:>10} {:>8}: {:8.1} ms ({:?}; {:.1} ms with read-back; {} vertices, {} splatted, {} hidden by nearer ones, {} special, {} batches, {} culled)",
                if matches!(stereo, Stereo::Mono) {
                    "mono"
                } else {
                    "ods"
                },
                format!("{proxy:?}"),
                format!("{imposter:?}"),
                best * 1e3,
                source.expect("one frame"),
                best_wall * 1e3,
                st.vertices,
                st.splatted,
                st.occluded,
                st.special,
                st.batches,
                st.culled
            );
        }
    }
    Ok(())
}
