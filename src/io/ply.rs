//! PLY (ascii, binary little and big endian) through `ply-rs-bw`, read one vertex at a time so
//! memory follows the chunk size.
//!
//! Read from the `vertex` element: `x y z` (any scalar type, read as f64), colour
//! `red green blue` (`uchar` → 8 bit, `ushort` → 16-bit fields scaled like LAS, `float`/`double`
//! in 0–1), `intensity` (rounded and clamped to u16), `classification` (clamped to u8; also
//! CloudCompare's `scalar_Classification`), `return_number` with `number_of_returns` (also
//! `scalar_Return_Number`, `scalar_Number_Of_Returns`) and `radius` (metres). Every other
//! property (normals, indices, lists) is read past and ignored.

use super::chunk::{RawChunk, RawRgb};
use super::error::LoadError;
use super::info::{AttributesPresent, ColorDepth, FileInfo, Format, PlyEncoding};
use crate::scene::Returns;
use glam::DVec3;
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{
    ElementDef, Encoding, Property, PropertyAccess, PropertyAccessResult, PropertyType, ScalarType,
};
use std::fs::File;
use std::io::{BufRead, BufReader, ErrorKind, Seek};
use std::path::{Path, PathBuf};

/// Property names this reader uses; everything else is skipped.
const POSITION: [&str; 3] = ["x", "y", "z"];
const COLOR: [&str; 3] = ["red", "green", "blue"];
const INTENSITY: &str = "intensity";
const CLASSIFICATION: [&str; 3] = [
    "classification",
    "scalar_Classification",
    "scalar_classification",
];
const RETURN_NUMBER: [&str; 3] = [
    "return_number",
    "scalar_Return_Number",
    "scalar_return_number",
];
const NUMBER_OF_RETURNS: [&str; 3] = [
    "number_of_returns",
    "scalar_Number_Of_Returns",
    "scalar_number_of_returns",
];
const RADIUS: &str = "radius";

/// One vertex as parsed; fields the file lacks stay 0.
struct PlyVertex {
    xyz: [f64; 3],
    rgb: [f64; 3],
    intensity: f64,
    classification: f64,
    return_number: f64,
    number_of_returns: f64,
    radius: f64,
}

/// A scalar PLY value as f64 (`None` for lists).
fn scalar(p: &Property) -> Option<f64> {
    Some(match *p {
        Property::Char(v) => f64::from(v),
        Property::UChar(v) => f64::from(v),
        Property::Short(v) => f64::from(v),
        Property::UShort(v) => f64::from(v),
        Property::Int(v) => f64::from(v),
        Property::UInt(v) => f64::from(v),
        Property::Float(v) => f64::from(v),
        Property::Double(v) => v,
        _ => return None,
    })
}

impl PropertyAccess for PlyVertex {
    fn new() -> Self {
        PlyVertex {
            xyz: [0.0; 3],
            rgb: [0.0; 3],
            intensity: 0.0,
            classification: 0.0,
            return_number: 0.0,
            number_of_returns: 0.0,
            radius: 0.0,
        }
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        let slot = match name {
            "x" => &mut self.xyz[0],
            "y" => &mut self.xyz[1],
            "z" => &mut self.xyz[2],
            "red" => &mut self.rgb[0],
            "green" => &mut self.rgb[1],
            "blue" => &mut self.rgb[2],
            INTENSITY => &mut self.intensity,
            n if CLASSIFICATION.contains(&n) => &mut self.classification,
            n if RETURN_NUMBER.contains(&n) => &mut self.return_number,
            n if NUMBER_OF_RETURNS.contains(&n) => &mut self.number_of_returns,
            RADIUS => &mut self.radius,
            _ => return PropertyAccessResult::Ignored,
        };
        match scalar(&property) {
            Some(v) => {
                *slot = v;
                PropertyAccessResult::Set
            }
            // Lists under a known name are validated away at open; skip defensively.
            None => PropertyAccessResult::Ignored,
        }
    }
}

/// Elements before `vertex` are read and dropped.
struct Skip;

impl PropertyAccess for Skip {
    fn new() -> Self {
        Skip
    }
}

/// How the file stores colour channels.
#[derive(Debug, Clone, Copy, PartialEq)]
enum ColorKind {
    Bits8,
    Bits16,
    Unit,
}

/// Streams the vertices of one PLY file.
pub(crate) struct PlySource {
    path: PathBuf,
    reader: Reader<BufReader<File>>,
    parser: Parser<PlyVertex>,
    vertex: ElementDef,
    encoding: Encoding,
    color: Option<ColorKind>,
    has_intensity: bool,
    has_classification: bool,
    has_returns: bool,
    has_radius: bool,
    declared: u64,
    read: u64,
    line: String,
    /// Byte offset of the first vertex.
    vertex_start: u64,
    /// Bytes per vertex in a binary file without list properties: binary seeks jump.
    record_len: Option<u64>,
    /// File size, bytes.
    file_len: u64,
}

fn scalar_size(t: &ScalarType) -> u64 {
    match t {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}

/// Bytes per element when no property is a list.
fn fixed_record_len(def: &ElementDef) -> Option<u64> {
    def.properties
        .iter()
        .map(|(_, p)| match &p.data_type {
            PropertyType::Scalar(t) => Some(scalar_size(t)),
            PropertyType::List(..) => None,
        })
        .sum()
}

fn scalar_type<'a>(def: &'a ElementDef, name: &str) -> Option<Option<&'a ScalarType>> {
    def.properties.get(name).map(|p| match &p.data_type {
        PropertyType::Scalar(t) => Some(t),
        PropertyType::List(..) => None,
    })
}

/// Opens a PLY file: parses the header, validates the vertex element, checks (binary files)
/// that the declared vertices fit in the file, and skips elements stored before `vertex`.
pub(crate) fn open(path: &Path) -> Result<(FileInfo, PlySource), LoadError> {
    open_with(path, true)
}

/// Header facts of a PLY file; a binary file whose vertices are cut short still gets them
/// ([`FileInfo::records_in_file`] says how many it holds).
pub(crate) fn header_info(path: &Path) -> Result<FileInfo, LoadError> {
    open_with(path, false).map(|(info, _)| info)
}

/// [`open`], checking that the declared vertices fit in the file when `check_points`.
fn open_with(path: &Path, check_points: bool) -> Result<(FileInfo, PlySource), LoadError> {
    let file = File::open(path).map_err(|e| LoadError::from_io(path, e))?;
    let file_len = file
        .metadata()
        .map_err(|e| LoadError::from_io(path, e))?
        .len();
    let mut reader = Reader::new(BufReader::new(file));
    let parser = Parser::<PlyVertex>::new();
    let header = parser
        .read_header(&mut reader)
        .map_err(|e| LoadError::CorruptHeader {
            path: path.to_path_buf(),
            format: "PLY",
            detail: e.to_string().replace('\n', " "),
        })?;
    let missing = |detail: String| LoadError::PlyMissingXyz {
        path: path.to_path_buf(),
        detail,
    };
    let vertex = header
        .elements
        .get("vertex")
        .cloned()
        .ok_or_else(|| missing("no 'vertex' element".into()))?;
    for name in POSITION {
        match scalar_type(&vertex, name) {
            Some(Some(_)) => {}
            Some(None) => return Err(missing(format!("'{name}' is a list"))),
            None => return Err(missing(format!("'{name}' is missing"))),
        }
    }
    let present = |name: &str| matches!(scalar_type(&vertex, name), Some(Some(_)));
    let color = if COLOR.iter().all(|c| present(c)) {
        match scalar_type(&vertex, "red").flatten() {
            Some(ScalarType::Char | ScalarType::UChar) => Some(ColorKind::Bits8),
            Some(ScalarType::Float | ScalarType::Double) => Some(ColorKind::Unit),
            _ => Some(ColorKind::Bits16),
        }
    } else {
        None
    };
    let encoding = header.encoding;
    let declared = vertex.count as u64;
    if declared == 0 {
        return Err(LoadError::NoPoints {
            path: path.to_path_buf(),
        });
    }

    // Elements stored before the vertices (rare) are read and dropped.
    let mut before_len = Some(0u64);
    for (_, def) in header.elements.iter() {
        if def.name == "vertex" {
            break;
        }
        before_len = before_len
            .zip(fixed_record_len(def))
            .map(|(a, r)| a + r * def.count as u64);
        skip_element(path, &mut reader, def, encoding)?;
    }
    let vertex_start = reader
        .get_mut()
        .stream_position()
        .map_err(|e| LoadError::from_io(path, e))?;
    let record_len = fixed_record_len(&vertex).filter(|_| encoding != Encoding::Ascii);
    let mut records_in_file = None;
    if let (Some(record), Some(_)) = (record_len, before_len) {
        let start = vertex_start;
        let available = file_len.saturating_sub(start) / record.max(1);
        records_in_file = Some(available);
        if check_points && declared > available {
            return Err(LoadError::PointCountExceedsFile {
                path: path.to_path_buf(),
                declared,
                available,
            });
        }
    }

    let any_present = |names: &[&str]| names.iter().any(|n| present(n));
    let has_returns = any_present(&RETURN_NUMBER) && any_present(&NUMBER_OF_RETURNS);
    let ignored_properties = vertex
        .properties
        .iter()
        .map(|(name, _)| name.clone())
        .filter(|name| {
            !(POSITION.contains(&name.as_str())
                || (color.is_some() && COLOR.contains(&name.as_str()))
                || [INTENSITY, RADIUS].contains(&name.as_str())
                || CLASSIFICATION.contains(&name.as_str())
                || (has_returns
                    && (RETURN_NUMBER.contains(&name.as_str())
                        || NUMBER_OF_RETURNS.contains(&name.as_str()))))
        })
        .collect();
    let info = FileInfo {
        path: path.to_path_buf(),
        format: Format::Ply(match encoding {
            Encoding::Ascii => PlyEncoding::Ascii,
            Encoding::BinaryLittleEndian => PlyEncoding::BinaryLittleEndian,
            Encoding::BinaryBigEndian => PlyEncoding::BinaryBigEndian,
        }),
        version: format!("{}.{}", header.version.major, header.version.minor),
        point_format: None,
        point_count: declared,
        bounds: None,
        attributes: AttributesPresent {
            rgb: color.is_some(),
            intensity: present(INTENSITY),
            classification: any_present(&CLASSIFICATION),
            returns: has_returns,
            radius: present(RADIUS),
        },
        color_depth: match color {
            None => ColorDepth::None,
            Some(ColorKind::Bits8) => ColorDepth::Bits8,
            Some(ColorKind::Bits16) => ColorDepth::Bits16,
            Some(ColorKind::Unit) => ColorDepth::Float,
        },
        ignored_properties,
        records_in_file,
        las: None,
        e57: None,
    };
    let source = PlySource {
        path: path.to_path_buf(),
        reader,
        parser,
        color,
        has_intensity: info.attributes.intensity,
        has_classification: info.attributes.classification,
        has_returns: info.attributes.returns,
        has_radius: info.attributes.radius,
        vertex,
        encoding,
        declared,
        read: 0,
        line: String::new(),
        vertex_start,
        record_len,
        file_len,
    };
    Ok((info, source))
}

fn skip_element(
    path: &Path,
    reader: &mut Reader<BufReader<File>>,
    def: &ElementDef,
    encoding: Encoding,
) -> Result<(), LoadError> {
    // Fixed-size binary records are skipped in one seek: a header may declare billions of
    // them (even of zero bytes), which one by one would take minutes.
    if let Some(record) = fixed_record_len(def).filter(|_| encoding != Encoding::Ascii) {
        let bytes = record.saturating_mul(def.count as u64);
        let file = reader.get_mut();
        let here = file
            .stream_position()
            .map_err(|e| LoadError::from_io(path, e))?;
        let len = file
            .get_ref()
            .metadata()
            .map_err(|e| LoadError::from_io(path, e))?
            .len();
        if bytes > len.saturating_sub(here) {
            return Err(LoadError::CorruptHeader {
                path: path.to_path_buf(),
                format: "PLY",
                detail: format!(
                    "element '{}' stored before 'vertex' declares {} records of {record} bytes, more than the file holds",
                    def.name, def.count
                ),
            });
        }
        file.seek_relative(bytes as i64)
            .map_err(|e| LoadError::from_io(path, e))?;
        return Ok(());
    }
    let skipper = Parser::<Skip>::new();
    let mut line = String::new();
    for _ in 0..def.count {
        let result = match encoding {
            Encoding::Ascii => {
                line.clear();
                match reader.get_mut().read_line(&mut line) {
                    Ok(0) => Err(ErrorKind::UnexpectedEof.into()),
                    Ok(_) => Ok(()),
                    Err(e) => Err(e),
                }
            }
            Encoding::BinaryLittleEndian => skipper
                .read_little_endian_element(reader.get_mut(), def)
                .map(|_| ())
                .map_err(std::io::Error::from),
            Encoding::BinaryBigEndian => skipper
                .read_big_endian_element(reader.get_mut(), def)
                .map(|_| ())
                .map_err(std::io::Error::from),
        };
        result.map_err(|e| LoadError::CorruptHeader {
            path: path.to_path_buf(),
            format: "PLY",
            detail: format!(
                "cannot skip element '{}' stored before 'vertex': {e}",
                def.name
            ),
        })?;
    }
    Ok(())
}

/// Parses one ascii vertex line. Done here rather than by `ply-rs-bw`, whose grammar rejects
/// `nan` and `inf`: those points must reach `load_scene` to be dropped and counted.
fn parse_ascii_vertex(line: &str, def: &ElementDef) -> Result<PlyVertex, String> {
    let mut tokens = line.split_ascii_whitespace();
    let mut vertex = PlyVertex::new();
    for (name, property) in &def.properties {
        let token = tokens
            .next()
            .ok_or_else(|| format!("line '{}' has too few values", line.trim()))?;
        match property.data_type {
            PropertyType::Scalar(_) => {
                let v: f64 = token
                    .parse()
                    .map_err(|_| format!("'{token}' is not a number (property '{name}')"))?;
                vertex.set_property(name, Property::Double(v));
            }
            PropertyType::List(..) => {
                let n: usize = token
                    .parse()
                    .map_err(|_| format!("'{token}' is not a list length (property '{name}')"))?;
                if tokens.by_ref().take(n).count() != n {
                    return Err(format!("list '{name}' is shorter than its length {n}"));
                }
            }
        }
    }
    Ok(vertex)
}

impl PlySource {
    fn corrupt(&self, detail: String) -> LoadError {
        LoadError::CorruptPoints {
            path: self.path.clone(),
            read: self.read,
            declared: self.declared,
            detail: detail.replace('\n', " "),
        }
    }

    fn next_vertex(&mut self) -> Result<PlyVertex, LoadError> {
        let parsed = match self.encoding {
            Encoding::Ascii => loop {
                self.line.clear();
                match self.reader.get_mut().read_line(&mut self.line) {
                    Ok(0) => return Err(self.corrupt("the file ends early".into())),
                    Ok(_) if self.line.trim().is_empty() => continue,
                    Ok(_) => {
                        return parse_ascii_vertex(&self.line, &self.vertex)
                            .map_err(|e| self.corrupt(e));
                    }
                    Err(e) => return Err(self.corrupt(e.to_string())),
                }
            },
            Encoding::BinaryLittleEndian => self
                .parser
                .read_little_endian_element(self.reader.get_mut(), &self.vertex),
            Encoding::BinaryBigEndian => self
                .parser
                .read_big_endian_element(self.reader.get_mut(), &self.vertex),
        };
        parsed.map_err(|e| {
            if e.kind() == ErrorKind::UnexpectedEof {
                self.corrupt("the file ends early".into())
            } else {
                self.corrupt(e.to_string())
            }
        })
    }

    /// Positions the next read at vertex `point` (`point == declared` reads nothing): binary
    /// files with fixed-size records jump there; ascii files (and binary ones with list
    /// properties) read and discard the vertices before it, from the start when going back.
    pub(crate) fn seek(&mut self, point: u64) -> Result<(), LoadError> {
        if point > self.declared {
            return Err(LoadError::SeekPastEnd {
                path: self.path.clone(),
                point,
                declared: self.declared,
            });
        }
        let failed = |e: std::io::Error| LoadError::SeekFailed {
            path: self.path.clone(),
            point,
            detail: e.to_string(),
        };
        if let Some(record) = self.record_len {
            let at = point
                .checked_mul(record)
                .and_then(|b| b.checked_add(self.vertex_start))
                .filter(|at| *at <= self.file_len)
                .ok_or_else(|| LoadError::SeekFailed {
                    path: self.path.clone(),
                    point,
                    detail: format!("the {}-byte file ends before it", self.file_len),
                })?;
            self.reader
                .get_mut()
                .seek(std::io::SeekFrom::Start(at))
                .map_err(failed)?;
            self.read = point;
            return Ok(());
        }
        if point < self.read {
            self.reader
                .get_mut()
                .seek(std::io::SeekFrom::Start(self.vertex_start))
                .map_err(failed)?;
            self.read = 0;
        }
        while self.read < point {
            if self.encoding == Encoding::Ascii {
                self.skip_ascii_line()?;
            } else {
                self.next_vertex()?;
            }
            self.read += 1;
        }
        Ok(())
    }

    /// Reads past one non-blank ascii line.
    fn skip_ascii_line(&mut self) -> Result<(), LoadError> {
        loop {
            self.line.clear();
            match self.reader.get_mut().read_line(&mut self.line) {
                Ok(0) => return Err(self.corrupt("the file ends early".into())),
                Ok(_) if self.line.trim().is_empty() => continue,
                Ok(_) => return Ok(()),
                Err(e) => return Err(self.corrupt(e.to_string())),
            }
        }
    }

    /// Reads up to `n` vertices; `None` once the declared count has been read.
    pub(crate) fn next_raw(&mut self, n: usize) -> Result<Option<RawChunk>, LoadError> {
        let n = (n as u64).min(self.declared - self.read) as usize;
        if n == 0 {
            return Ok(None);
        }
        let mut positions = Vec::with_capacity(n);
        let mut rgb8 = Vec::new();
        let mut rgb16 = Vec::new();
        let mut intensity = Vec::new();
        let mut classification = Vec::new();
        let mut returns = Vec::new();
        let mut radius = Vec::new();
        for _ in 0..n {
            let v = self.next_vertex()?;
            self.read += 1;
            positions.push(DVec3::from_array(v.xyz));
            match self.color {
                None => {}
                Some(ColorKind::Bits8) => rgb8.push(v.rgb.map(|c| c.clamp(0.0, 255.0) as u8)),
                Some(ColorKind::Unit) => {
                    rgb8.push(v.rgb.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8))
                }
                Some(ColorKind::Bits16) => rgb16.push(v.rgb.map(|c| c.clamp(0.0, 65535.0) as u16)),
            }
            if self.has_intensity {
                intensity.push(v.intensity.round().clamp(0.0, 65535.0) as u16);
            }
            if self.has_classification {
                classification.push(v.classification.clamp(0.0, 255.0) as u8);
            }
            if self.has_returns {
                returns.push(Returns {
                    number: v.return_number.clamp(0.0, 15.0) as u8,
                    of: v.number_of_returns.clamp(0.0, 15.0) as u8,
                });
            }
            if self.has_radius {
                radius.push(v.radius as f32);
            }
        }
        let rgb = match self.color {
            None => None,
            Some(ColorKind::Bits16) => Some(RawRgb::Bits16(rgb16)),
            Some(_) => Some(RawRgb::Bits8(rgb8)),
        };
        Ok(Some(RawChunk {
            positions,
            rgb,
            intensity: self.has_intensity.then_some(intensity),
            classification: self.has_classification.then_some(classification),
            returns: self.has_returns.then_some(returns),
            radius: self.has_radius.then_some(radius),
            gps_time: None,
        }))
    }
}
