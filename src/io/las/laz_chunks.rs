//! Checks a LAZ file's chunk layout against the file's size before the `laz` crate reads it.
//!
//! `laz` 0.13 trusts two sizes from the file and allocates them before reading: the number of
//! entries of the chunk table (`Vec::with_capacity`, 16 bytes each) and, in the layered
//! decoder of point formats 6–10, each chunk's layer byte counts (a zero-filled `Vec::resize`
//! of up to 4 GiB per layer, then a read that fails). A bit flip in either turns a small file
//! into gigabytes of memory or an abort. Both are checked here from the raw bytes, following
//! the decoder's own reading order, so such files give a [`LoadError`] instead.

use super::LoadError;
use std::io::{Read, Seek, SeekFrom};
use std::path::Path;

/// The LASzip VLR's user id (null-padded to 16 bytes in the file) and record id.
const LASZIP_USER_ID: &[u8] = b"laszip encoded";
const LASZIP_RECORD_ID: u16 = 22204;
/// Bytes of a VLR header: reserved, user id, record id, length, description.
const VLR_HEADER: u64 = 54;

/// `laz`'s compressor types (LASzip VLR, first u16).
const POINT_WISE: u16 = 1;
const POINT_WISE_CHUNKED: u16 = 2;
const LAYERED_CHUNKED: u16 = 3;
/// A chunk size of 0 or `u32::MAX` means variable-size chunks (their point counts are in the
/// chunk table, and in each layered chunk's header).
const VARIABLE_CHUNK_SIZE: u32 = u32::MAX;

/// Where the las crate reads the VLRs of a file with header `raw`: after its stated header
/// size, or after its version's header where that is longer (found by fuzzing: a COPC file
/// stating 374 bytes for a LAS 1.4 header of 375 hid its LASzip VLR from the checks, which
/// looked one byte early, while the decoder used it).
pub(in crate::io) fn vlrs_at(raw: &las::raw::Header) -> u64 {
    u64::from(raw.header_size.max(raw.version.header_size()))
}

/// What the checks need from the LAS header.
pub(in crate::io) struct Layout {
    /// Bytes in the file.
    pub file_len: u64,
    /// Where the VLRs start: after the header size the header states, or after the header
    /// its version has where that is longer, as the las crate reads them ([`vlrs_at`]).
    pub vlrs_at: u64,
    /// VLRs the header declares.
    pub number_of_vlrs: u32,
    /// Where the compressed point data starts.
    pub offset_to_point_data: u64,
    /// Points the header declares (the larger of the legacy and the LAS 1.4 count).
    pub declared_points: u64,
    /// Bytes of a point record, as the header states.
    pub record_length: u16,
}

/// The fields of the LASzip VLR that decide how `laz` reads the point data.
struct LaszipVlr {
    compressor: u16,
    chunk_size: u32,
    /// (item type, item size, item version).
    items: Vec<(u16, u16, u16)>,
}

/// How a checked LAZ file's chunks may be decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(in crate::io) enum Decoding {
    /// Several chunks at once: the chunk table's sizes agree with the file.
    Parallel,
    /// One chunk after another: no chunk table, variable-size chunks, or a table `laz`'s
    /// parallel decoder must not trust (it sizes its buffers from its entries before reading).
    Sequential,
}

/// Most bytes one decoded chunk may take for the parallel decoder (which holds a chunk
/// whole): larger chunks are decoded sequentially.
const MAX_PARALLEL_CHUNK_BYTES: u64 = 256 << 20;

/// Checks the chunk table's entry count and, for layered files, every chunk's layer sizes
/// the decoder will read; says whether the chunks may be decoded in parallel.
///
/// # Errors
/// [`LoadError::CorruptPoints`] naming the chunk and its byte offset when a size in the file
/// exceeds what the file holds; I/O errors as [`LoadError::Unreadable`].
pub(super) fn check<R: Read + Seek>(
    path: &Path,
    read: &mut R,
    layout: &Layout,
) -> Result<Decoding, LoadError> {
    let mut bytes = ByteReader {
        path,
        read,
        len: layout.file_len,
    };
    let Some(vlr) = find_laszip_vlr(&mut bytes, layout)? else {
        // The las crate reports the missing VLR itself.
        return Ok(Decoding::Sequential);
    };
    // A VLR without items still has its chunk table read (found by fuzzing: a table entry
    // count of 3 billion with no items, a 47 GB `Vec::with_capacity`).
    let first_version = vlr.items.first().map(|&(_, _, version)| version);
    let corrupt = |detail: String| LoadError::CorruptPoints {
        path: path.to_path_buf(),
        read: 0,
        declared: layout.declared_points,
        detail,
    };
    check_items(path, &vlr, layout)?;
    let per_chunk = match (vlr.compressor, vlr.chunk_size) {
        (POINT_WISE, _) | (_, 0 | VARIABLE_CHUNK_SIZE) => None,
        (_, n) => Some(u64::from(n)),
    };
    let mut data_start = layout.offset_to_point_data;
    let mut decoding = Decoding::Sequential;
    if matches!(vlr.compressor, POINT_WISE_CHUNKED | LAYERED_CHUNKED) {
        let record = first_point_bytes(&vlr.items).max(1);
        let table = check_chunk_table(&mut bytes, layout, record, per_chunk).map_err(corrupt)?;
        if let Some(table) = table {
            decoding = parallel_decoding(&mut bytes, layout, table, per_chunk)?;
        }
        // The chunk table's offset precedes the chunks.
        data_start += 8;
    } else if vlr.compressor != POINT_WISE {
        return Ok(Decoding::Sequential);
    }
    if matches!(first_version, Some(3 | 4)) {
        let Some(shape) = layered_shape(&vlr.items) else {
            return Ok(Decoding::Sequential); // laz rejects these items itself
        };
        check_layers(&mut bytes, layout, &shape, data_start, per_chunk).map_err(corrupt)?;
    }
    Ok(decoding)
}

/// Whether `laz`'s parallel decoder may read the file whose (count-checked) chunk table
/// starts at byte `table`, chunks of `per_chunk` points: it reads every chunk's byte count
/// and allocates it before decoding, so they must add up to what the file holds (the chunks
/// lie between the table's offset and the table), and a chunk must decode into at most
/// [`MAX_PARALLEL_CHUNK_BYTES`]. Files of variable-size chunks (COPC among them) are decoded
/// sequentially: laz 0.13's parallel `seek` takes a point's place in its chunk as its index
/// modulo the chunk size, which holds for fixed-size chunks only (with variable ones it
/// underflowed in a seek into a COPC file). Any other file is decoded sequentially too,
/// which reads the chunks as it goes.
fn parallel_decoding<R: Read + Seek>(
    bytes: &mut ByteReader<'_, R>,
    layout: &Layout,
    table: u64,
    per_chunk: Option<u64>,
) -> Result<Decoding, LoadError> {
    let point_bytes = u64::from(layout.record_length).max(1);
    let Some(per_chunk) = per_chunk else {
        return Ok(Decoding::Sequential);
    };
    if per_chunk.saturating_mul(point_bytes) > MAX_PARALLEL_CHUNK_BYTES {
        return Ok(Decoding::Sequential);
    }
    bytes
        .read
        .seek(SeekFrom::Start(table))
        .map_err(|e| LoadError::from_io(bytes.path, e))?;
    let Ok(entries) = laz::laszip::ChunkTable::read(&mut bytes.read, false) else {
        return Ok(Decoding::Sequential); // the decoder reports a table it cannot read
    };
    let entries = entries.as_ref();
    let chunk_bytes: u64 = entries
        .iter()
        .map(|e| e.byte_count)
        .fold(0, u64::saturating_add);
    let room = table.saturating_sub(layout.offset_to_point_data + 8);
    Ok(if !entries.is_empty() && chunk_bytes <= room {
        Decoding::Parallel
    } else {
        Decoding::Sequential
    })
}

/// The layered chunk shape of a COPC file's nodes (from its LASzip VLR), for
/// [`NodeChunks::check`]; `None` when the file's items are not layered.
#[derive(Debug)]
pub(in crate::io) struct NodeChunks {
    shape: Option<LayeredShape>,
}

impl NodeChunks {
    /// Reads the LASzip VLR of the file `read` (laid out as `layout` says).
    pub(in crate::io) fn new<R: Read + Seek>(
        path: &Path,
        read: &mut R,
        layout: &Layout,
    ) -> Result<Self, LoadError> {
        let mut bytes = ByteReader {
            path,
            read,
            len: layout.file_len,
        };
        let vlr = find_laszip_vlr(&mut bytes, layout)?;
        if let Some(vlr) = &vlr {
            check_items(path, vlr, layout)?;
        }
        let shape = vlr
            .filter(|v| matches!(v.items.first(), Some(&(_, _, 3 | 4))))
            .and_then(|v| layered_shape(&v.items));
        Ok(NodeChunks { shape })
    }

    /// Checks the layer sizes of the node chunk of `size` bytes at `offset` against its
    /// size: the decoder zero-fills each layer to its stated size before reading it (found by
    /// fuzzing: a node whose layer sizes added up to 2 GB, in a 2 kB file).
    ///
    /// # Errors
    /// A message naming the chunk's byte offset and sizes.
    pub(in crate::io) fn check<R: Read + Seek>(
        &self,
        path: &Path,
        read: &mut R,
        offset: u64,
        size: u64,
    ) -> Result<(), String> {
        let Some(shape) = &self.shape else {
            return Ok(());
        };
        let end = offset.saturating_add(size);
        let mut bytes = ByteReader {
            path,
            read,
            len: end,
        };
        let count_at = offset + shape.first_point;
        let layers_at = count_at + 4 + 4 * shape.layers as u64;

        let Some(sizes) = bytes
            .u32s(count_at + 4, shape.layers)
            .map_err(|e| e.to_string())?
        else {
            return Err(format!(
                "the chunk at byte {offset} ({size} bytes) is too short for its layer sizes"
            ));
        };
        let total: u64 = sizes.iter().map(|&s| u64::from(s)).sum();
        if total > end.saturating_sub(layers_at) {
            return Err(format!(
                "the chunk at byte {offset} ({size} bytes) declares {total} bytes of layers"
            ));
        }
        Ok(())
    }
}

/// Reads little-endian values at absolute offsets; `None` past the end of the file.
struct ByteReader<'a, R> {
    path: &'a Path,
    read: &'a mut R,
    len: u64,
}

impl<R: Read + Seek> ByteReader<'_, R> {
    fn bytes<const N: usize>(&mut self, at: u64) -> Result<Option<[u8; N]>, LoadError> {
        if at.saturating_add(N as u64) > self.len {
            return Ok(None);
        }
        let mut buf = [0u8; N];
        self.read
            .seek(SeekFrom::Start(at))
            .and_then(|_| self.read.read_exact(&mut buf))
            .map_err(|e| LoadError::from_io(self.path, e))?;
        Ok(Some(buf))
    }

    fn u16(&mut self, at: u64) -> Result<Option<u16>, LoadError> {
        Ok(self.bytes(at)?.map(u16::from_le_bytes))
    }

    fn u32(&mut self, at: u64) -> Result<Option<u32>, LoadError> {
        Ok(self.bytes(at)?.map(u32::from_le_bytes))
    }

    fn i64(&mut self, at: u64) -> Result<Option<i64>, LoadError> {
        Ok(self.bytes(at)?.map(i64::from_le_bytes))
    }

    /// `n` u32 values from `at` (the caller checks that they lie in the file).
    fn u32s(&mut self, at: u64, n: usize) -> Result<Option<Vec<u32>>, LoadError> {
        (0..n)
            .map(|k| self.u32(at + 4 * k as u64))
            .collect::<Result<Option<Vec<u32>>, LoadError>>()
    }
}

/// The first LASzip VLR, as the las crate finds it (VLRs from the end of the header, in
/// order).
fn find_laszip_vlr<R: Read + Seek>(
    bytes: &mut ByteReader<'_, R>,
    layout: &Layout,
) -> Result<Option<LaszipVlr>, LoadError> {
    let mut at = layout.vlrs_at;
    for _ in 0..layout.number_of_vlrs {
        let Some(head) = bytes.bytes::<{ VLR_HEADER as usize }>(at)? else {
            return Ok(None);
        };
        let user_id = &head[2..18];
        let record_id = u16::from_le_bytes([head[18], head[19]]);
        let length = u64::from(u16::from_le_bytes([head[20], head[21]]));
        // As the las crate reads a user id: up to its first NUL, whatever follows (found by
        // fuzzing: `laszip encoded\0X` went unchecked here and was decoded there).
        let user_id_matches = user_id.split(|&b| b == 0).next() == Some(LASZIP_USER_ID);
        if user_id_matches && record_id == LASZIP_RECORD_ID {
            return read_laszip_payload(bytes, at + VLR_HEADER, length);
        }
        at += VLR_HEADER + length;
    }
    Ok(None)
}

/// Compressor, chunk size and items of a LASzip VLR payload of `length` bytes at `at`.
fn read_laszip_payload<R: Read + Seek>(
    bytes: &mut ByteReader<'_, R>,
    at: u64,
    length: u64,
) -> Result<Option<LaszipVlr>, LoadError> {
    const ITEMS_AT: u64 = 34;
    let (Some(compressor), Some(chunk_size), Some(count)) =
        (bytes.u16(at)?, bytes.u32(at + 12)?, bytes.u16(at + 32)?)
    else {
        return Ok(None);
    };
    let mut items = Vec::with_capacity(usize::from(count).min(64));
    for k in 0..u64::from(count) {
        let item = at + ITEMS_AT + 6 * k;
        if item + 6 > at + length {
            break;
        }
        let (Some(t), Some(s), Some(v)) =
            (bytes.u16(item)?, bytes.u16(item + 2)?, bytes.u16(item + 4)?)
        else {
            break;
        };
        items.push((t, s, v));
    }
    Ok(Some(LaszipVlr {
        compressor,
        chunk_size,
        items,
    }))
}

/// The LASzip VLR's items must add up to the header's point record, as LASzip requires: the
/// decoder sets up its models from the items before reading a point (found by fuzzing: an
/// extra-bytes item of 65,000 bytes in a file of 38-byte records took 620 MB and a second
/// to open, whatever the file's size).
fn check_items(path: &Path, vlr: &LaszipVlr, layout: &Layout) -> Result<(), LoadError> {
    let stated: u64 = vlr.items.iter().map(|&(_, s, _)| u64::from(s)).sum();
    if vlr.items.is_empty() || stated == u64::from(layout.record_length) {
        return Ok(());
    }
    Err(LoadError::CorruptHeader {
        path: path.to_path_buf(),
        format: "LAS",
        detail: format!(
            "the LASzip VLR's items add up to {stated} bytes a point, the header's point \
             records are {} bytes",
            layout.record_length
        ),
    })
}

/// Bytes of one point as the decoder stores the first point of a chunk: the items' sizes.
fn first_point_bytes(items: &[(u16, u16, u16)]) -> u64 {
    items
        .iter()
        .map(|&(t, s, _)| match t {
            6 => 20,      // Point10
            7 => 8,       // GpsTime
            8 => 6,       // RGB12
            9 | 13 => 29, // WavePacket13/14
            10 => 30,     // Point14
            11 => 6,      // RGB14
            12 => 8,      // RGBNIR14
            _ => u64::from(s),
        })
        .sum()
}

/// A layered chunk's header: the raw first point and the number of u32 layer sizes after the
/// point count.
#[derive(Debug)]
struct LayeredShape {
    first_point: u64,
    layers: usize,
}

/// The layered decoder's fields: Point14 has 9 layers, RGB14 1, RGBNIR14 2 (RGB and NIR),
/// extra bytes one per byte, WavePacket14 1. `None` for items it does not accept.
fn layered_shape(items: &[(u16, u16, u16)]) -> Option<LayeredShape> {
    let mut layers = 0usize;
    for &(t, s, _) in items {
        layers += match t {
            10 => 9,
            11 | 13 => 1,
            12 => 2,
            14 => usize::from(s),
            _ => return None,
        };
    }
    Some(LayeredShape {
        first_point: first_point_bytes(items),
        layers,
    })
}

/// The chunk table's entry count must fit in the point data (every chunk holds at least one
/// raw point of `record` bytes) and, for chunks of a fixed size, match the point count: a
/// corrupt chunk size (found by fuzzing: 50,000 flipped to 1) otherwise makes the decoder
/// restart on every point, for minutes, reading garbage. `laz` reads the table's offset as an
/// i64 at the start of the point data (or, when that is not past it, from the file's last 8
/// bytes).
fn check_chunk_table<R: Read + Seek>(
    bytes: &mut ByteReader<'_, R>,
    layout: &Layout,
    record: u64,
    per_chunk: Option<u64>,
) -> Result<Option<u64>, String> {
    let io = |e: LoadError| e.to_string();
    let start = layout.offset_to_point_data;
    let past_start = |t: Option<i64>| t.filter(|&t| t > start as i64).map(|t| t as u64);
    let mut table = past_start(bytes.i64(start).map_err(io)?);
    if table.is_none() {
        let last = layout.file_len.saturating_sub(8);
        table = past_start(bytes.i64(last).map_err(io)?);
    }
    let Some(table) = table else {
        return Ok(None); // no table: laz fails with an error or reads without one
    };
    if table.saturating_add(8) > layout.file_len {
        // laz then reads the chunks from wherever its failed seek or read left the file
        // (found by fuzzing: an offset past what the file system can seek to made it start
        // 8 bytes late, reading layer sizes out of the compressed data).
        return Err(format!(
            "the LAZ chunk table offset {table} lies past the end of the {}-byte file \
             (truncated or corrupt)",
            layout.file_len
        ));
    }
    let Some(count) = bytes.u32(table + 4).map_err(io)? else {
        return Ok(None); // laz fails reading it
    };
    let room = table.saturating_sub(start + 8) / record;
    if u64::from(count) > room {
        return Err(format!(
            "the LAZ chunk table at byte {table} lists {count} chunks, but the point data \
             before it holds at most {room}"
        ));
    }
    if let Some(per_chunk) = per_chunk {
        let expected = layout.declared_points.div_ceil(per_chunk);
        if u64::from(count) != expected {
            return Err(format!(
                "the LASzip chunk size {per_chunk} makes {expected} chunks of the declared \
                 {} points, but the chunk table at byte {table} lists {count}",
                layout.declared_points
            ));
        }
    }
    Ok(Some(table))
}

/// Walks the layered chunks from `data_start` in the decoder's order, while it still needs
/// points, and refuses a chunk whose layer sizes add up to more than the file holds.
///
/// `per_chunk` is the fixed chunk size, `None` for variable chunks (the count stored in each
/// chunk's header is used) and for point-wise files (one chunk).
fn check_layers<R: Read + Seek>(
    bytes: &mut ByteReader<'_, R>,
    layout: &Layout,
    shape: &LayeredShape,
    data_start: u64,
    per_chunk: Option<u64>,
) -> Result<(), String> {
    let io = |e: LoadError| e.to_string();
    let file_len = layout.file_len;
    let mut at = data_start;
    let mut points = 0u64;
    let mut chunk = 0u64;
    while points < layout.declared_points {
        let count_at = at + shape.first_point;
        let layers_at = count_at + 4 + 4 * shape.layers as u64;
        if layers_at > file_len {
            return Ok(()); // the decoder stops on the end of the file
        }
        let (Some(count), Some(sizes)) = (
            bytes.u32(count_at).map_err(io)?,
            bytes.u32s(count_at + 4, shape.layers).map_err(io)?,
        ) else {
            return Ok(());
        };
        let total: u64 = sizes.iter().map(|&s| u64::from(s)).sum();
        if total > file_len.saturating_sub(layers_at) {
            // A file cut inside its last chunk needs no more than the file's size: the
            // decoder reports it. Larger sizes are corrupt and would be zero-filled first.
            if total > file_len {
                return Err(format!(
                    "LAZ chunk {chunk} at byte {at} declares {total} bytes of layers, \
                     more than the {file_len}-byte file holds"
                ));
            }
            return Ok(());
        }
        at = layers_at + total;
        points = points.saturating_add(per_chunk.unwrap_or(u64::from(count)).max(1));
        chunk += 1;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shapes_follow_the_layered_items() {
        // Point format 8 with 3 extra bytes: Point14, RGBNIR14, Byte14(3).
        let items = [(10, 30, 3), (12, 8, 3), (14, 3, 3)];
        let shape = layered_shape(&items).unwrap();
        assert_eq!(shape.first_point, 30 + 8 + 3);
        assert_eq!(shape.layers, 9 + 2 + 3);
        assert!(layered_shape(&[(6, 20, 2)]).is_none());
    }

    /// A LAZ file of `n` points in chunks of 50,000 (the las crate's default), format 7.
    fn written_laz(path: &std::path::Path, n: u32) {
        let mut builder = las::Builder::from((1, 4));
        builder.point_format = las::point::Format::new(7).unwrap();
        builder.point_format.is_compressed = true;
        let header = builder.into_header().unwrap();
        let mut writer = las::Writer::from_path(path, header).unwrap();
        for i in 0..n {
            let f = f64::from(i);
            writer
                .write_point(las::Point {
                    x: (f * 0.37).sin() * 100.0,
                    y: (f * 0.011).cos() * 50.0,
                    z: f * 0.001,
                    intensity: (i % 65_536) as u16,
                    gps_time: Some(f * 1e-3),
                    color: Some(las::Color::new(i as u16, (i * 7) as u16, 3)),
                    ..Default::default()
                })
                .unwrap();
        }
        writer.close().unwrap();
    }

    #[test]
    fn chunked_laz_decodes_in_parallel_to_the_same_points() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("chunks.laz");
        written_laz(&path, 123_457);
        let (mut read, file_len) = super::super::open_file(&path).unwrap();
        let (_, decoding) = super::super::checked_raw_header(&path, &mut read, file_len, true)
            .expect("a sound file");
        assert_eq!(decoding, Decoding::Parallel);

        let (_, mut source) = super::super::open(&path).unwrap();
        let mut ours = Vec::new();
        // Reads that start and stop inside chunks.
        while let Some(c) = source.next_raw(70_001).unwrap() {
            ours.extend(
                c.positions
                    .iter()
                    .zip(c.gps_time.unwrap())
                    .map(|(p, t)| (*p, t)),
            );
        }
        let options = las::ReaderOptions::default().with_laz_parallelism(las::LazParallelism::No);
        let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
        let mut reader = las::Reader::with_options(file, options).unwrap();
        let all = reader.read_all().unwrap();
        let theirs: Vec<_> = all
            .x()
            .zip(all.y())
            .zip(all.z())
            .zip(all.gps_time().unwrap())
            .map(|(((x, y), z), t)| (glam::DVec3::new(x, y, z), t))
            .collect();
        assert_eq!(ours.len(), 123_457);
        assert!(ours == theirs, "parallel decoding changed the points");
    }

    #[test]
    fn variable_size_chunks_decode_sequentially() {
        // A COPC file: one chunk per node, of variable size.
        let path = std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/data/courtyard.copc.laz"
        ));
        let (mut read, file_len) = super::super::open_file(path).unwrap();
        let (_, decoding) =
            super::super::checked_raw_header(path, &mut read, file_len, true).unwrap();
        assert_eq!(decoding, Decoding::Sequential);
    }
}
