//! `Image`: a render's frames with what writing them needs, and `compare`.

use std::path::PathBuf;
use std::sync::Arc;

use glam::DVec3;
use numpy::ndarray::{Array2, Array3};
use numpy::{IntoPyArray, PyArray2, PyArray3};
use omnicloud::Rendered;
use omnicloud::compare::eyes::ImageLayout;
use omnicloud::compare::{CompareError, CompareReport, compare_files, compare_named};
use omnicloud::output::{
    ImageDescription, Layout, LinearImage, OutputOptions, StoredEyes, write_depth_with,
    write_image_with,
};
use pyo3::prelude::*;

use crate::errors::{output_error, value_error};

/// A rendered image: `rgba` (H x W x 4 uint8, sRGB, alpha = coverage) and `depth`
/// (H x W float32, distance along each ray in the cloud's unit, inf where empty). A stereo
/// render stacks both eyes top-bottom, left on top, as the saved file does; `left` and
/// `right` are the eyes alone. `save` writes exactly what `omnicloud render -o` writes.
#[pyclass(frozen, module = "omnicloud")]
pub struct Image {
    rendered: Arc<Rendered>,
    options: OutputOptions,
    camera: Option<DVec3>,
}

impl Image {
    /// An image of `rendered`, to be written under `options`; `camera` is where it was
    /// rendered from (world coordinates).
    pub fn new(rendered: Rendered, options: OutputOptions, camera: Option<DVec3>) -> Self {
        Image {
            rendered: Arc::new(rendered),
            options,
            camera,
        }
    }

    /// The description a file of this image carries (projection, eyes, unit).
    fn description(&self) -> ImageDescription {
        ImageDescription {
            projection: self.options.projection,
            eyes: match *self.rendered {
                Rendered::Mono(_) => StoredEyes::Mono,
                Rendered::Stereo { .. } => StoredEyes::TopBottom,
            },
            metres_per_unit: self.options.metres_per_unit,
        }
    }

    /// One eye as an image of its own.
    fn eye(&self, left: bool) -> Option<Image> {
        match &*self.rendered {
            Rendered::Mono(_) => None,
            Rendered::Stereo { left: l, right: r } => Some(Image::new(
                Rendered::Mono(if left { l.clone() } else { r.clone() }),
                self.options,
                self.camera,
            )),
        }
    }
}

#[pymethods]
impl Image {
    /// H x W x 4 uint8 sRGB colour with alpha (255 covered, 0 empty; a fraction when
    /// supersampled); both eyes top-bottom for stereo.
    #[getter]
    fn rgba<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<u8>> {
        let frame = self.rendered.top_bottom();
        let (w, h) = (frame.width as usize, frame.height as usize);
        let values: Vec<u8> = frame.color.iter().flatten().copied().collect();
        Array3::from_shape_vec((h, w, 4), values)
            .expect("4 bytes a pixel")
            .into_pyarray(py)
    }

    /// H x W float32 distance along each ray (the cloud's unit), inf where nothing was hit.
    #[getter]
    fn depth<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        let frame = self.rendered.top_bottom();
        let (w, h) = (frame.width as usize, frame.height as usize);
        Array2::from_shape_vec((h, w), frame.depth)
            .expect("one depth a pixel")
            .into_pyarray(py)
    }

    /// The left eye of a stereo render, None for mono.
    #[getter]
    fn left(&self) -> Option<Image> {
        self.eye(true)
    }

    /// The right eye of a stereo render, None for mono.
    #[getter]
    fn right(&self) -> Option<Image> {
        self.eye(false)
    }

    /// True for a stereo pair.
    #[getter]
    fn stereo(&self) -> bool {
        matches!(*self.rendered, Rendered::Stereo { .. })
    }

    /// Width in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.rendered.frames()[0].width
    }

    /// Height in pixels (both eyes for stereo).
    #[getter]
    fn height(&self) -> u32 {
        self.rendered.frames().iter().map(|f| f.height).sum()
    }

    /// The camera's position in the cloud's coordinates.
    #[getter]
    fn camera(&self) -> Option<(f64, f64, f64)> {
        self.camera.map(Into::into)
    }

    /// Writes the image as `omnicloud render -o PATH` writes it: .png, .jpg, .vr.jpg (stereo
    /// ODS) or .exr (linear colour, coverage and depth), with the same metadata. `quality`:
    /// JPEG quality 1-100; `separate_eyes`: NAME_left.EXT and NAME_right.EXT instead of one
    /// top-bottom file; `depth`: also a depth-only .exr. Returns the paths written.
    ///
    /// Raises ValueError for a name the writers do not know, OSError when writing fails.
    #[pyo3(signature = (path, *, quality=90, separate_eyes=false, depth=None))]
    fn save(
        &self,
        py: Python<'_>,
        path: PathBuf,
        quality: u8,
        separate_eyes: bool,
        depth: Option<PathBuf>,
    ) -> PyResult<Vec<PathBuf>> {
        if !(1..=100).contains(&quality) {
            return Err(value_error(format!(
                "quality: {quality} is not within 1..=100"
            )));
        }
        let options = OutputOptions {
            layout: if separate_eyes {
                Layout::SeparateEyes
            } else {
                Layout::TopBottom
            },
            jpeg_quality: quality,
            ..self.options
        };
        let rendered = &self.rendered;
        py.detach(|| {
            let mut written = write_image_with(&path, rendered, &options)?;
            if let Some(d) = &depth {
                written.extend(write_depth_with(d, rendered, &options)?);
            }
            Ok(written)
        })
        .map_err(output_error)
    }

    /// PNG bytes of the image (both eyes top-bottom), for notebooks.
    fn _repr_png_(&self, py: Python<'_>) -> PyResult<Vec<u8>> {
        let frame = self.rendered.top_bottom();
        let mut png = Vec::new();
        py.detach(|| {
            omnicloud::output::png::encode_png(
                &frame,
                None,
                None,
                &mut png,
                std::path::Path::new("<notebook>"),
            )
        })
        .map_err(output_error)?;
        Ok(png)
    }

    fn __repr__(&self) -> String {
        format!(
            "Image({}x{}, {}, {})",
            self.width(),
            self.height(),
            if self.stereo() {
                "stereo top-bottom"
            } else {
                "mono"
            },
            self.options.projection
        )
    }
}

/// A reference and a test image for `compare`: both Images, or both file paths.
#[derive(FromPyObject)]
pub enum Compared<'py> {
    Image(Bound<'py, Image>),
    Path(PathBuf),
}

/// Compares a test image with a reference, as `omnicloud compare` does: coverage
/// (mismatched pixels, IoU), depth error and colour error, per eye, per latitude band and at
/// the seam. `reference` and `test` are both Images or both file paths (.exr, .png, .jpg).
/// Returns the report as a dict (the JSON `omnicloud compare --report` writes).
///
/// Raises ValueError when sizes or layouts differ, OSError when a file cannot be read.
#[pyfunction]
pub fn compare(py: Python<'_>, reference: Compared<'_>, test: Compared<'_>) -> PyResult<Py<PyAny>> {
    let report: Result<CompareReport, CompareError> = match (reference, test) {
        (Compared::Path(r), Compared::Path(t)) => py.detach(|| compare_files(&r, &t, None, None)),
        (Compared::Image(r), Compared::Image(t)) => {
            let (r, t) = (r.get(), t.get());
            let (rf, tf) = (r.rendered.top_bottom(), t.rendered.top_bottom());
            let description = r.description();
            let layout = ImageLayout::described(&description, rf.height)
                .ok_or_else(|| value_error("the reference's rows do not split into its eyes"))?;
            py.detach(|| {
                compare_named(
                    &LinearImage::from_frame(&rf),
                    &LinearImage::from_frame(&tf),
                    &layout,
                    "images",
                )
            })
        }
        _ => {
            return Err(value_error(
                "compare takes two Images or two file paths, not one of each",
            ));
        }
    };
    let report = report.map_err(|e| match e {
        CompareError::Output(e) => output_error(e),
        e => value_error(e),
    })?;
    let json = serde_json::to_string(&report).map_err(value_error)?;
    Ok(py.import("json")?.call_method1("loads", (json,))?.unbind())
}
