//! Ray tracer throughput: BVH build time, BVH memory, rays per second and peak memory.
//!
//! ```text
//! cargo run --release --example raytrace_perf -- autzen [PATH] [--width W] [--mono]
//! cargo run --release --example raytrace_perf -- generated N [--width W] [--mono]
//!     [--preset fastest|fast|medium|slow]
//! RAYON_NUM_THREADS=1 cargo run --release --example raytrace_perf -- generated 5000000
//! ```
//!
//! `autzen` reads a LAS/LAZ file (default: data/autzen_trim.laz, the sample);
//! `generated` builds N points of synthetic terrain with walls, spaced like aerial LiDAR.
//! The camera stands 1.7 m above open ground near the scene's XY centre; the radius is
//! [`auto_radius`]. Default: 3840×1920 per eye, ODS (ipd 0.064 m).

use std::time::Instant;

use clap::{Parser, ValueEnum};
use glam::{DVec3, Vec3};
use indicatif::ProgressBar;
use omnicloud::memory::{format_size, peak_resident};
use omnicloud::prepare::radius::auto_radius;
use omnicloud::projection::{Camera, OdsOffset, PoleMerging, Stereo};
use omnicloud::raytrace::{BvhBuildParams, Tracer, render_with_tracer};
use omnicloud::render::RenderSettings;
use omnicloud::rng::SplitMix64;
use omnicloud::{Radii, Scene};

/// Ray tracer throughput: BVH build time, BVH memory, rays per second and peak memory.
#[derive(Parser)]
struct Args {
    /// `autzen` (a LAS/LAZ file) or `generated` (synthetic terrain).
    #[arg(value_enum, default_value = "autzen")]
    scene: SceneKind,
    /// autzen: the file [data/autzen_trim.laz]; generated: the point count
    /// [5000000].
    source: Option<String>,
    /// Image width per eye.
    #[arg(long, default_value_t = 3840)]
    width: u32,
    /// One eye instead of an ODS pair.
    #[arg(long)]
    mono: bool,
    /// BVH build preset.
    #[arg(long, value_enum, default_value = "medium")]
    preset: Preset,
}

#[derive(Clone, Copy, ValueEnum)]
enum SceneKind {
    Autzen,
    Generated,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum Preset {
    Fastest,
    Fast,
    Medium,
    Slow,
}

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let (width, stereo) = (args.width, !args.mono);
    let t0 = Instant::now();
    let mut scene = match args.scene {
        SceneKind::Generated => {
            let n: usize = args.source.as_deref().map_or(Ok(5_000_000), str::parse)?;
            generated(n)
        }
        SceneKind::Autzen => {
            let default = concat!(env!("CARGO_MANIFEST_DIR"), "/data/autzen_trim.laz");
            load_las(args.source.as_deref().unwrap_or(default))?
        }
    };
    let load_s = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let radius = auto_radius(&scene);
    let radius_s = t0.elapsed().as_secs_f64();
    scene.radii = Radii::Uniform(radius);
    let camera = Camera::new(
        omnicloud::prepare::placement::open_ground_camera_position(&scene),
        0.0,
    );

    let params = match args.preset {
        Preset::Fastest => BvhBuildParams::fastest_build(),
        Preset::Fast => BvhBuildParams::fast_build(),
        Preset::Medium => BvhBuildParams::medium_build(),
        Preset::Slow => BvhBuildParams::slow_build(),
    };
    let tracer = Tracer::with_params(&scene, params)?;
    let mem = tracer.memory();
    let mut settings = RenderSettings::new(width, camera);
    if stereo {
        settings.stereo = Stereo::Ods {
            ipd: 0.064,
            merging: PoleMerging::OFF,
            offset: OdsOffset::Exact,
        };
    }
    let t0 = Instant::now();
    let rendered = render_with_tracer(&tracer, &scene, &settings, &ProgressBar::hidden())?;
    let render_s = t0.elapsed().as_secs_f64();
    let frames = rendered.frames();
    let rays: usize = frames.iter().map(|f| f.color.len()).sum();
    let covered: usize = frames.iter().map(|f| f.coverage_count()).sum();

    println!("points            {}", scene.len());
    println!("camera            {:.1?}", camera.center);
    println!("threads           {}", rayon::current_num_threads());
    println!("load/generate     {load_s:.2} s");
    println!("auto radius       {radius:.4} m ({radius_s:.2} s)");
    println!(
        "bvh build         {:.3} s ({})",
        tracer.build_time().as_secs_f64(),
        args.preset
            .to_possible_value()
            .map_or_else(String::new, |v| v.get_name().to_owned())
    );
    println!(
        "bvh memory        {} nodes ({} x 80 B) + {} indices + {} spheres = {}",
        format_size(mem.nodes as u64),
        tracer.node_count(),
        format_size(mem.primitive_indices as u64),
        format_size(mem.spheres as u64),
        format_size(mem.total() as u64)
    );
    println!(
        "image             {}x{} x {} view(s), coverage {:.3}",
        settings.image.width,
        settings.image.height,
        frames.len(),
        covered as f64 / rays as f64
    );
    println!("render            {render_s:.2} s");
    println!("rays per second   {:.2} M", rays as f64 / render_s / 1e6);
    if let Some(hwm) = peak_resident() {
        println!("peak memory       {}", format_size(hwm));
    }
    Ok(())
}

/// A LAS/LAZ/PLY file through the crate's loader (origin at the centre of the bounds).
fn load_las(path: &str) -> anyhow::Result<Scene> {
    let (scene, _) = omnicloud::io::load_scene(path.as_ref(), &Default::default())?;
    Ok(scene)
}

/// `n` points: 85 % rolling terrain over a square sized for ~4 points/m², 15 % on the walls
/// of box buildings; jittered so the spacing is irregular like a scan.
fn generated(n: usize) -> Scene {
    let mut rng = SplitMix64::new(0x2545_f491_4f6c_dd1d);
    let mut next = move || rng.next_f64() as f32;
    let ground_n = n * 85 / 100;
    let side = (ground_n as f32 / 4.0).sqrt();
    let height = |x: f32, y: f32| 3.0 * (x / 80.0).sin() * (y / 110.0).cos() + 0.02 * x;
    let mut positions = Vec::with_capacity(n);
    for _ in 0..ground_n {
        let x = (next() - 0.5) * side;
        let y = (next() - 0.5) * side;
        positions.push(Vec3::new(x, y, height(x, y)));
    }
    // Buildings: 10–30 m boxes, 5–20 m tall, none over the camera.
    let walls_n = n - ground_n;
    let buildings: Vec<(f32, f32, f32, f32, f32)> = (0..200)
        .map(|_| {
            let mut c = (next() - 0.5) * side * 0.9;
            let mut d = (next() - 0.5) * side * 0.9;
            if c.abs() < 40.0 && d.abs() < 40.0 {
                c += 80.0;
                d += 80.0;
            }
            (
                c,
                d,
                10.0 + 20.0 * next(),
                10.0 + 20.0 * next(),
                5.0 + 15.0 * next(),
            )
        })
        .collect();
    for k in 0..walls_n {
        let (cx, cy, sx, sy, h) = buildings[k % buildings.len()];
        let s = next() * 2.0 * (sx + sy);
        let (x, y) = if s < sx {
            (cx - sx / 2.0 + s, cy - sy / 2.0)
        } else if s < sx + sy {
            (cx + sx / 2.0, cy - sy / 2.0 + (s - sx))
        } else if s < 2.0 * sx + sy {
            (cx + sx / 2.0 - (s - sx - sy), cy + sy / 2.0)
        } else {
            (cx - sx / 2.0, cy + sy / 2.0 - (s - 2.0 * sx - sy))
        };
        positions.push(Vec3::new(x, y, height(cx, cy) + next() * h));
    }
    Scene::new(DVec3::ZERO, positions, 0.0)
}
