//! Command lines as a user types them: the first byte picks a subcommand prefix, the rest are
//! NUL-separated arguments. Each value also goes through every value parser; a parsed
//! `render` line goes through the checks and set-up that run before a render (output names,
//! memory budget, image, views, ray directions).
#![no_main]

use clap::Parser;
use omnicloud::cli::render_args::RenderArgs;
use omnicloud::cli::{Cli, Command, parse};
use omnicloud::prepare::{RadiusChoice, Subsample};
use omnicloud::projection::{Equirect, Image, PoleMerge};
use omnicloud::render::{ColorMode, Imposter, Proxy, RenderSettings, RendererKind, Shading};

/// Prefixes the first byte chooses from, so mutations spend their time on the options.
const PREFIXES: &[&[&str]] = &[
    &["render", "in.laz", "-o", "out.png"],
    &["render", "in.ply", "-o", "out.exr", "--stereo", "ods"],
    &["bench", "scene.laz"],
    &["compare", "ref.exr", "test.exr"],
    &["info", "in.las"],
    &["index", "in.las", "-o", "out.copc.laz"],
    &["view", "pano.png"],
    &["tour", "scan.laz", "--path", "walk.csv", "-o", "frames"],
    &["serve", "scan.laz"],
    &["video", "frames", "-o", "tour.mp4"],
    &[],
];
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Some((&pick, rest)) = data.split_first() else {
        return;
    };
    // Arguments are OS strings; clap sees lossy UTF-8 here, as from most shells.
    let text = String::from_utf8_lossy(rest);
    let values: Vec<&str> = text.split('\0').collect();
    for value in &values {
        every_value_parser(value);
    }
    let prefix = PREFIXES[pick as usize % PREFIXES.len()];
    let argv = std::iter::once("omnicloud")
        .chain(prefix.iter().copied())
        .chain(values.iter().copied());
    match Cli::try_parse_from(argv) {
        Ok(cli) => {
            if let Command::Render(args) = cli.command {
                before_render(&args);
            }
        }
        Err(e) => assert!(!e.to_string().is_empty()),
    }
});

fn every_value_parser(value: &str) {
    let _ = parse::vec3(value);
    let _ = omnicloud::value::positive_metres(value);
    let _ = parse::ipd(value);
    let _ = parse::degrees(value);
    let _ = parse::width(value).map(Equirect::from_width);
    let _ = value.parse::<RadiusChoice>();
    if let Ok(p) = value.parse::<PoleMerge>() {
        for k in 0..=180 {
            let f = p.factor((f64::from(k) * 0.5).to_radians());
            assert!((0.0..=1.0).contains(&f), "{value}: factor {f}");
        }
        let _ = p.full_merge_latitude();
    }
    let _ = value.parse::<Proxy>();
    let _ = value.parse::<Imposter>();
    let _ = value.parse::<RendererKind>();
    let _ = value.parse::<ColorMode>();
    let _ = value.parse::<Shading>();
    if let Ok(size) = omnicloud::memory::parse_size(value) {
        assert!(size >= 1);
        let _ = omnicloud::memory::format_size(size);
    }
    let _ = value.parse::<Subsample>();
    if let Ok(mode) = omnicloud::bench::BenchMode::parse(value) {
        let _ = mode.label();
    }
}

/// What `omnicloud render` does with its arguments before touching the input file.
fn before_render(args: &RenderArgs) {
    let _ = omnicloud::output::ImageFormat::from_path(&args.output);
    if let Some(d) = &args.depth {
        let _ = omnicloud::output::ImageFormat::require(d, omnicloud::output::ImageFormat::Exr);
    }
    if let Some(a) = &args.anaglyph {
        let _ = omnicloud::output::ImageFormat::require(a, omnicloud::output::ImageFormat::Png);
    }
    if args.separate_eyes {
        let _ = omnicloud::output::eye_path(&args.output, "left");
    }
    let eyes = args.view.eyes();
    let width = args.render_width();
    let cap = args.max_memory.unwrap_or(1 << 30);
    // The budget check, for point counts up to the largest a header can declare.
    for points in [0, 1, 1 << 20, u64::from(u32::MAX), u64::MAX] {
        let estimate = omnicloud::memory::raytrace_estimate(points, points, width, eyes);
        let _ = omnicloud::memory::check_budget(&args.file, &estimate, cap, false);
    }
    // The streamed rasterizer's chunk size under the cap.
    let _ = omnicloud::memory::raster_chunk_points(&args.file, width, eyes, cap, false);
    let _ = args.given_lengths();
    let _ = args.look();
    let Ok(image) = Image::new(args.view.projection, width) else {
        return;
    };
    let center = match args.view.camera {
        Some(omnicloud::prepare::CameraChoice::At(p)) => p,
        _ => glam::DVec3::ZERO,
    };
    let camera = args.view.camera_at(center);
    if let Ok(settings) = args.draw.settings(&args.view, image, camera) {
        check_views(&settings);
    }
}

/// Rays of a grid of pixels are finite unit vectors; projecting a point on each ray gives
/// finite angles.
fn check_views(settings: &RenderSettings) {
    let image = settings.image;
    for view in settings.views() {
        for j in (0..image.height).step_by((image.height as usize / 7).max(1)) {
            for i in (0..image.width).step_by((image.width as usize / 9).max(1)) {
                let Some((origin, dir)) = view.image_ray(&image, i, j) else {
                    continue;
                };
                assert!(
                    dir.is_finite() && (dir.length() - 1.0).abs() < 1e-9,
                    "{dir}"
                );
                let p = origin + 10.0 * dir;
                if let Some((lam, phi)) = view.project(p) {
                    assert!(
                        lam.is_finite() && phi.is_finite(),
                        "({i}, {j}): {lam} {phi}"
                    );
                }
            }
        }
    }
}
