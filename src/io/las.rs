//! LAS 1.0–1.4 and LAZ (point formats 0–10) through the `las` crate, read in chunks.

use super::chunk::{RawChunk, RawRgb};
use super::error::LoadError;
use super::fields::PointFields;
use super::guard::guarded;
use super::info::{
    AttributesPresent, ColorDepth, Crs, FileInfo, Format, GeoKey, LasHeaderInfo, VlrInfo,
};
use crate::scene::Returns;
use glam::DVec3;
use las::crs::GeoTiffData;
use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

pub(super) mod laz_chunks;

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
    /// Where the stored full-detail radius lies in a record's extra bytes, when it has one.
    radius_at: Option<usize>,
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

/// The raw header, checked: version 1.0–1.4, an extended VLR that fits, and (with
/// `check_points`) point records that fit in the file and a sound LAZ chunk table. Leaves
/// `read` at the start of the file. Also says how its LAZ chunks may be decoded.
fn checked_raw_header(
    path: &Path,
    read: &mut BufReader<File>,
    file_len: u64,
    check_points: bool,
) -> Result<(las::raw::Header, laz_chunks::Decoding), LoadError> {
    // The raw header gives the byte layout the parsed header hides; check it before the
    // las crate seeks around a file that may be cut short.
    let raw = las::raw::Header::read_from(&mut *read).map_err(|e| header_error(path, e))?;
    let (major, minor) = (raw.version.major, raw.version.minor);
    if major != 1 || minor > 4 {
        return Err(LoadError::UnsupportedLasVersion {
            path: path.to_path_buf(),
            major,
            minor,
        });
    }
    if check_points
        && let Some((declared, available)) = records_in_file(&raw, file_len)
        && declared > available
    {
        return Err(LoadError::PointCountExceedsFile {
            path: path.to_path_buf(),
            declared,
            available,
        });
    }
    if let Some(evlr) = raw.evlr {
        check_evlr(path, read, file_len, evlr.start_of_first_evlr)?;
    }
    let mut decoding = laz_chunks::Decoding::Sequential;
    if check_points && raw.point_data_record_format & 0xC0 != 0 {
        let layout = laz_chunks::Layout {
            file_len,
            vlrs_at: laz_chunks::vlrs_at(&raw),
            number_of_vlrs: raw.number_of_variable_length_records,
            offset_to_point_data: u64::from(raw.offset_to_point_data),
            declared_points: raw
                .large_file
                .map_or(0, |l| l.number_of_point_records)
                .max(u64::from(raw.number_of_point_records)),
            record_length: raw.point_data_record_length,
        };
        decoding = laz_chunks::check(path, read, &layout)?;
    }
    read.seek(SeekFrom::Start(0))
        .map_err(|e| LoadError::from_io(path, e))?;
    Ok((raw, decoding))
}

/// `(declared, whole records the file's bytes hold)` for an uncompressed file; `None` for
/// LAZ (its compressed size says nothing about its count) or a zero record length.
fn records_in_file(raw: &las::raw::Header, file_len: u64) -> Option<(u64, u64)> {
    let compressed = raw.point_data_record_format & 0xC0 != 0;
    let record_len = u64::from(raw.point_data_record_length);
    let offset = u64::from(raw.offset_to_point_data);
    (!compressed && record_len > 0).then(|| {
        let declared = (raw.offset_to_end_of_points() - offset) / record_len;
        (declared, file_len.saturating_sub(offset) / record_len)
    })
}

/// A header error that names the point count when the count is at fault: the `las` crate
/// seeks past the declared point records, which fails (`EINVAL`) once they would end beyond
/// what the filesystem can address.
fn point_count_error(
    path: &Path,
    raw: &las::raw::Header,
    file_len: u64,
    err: las::Error,
) -> LoadError {
    if let Some((declared, available)) = records_in_file(raw, file_len)
        && declared > available
    {
        return LoadError::PointCountExceedsFile {
            path: path.to_path_buf(),
            declared,
            available,
        };
    }
    match err {
        las::Error::Io(e) if e.kind() == std::io::ErrorKind::InvalidInput => {
            let declared = raw
                .large_file
                .map_or(0, |l| l.number_of_point_records)
                .max(u64::from(raw.number_of_point_records));
            LoadError::CorruptHeader {
                path: path.to_path_buf(),
                format: "LAS",
                detail: format!(
                    "the header declares {declared} points of {} bytes, more than a file can \
                     hold ({e})",
                    raw.point_data_record_length
                ),
            }
        }
        other => header_error(path, other),
    }
}

fn laz_options(parallelism: las::LazParallelism) -> las::ReaderOptions {
    las::ReaderOptions::default().with_laz_parallelism(parallelism)
}

fn open_file(path: &Path) -> Result<(BufReader<File>, u64), LoadError> {
    let file = File::open(path).map_err(|e| LoadError::from_io(path, e))?;
    let file_len = file
        .metadata()
        .map_err(|e| LoadError::from_io(path, e))?
        .len();
    Ok((BufReader::new(file), file_len))
}

/// Header facts of a LAS/LAZ file from its header and (extended) VLRs alone: the point data
/// is neither read nor checked, so a file whose points are cut short still gets its facts
/// ([`FileInfo::records_in_file`] then says how many records it holds).
pub(crate) fn header_info(path: &Path) -> Result<FileInfo, LoadError> {
    let (mut read, file_len) = open_file(path)?;
    let (raw, _) = checked_raw_header(path, &mut read, file_len, false)?;
    let records = records_in_file(&raw, file_len).map(|(_, available)| available);
    let header = guarded(path, "reading the header", || {
        las::Header::new(&mut read).map_err(|e| point_count_error(path, &raw, file_len, e))
    })?;
    let mut info = file_info(path, &header)?;
    info.records_in_file = records;
    Ok(info)
}

/// The [`FileInfo`] of a parsed header.
fn file_info(path: &Path, header: &las::Header) -> Result<FileInfo, LoadError> {
    let format = header.point_format();
    let point_format = format.to_u8().map_err(|e| header_error(path, e))?;
    let b = header.bounds();
    let bounds = Some((
        DVec3::new(b.min.x, b.min.y, b.min.z),
        DVec3::new(b.max.x, b.max.y, b.max.z),
    ))
    .filter(|(lo, hi)| lo.is_finite() && hi.is_finite() && lo.cmple(*hi).all());
    let t = header.transforms();
    let points_by_return: Vec<u64> = {
        let mut v: Vec<u64> = (1..=15)
            .map(|n| header.number_of_points_by_return(n).unwrap_or(0))
            .collect();
        while v.last() == Some(&0) {
            v.pop();
        }
        v
    };
    let vlrs = header
        .vlrs()
        .iter()
        .map(|v| (v, false))
        .chain(header.evlrs().iter().map(|v| (v, true)))
        .map(|(v, extended)| VlrInfo {
            user_id: v.user_id.clone(),
            record_id: v.record_id,
            description: v.description.clone(),
            bytes: v.data.len() as u64,
            extended,
        })
        .collect();
    Ok(FileInfo {
        path: path.to_path_buf(),
        format: if format.is_compressed {
            Format::Laz
        } else {
            Format::Las
        },
        version: format!("{}.{}", header.version().major, header.version().minor),
        point_format: Some(point_format),
        point_count: header.number_of_points(),
        bounds,
        attributes: AttributesPresent {
            rgb: format.has_color,
            intensity: true,
            classification: true,
            returns: true,
            radius: stored_f32_field(header, super::extra_bytes::RADIUS_FIELD).is_some(),
        },
        color_depth: if format.has_color {
            ColorDepth::Bits16
        } else {
            ColorDepth::None
        },
        ignored_properties: Vec::new(),
        records_in_file: None,
        las: Some(LasHeaderInfo {
            scale: DVec3::new(t.x.scale, t.y.scale, t.z.scale),
            offset: DVec3::new(t.x.offset, t.y.offset, t.z.offset),
            system_identifier: header
                .system_identifier()
                .trim_end_matches('\0')
                .to_string(),
            generating_software: header
                .generating_software()
                .trim_end_matches('\0')
                .to_string(),
            creation_date: header.date().map(|d| d.to_string()),
            file_source_id: header.file_source_id(),
            record_length: format.len(),
            points_by_return,
            vlrs,
            crs: crs(header),
        }),
        e57: None,
    })
}

/// The coordinate system a header's VLRs declare: the WKT VLR when there is one (EPSG codes
/// it lacks taken from the GeoTIFF keys, when both are present), else the GeoTIFF keys.
fn crs(header: &las::Header) -> Option<Crs> {
    let geotiff = geotiff_crs(header);
    let Some(bytes) = header.get_wkt_crs_bytes() else {
        return geotiff;
    };
    let text = String::from_utf8_lossy(bytes);
    let mut crs = Crs::from_wkt(text.trim_end_matches('\0'));
    if let Some(g) = geotiff {
        crs.epsg = crs.epsg.or(g.epsg);
        crs.vertical_epsg = crs.vertical_epsg.or(g.vertical_epsg);
        crs.name = crs.name.or(g.name);
        crs.units = crs.units.or(g.units);
    }
    Some(crs)
}

/// The coordinate system the GeoTIFF keys declare; `None` without them or when they do
/// not parse.
fn geotiff_crs(header: &las::Header) -> Option<Crs> {
    let keys = header.get_geotiff_crs().ok().flatten()?;
    let key = |id: u16| {
        keys.entries
            .iter()
            .find(|e| e.id == id)
            .map(|e| match &e.data {
                GeoTiffData::U16(v) => GeoKey::Code(*v),
                GeoTiffData::String(s) => GeoKey::Text(s.clone()),
                GeoTiffData::Doubles(_) => GeoKey::Other,
            })
    };
    Some(Crs::from_geotiff_keys(key))
}

/// Opens a LAS/LAZ file, validating version, point format and, for uncompressed files, that
/// the declared points fit in the file.
pub(crate) fn open(path: &Path) -> Result<(FileInfo, LasSource), LoadError> {
    let (mut read, file_len) = open_file(path)?;
    let (raw, decoding) = checked_raw_header(path, &mut read, file_len, true)?;
    let record_len = u64::from(raw.point_data_record_length);
    let records = records_in_file(&raw, file_len).map(|(_, available)| available);

    let reader = guarded(path, "reading the header", || {
        // LAZ chunks decode in parallel where the chunk table agrees with the file.
        let parallelism = match decoding {
            laz_chunks::Decoding::Parallel => las::LazParallelism::Yes,
            laz_chunks::Decoding::Sequential => las::LazParallelism::No,
        };
        las::Reader::with_options(read, laz_options(parallelism)).map_err(|e| header_error(path, e))
    })?;
    let header = reader.header();
    let declared = header.number_of_points();
    if declared == 0 {
        return Err(LoadError::NoPoints {
            path: path.to_path_buf(),
        });
    }
    let mut info = file_info(path, header)?;
    info.records_in_file = records;
    let buffer = las::PointDataBuilder::new().for_header(header).build();
    let radius_at = stored_f32_field(header, super::extra_bytes::RADIUS_FIELD);
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
            radius_at,
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
        Ok(Some(raw_chunk(
            &self.buffer,
            self.radius_at,
            PointFields::ALL,
        )))
    }
}

/// Byte offset within a record's extra bytes of the f32 field `name` that the header's Extra
/// Bytes VLR describes; `None` without one.
pub(super) fn stored_f32_field(header: &las::Header, name: &str) -> Option<usize> {
    use super::extra_bytes::{RECORD_ID, USER_ID, f32_field_offset};
    let at = header
        .vlrs()
        .iter()
        .chain(header.evlrs())
        .find(|v| v.user_id.trim_end_matches('\0') == USER_ID && v.record_id == RECORD_ID)
        .and_then(|v| f32_field_offset(&v.data, name))?;
    let extra = usize::from(header.point_format().extra_bytes);
    (at + 4 <= extra).then_some(at)
}

/// The decoded points of a [`las::PointData`] as a raw chunk (LAS and COPC alike), with the
/// attributes of `fields` only (the others may hold anything: a selective decoder skipped
/// them); `radius_at` locates a stored f32 radius in the records' extra bytes.
pub(super) fn raw_chunk(
    pd: &las::PointData,
    radius_at: Option<usize>,
    fields: PointFields,
) -> RawChunk {
    let radius = radius_at.map(|at| {
        super::extra_bytes::f32_column(
            pd.raw_bytes(),
            pd.record_len(),
            usize::from(pd.format().extra_bytes),
            at,
        )
    });
    RawChunk {
        positions: pd
            .x()
            .zip(pd.y())
            .zip(pd.z())
            .map(|((x, y), z)| DVec3::new(x, y, z))
            .collect(),
        rgb: pd
            .rgb()
            .filter(|_| fields.rgb)
            .map(|it| RawRgb::Bits16(it.map(|(r, g, b)| [r, g, b]).collect())),
        intensity: fields.intensity.then(|| pd.intensity().collect()),
        classification: fields.classification.then(|| pd.classification().collect()),
        returns: Some(
            pd.return_number()
                .zip(pd.number_of_returns())
                .map(|(number, of)| Returns { number, of })
                .collect(),
        ),
        radius,
        gps_time: pd
            .gps_time()
            .filter(|_| fields.gps_time)
            .map(Iterator::collect),
    }
}
