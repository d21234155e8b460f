//! `omnicloud info`: a file's header (fast on any size), with `--stats` a pass over its
//! points, as text or JSON.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use glam::DVec3;
use serde_json::Value;

use crate::io::{self, FileInfo, PointStats};
use crate::prepare::radius;
use crate::scene::Scene;
use crate::stream::{SURVEY_POINTS, plan::survey_blocks};

use super::progress;

/// Options of `omnicloud info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// LAS, LAZ, PLY or E57 files (FILE.e57#scan:N,.. for some scans).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Also read every point: class, return-number and returns-per-pulse histograms,
    /// intensity and colour ranges, actual bounds and the point spacing.
    #[arg(long)]
    pub stats: bool,
    /// Print JSON (one object per file, one per line) instead of text.
    #[arg(long)]
    pub json: bool,
    /// Write every image of an E57 file into DIR as it is stored (image_000.png or .jpg,
    /// numbered as `info` lists them; FILE_image_000.* with several files).
    #[arg(long, value_name = "DIR")]
    pub extract_images: Option<PathBuf>,
}

/// Runs `omnicloud info`.
pub fn run(args: &InfoArgs) -> Result<()> {
    for (i, file) in args.files.iter().enumerate() {
        let info = io::read_info(file)?;
        if !args.json {
            if i > 0 {
                println!();
            }
            println!("{info}");
        }
        // The hierarchy EVLR is part of the header read: cheap on any size.
        let copc = io::is_copc(&info).then(|| io::read_octree(file));
        if let (false, Some(copc)) = (args.json, &copc) {
            match copc {
                Ok(o) => println!(
                    "copc:          octree of depth {}, {} nodes with points, root spacing {:.4} {}",
                    o.depth(),
                    o.nonempty_nodes(),
                    o.spacing,
                    info.length_symbol()
                ),
                Err(e) => println!("copc:          {e}"),
            }
        }
        let stats = args.stats.then(|| stats(file, &info, args.json));
        if args.json {
            let mut out = info.to_json();
            match &copc {
                Some(Ok(o)) => {
                    out["copc"] = serde_json::json!({
                        "depth": o.depth(),
                        "nodes": o.nonempty_nodes(),
                        "spacing": o.spacing,
                        "center": [o.center.x, o.center.y, o.center.z],
                        "halfsize": o.halfsize,
                    });
                }
                Some(Err(e)) => out["copc_error"] = Value::from(e.to_string()),
                None => {}
            }
            if let Some(result) = &stats {
                let (key, value) = match result {
                    Ok((stats, spacing)) => {
                        let mut v = stats.to_json();
                        v["spacing"] = (*spacing).into();
                        ("stats", v)
                    }
                    Err(e) => ("stats_error", Value::from(format!("{e:#}"))),
                };
                out[key] = value;
            }
            println!("{out}");
        } else if let Some(Ok((stats, spacing))) = &stats {
            println!("{stats}");
            match spacing {
                Some(s) => println!(
                    "spacing:       {s:.4} {unit} median nearest-neighbour (auto radius {:.4} {unit})",
                    radius::radius_for_spacing(Some(*s)),
                    unit = info.length_symbol()
                ),
                None => println!("spacing:       n/a (fewer than two distinct points)"),
            }
        }
        if let Some(Err(e)) = stats {
            return Err(e);
        }
        if let (Some(dir), Some(e57)) = (&args.extract_images, &info.e57) {
            let prefix = if args.files.len() > 1 {
                format!(
                    "{}_",
                    file.file_stem().unwrap_or_default().to_string_lossy()
                )
            } else {
                String::new()
            };
            extract_images(file, e57.images.len(), dir, &prefix, args.json)?;
        }
    }
    Ok(())
}

/// Writes the `count` images of the E57 `file` into `dir`, named `{prefix}image_NNN.EXT`.
fn extract_images(file: &Path, count: usize, dir: &Path, prefix: &str, quiet: bool) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    for i in 0..count {
        let (image, bytes) = io::e57::read_image(file, i)?;
        let extension = if image.encoding == "jpeg" {
            "jpg"
        } else {
            "png"
        };
        let out = dir.join(format!("{prefix}image_{i:03}.{extension}"));
        crate::output::write_atomically(&out, |w| {
            std::io::Write::write_all(w, &bytes).map_err(|source| crate::output::OutputError::Io {
                path: out.clone(),
                action: "writing",
                source,
            })
        })?;
        if !quiet {
            println!("extracted:     image {i} to {}", out.display());
        }
    }
    Ok(())
}

/// The full pass: statistics, and the median spacing measured where a render's survey would
/// measure it (every point of a file of up to [`SURVEY_POINTS`], else evenly spaced blocks).
fn stats(file: &Path, info: &FileInfo, quiet: bool) -> Result<(PointStats, Option<f32>)> {
    let declared = info.point_count;
    let blocks = if declared <= SURVEY_POINTS as u64 {
        vec![(0, declared)]
    } else {
        survey_blocks(declared, SURVEY_POINTS)
    };
    let pb = progress::bar(quiet, declared, "reading");
    let (stats, sample) = io::point_stats(file, &blocks, &pb).context("--stats")?;
    pb.finish_and_clear();
    let origin = sample.first().copied().unwrap_or(DVec3::ZERO);
    let positions = sample.iter().map(|p| (*p - origin).as_vec3()).collect();
    let spacing = radius::median_spacing(&Scene::new(origin, positions, 0.0));
    Ok((stats, spacing))
}
