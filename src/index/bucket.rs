//! Points spilled to temporary files by the coarse octree node holding them (a bucket), so
//! that each bucket can later be built in memory on its own.
//!
//! Records are gathered per bucket in memory and appended to the bucket's file whenever the
//! buffers together pass their limit: the files are opened only while written, so any number
//! of buckets works with few open files.

use std::collections::HashMap;
use std::fs::OpenOptions;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use super::IndexError;
use super::build::Cube;
use super::record::{Layout, Quantizer};
use crate::io::NodeKey;

/// One bucket's file.
#[derive(Debug, Clone, PartialEq)]
pub struct Bucket {
    /// The node whose cube the bucket covers.
    pub key: NodeKey,
    /// Its temporary file.
    pub path: PathBuf,
    /// Points in it.
    pub points: u64,
}

/// Buffers records per bucket and appends them to files in `dir`.
#[derive(Debug)]
pub struct Spill {
    dir: PathBuf,
    record_len: usize,
    buffers: HashMap<NodeKey, Vec<u8>>,
    buffered: usize,
    limit: usize,
    counts: HashMap<NodeKey, u64>,
}

fn io_error(path: &Path, action: &'static str, source: std::io::Error) -> IndexError {
    IndexError::Scratch {
        path: path.to_path_buf(),
        action,
        source,
    }
}

impl Spill {
    /// Buckets in `dir`, buffering up to `limit` bytes in memory.
    pub fn new(dir: &Path, layout: Layout, limit: usize) -> Spill {
        Spill {
            dir: dir.to_path_buf(),
            record_len: layout.len,
            buffers: HashMap::new(),
            buffered: 0,
            limit: limit.max(1 << 16),
            counts: HashMap::new(),
        }
    }

    fn path_of(&self, key: NodeKey) -> PathBuf {
        self.dir.join(format!(
            "{}-{}-{}-{}.points",
            key.depth, key.x, key.y, key.z
        ))
    }

    /// Adds one record to bucket `key`.
    ///
    /// # Errors
    /// [`IndexError::Scratch`] when a flush fails (a full disk).
    pub fn push(&mut self, key: NodeKey, record: &[u8]) -> Result<(), IndexError> {
        self.push_many(key, record)
    }

    /// Adds whole records (`records.len()` a multiple of the record length) to bucket `key`.
    ///
    /// # Errors
    /// [`IndexError::Scratch`] when a flush fails (a full disk).
    pub fn push_many(&mut self, key: NodeKey, records: &[u8]) -> Result<(), IndexError> {
        debug_assert_eq!(records.len() % self.record_len, 0);
        self.buffers
            .entry(key)
            .or_default()
            .extend_from_slice(records);
        *self.counts.entry(key).or_default() += (records.len() / self.record_len) as u64;
        self.buffered += records.len();
        if self.buffered >= self.limit {
            self.flush()?;
        }
        Ok(())
    }

    /// Appends every buffer to its file.
    ///
    /// # Errors
    /// [`IndexError::Scratch`].
    pub fn flush(&mut self) -> Result<(), IndexError> {
        for (key, buffer) in &mut self.buffers {
            if buffer.is_empty() {
                continue;
            }
            let path = self.dir.join(format!(
                "{}-{}-{}-{}.points",
                key.depth, key.x, key.y, key.z
            ));
            let mut file = OpenOptions::new()
                .create(true)
                .append(true)
                .open(&path)
                .map_err(|e| io_error(&path, "creating", e))?;
            file.write_all(buffer)
                .map_err(|e| io_error(&path, "writing", e))?;
            buffer.clear();
        }
        // Buffers of buckets that stopped growing give their memory back.
        self.buffers.retain(|_, b| b.capacity() < 1 << 20);
        self.buffered = 0;
        Ok(())
    }

    /// Flushes and lists the buckets, fullest first.
    ///
    /// # Errors
    /// [`IndexError::Scratch`].
    pub fn finish(mut self) -> Result<Vec<Bucket>, IndexError> {
        self.flush()?;
        let mut buckets: Vec<Bucket> = self
            .counts
            .iter()
            .map(|(key, points)| Bucket {
                key: *key,
                path: self.path_of(*key),
                points: *points,
            })
            .collect();
        buckets.sort_by(|a, b| b.points.cmp(&a.points).then(a.key.cmp(&b.key)));
        Ok(buckets)
    }

    /// Bytes buffered before a flush.
    pub fn limit(&self) -> usize {
        self.limit
    }

    /// Bytes per record.
    pub fn record_len(&self) -> usize {
        self.record_len
    }
}

/// Reads a bucket's records.
///
/// # Errors
/// [`IndexError::Scratch`].
pub fn read(bucket: &Bucket) -> Result<Vec<u8>, IndexError> {
    let mut bytes = Vec::new();
    std::fs::File::open(&bucket.path)
        .and_then(|mut f| f.read_to_end(&mut bytes))
        .map_err(|e| io_error(&bucket.path, "reading", e))?;
    Ok(bytes)
}

/// Splits buckets holding more than `most` points into their eight children (again, until
/// each fits or the depth limit is reached), streaming each file once per split.
///
/// # Errors
/// [`IndexError::Scratch`].
pub fn split_large(
    buckets: Vec<Bucket>,
    most: u64,
    cube: &Cube,
    q: &Quantizer,
    layout: Layout,
    dir: &Path,
    buffer: usize,
) -> Result<Vec<Bucket>, IndexError> {
    let mut done = Vec::new();
    let mut pending = buckets;
    while let Some(b) = pending.pop() {
        if b.points <= most || b.key.depth >= super::build::MAX_INDEX_DEPTH {
            done.push(b);
            continue;
        }
        let mut spill = Spill::new(dir, layout, buffer);
        let mut file = std::fs::File::open(&b.path).map_err(|e| io_error(&b.path, "reading", e))?;
        let mut block = vec![0u8; layout.len * 65_536];
        let mut filled = 0;
        loop {
            let n = file
                .read(&mut block[filled..])
                .map_err(|e| io_error(&b.path, "reading", e))?;
            filled += n;
            let whole = filled / layout.len * layout.len;
            for r in block[..whole].chunks_exact(layout.len) {
                let p = q.position(Layout::xyz(r));
                spill.push(cube.key_at(b.key.depth + 1, p), r)?;
            }
            block.copy_within(whole..filled, 0);
            filled -= whole;
            if n == 0 {
                break;
            }
        }
        drop(file);
        std::fs::remove_file(&b.path).map_err(|e| io_error(&b.path, "removing", e))?;
        pending.extend(spill.finish()?);
    }
    done.sort_by(|a, b| b.points.cmp(&a.points).then(a.key.cmp(&b.key)));
    Ok(done)
}
