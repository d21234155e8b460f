//! `omnicloud render`: load, place the camera, choose radii, render, write.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Result, anyhow, bail};
use glam::DVec3;
use indicatif::ProgressBar;

use crate::compare::rendered_disparity::left_eye_disparity;
use crate::output::{AnaglyphMethod, ImageFormat, Layout, OutputOptions};
use crate::prepare::{CameraChoice, PrepareOptions, Prepared, prepare_files, subsample};
use crate::projection::Image;
use crate::projection::disparity_image::comfort;
use crate::render::{RenderSettings, RendererKind};
use crate::renderer::Resident;
use crate::{Rendered, output, raytrace};

use super::progress;
use super::render_args::RenderArgs;

/// Runs `omnicloud render`: lengths converted from `--units` to the first input's unit.
pub fn run(given: &RenderArgs) -> Result<()> {
    let first = crate::io::read_info(&given.file)?;
    let scale = given.view.length_scale(&first);
    let args = &given.in_file_units(&scale);
    // Check output names before the (long) render, not after it.
    let format = ImageFormat::from_path(&args.output)?;
    let stereo = args.view.eyes() == 2;
    if format == ImageFormat::VrJpeg && !stereo {
        bail!("a VR photo (.vr.jpg) holds two eyes: it needs --stereo ods");
    }
    if format == ImageFormat::VrJpeg && !args.view.projection.is_full_equirect() {
        bail!(
            "a VR photo (.vr.jpg) holds 360° x 180° equirectangular eyes: drop --projection {} \
             or write a .png",
            args.view.projection
        );
    }
    if format == ImageFormat::VrJpeg && args.separate_eyes {
        bail!("a VR photo (.vr.jpg) holds both eyes in one file: drop --separate-eyes");
    }
    if args.height.is_some() && matches!(args.view.camera, Some(CameraChoice::At(_))) {
        bail!("--height places an automatic camera: drop it with --camera X,Y,Z");
    }
    if let Some(d) = &args.depth {
        ImageFormat::require(d, ImageFormat::Exr)?;
    }
    if let Some(a) = &args.anaglyph {
        ImageFormat::require(a, ImageFormat::Png)?;
    }
    if args.anaglyph.is_some() && !stereo {
        bail!("--anaglyph needs --stereo ods (a mono panorama has no second eye)");
    }
    if args.look.wants_alpha() && matches!(format, ImageFormat::Jpeg | ImageFormat::VrJpeg) {
        bail!(
            "{}: a JPEG has no alpha, so its background cannot be transparent: write a .png or \
             .exr, or give a colour (--background black)",
            args.output.display()
        );
    }
    let look = args.look();
    let map = args.view.projection.is_map();
    if map && stereo {
        bail!("--projection map is a top-down view: it has one eye (drop --stereo)");
    }
    if map && args.subsample.is_some() {
        bail!("--subsample thins by panorama pixels: it does not apply to --projection map");
    }
    if (args.disparity.is_some() || args.comfort) && !stereo {
        bail!(
            "--disparity and --comfort measure two eyes: add --stereo ods (or parallel, cubemap)"
        );
    }
    if let Some(d) = &args.disparity {
        ImageFormat::require(d, ImageFormat::Exr)?;
    }
    // The map's size follows from the scan's extent, known once it is loaded.
    let out_image = if map {
        None
    } else {
        Some(
            Image::new(args.view.projection, args.draw.width)
                .map_err(|e| anyhow!("--width: {e}"))?,
        )
    };
    let image = match &out_image {
        Some(out) => look.render_image(out)?,
        None => Image::equirect(args.draw.width),
    };
    let say = |msg: String| {
        if !args.quiet {
            eprintln!("{msg}");
        }
    };

    super::interrupt::install_interrupt_handler();
    super::notes::say_units(&first, &scale, &given.given_lengths(), &say);
    super::notes::say_index_hint(&args.inputs(), &say);
    if !args.more_files.is_empty() {
        warn_mixed_crs(args, &say)?;
    }

    // Scenes are centred on the camera: it sits at the local origin.
    let settings = args
        .draw
        .settings(&args.view, image, args.view.camera_at(DVec3::ZERO))?;
    let render_start = Instant::now();
    let rendered = match (args.origin, args.draw.renderer) {
        _ if map => render_map(args, &settings, &look, &say)?,
        (Some(origin), _) => render_resident(args, origin, &settings, &say)?,
        (None, RendererKind::Raytrace) => ray_trace(args, &settings, &say)?,
        (None, RendererKind::Raster) => super::render_stream::rasterize(args, &settings, &say)?,
    };
    let drawn = (rendered.frames()[0].width, rendered.frames()[0].height);
    let rendered = look.finish(rendered);
    if args.look.supersample > 1 {
        let out = rendered.frames()[0];
        say(format!(
            "supersample {n}x{n}: rendered {}x{} per eye, reduced to {}x{}",
            drawn.0,
            drawn.1,
            out.width,
            out.height,
            n = args.look.supersample
        ));
    }
    say(format!("rendered in {:.2?}", render_start.elapsed()));

    let layout = if args.separate_eyes {
        Layout::SeparateEyes
    } else {
        Layout::TopBottom
    };
    let options = OutputOptions {
        layout,
        jpeg_quality: args.quality,
        yaw_degrees: args.view.yaw,
        projection: args.view.projection,
        metres_per_unit: scale.metres_per_unit,
    };
    let mut written = output::write_image_with(&args.output, &rendered, &options)?;
    if let Some(d) = &args.depth {
        written.extend(output::write_depth_with(d, &rendered, &options)?);
    }
    if let (Some(out), true) = (out_image, args.disparity.is_some() || args.comfort) {
        let disparity = left_eye_disparity(&rendered, &settings, &out, None);
        // Perceived distances in metres (angles do not change with the unit of length): the
        // lengths as given, or in file units converted.
        let metres = |given: f64, file: f64| match scale.units {
            crate::prepare::Units::Metres => given,
            crate::prepare::Units::File => scale.to_metres(file).unwrap_or(file),
        };
        let half_ipd = 0.5 * metres(given.view.ipd, settings.stereo.ipd());
        let near = metres(given.comfort_near, args.comfort_near);
        let wraps = out.projection.is_full_equirect();
        let comfort = comfort(&disparity, half_ipd, near, wraps);
        eprintln!("{comfort}");
        if let Some(path) = &args.disparity {
            output::disparity_exr::write_disparity_exr(path, &disparity)?;
            written.push(path.clone());
        }
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
    // A top-bottom PNG/JPEG carries no GPano (it would describe one sphere, not two), so its
    // name is what tells players it is stereo.
    if stereo
        && options.panorama()
        && layout == Layout::TopBottom
        && matches!(format, ImageFormat::Png | ImageFormat::Jpeg)
        && !names_top_bottom(&args.output)
    {
        say(format!(
            "hint: players such as the Quest's recognise top-bottom stereo from a name \
             ending `_360_TB` (e.g. {})",
            top_bottom_name(&args.output).display()
        ));
    }
    Ok(())
}

/// Warns when the input files declare different coordinate systems: their coordinates are
/// used as they are, so tiles in different systems do not line up.
fn warn_mixed_crs(args: &RenderArgs, say: &impl Fn(String)) -> Result<()> {
    let mut seen: Vec<(String, PathBuf)> = Vec::new();
    for path in args.inputs() {
        let info = crate::io::read_info(&path)?;
        let crs = match info.las.and_then(|l| l.crs) {
            Some(c) => c.to_string(),
            None => "none declared".to_string(),
        };
        if !seen.iter().any(|(c, _)| *c == crs) {
            seen.push((crs, path));
        }
    }
    if seen.len() > 1 {
        let list: Vec<String> = seen
            .iter()
            .map(|(c, p)| format!("{} ({c})", p.display()))
            .collect();
        say(format!(
            "warning: the files declare different coordinate systems, used as they are: {}",
            list.join("; ")
        ));
    }
    Ok(())
}

/// True when the file name already marks a top-bottom 360° image (`_360_TB`, any case).
fn names_top_bottom(path: &Path) -> bool {
    path.file_stem()
        .is_some_and(|s| s.to_string_lossy().to_ascii_uppercase().contains("_360_TB"))
}

/// `pano.png` -> `pano_360_TB.png`, the name the hint suggests.
fn top_bottom_name(path: &Path) -> PathBuf {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let ext = path
        .extension()
        .map(|e| format!(".{}", e.to_string_lossy()))
        .unwrap_or_default();
    path.with_file_name(format!("{stem}_360_TB{ext}"))
}

/// The inputs loaded whole (within `--max-memory`), around `origin` when given, with what
/// the level of detail, the reader and the filters dropped said.
fn load_whole(args: &RenderArgs, origin: Option<DVec3>, say: &impl Fn(String)) -> Result<Prepared> {
    crate::cli::render_guard::check_memory(args)?;
    let options = PrepareOptions {
        origin: origin.or(args.prepare_options().origin),
        ..args.prepare_options()
    };
    let prepared = prepare_files(&args.inputs(), &options, &ProgressBar::hidden())?;
    if let Some(lod) = &prepared.lod {
        say(format!("{}: {lod}", args.inputs_name()));
    }
    super::notes::say_load_notes(Path::new(&args.inputs_name()), &prepared.report, say);
    args.say_filtered(&prepared.filtered, prepared.scene.len() as u64, say);
    Ok(prepared)
}

/// `--origin`: the scan loaded whole around `origin` and rendered as a tour renders each frame
/// (the camera moves in that frame), so that the two give the same file.
fn render_resident(
    args: &RenderArgs,
    origin: DVec3,
    settings: &RenderSettings,
    say: &impl Fn(String),
) -> Result<Rendered> {
    if args.subsample.is_some() {
        bail!("--subsample is not available with --origin (a tour keeps the whole scan)");
    }
    let prepared = load_whole(args, Some(origin), say)?;
    let settings = RenderSettings {
        camera: args.view.camera_at(prepared.camera_world - origin),
        ..*settings
    };
    let resident = Resident::new(&prepared.scene, args.draw.renderer, &settings)?;
    say(format!(
        "{}: camera at ({}, {}, {}) in the frame of origin ({}, {}, {}); {}",
        args.inputs_name(),
        prepared.camera_world.x,
        prepared.camera_world.y,
        prepared.camera_world.z,
        origin.x,
        origin.y,
        origin.z,
        resident.describe()
    ));
    Ok(resident.render(&settings, &ProgressBar::hidden())?)
}

/// `--projection map`: the scan loaded whole, the map laid over its extent (around the
/// camera's origin, whose orientation it ignores), drawn by either renderer.
fn render_map(
    args: &RenderArgs,
    settings: &RenderSettings,
    look: &crate::render::Look,
    say: &impl Fn(String),
) -> Result<Rendered> {
    let prepared = load_whole(args, args.origin, say)?;
    let map = crate::prepare::map_extent::map_image(&prepared.scene, args.draw.width)
        .map_err(|e| anyhow!("{}: {e}", args.inputs_name()))?;
    if let crate::projection::Projection::Map(Some(f)) = map.projection {
        let o = prepared.scene.origin;
        let unit = prepared.report.info.length_symbol();
        say(format!(
            "{}: map over x {:.2}..{:.2}, y {:.2}..{:.2} ({:.1} x {:.1} {unit}), {}x{} px",
            args.inputs_name(),
            f.x0 + o.x,
            f.x1 + o.x,
            f.y0 + o.y,
            f.y1 + o.y,
            f.x1 - f.x0,
            f.y1 - f.y0,
            map.width,
            map.height
        ));
    }
    let settings = RenderSettings {
        image: look.render_image(&map)?,
        ..*settings
    };
    let resident = Resident::new(&prepared.scene, args.draw.renderer, &settings)?;
    Ok(resident.render(&settings, &ProgressBar::hidden())?)
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
        radii,
        report,
        filtered,
        lod,
    } = prepare_files(
        &args.inputs(),
        &args.prepare_options(),
        &ProgressBar::hidden(),
    )?;
    if let Some(lod) = &lod {
        say(format!("{}: {lod}", args.inputs_name()));
        crate::cli::render_guard::check_memory_after_selection(
            args,
            lod.points_read,
            scene.len() as u64,
        )?;
    }
    super::notes::say_load_notes(Path::new(&args.inputs_name()), &report, say);
    args.say_filtered(&filtered, scene.len() as u64, say);
    if let Some(how) = args.subsample {
        let before = scene.len();
        scene = subsample::apply(&scene, how, &settings.camera, settings.image.width);
        say(format!(
            "subsample {how:?}: kept {} of {before} points ({:.1}%)",
            scene.len(),
            100.0 * scene.len() as f64 / before.max(1) as f64
        ));
        crate::cli::render_guard::check_memory_after_subsample(args, &scene)?;
    }
    say(format!(
        "{}: {} points, radius {}, camera at ({:.3}, {:.3}, {:.3}) loaded in {:.2?}",
        args.inputs_name(),
        scene.len(),
        radii.describe(&report.info.length_symbol()),
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
