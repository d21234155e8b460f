//! Point-cloud input: LAS/LAZ, PLY and E57 readers, streamed in chunks.
//!
//! [`open`] detects the format (magic bytes first, extension second), reads the header into a
//! [`FileInfo`] and returns a [`PointReader`] whose [`PointReader::chunks`] streams the points
//! in file coordinates (f64) with memory proportional to the chunk size. [`load_scene`] reads a
//! whole file into a [`crate::Scene`]: coordinates minus one f64 origin, stored as f32
//! (DESIGN §1); [`load_files_with_progress`] reads several into one. [`read_info`] reads a
//! header without touching the points; [`point_stats`] makes one streamed pass for
//! `info --stats`.

mod chunk;
pub mod copc;
pub mod e57;
mod error;
pub mod extra_bytes;
mod fields;
mod guard;
mod info;
mod las;
mod load;
mod ply;
mod stats;
mod units;
mod wkt;

pub use chunk::{ColorScale, PointChunk};
pub use copc::{CopcFile, NodeKey, Octree, is_copc, open_nodes, open_nodes_stopping, read_octree};
pub use error::LoadError;
pub use fields::PointFields;
pub use info::{
    AttributesPresent, ColorDepth, Crs, CrsSource, FileInfo, Format, GeoKey, LasHeaderInfo,
    PlyEncoding, VlrInfo, asprs_class_name,
};
pub use load::{
    LoadOptions, LoadReport, Up, load_files_with_progress, load_files_with_reader, load_scene,
    load_scene_with_progress,
};
pub(crate) use load::{MAX_HEADER_EXTENT, header_extent, usable};
pub use stats::{PointStats, point_stats};
pub use units::{Across, CrsUnits, LinearUnit};

pub(crate) use chunk::{RawChunk, RawRgb};
use std::collections::VecDeque;
use std::io::Read;
use std::path::Path;

/// Points read ahead to decide the scale of 16-bit colour when streaming.
pub const COLOR_DETECTION_POINTS: usize = 65_536;

/// The format-specific point source behind a [`PointReader`].
enum Source {
    Las(Box<las::LasSource>),
    Ply(Box<ply::PlySource>),
    /// Chosen nodes of a COPC file ([`open_nodes`]).
    Copc(Box<copc::CopcSource>),
    /// The picked scans of an E57 file.
    E57(Box<e57::E57Source>),
}

impl Source {
    fn next_raw(&mut self, n: usize) -> Result<Option<RawChunk>, LoadError> {
        match self {
            Source::Las(s) => s.next_raw(n),
            Source::Ply(s) => s.next_raw(n),
            Source::Copc(s) => s.next_raw(),
            Source::E57(s) => s.next_raw(n),
        }
    }

    fn seek(&mut self, point: u64) -> Result<(), LoadError> {
        match self {
            Source::Las(s) => s.seek(point),
            Source::Ply(s) => s.seek(point),
            Source::Copc(s) => Err(s.seek_unsupported(point)),
            Source::E57(s) => s.seek(point),
        }
    }
}

/// An opened point-cloud file: its header facts and a stream of its points.
pub struct PointReader {
    info: FileInfo,
    source: Source,
}

impl std::fmt::Debug for PointReader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PointReader")
            .field("info", &self.info)
            .finish_non_exhaustive()
    }
}

/// The formats we can read, by what the file says it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Las,
    Ply,
    E57,
}

/// Detects the format from the first bytes, falling back to the extension to word the error.
fn detect(path: &Path) -> Result<Kind, LoadError> {
    // An E57 path may pick scans or an image after '#'; the file is the part before.
    if let Ok((file, parts)) = e57::select::split(path)
        && parts != e57::select::Parts::default()
    {
        return match detect_file(&file, path)? {
            Kind::E57 => Ok(Kind::E57),
            _ => Err(LoadError::CorruptHeader {
                path: path.to_path_buf(),
                format: "E57",
                detail: if parts.color_from_images {
                    "colour from the scanner's images (--color image) needs an E57 file".into()
                } else {
                    "only E57 files have scans and images to pick (--scan, '#scan:', '#image:')"
                        .into()
                },
            }),
        };
    }
    detect_file(path, path)
}

/// [`detect`] for `path` itself; errors name `shown`.
fn detect_file(path: &Path, shown: &Path) -> Result<Kind, LoadError> {
    let meta = std::fs::metadata(path).map_err(|e| LoadError::from_io(shown, e))?;
    if meta.is_dir() {
        return Err(LoadError::Unreadable {
            path: shown.to_path_buf(),
            source: std::io::Error::other("it is a directory"),
        });
    }
    if meta.len() == 0 {
        return Err(LoadError::EmptyFile {
            path: shown.to_path_buf(),
        });
    }
    let mut magic = Vec::with_capacity(8);
    std::fs::File::open(path)
        .and_then(|f| f.take(8).read_to_end(&mut magic))
        .map_err(|e| LoadError::from_io(shown, e))?;
    if magic == e57::SIGNATURE {
        return Ok(Kind::E57);
    }
    if magic.starts_with(b"LASF") {
        return Ok(Kind::Las);
    }
    if magic.starts_with(b"ply") && matches!(magic.get(3), Some(b'\n' | b'\r')) {
        return Ok(Kind::Ply);
    }
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    let expected = match extension.as_str() {
        "las" | "laz" => Some(("LAS", "'LASF'")),
        "ply" => Some(("PLY", "'ply' and a newline")),
        "e57" => Some((
            "E57",
            "'ASTM-E57' (not an E57 file, or one cut before its header)",
        )),
        _ => None,
    };
    match expected {
        Some((format, signature)) => Err(LoadError::CorruptHeader {
            path: shown.to_path_buf(),
            format,
            detail: format!("the file does not start with {signature}"),
        }),
        None => Err(LoadError::UnsupportedFormat {
            path: shown.to_path_buf(),
            extension,
        }),
    }
}

/// Opens a LAS, LAZ, PLY or E57 file and reads its header.
///
/// # Errors
/// Any [`LoadError`] about the file's existence, format or header; point data is not read.
pub fn open(path: &Path) -> Result<PointReader, LoadError> {
    match detect(path)? {
        Kind::Las => {
            let (info, source) = las::open(path)?;
            Ok(PointReader {
                info,
                source: Source::Las(Box::new(source)),
            })
        }
        Kind::Ply => {
            let (info, source) = ply::open(path)?;
            Ok(PointReader {
                info,
                source: Source::Ply(Box::new(source)),
            })
        }
        Kind::E57 => {
            let (info, source) = e57::open(path)?;
            Ok(PointReader {
                info,
                source: Source::E57(Box::new(source)),
            })
        }
    }
}

/// Header facts of a LAS, LAZ or PLY file without reading or checking its point data: fast
/// on any size, and a file whose points are cut short still gets them (see
/// [`FileInfo::records_in_file`]). [`open`] is the reader that checks the points fit.
///
/// # Errors
/// Any [`LoadError`] about the file's existence, format or header.
pub fn read_info(path: &Path) -> Result<FileInfo, LoadError> {
    match detect(path)? {
        Kind::Las => las::header_info(path),
        Kind::Ply => ply::header_info(path),
        Kind::E57 => e57::header_info(path),
    }
}

impl PointReader {
    /// Header facts of the file.
    pub fn info(&self) -> &FileInfo {
        &self.info
    }

    /// Points this reader will yield as far as its header says: the file's count, or for
    /// chosen nodes of a COPC file the sum of their counts (untrusted either way).
    pub fn points_to_read(&self) -> u64 {
        match &self.source {
            Source::Copc(s) => s.points_pending(),
            _ => self.info.point_count,
        }
    }

    /// Streams the points in chunks of at most `chunk_size` points (file coordinates).
    ///
    /// 16-bit colour is scaled to 8 bits by a [`ColorScale`] decided from the first
    /// `max(chunk_size, COLOR_DETECTION_POINTS)` points, which are read ahead; later values
    /// above 255 in a file judged 8-bit saturate. After an error the iterator ends.
    pub fn chunks(self, chunk_size: usize) -> Chunks {
        Chunks {
            source: self.source,
            chunk_size: chunk_size.max(1),
            scale: None,
            pending: VecDeque::new(),
            done: false,
        }
    }

    /// Streams the points in chunks like [`PointReader::chunks`], with 16-bit colour scaled by
    /// `scale` instead of a scale detected from the first points: for streams whose scale
    /// was decided beforehand (from a survey of the whole file), so every chunk agrees.
    pub fn chunks_with_scale(self, chunk_size: usize, scale: ColorScale) -> Chunks {
        Chunks {
            scale: Some(scale),
            ..self.chunks(chunk_size)
        }
    }

    /// Positions the next read at point index `point`: LAS jumps to the record, LAZ to its
    /// compressed chunk (through the chunk table) and decodes up to the point, binary PLY
    /// jumps to the record, ascii PLY reads and discards lines. `point` equal to the declared
    /// count leaves nothing to read.
    ///
    /// # Errors
    /// [`LoadError::SeekPastEnd`] beyond the declared count; [`LoadError::SeekFailed`] when
    /// the reader cannot get there (a LAZ file without a chunk table, an I/O error); a
    /// [`LoadError::CorruptPoints`] when an ascii PLY file ends before the point. After a
    /// failed seek the reader's position is unknown: open the file again.
    pub fn seek(&mut self, point: u64) -> Result<(), LoadError> {
        self.source.seek(point)
    }

    /// Asks for `fields` only: the readers that can skip attributes without decoding them
    /// (COPC nodes) leave the others out; the rest read every attribute they have.
    #[must_use]
    pub fn decode_only(mut self, fields: PointFields) -> Self {
        if let Source::Copc(s) = &mut self.source {
            s.decode_only(fields);
        }
        self
    }

    /// Reads raw (unscaled) chunks: for [`load_scene`], which decides the colour scale from
    /// every point.
    pub(crate) fn next_raw(&mut self, n: usize) -> Result<Option<RawChunk>, LoadError> {
        self.source.next_raw(n)
    }
}

/// Iterator over the chunks of a [`PointReader`]; see [`PointReader::chunks`].
pub struct Chunks {
    source: Source,
    chunk_size: usize,
    scale: Option<ColorScale>,
    pending: VecDeque<RawChunk>,
    done: bool,
}

impl std::fmt::Debug for Chunks {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Chunks")
            .field("chunk_size", &self.chunk_size)
            .field("scale", &self.scale)
            .finish_non_exhaustive()
    }
}

impl Chunks {
    /// The colour scale in use (`None` before the first chunk is read).
    pub fn color_scale(&self) -> Option<ColorScale> {
        self.scale
    }

    fn next_chunk(&mut self) -> Result<Option<PointChunk>, LoadError> {
        if self.scale.is_none() {
            let first = self
                .source
                .next_raw(self.chunk_size.max(COLOR_DETECTION_POINTS))?;
            let Some(first) = first else {
                return Ok(None);
            };
            let scale = first
                .rgb
                .as_ref()
                .and_then(|c| c.max_16())
                .map_or(ColorScale::Direct8, ColorScale::detect_16);
            self.scale = Some(scale);
            self.pending = first.split_into(self.chunk_size).into();
        }
        let scale = self.scale.unwrap_or(ColorScale::Direct8);
        if let Some(raw) = self.pending.pop_front() {
            return Ok(Some(raw.into_chunk(scale)));
        }
        Ok(self
            .source
            .next_raw(self.chunk_size)?
            .map(|raw| raw.into_chunk(scale)))
    }
}

impl Iterator for Chunks {
    type Item = Result<PointChunk, LoadError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        let item = self.next_chunk().transpose();
        if !matches!(item, Some(Ok(_))) {
            self.done = true;
        }
        item
    }
}
