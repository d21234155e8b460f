//! Writing a COPC index out of core: any scan (LAS, LAZ, PLY, several tiles) read once
//! through [`crate::io::open`], written as one COPC file whose points carry their sphere
//! radii, so that renders read only the nodes a view needs and search no neighbours.
//!
//! The method (as PDAL's `writers.copc` and untwine do): the points are spilled to temporary
//! files by the coarse octree node holding them ([`bucket`]); each bucket is then built in
//! memory ([`build`]: sampled into nodes from the root down, radii decided) and its nodes
//! compressed into LAZ chunks ([`copc_file`]), several buckets at once. Nodes above the
//! buckets' level gather the samples of every bucket below them and are written last.
//! The buckets and the spill buffers are sized for [`IndexOptions::max_memory`]; the nodes
//! above the buckets' level stay in memory until the end (a few hundred MB up to about a
//! billion points of a city; docs/SCALE.md has the calculation).
//!
//! The output is staged next to its destination and renamed when complete; the temporary
//! files live in a working folder there too. Both go on failure and on an interrupt.

pub mod bucket;
pub mod build;
pub mod copc_file;
mod error;
pub mod record;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::mpsc::sync_channel;
use std::time::Instant;

use glam::DVec3;
use indicatif::ProgressBar;
use rayon::prelude::*;

use crate::io::{self, FileInfo, LoadError, NodeKey, RawChunk, RawRgb, Up};
use crate::output::{ScratchDir, StagedFile};
use crate::prepare::lengths::{LengthScale, Units};
use crate::prepare::radius::{DEFAULT_K, RadiusChoice};
use build::{Cube, RadiusRule};
use copc_file::{CopcWriter, Summary, Vlr};
pub use error::IndexError;
use record::{Fields, Layout, Quantizer};

/// Default memory cap: 2 GB.
pub const DEFAULT_MAX_MEMORY: u64 = 2_000_000_000;
/// Bytes a point takes while its bucket is built (record, coordinates, neighbour tree, radii,
/// node lists, compressed chunk), with room to spare.
pub const BUILD_BYTES_PER_POINT: u64 = 240;
/// Deepest bucket level.
const MAX_BUCKET_DEPTH: u32 = 7;
/// Points read at a time while spilling, at least and at most.
const MIN_READ_CHUNK: usize = 1 << 16;
const MAX_READ_CHUNK: usize = 1 << 18;
/// Points read at a time while finding bounds.
const READ_CHUNK: usize = 1 << 16;

/// What an index may be told.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IndexOptions {
    /// Memory the index may use, bytes (buckets are sized for it).
    pub max_memory: u64,
    /// The full-detail radius: a length in [`Self::units`], or `adaptive[:K]`; `None` = the
    /// files' own radii where they have them, else `adaptive`.
    pub radius: Option<RadiusChoice>,
    /// What a fixed radius is given in: metres (converted to the unit the first file's
    /// coordinate system declares) or the file's own unit.
    pub units: Units,
}

impl Default for IndexOptions {
    fn default() -> Self {
        IndexOptions {
            max_memory: DEFAULT_MAX_MEMORY,
            radius: None,
            units: Units::Metres,
        }
    }
}

/// What an index did.
#[derive(Debug, Clone, PartialEq)]
pub struct IndexReport {
    /// Points written.
    pub points: u64,
    /// Points left out: a NaN or infinite coordinate, or one beyond the integer grid.
    pub dropped: u64,
    /// Nodes written.
    pub nodes: usize,
    /// Deepest level.
    pub depth: u32,
    /// Buckets built.
    pub buckets: usize,
    /// Most points in one bucket.
    pub largest_bucket: u64,
    /// LAS point format written.
    pub point_format: u8,
    /// Output size, bytes.
    pub bytes: u64,
    /// Seconds spent reading and spilling.
    pub spill_seconds: f64,
    /// Seconds spent building and writing.
    pub build_seconds: f64,
}

/// Integer grid and root cube for points within `(lo, hi)`.
fn plan_grid(infos: &[FileInfo], lo: DVec3, hi: DVec3) -> Result<(Quantizer, Cube), IndexError> {
    let extent = (hi - lo).max_element().max(0.0);
    let las: Vec<_> = infos.iter().filter_map(|i| i.las.as_ref()).collect();
    let (scale, offset) = if las.len() == infos.len() {
        // Every input has an integer grid: the finest scale, the first offset, so that the
        // points of tiles sharing a grid come back exactly.
        let scale = las
            .iter()
            .map(|l| l.scale)
            .reduce(DVec3::min)
            .unwrap_or(DVec3::ONE);
        (scale, las[0].offset)
    } else {
        let step = 10f64.powf((extent.max(1e-3) / 1e8).log10().floor());
        (DVec3::splat(step), DVec3::ZERO)
    };
    let mut q = Quantizer { scale, offset };
    if q.ints(lo).is_none() || q.ints(hi).is_none() {
        q.offset = (((lo + hi) * 0.5) / scale).round() * scale;
    }
    if q.ints(lo).is_none() || q.ints(hi).is_none() {
        return Err(IndexError::TooWide {
            path: infos[0].path.clone(),
            extent,
            scale: scale.max_element(),
        });
    }
    let cube = Cube {
        center: (lo + hi) * 0.5,
        halfsize: extent * 0.5 * (1.0 + 1e-9) + scale.max_element(),
    };
    Ok((q, cube))
}

/// The coordinate-system VLRs of the first LAS input that has any.
fn crs_vlrs(infos: &[FileInfo]) -> Vec<Vlr> {
    for info in infos.iter().filter(|i| i.las.is_some()) {
        let Ok(reader) = las::Reader::from_path(&info.path) else {
            continue;
        };
        let h = reader.header();
        let vlrs: Vec<Vlr> = h
            .vlrs()
            .iter()
            .chain(h.evlrs())
            .filter(|v| v.user_id.trim_end_matches('\0') == "LASF_Projection")
            .filter(|v| v.data.len() <= usize::from(u16::MAX))
            .map(|v| Vlr {
                user_id: v.user_id.clone(),
                record_id: v.record_id,
                description: v.description.clone(),
                data: v.data.clone(),
            })
            .collect();
        if !vlrs.is_empty() {
            return vlrs;
        }
    }
    Vec::new()
}

/// Bounds of every usable point, read from the headers when all have them, else from a pass
/// over the points.
fn bounds(paths: &[PathBuf], infos: &[FileInfo]) -> Result<(DVec3, DVec3), IndexError> {
    if infos.iter().all(|i| i.bounds.is_some()) {
        let (lo, hi) = infos
            .iter()
            .filter_map(|i| i.bounds)
            .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
            .expect("at least one input");
        if io::usable(lo) && io::usable(hi) {
            return Ok((lo, hi));
        }
    }
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for p in paths {
        let mut reader = io::open(p)?;
        while let Some(chunk) = reader.next_raw(READ_CHUNK)? {
            for q in chunk.positions.iter().filter(|q| io::usable(**q)) {
                lo = lo.min(*q);
                hi = hi.max(*q);
            }
        }
    }
    if lo.cmpgt(hi).any() {
        return Err(IndexError::NoPoints {
            path: paths[0].clone(),
        });
    }
    Ok((lo, hi))
}

/// The per-point fields of a chunk's point `i`.
fn fields(c: &RawChunk, i: usize) -> Fields {
    Fields {
        intensity: c.intensity.as_ref().map(|v| v[i]),
        returns: c.returns.as_ref().map(|v| (v[i].number, v[i].of)),
        classification: c.classification.as_ref().map(|v| v[i]),
        gps_time: c.gps_time.as_ref().map(|v| v[i]),
        rgb: c.rgb.as_ref().map(|rgb| match rgb {
            RawRgb::Bits16(v) => v[i],
            // 8-bit colour spans the 16-bit range: 255 becomes 65535.
            RawRgb::Bits8(v) => v[i].map(|c| u16::from(c) * 257),
        }),
        radius: c.radius.as_ref().map(|v| v[i]),
    }
}

/// What the spill pass counted.
#[derive(Debug, Clone)]
struct Tally {
    points: u64,
    dropped: u64,
    lo: [i32; 3],
    hi: [i32; 3],
    by_return: [u64; 15],
    gps: (f64, f64),
}

impl Tally {
    fn new() -> Tally {
        Tally {
            points: 0,
            dropped: 0,
            lo: [i32::MAX; 3],
            hi: [i32::MIN; 3],
            by_return: [0; 15],
            gps: (f64::INFINITY, f64::NEG_INFINITY),
        }
    }

    fn add(&mut self, xyz: [i32; 3], record: &[u8], has_gps: bool) {
        self.points += 1;
        for ((lo, hi), v) in self.lo.iter_mut().zip(&mut self.hi).zip(xyz) {
            *lo = (*lo).min(v);
            *hi = (*hi).max(v);
        }
        let rn = Layout::return_number(record);
        if (1..=15).contains(&rn) {
            self.by_return[usize::from(rn) - 1] += 1;
        }
        if has_gps {
            let t = Layout::gps_time(record);
            self.gps = (self.gps.0.min(t), self.gps.1.max(t));
        }
    }

    fn merge(&mut self, other: &Tally) {
        self.points += other.points;
        self.dropped += other.dropped;
        for a in 0..3 {
            self.lo[a] = self.lo[a].min(other.lo[a]);
            self.hi[a] = self.hi[a].max(other.hi[a]);
        }
        for (mine, theirs) in self.by_return.iter_mut().zip(other.by_return) {
            *mine += theirs;
        }
        self.gps = (self.gps.0.min(other.gps.0), self.gps.1.max(other.gps.1));
    }
}

/// Points of a read chunk made into records, grouped by bucket (in input order within each).
struct Filed {
    /// `(bucket, records)`, ordered by where each bucket first appears.
    groups: Vec<(NodeKey, Vec<u8>)>,
    tally: Tally,
    read: u64,
}

/// Points handed to one task when a read chunk is made into records.
const FILE_TASK: usize = 1 << 14;

/// Makes a chunk's points into records grouped by their bucket at `depth`, on every core.
fn file_chunk(chunk: &RawChunk, layout: Layout, q: &Quantizer, cube: &Cube, depth: u32) -> Filed {
    let has_gps = chunk.gps_time.is_some();
    let n = chunk.positions.len();
    let parts: Vec<Filed> = (0..n.div_ceil(FILE_TASK))
        .into_par_iter()
        .map(|t| {
            let mut tally = Tally::new();
            let mut groups: Vec<(NodeKey, Vec<u8>)> = Vec::new();
            let mut at: HashMap<NodeKey, usize> = HashMap::new();
            let mut last: Option<(NodeKey, usize)> = None;
            let mut record = Vec::with_capacity(layout.len);
            let points = t * FILE_TASK..((t + 1) * FILE_TASK).min(n);
            let read = points.len() as u64;
            for i in points {
                let p = chunk.positions[i];
                let Some(xyz) = io::usable(p).then(|| q.ints(p)).flatten() else {
                    tally.dropped += 1;
                    continue;
                };
                record.clear();
                layout.push(&mut record, xyz, &fields(chunk, i));
                tally.add(xyz, &record, has_gps);
                let key = cube.key_at(depth, p);
                // Scans run along surfaces: most points fall in the bucket of the one before.
                let g = match last {
                    Some((k, g)) if k == key => g,
                    _ => {
                        let g = *at.entry(key).or_insert_with(|| {
                            groups.push((key, Vec::new()));
                            groups.len() - 1
                        });
                        last = Some((key, g));
                        g
                    }
                };
                groups[g].1.extend_from_slice(&record);
            }
            Filed {
                groups,
                tally,
                read,
            }
        })
        .collect();
    let mut whole = Filed {
        groups: Vec::new(),
        tally: Tally::new(),
        read: 0,
    };
    for part in parts {
        whole.tally.merge(&part.tally);
        whole.groups.extend(part.groups);
        whole.read += part.read;
    }
    whole
}

/// Reads every input once into `spill`: a reader thread decodes (LAZ chunks in parallel)
/// and makes the points into records on every core while this one appends them to buckets.
fn spill_inputs(
    paths: &[PathBuf],
    layout: Layout,
    q: &Quantizer,
    cube: &Cube,
    depth: u32,
    spill: &mut bucket::Spill,
    progress: &ProgressBar,
) -> Result<Tally, IndexError> {
    let mut tally = Tally::new();
    // Points per read: large enough for several LAZ chunks to decode at once, small enough
    // that the chunks in flight (about 100 bytes a point, six at a time) stay within an
    // eighth of the cap.
    let read_points = (spill.limit() / 6 / 100).clamp(MIN_READ_CHUNK, MAX_READ_CHUNK);
    std::thread::scope(|scope| {
        let (tx, rx) = sync_channel::<Result<Filed, LoadError>>(2);
        scope.spawn(move || {
            for p in paths {
                let mut reader = match io::open(p) {
                    Ok(r) => r,
                    Err(e) => {
                        let _ = tx.send(Err(e));
                        return;
                    }
                };
                loop {
                    let item = reader.next_raw(read_points).transpose();
                    let Some(item) = item else { break };
                    let failed = item.is_err();
                    let item = item.map(|c| file_chunk(&c, layout, q, cube, depth));
                    if tx.send(item).is_err() || failed {
                        return;
                    }
                }
            }
        });
        for filed in rx {
            let filed = filed?;
            tally.merge(&filed.tally);
            for (key, records) in &filed.groups {
                spill.push_many(*key, records)?;
            }
            progress.inc(filed.read);
        }
        Ok::<(), IndexError>(())
    })?;
    Ok(tally)
}

/// The radius rule for `choice` and inputs that do (or not) carry radii.
fn radius_rule(choice: Option<RadiusChoice>, file_radii: bool) -> RadiusRule {
    match choice {
        Some(RadiusChoice::Fixed(r)) => RadiusRule::Fixed(r),
        Some(RadiusChoice::Adaptive { k }) => RadiusRule::Adaptive(k),
        // `auto` in an index is the adaptive radius: per point, from its neighbours.
        Some(RadiusChoice::Auto) => RadiusRule::Adaptive(DEFAULT_K),
        None if file_radii => RadiusRule::FromFile,
        None => RadiusRule::Adaptive(DEFAULT_K),
    }
}

/// Nodes above the buckets' level, gathered from every bucket below them.
type Upper = HashMap<NodeKey, Vec<u8>>;

/// What every bucket is built with.
#[derive(Debug, Clone, Copy)]
struct Plan<'a> {
    layout: Layout,
    q: Quantizer,
    cube: Cube,
    rule: RadiusRule,
    output: &'a Path,
}

/// Builds one bucket: its own nodes compressed and written, its share of the nodes above kept.
fn build_bucket<W: std::io::Write + std::io::Seek>(
    b: &bucket::Bucket,
    plan: &Plan,
    writer: &Mutex<CopcWriter<W>>,
    upper: &Mutex<Upper>,
) -> Result<(), IndexError> {
    let Plan {
        layout,
        ref q,
        ref cube,
        rule,
        output,
    } = *plan;
    let mut records = bucket::read(b)?;
    let positions = build::positions(layout, &records, q);
    let nodes = build::sample(cube, &positions);
    build::store_radii(layout, &mut records, &positions, &nodes, rule);
    drop(positions);
    let gather = |n: &build::Node| {
        let mut bytes = Vec::with_capacity(n.points.len() * layout.len);
        for i in &n.points {
            let at = *i as usize * layout.len;
            bytes.extend_from_slice(&records[at..at + layout.len]);
        }
        bytes
    };
    let (own, above): (Vec<&build::Node>, Vec<&build::Node>) =
        nodes.iter().partition(|n| n.key.depth >= b.key.depth);
    let vlr = copc_file::laz_vlr(layout);
    let chunks = own
        .par_iter()
        .map(|n| {
            copc_file::compress(&vlr, &gather(n))
                .map(|c| (n.key, n.points.len() as u64, c))
                .map_err(|detail| IndexError::Write {
                    path: output.to_path_buf(),
                    detail,
                })
        })
        .collect::<Result<Vec<_>, _>>()?;
    {
        let mut w = writer
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        for (key, points, chunk) in chunks {
            w.push(key, points, &chunk).map_err(|e| IndexError::Write {
                path: output.to_path_buf(),
                detail: e.to_string(),
            })?;
        }
    }
    let mut up = upper
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    for n in above {
        up.entry(n.key).or_default().extend_from_slice(&gather(n));
    }
    Ok(())
}

/// Indexes `inputs` into the COPC file `output` (see the module docs). `progress` counts
/// points, once while reading and once while building.
///
/// # Errors
/// [`IndexError`]; nothing is then left at `output`, nor any temporary file.
///
/// # Panics
/// When `inputs` is empty.
pub fn index(
    inputs: &[PathBuf],
    output: &Path,
    options: &IndexOptions,
    progress: &ProgressBar,
) -> Result<IndexReport, IndexError> {
    assert!(!inputs.is_empty(), "index needs an input");
    let infos = inputs
        .iter()
        .map(|p| io::read_info(p))
        .collect::<Result<Vec<_>, _>>()?;
    let declared: u64 = infos.iter().map(|i| i.point_count).sum();
    let layout = Layout::new(infos.iter().any(|i| i.attributes.rgb));
    let file_radii = infos.iter().all(|i| i.attributes.radius);
    let per_given = LengthScale::for_info(&infos[0], options.units, Up::Z).length(1.0);
    let rule = radius_rule(options.radius.map(|r| r.scaled(per_given)), file_radii);
    let (lo, hi) = bounds(inputs, &infos)?;
    let (q, cube) = plan_grid(&infos, lo, hi)?;

    // Memory: the spill buffers while reading; then one bucket per thread at a time.
    let threads = rayon::current_num_threads().max(1) as u64;
    let spill_buffer = (options.max_memory / 8).clamp(4 << 20, 256 << 20) as usize;
    let per_bucket = (options.max_memory * 3 / 4 / threads / BUILD_BYTES_PER_POINT).max(50_000);
    // Scans sample surfaces: a level of 4^d nodes holds them, not 8^d.
    let depth = (0..=MAX_BUCKET_DEPTH)
        .find(|d| declared / 4u64.pow(*d) <= per_bucket / 2)
        .unwrap_or(MAX_BUCKET_DEPTH);

    let scratch = ScratchDir::next_to(output, "index")?;
    let started = Instant::now();
    progress.set_length(declared);
    progress.set_message("reading");
    let mut spill = bucket::Spill::new(scratch.path(), layout, spill_buffer);
    let tally = spill_inputs(inputs, layout, &q, &cube, depth, &mut spill, progress)?;
    if tally.points == 0 {
        return Err(IndexError::NoPoints {
            path: inputs[0].clone(),
        });
    }
    let buckets = spill.finish()?;
    let buckets = bucket::split_large(
        buckets,
        per_bucket,
        &cube,
        &q,
        layout,
        scratch.path(),
        spill_buffer,
    )?;
    let spill_seconds = started.elapsed().as_secs_f64();

    let started = Instant::now();
    progress.set_message("indexing");
    progress.set_length(tally.points);
    progress.set_position(0);
    let summary = Summary {
        quantizer: q,
        cube,
        bounds: (q.position(tally.lo), q.position(tally.hi)),
        by_return: tally.by_return,
        gps: if tally.gps.0 <= tally.gps.1 {
            tally.gps
        } else {
            (0.0, 0.0)
        },
        crs: crs_vlrs(&infos),
        software: format!("omnicloud {}", env!("CARGO_PKG_VERSION")),
    };
    let mut report = IndexReport {
        points: tally.points,
        dropped: tally.dropped,
        nodes: 0,
        depth: 0,
        buckets: buckets.len(),
        largest_bucket: buckets.iter().map(|b| b.points).max().unwrap_or(0),
        point_format: layout.format,
        bytes: 0,
        spill_seconds,
        build_seconds: 0.0,
    };
    let write_error = |detail: String| IndexError::Write {
        path: output.to_path_buf(),
        detail,
    };
    let staged = StagedFile::create_with(output, |out| {
        let writer =
            CopcWriter::new(out, layout, &summary.crs).map_err(|e| write_error(e.to_string()))?;
        let writer = Mutex::new(writer);
        let upper = Mutex::new(Upper::new());
        let plan = Plan {
            layout,
            q,
            cube,
            rule,
            output,
        };
        buckets.par_iter().try_for_each(|b| {
            build_bucket(b, &plan, &writer, &upper)?;
            // The bucket's file is no longer needed: free its disk space now.
            let _ = std::fs::remove_file(&b.path);
            progress.inc(b.points);
            Ok::<(), IndexError>(())
        })?;
        let mut writer = writer
            .into_inner()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let mut upper: Vec<(NodeKey, Vec<u8>)> = upper
            .into_inner()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .into_iter()
            .collect();
        upper.sort_by_key(|(k, _)| *k);
        let vlr = writer.vlr().clone();
        let chunks = upper
            .par_iter()
            .map(|(k, r)| {
                copc_file::compress(&vlr, r).map(|c| (*k, (r.len() / layout.len) as u64, c))
            })
            .collect::<Result<Vec<_>, _>>()
            .map_err(write_error)?;
        for (key, points, chunk) in chunks {
            writer
                .push(key, points, &chunk)
                .map_err(|e| write_error(e.to_string()))?;
        }
        report.nodes = writer.nodes().len();
        report.depth = writer
            .nodes()
            .iter()
            .map(|n| n.key.depth)
            .max()
            .unwrap_or(0);
        let (_, bytes) = writer
            .finish(&summary)
            .map_err(|e| write_error(e.to_string()))?;
        report.bytes = bytes;
        Ok::<(), IndexError>(())
    })?;
    staged.commit()?;
    drop(scratch);
    report.build_seconds = started.elapsed().as_secs_f64();
    Ok(report)
}
