//! LAS 1.0–1.4 and LAZ (point formats 0–10) through the `las` crate, read in chunks.

use super::chunk::{RawChunk, RawRgb};
use super::error::LoadError;
use super::info::{AttributesPresent, ColorDepth, FileInfo, Format};
use glam::DVec3;
use std::fs::File;
use std::io::{BufReader, Seek, SeekFrom};
use std::path::{Path, PathBuf};

/// Streams the points of one LAS/LAZ file.
pub(crate) struct LasSource {
    path: PathBuf,
    reader: las::Reader,
    buffer: las::PointData,
    declared: u64,
    read: u64,
}

/// Header problems as typed errors.
fn header_error(path: &Path, err: las::Error) -> LoadError {
    let path = path.to_path_buf();
    match err {
        las::Error::InvalidPointFormatNumber(_)
        | las::Error::InvalidPointFormat(_)
        | las::Error::UnsupportedFormat { .. }
        | las::Error::UnsupportedFeature { .. }
        | las::Error::PointDataRecordLengthTooLarge { .. } => {
            LoadError::UnsupportedLasPointFormat {
                path,
                detail: err.to_string(),
            }
        }
        las::Error::Io(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
            LoadError::CorruptHeader {
                path,
                format: "LAS",
                detail: "the file ends inside the header or its VLRs".into(),
            }
        }
        other => LoadError::CorruptHeader {
            path,
            format: "LAS",
            detail: other.to_string(),
        },
    }
}

/// Opens a LAS/LAZ file, validating version, point format and, for uncompressed files, that
/// the declared points fit in the file.
pub(crate) fn open(path: &Path) -> Result<(FileInfo, LasSource), LoadError> {
    let file = File::open(path).map_err(|e| LoadError::from_io(path, e))?;
    let file_len = file
        .metadata()
        .map_err(|e| LoadError::from_io(path, e))?
        .len();
    let mut read = BufReader::new(file);

    // The raw header gives the byte layout the parsed header hides; check it before the
    // las crate seeks around a file that may be cut short.
    let raw = las::raw::Header::read_from(&mut read).map_err(|e| header_error(path, e))?;
    let (major, minor) = (raw.version.major, raw.version.minor);
    if major != 1 || minor > 4 {
        return Err(LoadError::UnsupportedLasVersion {
            path: path.to_path_buf(),
            major,
            minor,
        });
    }
    let compressed = raw.point_data_record_format & 0xC0 != 0;
    let record_len = u64::from(raw.point_data_record_length);
    let offset = u64::from(raw.offset_to_point_data);
    if !compressed && record_len > 0 {
        let declared = (raw.offset_to_end_of_points() - offset) / record_len;
        let available = file_len.saturating_sub(offset) / record_len;
        if declared > available {
            return Err(LoadError::PointCountExceedsFile {
                path: path.to_path_buf(),
                declared,
                available,
            });
        }
    }
    read.seek(SeekFrom::Start(0))
        .map_err(|e| LoadError::from_io(path, e))?;

    let reader = las::Reader::new(read).map_err(|e| header_error(path, e))?;
    let header = reader.header();
    let declared = header.number_of_points();
    if declared == 0 {
        return Err(LoadError::NoPoints {
            path: path.to_path_buf(),
        });
    }
    let format = header.point_format();
    let point_format = format.to_u8().map_err(|e| header_error(path, e))?;
    let b = header.bounds();
    let bounds = Some((
        DVec3::new(b.min.x, b.min.y, b.min.z),
        DVec3::new(b.max.x, b.max.y, b.max.z),
    ))
    .filter(|(lo, hi)| lo.is_finite() && hi.is_finite() && lo.cmple(*hi).all());
    let info = FileInfo {
        path: path.to_path_buf(),
        format: if format.is_compressed {
            Format::Laz
        } else {
            Format::Las
        },
        version: format!("{}.{}", header.version().major, header.version().minor),
        point_format: Some(point_format),
        point_count: declared,
        bounds,
        attributes: AttributesPresent {
            rgb: format.has_color,
            intensity: true,
            classification: true,
            radius: false,
        },
        color_depth: if format.has_color {
            ColorDepth::Bits16
        } else {
            ColorDepth::None
        },
        ignored_properties: Vec::new(),
    };
    let buffer = las::PointDataBuilder::new().for_header(header).build();
    Ok((
        info,
        LasSource {
            path: path.to_path_buf(),
            reader,
            buffer,
            declared,
            read: 0,
        },
    ))
}

impl LasSource {
    /// Reads up to `n` points; `None` once the declared count has been read.
    pub(crate) fn next_raw(&mut self, n: usize) -> Result<Option<RawChunk>, LoadError> {
        if self.read >= self.declared {
            return Ok(None);
        }
        let got = self
            .reader
            .fill_points(n as u64, &mut self.buffer)
            .map_err(|e| LoadError::CorruptPoints {
                path: self.path.clone(),
                read: self.read,
                declared: self.declared,
                detail: e.to_string(),
            })?;
        if got == 0 {
            return Ok(None);
        }
        self.read += got;
        let pd = &self.buffer;
        let positions = pd
            .x()
            .zip(pd.y())
            .zip(pd.z())
            .map(|((x, y), z)| DVec3::new(x, y, z))
            .collect();
        let rgb = pd
            .rgb()
            .map(|it| RawRgb::Bits16(it.map(|(r, g, b)| [r, g, b]).collect()));
        Ok(Some(RawChunk {
            positions,
            rgb,
            intensity: Some(pd.intensity().collect()),
            classification: Some(pd.classification().collect()),
            radius: None,
        }))
    }
}
