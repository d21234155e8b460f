//! `omnicloud render`: load, place the camera, choose radii, render, write.

use std::time::Instant;

use anyhow::{Result, bail};
use glam::DVec3;
use indicatif::ProgressBar;

use crate::output::{AnaglyphMethod, ImageFormat, Layout};
use crate::prepare::{Prepared, prepare, subsample};
use crate::projection::{Camera, Equirect, Stereo, StereoKind};
use crate::render::{RenderSettings, RendererKind};
use crate::scene::Radii;
use crate::{Rendered, output, raytrace};

use super::args::RenderArgs;
use super::progress;

/// Runs `omnicloud render`.
pub fn run(args: &RenderArgs) -> Result<()> {
    // Check output names before the (long) render, not after it.
    ImageFormat::from_path(&args.output)?;
    if let Some(d) = &args.depth {
        ImageFormat::require(d, ImageFormat::Exr)?;
    }
    if let Some(a) = &args.anaglyph {
        ImageFormat::require(a, ImageFormat::Png)?;
    }
    if args.anaglyph.is_some() && args.view.stereo != Some(StereoKind::Ods) {
        bail!("--anaglyph needs --stereo ods (a mono panorama has no second eye)");
    }
    let say = |msg: String| {
        if !args.quiet {
            eprintln!("{msg}");
        }
    };

    crate::cli::render_guard::install_interrupt_handler();

    let settings = RenderSettings {
        image: Equirect::from_width(args.width),
        // Scenes are centred on the camera: it sits at the local origin.
        camera: Camera::new(DVec3::ZERO, args.view.yaw),
        stereo: args.view.stereo_mode().unwrap_or(Stereo::Mono),
        color: args.color,
        shading: args.shading,
        proxy: args.proxy,
        imposter: args.imposter,
    };
    let render_start = Instant::now();
    let rendered = match args.renderer {
        RendererKind::Raytrace => ray_trace(args, &settings, &say)?,
        RendererKind::Raster => super::render_stream::rasterize(args, &settings, &say)?,
    };
    say(format!("rendered in {:.2?}", render_start.elapsed()));

    let layout = if args.separate_eyes {
        Layout::SeparateEyes
    } else {
        Layout::TopBottom
    };
    let mut written = output::write_image(&args.output, &rendered, layout)?;
    if let Some(d) = &args.depth {
        written.extend(output::write_depth(d, &rendered, layout)?);
    }
    if let Some(a) = &args.anaglyph {
        written.push(output::write_anaglyph(
            a,
            &rendered,
            AnaglyphMethod::default(),
        )?);
    }
    for path in &written {
        say(format!("wrote {}", path.display()));
    }
    Ok(())
}

/// The ray tracer needs the whole cloud (and its BVH) in memory: load, subsample, trace.
fn ray_trace(
    args: &RenderArgs,
    settings: &RenderSettings,
    say: &impl Fn(String),
) -> Result<Rendered> {
    crate::cli::render_guard::check_memory(args)?;
    let started = Instant::now();
    let Prepared {
        mut scene,
        camera_world,
        report,
        ..
    } = prepare(
        &args.file,
        &args.view.prepare_options(),
        &ProgressBar::hidden(),
    )?;
    super::warn_dropped(&args.file, &report, say);
    if let Some(how) = args.subsample {
        let before = scene.len();
        scene = subsample::apply(&scene, how, &settings.camera, settings.image);
        say(format!(
            "subsample {how:?}: kept {} of {before} points ({:.1}%)",
            scene.len(),
            100.0 * scene.len() as f64 / before.max(1) as f64
        ));
        crate::cli::render_guard::check_memory_after_subsample(args, &scene)?;
    }
    say(format!(
        "{}: {} points, radius {}, camera at ({:.3}, {:.3}, {:.3}) loaded in {:.2?}",
        args.file.display(),
        scene.len(),
        match &scene.radii {
            Radii::Uniform(r) => format!("{r:.4} m"),
            Radii::PerPoint(_) => "per point".to_string(),
        },
        camera_world.x,
        camera_world.y,
        camera_world.z,
        started.elapsed()
    ));
    let tracer = raytrace::Tracer::new(&scene)?;
    let m = tracer.memory();
    say(format!(
        "BVH over {} spheres built in {:.2?}: {} resident ({} nodes, {} indices, {} sphere records; \
         {:.0} bytes a point)",
        tracer.len(),
        tracer.build_time(),
        crate::memory::format_size(m.total() as u64),
        crate::memory::format_size(m.nodes as u64),
        crate::memory::format_size(m.primitive_indices as u64),
        crate::memory::format_size(m.spheres as u64),
        m.total() as f64 / tracer.len().max(1) as f64
    ));
    let rows = settings.image.height as u64 * settings.views().len() as u64;
    let pb = progress::bar(args.quiet, rows, "ray tracing");
    let r = raytrace::render_with_tracer(&tracer, &scene, settings, &pb)?;
    pb.finish_and_clear();
    Ok(r)
}
