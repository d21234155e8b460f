//! Stereo methods side by side (`bench --stereo-methods`): exact ODS, the paper's per-vertex
//! offset, two parallel cameras and Trapp's cube maps, each rendered by the ray tracer and
//! compared by the angular disparity of the surface every left-eye pixel sees (DESIGN §9).

use std::path::{Path, PathBuf};
use std::time::Instant;

use indicatif::ProgressBar;

use super::disparity_chart::{
    DisparityErrorSeries, disparity_error_series, disparity_error_table, write_disparity_charts,
};
use crate::compare::rendered_disparity::left_eye_disparity;
use crate::projection::disparity_image::DisparityImage;
use crate::projection::{OdsOffset, PoleMerging, Stereo};
use crate::raytrace::{self, RaytraceError, Tracer};
use crate::render::RenderSettings;
use crate::scene::Scene;

/// Longitude bins of the charts (latitude gets half as many).
pub const BINS: usize = 72;

/// What to compare.
#[derive(Debug, Clone, PartialEq)]
pub struct StereoMethodsOptions {
    /// Interocular distance, metres.
    pub ipd: f64,
    /// Pole merging of the ODS methods.
    pub merging: PoleMerging,
    /// Cube-map face sizes to render `cubemap:N` at.
    pub faces: Vec<u32>,
}

/// One method's render and disparity.
#[derive(Debug, Clone)]
pub struct MethodResult {
    /// `ods`, `ods paper offset`, `parallel`, `cubemap:N`.
    pub name: String,
    /// Seconds to render both eyes (0 for the paper offset, which reuses the ODS render).
    pub seconds: f64,
    /// Disparity of each left-eye pixel, arcminutes.
    pub disparity: DisparityImage,
}

/// Every method, its error against exact ODS, and the cube maps' error against `parallel`.
#[derive(Debug, Clone)]
pub struct StereoMethodsReport {
    /// The methods, exact ODS first.
    pub methods: Vec<MethodResult>,
    /// Each method but ODS against exact ODS.
    pub against_ods: Vec<DisparityErrorSeries>,
    /// Each `cubemap:N` against `parallel`: how fast it converges.
    pub cubemap_against_parallel: Vec<DisparityErrorSeries>,
}

/// Why the comparison failed.
#[derive(Debug, thiserror::Error)]
pub enum StereoMethodsError {
    /// The ray tracer failed.
    #[error(transparent)]
    Raytrace(#[from] RaytraceError),
    /// Two disparity images could not be compared.
    #[error(transparent)]
    Series(#[from] super::disparity_chart::DisparityErrorSeriesError),
    /// Writing the charts or the table failed.
    #[error("writing {}: {message}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

/// Renders `scene` under `base` (its camera, image and colours) with each method and compares
/// their disparities. The progress bar counts methods.
pub fn run(
    tracer: &Tracer,
    scene: &Scene,
    base: &RenderSettings,
    options: &StereoMethodsOptions,
    progress: &ProgressBar,
) -> Result<StereoMethodsReport, StereoMethodsError> {
    let ods = Stereo::Ods {
        ipd: options.ipd,
        merging: options.merging,
        offset: OdsOffset::Exact,
    };
    let paper = Stereo::Ods {
        ipd: options.ipd,
        merging: options.merging,
        offset: OdsOffset::Paper,
    };
    let parallel = Stereo::Parallel { ipd: options.ipd };
    progress.set_length(2 + options.faces.len() as u64);
    let hidden = ProgressBar::hidden();
    let mut methods = Vec::new();
    let mut render = |name: String, stereo: Stereo, model: Stereo| {
        let settings = RenderSettings { stereo, ..*base };
        let started = Instant::now();
        let rendered = raytrace::render_with_tracer(tracer, scene, &settings, &hidden)?;
        let seconds = started.elapsed().as_secs_f64();
        progress.inc(1);
        let disparity = left_eye_disparity(&rendered, &settings, &settings.image, Some(model));
        methods.push(MethodResult {
            name,
            seconds,
            disparity,
        });
        Ok::<_, StereoMethodsError>(rendered)
    };
    let ods_render = render("ods".into(), ods, ods)?;
    render("parallel".into(), parallel, parallel)?;
    for &n in &options.faces {
        let cube = Stereo::Cubemap {
            ipd: options.ipd,
            face: n,
        };
        render(format!("cubemap:{n}"), cube, parallel)?;
    }
    // The paper's offset moves where a point is drawn, not what a pixel's ray hits: the
    // surface each ODS pixel sees, placed in both eyes by its per-vertex offset.
    let ods_settings = RenderSettings {
        stereo: ods,
        ..*base
    };
    let paper_disparity =
        left_eye_disparity(&ods_render, &ods_settings, &ods_settings.image, Some(paper));
    methods.insert(
        1,
        MethodResult {
            name: "ods paper offset".into(),
            seconds: 0.0,
            disparity: paper_disparity,
        },
    );
    let reference = &methods[0].disparity;
    let against_ods = methods[1..]
        .iter()
        .map(|m| disparity_error_series(m.name.clone(), reference, &m.disparity, BINS))
        .collect::<Result<Vec<_>, _>>()?;
    let parallel_disparity = &methods
        .iter()
        .find(|m| m.name == "parallel")
        .expect("rendered above")
        .disparity;
    let cubemap_against_parallel = methods
        .iter()
        .filter(|m| m.name.starts_with("cubemap"))
        .map(|m| {
            disparity_error_series(
                format!("{} vs parallel", m.name),
                parallel_disparity,
                &m.disparity,
                BINS,
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(StereoMethodsReport {
        methods,
        against_ods,
        cubemap_against_parallel,
    })
}

/// Writes the charts (`disparity_error_{longitude,latitude}.{png,svg}`) and
/// `stereo_methods.md` into `dir`; returns the files.
pub fn write_outputs(
    report: &StereoMethodsReport,
    dir: &Path,
) -> Result<Vec<PathBuf>, StereoMethodsError> {
    std::fs::create_dir_all(dir).map_err(|e| StereoMethodsError::Write {
        path: dir.to_path_buf(),
        message: e.to_string(),
    })?;
    let mut written = write_disparity_charts(dir, &report.against_ods).map_err(|e| {
        StereoMethodsError::Write {
            path: dir.to_path_buf(),
            message: e.to_string(),
        }
    })?;
    let md = dir.join("stereo_methods.md");
    std::fs::write(&md, markdown(report)).map_err(|e| StereoMethodsError::Write {
        path: md.clone(),
        message: e.to_string(),
    })?;
    written.push(md);
    Ok(written)
}

/// The report as markdown: render times, error against exact ODS, cube-map convergence.
pub fn markdown(report: &StereoMethodsReport) -> String {
    let mut out = String::from(
        "## Stereo methods: angular disparity error against exact ODS\n\n\
         | method | ray-traced pair (s) | pixels with disparity |\n|---|---:|---:|\n",
    );
    for m in &report.methods {
        let time = if m.seconds > 0.0 {
            format!("{:.2}", m.seconds)
        } else {
            "(ODS render)".to_string()
        };
        out.push_str(&format!(
            "| {} | {time} | {} |\n",
            m.name,
            m.disparity.covered_count()
        ));
    }
    out.push('\n');
    out.push_str(&disparity_error_table(&report.against_ods));
    if !report.cubemap_against_parallel.is_empty() {
        out.push_str("\n### Cube maps against parallel cameras (resampling error)\n\n");
        out.push_str(&disparity_error_table(&report.cubemap_against_parallel));
    }
    out
}
