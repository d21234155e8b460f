//! The COPC file itself (<https://copc.io>): a LAS 1.4 header, the COPC info VLR first, the
//! LAZ VLR, the Extra Bytes VLR of the stored radii and the coordinate system's VLRs; then one
//! LAZ chunk per octree node, the LAZ chunk table, and the hierarchy EVLR listing every node.
//!
//! Chunks are compressed independently ([`compress`], any thread) and appended as they come;
//! the header, which needs the totals, is written last over the space kept for it.

use std::io::{Cursor, Seek, SeekFrom, Write};

use glam::DVec3;
use laz::laszip::{ChunkTable, ChunkTableEntry};
use laz::{LasZipCompressor, LazItemRecordBuilder, LazVlr, LazVlrBuilder};

use super::build::Cube;
use super::record::{EXTRA_BYTES, Layout, Quantizer};
use crate::io::NodeKey;
use crate::io::extra_bytes;

/// LAS 1.4 header size.
const HEADER_LEN: u64 = 375;
/// A VLR's header size.
const VLR_HEADER_LEN: u64 = 54;
/// An extended VLR's header size.
const EVLR_HEADER_LEN: u64 = 60;
/// The COPC info VLR's payload size.
const COPC_INFO_LEN: usize = 160;
/// One hierarchy entry.
const ENTRY_LEN: usize = 32;

/// A VLR to write: user id, record id, description, payload.
#[derive(Debug, Clone, PartialEq)]
pub struct Vlr {
    /// User id (at most 16 bytes).
    pub user_id: String,
    /// Record id.
    pub record_id: u16,
    /// Description (at most 32 bytes).
    pub description: String,
    /// Payload.
    pub data: Vec<u8>,
}

fn text<const N: usize>(s: &str) -> [u8; N] {
    let mut out = [0u8; N];
    let b = s.as_bytes();
    let n = b.len().min(N);
    out[..n].copy_from_slice(&b[..n]);
    out
}

/// The LAZ description of an index's records: point format 6 or 7 with the extra bytes,
/// variable-size chunks (one per node).
pub fn laz_vlr(layout: Layout) -> LazVlr {
    let items =
        LazItemRecordBuilder::default_for_point_format_id(layout.format, EXTRA_BYTES as u16)
            .expect("formats 6 and 7 are LAZ formats");
    LazVlrBuilder::new(items).with_variable_chunk_size().build()
}

/// Compresses the records of one node into one LAZ chunk.
///
/// # Errors
/// The compressor's error, as text.
pub fn compress(vlr: &LazVlr, records: &[u8]) -> Result<Vec<u8>, String> {
    let mut compressor =
        LasZipCompressor::new(Cursor::new(Vec::new()), vlr.clone()).map_err(|e| e.to_string())?;
    compressor
        .compress_many(records)
        .map_err(|e| e.to_string())?;
    compressor
        .finish_current_chunk()
        .map_err(|e| e.to_string())?;
    let mut bytes = compressor.into_inner().into_inner();
    // The compressor starts its stream with the 8-byte chunk table offset: not part of a chunk.
    bytes.drain(..ChunkTable::OFFSET_SIZE);
    Ok(bytes)
}

/// A node written to the file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Written {
    /// Address.
    pub key: NodeKey,
    /// Byte offset of its chunk.
    pub offset: u64,
    /// Chunk size.
    pub bytes: u64,
    /// Points.
    pub points: u64,
}

/// Totals the header and the info VLR need.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Integer coordinates.
    pub quantizer: Quantizer,
    /// The octree's root cube.
    pub cube: Cube,
    /// `(min, max)` of the points.
    pub bounds: (DVec3, DVec3),
    /// Points per return number (index 0: return 1 … 14: return 15).
    pub by_return: [u64; 15],
    /// `(min, max)` GPS time.
    pub gps: (f64, f64),
    /// Coordinate system VLRs to copy (WKT, GeoTIFF keys).
    pub crs: Vec<Vlr>,
    /// Software name for the header.
    pub software: String,
}

/// Writes chunks after the space kept for the header, then the rest.
#[derive(Debug)]
pub struct CopcWriter<W: Write + Seek> {
    out: W,
    layout: Layout,
    vlr: LazVlr,
    /// Where the point data starts (the chunk table offset, then the chunks).
    data_start: u64,
    position: u64,
    nodes: Vec<Written>,
}

impl<W: Write + Seek> CopcWriter<W> {
    /// Starts a file whose VLRs will be the info VLR, the LAZ VLR, the Extra Bytes VLR and
    /// `crs`: their space is kept, the chunk table offset reserved.
    ///
    /// # Errors
    /// The writer's.
    pub fn new(mut out: W, layout: Layout, crs: &[Vlr]) -> std::io::Result<Self> {
        let vlr = laz_vlr(layout);
        let vlrs = fixed_vlrs(&vlr, &Vec::new())
            .iter()
            .chain(crs)
            .map(|v| VLR_HEADER_LEN + v.data.len() as u64)
            .sum::<u64>();
        let data_start = HEADER_LEN + vlrs;
        out.seek(SeekFrom::Start(0))?;
        out.write_all(&vec![0u8; data_start as usize])?;
        out.write_all(&(-1i64).to_le_bytes())?;
        Ok(CopcWriter {
            out,
            layout,
            vlr,
            data_start,
            position: data_start + ChunkTable::OFFSET_SIZE as u64,
            nodes: Vec::new(),
        })
    }

    /// The LAZ description chunks must be compressed with.
    pub fn vlr(&self) -> &LazVlr {
        &self.vlr
    }

    /// Appends a node's compressed chunk.
    ///
    /// # Errors
    /// The writer's.
    pub fn push(&mut self, key: NodeKey, points: u64, chunk: &[u8]) -> std::io::Result<()> {
        self.out.write_all(chunk)?;
        self.nodes.push(Written {
            key,
            offset: self.position,
            bytes: chunk.len() as u64,
            points,
        });
        self.position += chunk.len() as u64;
        Ok(())
    }

    /// Nodes written so far.
    pub fn nodes(&self) -> &[Written] {
        &self.nodes
    }

    /// Writes the chunk table, the hierarchy EVLR and the header with its VLRs; returns the
    /// writer and the file's size.
    ///
    /// # Errors
    /// The writer's.
    pub fn finish(mut self, summary: &Summary) -> std::io::Result<(W, u64)> {
        let table_at = self.position;
        let mut table = ChunkTable::with_capacity(self.nodes.len());
        for n in &self.nodes {
            table.push(ChunkTableEntry {
                point_count: n.points,
                byte_count: n.bytes,
            });
        }
        let mut table_bytes = Vec::new();
        table.write_to(&mut table_bytes, &self.vlr)?;
        self.out.write_all(&table_bytes)?;
        let evlr_at = table_at + table_bytes.len() as u64;
        let mut hierarchy = Vec::with_capacity(self.nodes.len() * ENTRY_LEN);
        for n in &self.nodes {
            for v in [n.key.depth, n.key.x, n.key.y, n.key.z] {
                hierarchy.extend_from_slice(&(v as i32).to_le_bytes());
            }
            hierarchy.extend_from_slice(&n.offset.to_le_bytes());
            hierarchy.extend_from_slice(&(n.bytes as i32).to_le_bytes());
            hierarchy.extend_from_slice(&(n.points as i32).to_le_bytes());
        }
        write_evlr(&mut self.out, "copc", 1000, "EPT hierarchy", &hierarchy)?;
        let end = evlr_at + EVLR_HEADER_LEN + hierarchy.len() as u64;

        let info = copc_info(summary, evlr_at + EVLR_HEADER_LEN, hierarchy.len() as u64);
        let vlrs: Vec<Vlr> = fixed_vlrs(&self.vlr, &info)
            .into_iter()
            .chain(summary.crs.iter().cloned())
            .collect();
        self.out.seek(SeekFrom::Start(0))?;
        let points: u64 = self.nodes.iter().map(|n| n.points).sum();
        write_header(
            &mut self.out,
            self.layout,
            summary,
            &vlrs,
            self.data_start,
            points,
            evlr_at,
        )?;
        for v in &vlrs {
            write_vlr(&mut self.out, v)?;
        }
        self.out.write_all(&(table_at as i64).to_le_bytes())?;
        self.out.seek(SeekFrom::Start(end))?;
        self.out.flush()?;
        Ok((self.out, end))
    }
}

/// The info VLR (its payload given), the LAZ VLR and the Extra Bytes VLR, in that order.
fn fixed_vlrs(laz: &LazVlr, info: &[u8]) -> Vec<Vlr> {
    let mut info = info.to_vec();
    info.resize(COPC_INFO_LEN, 0);
    let mut laz_data = Vec::new();
    laz.write_to(&mut laz_data).expect("writing to a Vec");
    let mut extra = Vec::new();
    extra.extend_from_slice(&extra_bytes::f32_descriptor(
        extra_bytes::RADIUS_FIELD,
        "sphere radius, full detail",
    ));
    extra.extend_from_slice(&extra_bytes::f32_descriptor(
        extra_bytes::LOD_RADIUS_FIELD,
        "sphere radius, view stops here",
    ));
    vec![
        Vlr {
            user_id: "copc".into(),
            record_id: 1,
            description: "COPC info VLR".into(),
            data: info,
        },
        Vlr {
            user_id: LazVlr::USER_ID.into(),
            record_id: LazVlr::RECORD_ID,
            description: "laz variable chunks".into(),
            data: laz_data,
        },
        Vlr {
            user_id: extra_bytes::USER_ID.into(),
            record_id: extra_bytes::RECORD_ID,
            description: "omnicloud radii".into(),
            data: extra,
        },
    ]
}

fn copc_info(s: &Summary, hierarchy_at: u64, hierarchy_len: u64) -> Vec<u8> {
    let mut d = Vec::with_capacity(COPC_INFO_LEN);
    for v in [
        s.cube.center.x,
        s.cube.center.y,
        s.cube.center.z,
        s.cube.halfsize,
        s.cube.spacing(),
    ] {
        d.extend_from_slice(&v.to_le_bytes());
    }
    d.extend_from_slice(&hierarchy_at.to_le_bytes());
    d.extend_from_slice(&hierarchy_len.to_le_bytes());
    d.extend_from_slice(&s.gps.0.to_le_bytes());
    d.extend_from_slice(&s.gps.1.to_le_bytes());
    d.resize(COPC_INFO_LEN, 0);
    d
}

fn write_vlr<W: Write>(out: &mut W, v: &Vlr) -> std::io::Result<()> {
    out.write_all(&0u16.to_le_bytes())?;
    out.write_all(&text::<16>(&v.user_id))?;
    out.write_all(&v.record_id.to_le_bytes())?;
    let len = u16::try_from(v.data.len()).map_err(|_| {
        std::io::Error::other(format!(
            "a VLR of {} bytes does not fit in a VLR",
            v.data.len()
        ))
    })?;
    out.write_all(&len.to_le_bytes())?;
    out.write_all(&text::<32>(&v.description))?;
    out.write_all(&v.data)
}

fn write_evlr<W: Write>(
    out: &mut W,
    user_id: &str,
    record_id: u16,
    description: &str,
    data: &[u8],
) -> std::io::Result<()> {
    out.write_all(&0u16.to_le_bytes())?;
    out.write_all(&text::<16>(user_id))?;
    out.write_all(&record_id.to_le_bytes())?;
    out.write_all(&(data.len() as u64).to_le_bytes())?;
    out.write_all(&text::<32>(description))?;
    out.write_all(data)
}

fn write_header<W: Write>(
    out: &mut W,
    layout: Layout,
    s: &Summary,
    vlrs: &[Vlr],
    data_start: u64,
    points: u64,
    evlr_at: u64,
) -> std::io::Result<()> {
    let mut h = Vec::with_capacity(HEADER_LEN as usize);
    h.extend_from_slice(b"LASF");
    h.extend_from_slice(&0u16.to_le_bytes()); // file source id
    h.extend_from_slice(&0x0010u16.to_le_bytes()); // global encoding: WKT coordinate system
    h.extend_from_slice(&[0u8; 16]); // project GUID
    h.extend_from_slice(&[1, 4]); // version 1.4
    h.extend_from_slice(&text::<32>("omnicloud"));
    h.extend_from_slice(&text::<32>(&s.software));
    h.extend_from_slice(&1u16.to_le_bytes()); // creation day of year
    h.extend_from_slice(&2026u16.to_le_bytes()); // creation year
    h.extend_from_slice(&(HEADER_LEN as u16).to_le_bytes());
    h.extend_from_slice(&(data_start as u32).to_le_bytes());
    h.extend_from_slice(&(vlrs.len() as u32).to_le_bytes());
    h.push(layout.format | 0x80); // compressed
    h.extend_from_slice(&(layout.len as u16).to_le_bytes());
    h.extend_from_slice(&0u32.to_le_bytes()); // legacy point count: 0 for formats 6+
    h.extend_from_slice(&[0u8; 20]); // legacy points by return
    let q = &s.quantizer;
    for v in [
        q.scale.x, q.scale.y, q.scale.z, q.offset.x, q.offset.y, q.offset.z,
    ] {
        h.extend_from_slice(&v.to_le_bytes());
    }
    let (lo, hi) = s.bounds;
    for v in [hi.x, lo.x, hi.y, lo.y, hi.z, lo.z] {
        h.extend_from_slice(&v.to_le_bytes());
    }
    h.extend_from_slice(&0u64.to_le_bytes()); // waveform data
    h.extend_from_slice(&evlr_at.to_le_bytes());
    h.extend_from_slice(&1u32.to_le_bytes()); // one EVLR: the hierarchy
    h.extend_from_slice(&points.to_le_bytes());
    for n in s.by_return {
        h.extend_from_slice(&n.to_le_bytes());
    }
    debug_assert_eq!(h.len() as u64, HEADER_LEN);
    out.write_all(&h)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_decompress_back() {
        let layout = Layout::new(true);
        let vlr = laz_vlr(layout);
        let mut records = Vec::new();
        for i in 0..1000 {
            layout.push(
                &mut records,
                [i, -i, i * 7],
                &super::super::record::Fields {
                    intensity: Some(i as u16),
                    gps_time: Some(f64::from(i) * 0.5),
                    rgb: Some([i as u16, 2, 3]),
                    radius: Some(0.1),
                    ..Default::default()
                },
            );
        }
        let chunk = compress(&vlr, &records).unwrap();
        assert!(chunk.len() < records.len() / 2, "{}", chunk.len());
        // A LAZ stream of that one chunk: the chunk table offset, the chunk, the table.
        let mut stream = ((8 + chunk.len()) as i64).to_le_bytes().to_vec();
        stream.extend_from_slice(&chunk);
        let mut table = ChunkTable::with_capacity(1);
        table.push(ChunkTableEntry {
            point_count: 1000,
            byte_count: chunk.len() as u64,
        });
        table.write_to(&mut stream, &vlr).unwrap();
        let mut back = vec![0u8; records.len()];
        let mut d = laz::LasZipDecompressor::new(Cursor::new(stream), vlr).unwrap();
        d.decompress_many(&mut back).unwrap();
        assert_eq!(back, records);
    }
}
