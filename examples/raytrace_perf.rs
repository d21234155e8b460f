//! Ray tracer throughput: BVH build time, BVH memory, rays per second and peak memory.
//!
//! ```text
//! cargo run --release --example raytrace_perf -- autzen [PATH] [--width W] [--mono]
//! cargo run --release --example raytrace_perf -- generated N [--width W] [--mono]
//!     [--preset fastest|fast|medium|slow]
//! RAYON_NUM_THREADS=1 cargo run --release --example raytrace_perf -- generated 5000000
//! ```
//!
//! `autzen` reads a LAS/LAZ file (default: ../shared/data/las/autzen_trim.laz);
//! `generated` builds N points of synthetic terrain with walls, spaced like aerial LiDAR.
//! The camera stands 1.7 m above open ground near the scene's XY centre; the radius is
//! [`auto_radius`]. Default: 3840×1920 per eye, ODS (ipd 0.064 m).

use std::time::Instant;

use glam::{DVec3, Vec3};
use indicatif::ProgressBar;
use omnicloud::projection::{Camera, OdsOffset, PoleMerging, Stereo};
use omnicloud::radius::auto_radius;
use omnicloud::raytrace::{BvhBuildParams, Tracer, render_with_tracer};
use omnicloud::render::RenderSettings;
use omnicloud::rng::SplitMix64;
use omnicloud::{Radii, Scene};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut width = 3840u32;
    let mut stereo = true;
    let mut preset = "medium".to_string();
    let mut positional = Vec::new();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--width" => width = it.next().ok_or(anyhow::anyhow!("--width W"))?.parse()?,
            "--mono" => stereo = false,
            "--preset" => preset = it.next().ok_or(anyhow::anyhow!("--preset NAME"))?.clone(),
            _ => positional.push(a.clone()),
        }
    }
    let t0 = Instant::now();
    let mut scene = match positional.first().map(String::as_str) {
        Some("generated") => {
            let n: usize = positional.get(1).map_or(Ok(5_000_000), |s| s.parse())?;
            generated(n)
        }
        Some("autzen") | None => {
            let default = concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../shared/data/las/autzen_trim.laz"
            );
            load_las(positional.get(1).map_or(default, String::as_str))?
        }
        Some(other) => anyhow::bail!("unknown scene {other}: autzen [PATH] | generated N"),
    };
    let load_s = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let radius = auto_radius(&scene);
    let radius_s = t0.elapsed().as_secs_f64();
    scene.radii = Radii::Uniform(radius);
    let camera = Camera::new(
        omnicloud::placement::open_ground_camera_position(&scene),
        0.0,
    );

    let params = match preset.as_str() {
        "fastest" => BvhBuildParams::fastest_build(),
        "fast" => BvhBuildParams::fast_build(),
        "medium" => BvhBuildParams::medium_build(),
        "slow" => BvhBuildParams::slow_build(),
        other => anyhow::bail!("unknown preset {other}: fastest | fast | medium | slow"),
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
        "bvh build         {:.3} s ({preset})",
        tracer.build_time().as_secs_f64()
    );
    println!(
        "bvh memory        {:.1} MiB nodes ({} x 80 B) + {:.1} MiB indices + {:.1} MiB spheres = {:.1} MiB",
        mib(mem.nodes),
        tracer.node_count(),
        mib(mem.primitive_indices),
        mib(mem.spheres),
        mib(mem.total())
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
    if let Some(hwm) = peak_memory() {
        println!("peak memory       {hwm}");
    }
    Ok(())
}

fn mib(bytes: usize) -> f64 {
    bytes as f64 / (1024.0 * 1024.0)
}

/// VmHWM (peak resident set) from /proc, where there is one.
fn peak_memory() -> Option<String> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    Some(line["VmHWM:".len()..].trim().to_string())
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
