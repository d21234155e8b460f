//! The render command's safeguard: the memory cap checked before loading.

use anyhow::Result;

use crate::memory::{self, check_budget};
use crate::prepare::Subsample;
use crate::render::RendererKind;

use super::render_args::RenderArgs;

/// Refuses, from the header's point count and before loading, a ray-traced render whose
/// estimated peak exceeds the cap. With `--subsample auto` the kept count is not known yet:
/// only the loading part is checked here, the rest by [`check_memory_after_subsample`].
pub(super) fn check_memory(args: &RenderArgs) -> Result<()> {
    if args.draw.renderer != RendererKind::Raytrace {
        return Ok(());
    }
    let Some((cap, is_default)) = args.memory_cap() else {
        return Ok(());
    };
    if reads_copc_selection(args)? {
        // The selection is known after the camera only: see `check_memory_after_selection`.
        return Ok(());
    }
    let info = inputs_info(args)?;
    let estimate = match args.subsample {
        Some(Subsample::Auto) => {
            memory::raytrace_estimate(info.point_count, 0, args.render_width(), args.view.eyes())
        }
        Some(Subsample::Every(n)) => {
            memory::raytrace_estimate_for(&info, n, args.render_width(), args.view.eyes())
        }
        None => memory::raytrace_estimate_for(&info, 1, args.render_width(), args.view.eyes()),
    };
    check_budget(&args.file, &estimate, cap, is_default)?;
    Ok(())
}

/// True when the render reads a level-of-detail selection: `--lod` on and every input COPC.
fn reads_copc_selection(args: &RenderArgs) -> Result<bool> {
    if args.lod == crate::prepare::LodChoice::Off {
        return Ok(false);
    }
    for path in args.inputs() {
        if !crate::io::is_copc(&crate::io::read_info(&path)?) {
            return Ok(false);
        }
    }
    Ok(true)
}

/// After a level-of-detail read of `read` points, checks the tracer's estimate for them
/// (`kept` of them after `--subsample`).
pub(super) fn check_memory_after_selection(args: &RenderArgs, read: u64, kept: u64) -> Result<()> {
    if args.draw.renderer != RendererKind::Raytrace {
        return Ok(());
    }
    let Some((cap, is_default)) = args.memory_cap() else {
        return Ok(());
    };
    let estimate = memory::raytrace_estimate(read, kept, args.draw.width, args.view.eyes());
    check_budget(&args.file, &estimate, cap, is_default)?;
    Ok(())
}

/// The first input's header facts, its point count the sum over every input.
fn inputs_info(args: &RenderArgs) -> Result<crate::io::FileInfo> {
    let mut info = crate::io::open(&args.file)?.info().clone();
    for more in &args.more_files {
        info.point_count += crate::io::read_info(more)?.point_count;
    }
    Ok(info)
}

/// After `--subsample`, checks the tracer's part for the points actually kept.
pub(super) fn check_memory_after_subsample(args: &RenderArgs, scene: &crate::Scene) -> Result<()> {
    if args.draw.renderer != RendererKind::Raytrace {
        return Ok(());
    }
    let Some((cap, is_default)) = args.memory_cap() else {
        return Ok(());
    };
    let info = inputs_info(args)?;
    let estimate = memory::raytrace_estimate(
        info.point_count,
        scene.len() as u64,
        args.render_width(),
        args.view.eyes(),
    );
    check_budget(&args.file, &estimate, cap, is_default)?;
    Ok(())
}
