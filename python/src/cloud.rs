//! `PointCloud`: a scan in memory as the library holds it (an f64 origin and f32 offsets,
//! per-point attributes), made by reading a file or from numpy arrays.

use std::path::PathBuf;
use std::sync::Arc;

use glam::DVec3;
use numpy::ndarray::Array2;
use numpy::{Element, IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use omnicloud::io::{
    Across, ColorScale, CrsUnits, FileInfo, LinearUnit, LoadOptions, Up, load_files_with_progress,
};
use omnicloud::scene::{Radii, Returns, Scene};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::errors::{load_error, value_error};
use crate::options::{self, FilterArgs};
use crate::progress::with_progress;

/// A point cloud: positions, colour and the attributes LiDAR files carry, with the
/// coordinate system's unit.
///
/// Make one with `omnicloud.read(path)`, `PointCloud.from_arrays(xyz, ...)` or
/// `PointCloud.from_laspy(las)`. Positions are held as the renderers use them: one float64
/// origin and float32 offsets from it (sub-millimetre within a few kilometres), so `xyz`
/// is computed on each access.
#[pyclass(frozen, module = "omnicloud")]
pub struct PointCloud {
    pub(crate) scene: Arc<Scene>,
    /// Header facts when read from a file.
    pub(crate) info: Option<FileInfo>,
    /// The unit of the coordinates (from the file's coordinate system, or as given).
    pub(crate) units: CrsUnits,
    /// The file's up axis (the points are held Z-up).
    pub(crate) up: Up,
    /// How errors name the cloud.
    pub(crate) name: PathBuf,
}

/// Reads a LAS, LAZ, COPC or PLY file into a `PointCloud` (every point: a COPC file's level
/// of detail, which `omnicloud render` applies per camera, does not apply to a cloud).
///
/// Filters drop points from the cloud (`render` takes the same filters and applies them as
/// the command line does, after placing the camera on every point): `classes="2,6"` (or a list of codes) keeps those classification codes, `drop_classes`
/// drops some, `returns` is "all", "first" or "last", `crop=(x0, y0, x1, y1)` keeps a
/// rectangle in file coordinates. `up` is the file's up axis ("z" or "y"). `progress`, when
/// given, is called as `progress(points_read, points_declared)` while the file is read.
///
/// Raises OSError (FileNotFoundError) for a file that cannot be read, ValueError for a bad
/// argument or a filter the file has no attribute for.
#[pyfunction]
#[pyo3(signature = (path, *, classes=None, drop_classes=None, returns="all", crop=None, up="z", progress=None))]
#[allow(clippy::too_many_arguments)]
pub fn read(
    py: Python<'_>,
    path: PathBuf,
    classes: Option<&Bound<'_, PyAny>>,
    drop_classes: Option<&Bound<'_, PyAny>>,
    returns: &str,
    crop: Option<&Bound<'_, PyAny>>,
    up: &str,
    progress: Option<Py<PyAny>>,
) -> PyResult<PointCloud> {
    let up: Up = options::value_enum("up", up)?;
    let filter = FilterArgs {
        classes,
        drop_classes,
        returns,
        crop,
        max_distance: None,
    }
    .filter(1.0)?;
    let info = py
        .detach(|| omnicloud::io::read_info(&path))
        .map_err(load_error)?;
    filter.check(&info).map_err(value_error)?;
    let load = LoadOptions {
        up,
        ..LoadOptions::default()
    };
    let paths = [path.clone()];
    let (scene, _) = with_progress(py, progress, |pb| {
        let (scene, report) = load_files_with_progress(&paths, &load, pb)?;
        // Every filter here (none is relative to a camera): the points dropped are not in
        // the cloud at all, so a camera placed later does not see them either.
        let (scene, _) = filter.apply(scene, up, omnicloud::prepare::filter::Stage::All);
        Ok::<_, omnicloud::io::LoadError>((scene, report))
    })?
    .map_err(load_error)?;
    if scene.is_empty() {
        return Err(value_error(format!(
            "{}: the filters left no point",
            path.display()
        )));
    }
    Ok(PointCloud {
        units: info.units(),
        scene: Arc::new(scene),
        info: Some(info),
        up,
        name: path,
    })
}

/// A unit of length by name: metre, foot (international, 0.3048 m) or US survey foot.
fn unit_named(name: &str) -> PyResult<LinearUnit> {
    let (name, metres) = match name.trim().to_ascii_lowercase().as_str() {
        "m" | "metre" | "meter" | "metres" | "meters" => ("metre", 1.0),
        "ft" | "foot" | "feet" => ("foot", 0.3048),
        "ftus" | "us-ft" | "us survey foot" | "us_survey_foot" => {
            ("US survey foot", 1200.0 / 3937.0)
        }
        _ => {
            return Err(value_error(format!(
                "unit: unknown unit `{name}`: use \"metre\", \"foot\" or \"us survey foot\""
            )));
        }
    };
    Ok(LinearUnit {
        name: name.into(),
        metres,
    })
}

/// A 1-D array argument of `n` values of type `T`, converted; `None` when not given.
fn column<T: Element + Copy>(
    what: &str,
    array: Option<&Bound<'_, PyAny>>,
    n: usize,
    dtype: &str,
) -> PyResult<Option<Vec<T>>> {
    let Some(array) = array else {
        return Ok(None);
    };
    let values: PyReadonlyArray1<'_, T> = array.extract().map_err(|_| {
        value_error(format!(
            "{what} must be a 1-D numpy array of {dtype}, got {}",
            describe(array)
        ))
    })?;
    let view = values.as_array();
    if view.len() != n {
        return Err(value_error(format!(
            "{what} has {} values for {n} points",
            view.len()
        )));
    }
    Ok(Some(view.iter().copied().collect()))
}

/// What an argument is, for messages: a numpy array's dtype and shape, or its Python type.
fn describe(value: &Bound<'_, PyAny>) -> String {
    match (value.getattr("dtype"), value.getattr("shape")) {
        (Ok(dtype), Ok(shape)) => format!("an array of {dtype} with shape {shape}"),
        _ => value
            .get_type()
            .name()
            .map_or_else(|_| "another type".into(), |n| n.to_string()),
    }
}

/// Colour as 8-bit sRGB: uint8 as it is, uint16 scaled as the readers scale LAS colour
/// (values within 0-255 taken as they are, else the high byte).
fn colors(rgb: Option<&Bound<'_, PyAny>>, n: usize) -> PyResult<Option<Vec<[u8; 3]>>> {
    let Some(rgb) = rgb else { return Ok(None) };
    let wrong = || {
        value_error(format!(
            "rgb must be an (N, 3) numpy array of uint8 or uint16 for N = {n} points, got {}",
            describe(rgb)
        ))
    };
    if let Ok(a) = rgb.extract::<PyReadonlyArray2<'_, u8>>() {
        let a = a.as_array();
        if a.dim() != (n, 3) {
            return Err(wrong());
        }
        return Ok(Some(
            a.rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect(),
        ));
    }
    let a: PyReadonlyArray2<'_, u16> = rgb.extract().map_err(|_| wrong())?;
    let a = a.as_array();
    if a.dim() != (n, 3) {
        return Err(wrong());
    }
    Ok(Some(scale_16(n, |i, c| a[[i, c]])))
}

/// 16-bit colour channels `channel(i, c)` scaled to 8 bits as the readers scale them.
fn scale_16(n: usize, channel: impl Fn(usize, usize) -> u16) -> Vec<[u8; 3]> {
    let max = (0..n)
        .flat_map(|i| (0..3).map(move |c| (i, c)))
        .map(|(i, c)| channel(i, c))
        .max()
        .unwrap_or(0);
    let scale = ColorScale::detect_16(max);
    (0..n)
        .map(|i| std::array::from_fn(|c| scale.to_u8(channel(i, c))))
        .collect()
}

/// Return numbers and counts: both, or the number alone (its pulse's count then unknown).
fn returns(number: Option<Vec<u8>>, of: Option<Vec<u8>>) -> PyResult<Option<Vec<Returns>>> {
    match (number, of) {
        (Some(number), Some(of)) => Ok(Some(
            number
                .into_iter()
                .zip(of)
                .map(|(number, of)| Returns { number, of })
                .collect(),
        )),
        (Some(number), None) => Ok(Some(
            number
                .into_iter()
                .map(|number| Returns { number, of: 0 })
                .collect(),
        )),
        (None, Some(_)) => Err(value_error("number_of_returns needs return_number too")),
        (None, None) => Ok(None),
    }
}

/// The first row of `point` whose coordinates are not finite, as an error.
fn check_finite(n: usize, point: impl Fn(usize) -> DVec3) -> PyResult<()> {
    match (0..n).find(|&i| !point(i).is_finite()) {
        Some(i) => Err(value_error(format!(
            "xyz row {i} is not finite: {:?}; drop such points first",
            point(i).to_array()
        ))),
        None => Ok(()),
    }
}

/// The attributes every constructor takes besides positions.
struct Extras<'a, 'py> {
    rgb: Option<&'a Bound<'py, PyAny>>,
    radius: Option<&'a Bound<'py, PyAny>>,
    intensity: Option<&'a Bound<'py, PyAny>>,
    classification: Option<&'a Bound<'py, PyAny>>,
    return_number: Option<&'a Bound<'py, PyAny>>,
    number_of_returns: Option<&'a Bound<'py, PyAny>>,
    unit: &'a str,
}

impl Extras<'_, '_> {
    /// A cloud of `n` points at `point(i)` (world coordinates) with these attributes.
    fn cloud(
        &self,
        py: Python<'_>,
        n: usize,
        point: impl Fn(usize) -> DVec3 + Sync,
        rgb: Option<Vec<[u8; 3]>>,
    ) -> PyResult<PointCloud> {
        if n == 0 {
            return Err(value_error("xyz holds no point"));
        }
        let unit = unit_named(self.unit)?;
        let radius: Option<Vec<f32>> = match self.radius {
            None => None,
            Some(r) => match column::<f32>("radius", Some(r), n, "float32") {
                Ok(r) => r,
                Err(_) => column::<f64>("radius", Some(r), n, "float32 or float64")?
                    .map(|r| r.into_iter().map(|x| x as f32).collect()),
            },
        };
        let intensity = column::<u16>("intensity", self.intensity, n, "uint16")?;
        let classification = column::<u8>("classification", self.classification, n, "uint8")?;
        let returns = returns(
            column::<u8>("return_number", self.return_number, n, "uint8")?,
            column::<u8>("number_of_returns", self.number_of_returns, n, "uint8")?,
        )?;
        let mut scene = py.detach(|| {
            check_finite(n, &point)
                .map(|()| Scene::from_world(n, &point, None, LoadOptions::default().default_radius))
        })?;
        scene.radii = Radii::from_file(radius, LoadOptions::default().default_radius);
        scene.attributes.rgb = rgb;
        scene.attributes.intensity = intensity;
        scene.attributes.classification = classification;
        scene.attributes.returns = returns;
        Ok(PointCloud {
            scene: Arc::new(scene),
            info: None,
            units: CrsUnits {
                across: Across::Linear(unit),
                up: None,
            },
            up: Up::Z,
            name: PathBuf::from("<arrays>"),
        })
    }
}

/// A numpy array of `values` with `shape`.
fn array2<'py, T: Element>(
    py: Python<'py>,
    rows: usize,
    cols: usize,
    values: Vec<T>,
) -> Bound<'py, PyArray2<T>> {
    Array2::from_shape_vec((rows, cols), values)
        .expect("rows x cols values")
        .into_pyarray(py)
}

#[pymethods]
impl PointCloud {
    /// A cloud from numpy arrays.
    ///
    /// `xyz`: (N, 3) float64 (or float32) world coordinates, all finite. Optional, one row or
    /// value per point: `rgb` (N, 3) uint8 or uint16 (16-bit colour is scaled as LAS colour
    /// is), `radius` sphere radii (float32/float64, in the unit of the coordinates),
    /// `intensity` uint16, `classification` uint8 (ASPRS codes), `return_number` and
    /// `number_of_returns` uint8. `unit` names the unit of the coordinates: "metre" (default),
    /// "foot" or "us survey foot"; lengths given to `render` in metres are converted to it.
    ///
    /// Raises ValueError for a wrong dtype or shape, a non-finite coordinate or a length
    /// that does not match N.
    #[staticmethod]
    #[pyo3(signature = (xyz, *, rgb=None, radius=None, intensity=None, classification=None, return_number=None, number_of_returns=None, unit="metre"))]
    #[allow(clippy::too_many_arguments)]
    fn from_arrays(
        py: Python<'_>,
        xyz: &Bound<'_, PyAny>,
        rgb: Option<&Bound<'_, PyAny>>,
        radius: Option<&Bound<'_, PyAny>>,
        intensity: Option<&Bound<'_, PyAny>>,
        classification: Option<&Bound<'_, PyAny>>,
        return_number: Option<&Bound<'_, PyAny>>,
        number_of_returns: Option<&Bound<'_, PyAny>>,
        unit: &str,
    ) -> PyResult<PointCloud> {
        let extras = Extras {
            rgb,
            radius,
            intensity,
            classification,
            return_number,
            number_of_returns,
            unit,
        };
        let wrong = || {
            value_error(format!(
                "xyz must be an (N, 3) numpy array of float64 or float32, got {}",
                describe(xyz)
            ))
        };
        if let Ok(a) = xyz.extract::<PyReadonlyArray2<'_, f64>>() {
            let a = a.as_array();
            let (n, cols) = a.dim();
            if cols != 3 {
                return Err(wrong());
            }
            let rgb = colors(extras.rgb, n)?;
            return extras.cloud(py, n, |i| DVec3::new(a[[i, 0]], a[[i, 1]], a[[i, 2]]), rgb);
        }
        let a: PyReadonlyArray2<'_, f32> = xyz.extract().map_err(|_| wrong())?;
        let a = a.as_array();
        let (n, cols) = a.dim();
        if cols != 3 {
            return Err(wrong());
        }
        let rgb = colors(extras.rgb, n)?;
        extras.cloud(
            py,
            n,
            |i| DVec3::new(a[[i, 0]].into(), a[[i, 1]].into(), a[[i, 2]].into()),
            rgb,
        )
    }

    /// A cloud from a `laspy.LasData`: its point records are read in place (no float64 copy
    /// of the coordinates is made), world = X * scale + offset as a LAS reader computes it.
    /// `unit` names the unit of the coordinates ("metre", "foot" or "us survey foot"): laspy
    /// does not parse the coordinate system without pyproj.
    #[staticmethod]
    #[pyo3(signature = (las, *, unit="metre"))]
    fn from_laspy(py: Python<'_>, las: &Bound<'_, PyAny>, unit: &str) -> PyResult<Py<PyAny>> {
        let fields = py
            .import("omnicloud._laspy")?
            .getattr("las_fields")?
            .call1((las, unit))?;
        let (args, kwargs): (Bound<'_, PyTuple>, Bound<'_, PyDict>) = fields.extract()?;
        Ok(py
            .get_type::<PointCloud>()
            .call_method("_from_las_records", args, Some(&kwargs))?
            .unbind())
    }

    /// A cloud from packed LAS point records (`records`, `record_size` bytes each, the
    /// byte `fields` offsets of X, Y, Z and optionally red, green, blue and intensity, little
    /// endian as LAS stores them) with `scales` and `offsets`; the other attributes as
    /// arrays. `PointCloud.from_laspy` calls this.
    #[staticmethod]
    #[pyo3(signature = (records, record_size, fields, scales, offsets, *, classification=None, return_number=None, number_of_returns=None, unit="metre"))]
    #[allow(clippy::too_many_arguments)]
    fn _from_las_records(
        py: Python<'_>,
        records: PyReadonlyArray1<'_, u8>,
        record_size: usize,
        fields: std::collections::HashMap<String, usize>,
        scales: [f64; 3],
        offsets: [f64; 3],
        classification: Option<&Bound<'_, PyAny>>,
        return_number: Option<&Bound<'_, PyAny>>,
        number_of_returns: Option<&Bound<'_, PyAny>>,
        unit: &str,
    ) -> PyResult<PointCloud> {
        let bytes = records
            .as_slice()
            .map_err(|_| value_error("the point records must be contiguous bytes"))?;
        if record_size == 0 || bytes.len() % record_size != 0 {
            return Err(value_error("the records are not a whole number of points"));
        }
        let n = bytes.len() / record_size;
        let field = |name: &str, size: usize| -> PyResult<Option<usize>> {
            match fields.get(name) {
                Some(&o) if o + size <= record_size => Ok(Some(o)),
                Some(_) => Err(value_error(format!("field {name} lies outside the record"))),
                None => Ok(None),
            }
        };
        let need = |name: &str| {
            field(name, 4)?.ok_or_else(|| value_error(format!("the records have no {name}")))
        };
        let xyz = [need("X")?, need("Y")?, need("Z")?];
        let rgb = [field("red", 2)?, field("green", 2)?, field("blue", 2)?];
        let at = |i: usize, o: usize, size: usize| &bytes[i * record_size + o..][..size];
        let int = |i: usize, o: usize| i32::from_le_bytes(at(i, o, 4).try_into().expect("4 bytes"));
        let short =
            |i: usize, o: usize| u16::from_le_bytes(at(i, o, 2).try_into().expect("2 bytes"));
        let rgb = match rgb {
            [Some(r), Some(g), Some(b)] => {
                Some(py.detach(|| scale_16(n, |i, c| short(i, [r, g, b][c]))))
            }
            _ => None,
        };
        let intensity = field("intensity", 2)?.map(|o| (0..n).map(|i| short(i, o)).collect());
        let extras = Extras {
            rgb: None,
            radius: None,
            intensity: None,
            classification,
            return_number,
            number_of_returns,
            unit,
        };
        let world = |i: usize| {
            DVec3::from_array(std::array::from_fn(|k| {
                f64::from(int(i, xyz[k])) * scales[k] + offsets[k]
            }))
        };
        let cloud = extras.cloud(py, n, world, rgb)?;
        let mut scene = Arc::try_unwrap(cloud.scene).unwrap_or_else(|s| (*s).clone());
        scene.attributes.intensity = intensity;
        Ok(PointCloud {
            scene: Arc::new(scene),
            ..cloud
        })
    }

    /// Number of points.
    fn __len__(&self) -> usize {
        self.scene.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "PointCloud({} points from {}, unit {})",
            self.scene.len(),
            self.name.display(),
            self.unit()
        )
    }

    /// (N, 3) float64 world coordinates (Z up), computed from the origin and the float32
    /// offsets on each access.
    #[getter]
    fn xyz<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let s = &self.scene;
        let values = py.detach(|| {
            s.positions
                .iter()
                .flat_map(|p| (s.origin + p.as_dvec3()).to_array())
                .collect()
        });
        array2(py, s.len(), 3, values)
    }

    /// (N, 3) uint8 sRGB colour, or None.
    #[getter]
    fn rgb<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<u8>>> {
        let rgb = self.scene.attributes.rgb.as_ref()?;
        Some(array2(
            py,
            rgb.len(),
            3,
            rgb.iter().flatten().copied().collect(),
        ))
    }

    /// uint16 intensity, or None.
    #[getter]
    fn intensity<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<u16>>> {
        let v = self.scene.attributes.intensity.as_ref()?;
        Some(PyArray1::from_slice(py, v))
    }

    /// uint8 ASPRS classification codes, or None.
    #[getter]
    fn classification<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<u8>>> {
        let v = self.scene.attributes.classification.as_ref()?;
        Some(PyArray1::from_slice(py, v))
    }

    /// uint8 return number of each point (1 = first), or None.
    #[getter]
    fn return_number<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<u8>>> {
        let v = self.scene.attributes.returns.as_ref()?;
        Some(PyArray1::from_iter(py, v.iter().map(|r| r.number)))
    }

    /// uint8 number of returns of each point's pulse, or None.
    #[getter]
    fn number_of_returns<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<u8>>> {
        let v = self.scene.attributes.returns.as_ref()?;
        Some(PyArray1::from_iter(py, v.iter().map(|r| r.of)))
    }

    /// float32 per-point sphere radii (a PLY `radius` or `from_arrays(radius=...)`), or None.
    #[getter]
    fn radius<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f32>>> {
        match &self.scene.radii {
            Radii::PerPoint(v) => Some(PyArray1::from_slice(py, v)),
            Radii::Uniform(_) => None,
        }
    }

    /// The float64 world position the float32 offsets are measured from.
    #[getter]
    fn origin(&self) -> (f64, f64, f64) {
        self.scene.origin.into()
    }

    /// The coordinate system the file declares (its name or EPSG code), or None.
    #[getter]
    fn crs(&self) -> Option<String> {
        let crs = self.info.as_ref()?.las.as_ref()?.crs.as_ref()?;
        Some(crs.to_string())
    }

    /// The unit of the coordinates, e.g. "metre" or "foot"; "metre" when none is declared,
    /// "degree" for longitude and latitude.
    #[getter]
    fn unit(&self) -> String {
        match &self.units.across {
            Across::Linear(u) => u.name.clone(),
            Across::Unknown => "metre".into(),
            Across::Degrees => "degree".into(),
        }
    }

    /// Metres per unit of the coordinates; None for degrees.
    #[getter]
    fn metres_per_unit(&self) -> Option<f64> {
        match &self.units.across {
            Across::Linear(u) => Some(u.metres),
            Across::Unknown => Some(1.0),
            Across::Degrees => None,
        }
    }
}
