//! LAS 1.0–1.4 and LAZ (point formats 0–10) through the `las` crate, read in chunks.

use super::chunk::{RawChunk, RawRgb};
use super::error::LoadError;
use super::guard::guarded;
use super::info::{AttributesPresent, ColorDepth, FileInfo, Format};
use glam::DVec3;
use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

mod laz_chunks;

/// Largest decoded byte buffer per read: 16 MiB, well above 65,536 points of any real format.
const MAX_CHUNK_BYTES: u64 = 16 << 20;

/// Streams the points of one LAS/LAZ file.
pub(crate) struct LasSource {
    path: PathBuf,
    reader: las::Reader,
    buffer: las::PointData,
    declared: u64,
    read: u64,
    /// Bytes per point record, as the header declares.
    record_len: u64,
    /// Set after the decoder panicked or a seek failed: its state is unknown, so nothing more
    /// is read.
    broken: bool,
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

/// Checks that the first extended VLR (the one the `las` crate reads) fits in the file: its
/// 64-bit length is otherwise handed to a `Vec::resize` unchecked (found by fuzzing: a flipped
/// bit asked for 17 GB).
fn check_evlr(
    path: &Path,
    read: &mut BufReader<File>,
    file_len: u64,
    start: u64,
) -> Result<(), LoadError> {
    /// reserved u16, user id [u8; 16], record id u16, then the u64 length.
    const LENGTH_AT: u64 = 20;
    const EVLR_HEADER: u64 = 60;
    let corrupt = |detail: String| LoadError::CorruptHeader {
        path: path.to_path_buf(),
        format: "LAS",
        detail,
    };
    if start.saturating_add(EVLR_HEADER) > file_len {
        return Err(corrupt(format!(
            "the extended VLRs start at byte {start}, past the end of the {file_len}-byte file"
        )));
    }
    let mut length = [0u8; 8];
    read.seek(SeekFrom::Start(start + LENGTH_AT))
        .and_then(|_| read.read_exact(&mut length))
        .map_err(|e| LoadError::from_io(path, e))?;
    let length = u64::from_le_bytes(length);
    if (start + EVLR_HEADER).saturating_add(length) > file_len {
        return Err(corrupt(format!(
            "an extended VLR at byte {start} declares {length} bytes, more than the file holds"
        )));
    }
    Ok(())
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
    if let Some(evlr) = raw.evlr {
        check_evlr(path, &mut read, file_len, evlr.start_of_first_evlr)?;
    }
    if compressed {
        let layout = laz_chunks::Layout {
            file_len,
            header_size: u64::from(raw.header_size),
            number_of_vlrs: raw.number_of_variable_length_records,
            offset_to_point_data: offset,
            declared_points: raw
                .large_file
                .map_or(0, |l| l.number_of_point_records)
                .max(u64::from(raw.number_of_point_records)),
        };
        laz_chunks::check(path, &mut read, &layout)?;
    }
    read.seek(SeekFrom::Start(0))
        .map_err(|e| LoadError::from_io(path, e))?;

    let reader = guarded(path, "reading the header", || {
        las::Reader::new(read).map_err(|e| header_error(path, e))
    })?;
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
            broken: false,
            record_len: record_len.max(1),
        },
    ))
}

impl LasSource {
    /// Positions the next read at point index `point` (`point == declared` reads nothing).
    pub(crate) fn seek(&mut self, point: u64) -> Result<(), LoadError> {
        let failed = |detail: String| LoadError::SeekFailed {
            path: self.path.clone(),
            point,
            detail,
        };
        if self.broken {
            return Err(failed("the decoder failed earlier in this file".into()));
        }
        if point > self.declared {
            return Err(LoadError::SeekPastEnd {
                path: self.path.clone(),
                point,
                declared: self.declared,
            });
        }
        let (path, reader) = (&self.path, &mut self.reader);
        guarded(path, "seeking", || {
            reader.seek(point).map_err(|e| LoadError::SeekFailed {
                path: path.clone(),
                point,
                detail: e.to_string(),
            })
        })
        .inspect_err(|_| self.broken = true)?;
        self.read = point;
        Ok(())
    }

    /// Reads up to `n` points; `None` once the declared count has been read.
    pub(crate) fn next_raw(&mut self, n: usize) -> Result<Option<RawChunk>, LoadError> {
        if self.read >= self.declared || self.broken {
            return Ok(None);
        }
        // The decoder sizes its byte buffer as points x record length before decoding; a
        // corrupt record length (up to 65,535 bytes) would make that gigabytes per chunk.
        let n = (n as u64).min((MAX_CHUNK_BYTES / self.record_len).max(1));
        let (path, read, declared) = (&self.path, self.read, self.declared);
        let (reader, buffer) = (&mut self.reader, &mut self.buffer);
        let got = guarded(path, "decoding points", || {
            reader
                .fill_points(n, buffer)
                .map_err(|e| LoadError::CorruptPoints {
                    path: path.clone(),
                    read,
                    declared,
                    detail: e.to_string(),
                })
        })
        .inspect_err(|e| self.broken = matches!(e, LoadError::DecoderPanic { .. }))?;
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
