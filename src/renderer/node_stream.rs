//! A COPC scan drawn through its level of detail for many camera positions: each frame selects
//! the octree nodes its camera needs (the rule `render` uses, [`lod::select`]), draws those
//! already on the GPU and uploads the others once into a [`NodeCache`] bounded in bytes, which
//! evicts the least recently used. Host memory holds one node at a time, not the scan.
//!
//! The nodes sit on the GPU relative to an [`Anchor`] (the local zero for a tour; the camera
//! for `serve`, as a resident scene): placing them at another anchor empties the cache, and
//! the next frame reads its nodes again.

use std::path::{Path, PathBuf};

use indicatif::ProgressBar;
use rayon::prelude::*;

use super::anchor::Anchor;
use super::error::ResidentError;
use crate::Rendered;
use crate::io::{CopcFile, NodeKey};
use crate::prepare::lod::{self, NodeRadii};
use crate::prepare::{PrepareError, PrepareOptions};
use crate::projection::Camera;
use crate::raster::{Rasterizer, UploadedScene};
use crate::render::{ColorRule, RenderSettings};
use crate::stream::node_cache::{CacheCounts, NodeCache};

/// Nodes read at once per thread when a frame needs nodes not on the GPU.
const NODES_PER_THREAD: usize = 4;

/// A cached node: its key and whether refinement stopped at it (its radii differ then).
type NodeId = (NodeKey, bool);

/// What the last frame drew.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FrameNodes {
    /// Nodes drawn.
    pub nodes: usize,
    /// Points in them (as the hierarchy counts them).
    pub points: u64,
    /// Nodes read and uploaded for this frame.
    pub uploaded: usize,
    /// Nodes skipped unread by the rasterizer, hidden whole behind nearer ones.
    pub hidden: u64,
    /// Points skipped unread as hidden: those of the hidden nodes and of hidden cells of the
    /// others.
    pub hidden_points: u64,
}

/// How a node stream reads, sizes, colours and keeps its nodes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeRules {
    /// How the spheres are sized.
    pub radii: NodeRadii,
    /// Colours, fixed for the whole scan.
    pub color: ColorRule,
    /// A node is fine enough when its spacing spans less than this many pixels of the frame
    /// (0 reads every node).
    pub pixels: f64,
    /// Points a frame reads at least, where the file holds them ([`lod::select`]).
    pub floor: u64,
    /// Bytes of nodes kept on the GPU between frames.
    pub budget: u64,
}

/// What identifies a file's content for a reader that opens it again for every node: its
/// length, modification time and (Unix) inode. A file truncated, rewritten or replaced by a
/// rename differs in one of them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct FileStamp {
    len: u64,
    modified: Option<std::time::SystemTime>,
    inode: u64,
}

impl FileStamp {
    fn of(path: &Path) -> Result<Self, ResidentError> {
        let meta = std::fs::metadata(path).map_err(|e| ResidentError::ScanChanged {
            path: path.to_path_buf(),
            what: format!("it can no longer be read: {e}"),
        })?;
        #[cfg(unix)]
        let inode = std::os::unix::fs::MetadataExt::ino(&meta);
        #[cfg(not(unix))]
        let inode = 0;
        Ok(FileStamp {
            len: meta.len(),
            modified: meta.modified().ok(),
            inode,
        })
    }

    /// An error naming `path` when it no longer has this stamp.
    fn check(&self, path: &Path) -> Result<(), ResidentError> {
        let now = FileStamp::of(path)?;
        let what = if now.len != self.len {
            format!("{} bytes when opened, {} now", self.len, now.len)
        } else if now.inode != self.inode {
            "another file now has its name".to_string()
        } else if now.modified != self.modified {
            "modified since it was opened".to_string()
        } else {
            return Ok(());
        };
        Err(ResidentError::ScanChanged {
            path: path.to_path_buf(),
            what,
        })
    }
}

/// The rasterizer, the file's octree and the nodes on the GPU; see the module docs.
pub struct NodeStream {
    rasterizer: Rasterizer,
    path: PathBuf,
    /// The file as it was when its octree was read: every frame checks it still is.
    stamp: FileStamp,
    /// The file's header and hierarchy, read once for every node read.
    copc: CopcFile,
    options: PrepareOptions,
    radii: NodeRadii,
    color: ColorRule,
    upload: RenderSettings,
    anchor: Anchor,
    pixels: f64,
    floor: u64,
    cache: NodeCache<NodeId, UploadedScene>,
    last: FrameNodes,
    /// Nodes skipped as hidden, summed over the frames.
    hidden: u64,
}

impl NodeStream {
    /// Reads the octree of the COPC file `path`; frames will be drawn by `rasterizer` from
    /// nodes read with `options` (its origin is the frames' local zero; up axis and filters
    /// apply) under `rules`, in the modes of `settings`.
    ///
    /// # Errors
    /// The file's hierarchy cannot be read.
    pub fn new(
        rasterizer: Rasterizer,
        path: &Path,
        options: &PrepareOptions,
        rules: NodeRules,
        settings: &RenderSettings,
    ) -> Result<Self, ResidentError> {
        let stamp = FileStamp::of(path)?;
        let copc = CopcFile::open(path).map_err(PrepareError::from)?;
        stamp.check(path)?;
        Ok(NodeStream {
            rasterizer,
            path: path.to_path_buf(),
            stamp,
            copc,
            options: *options,
            radii: rules.radii,
            color: rules.color,
            // Every node relative to the local zero: one upload serves every camera.
            upload: RenderSettings {
                camera: Camera::new(glam::DVec3::ZERO, 0.0),
                ..*settings
            },
            anchor: Anchor::SceneZero,
            pixels: rules.pixels,
            floor: rules.floor,
            cache: NodeCache::new(rules.budget),
            last: FrameNodes::default(),
            hidden: 0,
        })
    }

    /// The rasterizer.
    pub fn rasterizer(&self) -> &Rasterizer {
        &self.rasterizer
    }

    /// Where the nodes on the GPU are measured from.
    pub fn anchor(&self) -> Anchor {
        self.anchor
    }

    /// Measures the nodes from `anchor` for the frames to come: at another position than
    /// now, the nodes held are dropped and the next frame reads and uploads its own again.
    pub fn place(&mut self, anchor: Anchor) {
        if anchor.position() != self.anchor.position() {
            self.release();
        }
        self.anchor = anchor;
        self.upload.camera = Camera::new(anchor.position(), 0.0);
    }

    /// Drops every node held on the GPU (the next frame reads its own again).
    pub fn release(&mut self) {
        self.cache.clear();
    }

    /// What the cache did so far.
    pub fn cache_counts(&self) -> CacheCounts {
        self.cache.counts()
    }

    /// Bytes of nodes on the GPU now, and the bound.
    pub fn cache_bytes(&self) -> (u64, u64) {
        (self.cache.used(), self.cache.budget())
    }

    /// What the last frame drew.
    pub fn last_frame(&self) -> FrameNodes {
        self.last
    }

    /// Nodes the frames so far skipped as hidden behind nearer ones, summed.
    pub fn hidden_nodes(&self) -> u64 {
        self.hidden
    }

    /// What renders, for messages.
    pub fn describe(&self) -> String {
        format!(
            "level of detail ({} px, floor {} points): {} points in {} nodes, read per frame into \
             a cache of {} on the GPU ({})",
            self.pixels,
            self.floor,
            self.copc.octree().point_count,
            self.copc.octree().nonempty_nodes(),
            crate::memory::format_size(self.cache.budget()),
            self.rasterizer.adapter_name()
        )
    }

    /// Renders one frame; `settings.camera.center` is in the local frame of the options'
    /// origin, and `settings` has the modes given to [`NodeStream::new`].
    ///
    /// # Errors
    /// A node cannot be read, or the rasterizer failed.
    pub fn render(
        &mut self,
        settings: &RenderSettings,
        progress: &ProgressBar,
    ) -> Result<Rendered, ResidentError> {
        let origin = self.options.origin.unwrap_or_default();
        let camera = lod::to_file(self.options.up, origin + settings.camera.center);
        let threshold =
            std::f64::consts::TAU / f64::from(settings.image.width.max(1)) * self.pixels;
        let selection = lod::select(self.copc.octree(), camera, threshold, self.floor);
        // The octree and the nodes on the GPU are the file as it was opened: a frame drawn
        // from them and nodes of a changed file would be a wrong frame, not an error.
        self.stamp.check(&self.path)?;
        // Nodes held are marked used first, so that the new ones, held once drawn, evict
        // older frames' nodes rather than this one's.
        let mut fresh: Vec<(NodeId, UploadedScene)> = Vec::new();
        let missing: Vec<NodeId> = selection
            .read
            .iter()
            .map(|key| (*key, selection.nodes[key]))
            .filter(|id| self.cache.get(id).is_none())
            .collect();
        // Nodes are read a few per thread at a time, in parallel (each is its own LAZ
        // chunk), and uploaded before the next few: host memory holds a batch, not a frame.
        let batch = rayon::current_num_threads().max(1) * NODES_PER_THREAD;
        for ids in missing.chunks(batch) {
            let scenes: Vec<_> = ids
                .par_iter()
                .map(|id| lod::node_scene(&self.copc, id.0, id.1, &self.options, self.radii))
                .collect();
            for (id, scene) in ids.iter().zip(scenes) {
                let node = self
                    .rasterizer
                    .upload_colored(&scene?, &self.upload, self.color)?;
                fresh.push((*id, node));
            }
        }
        if !fresh.is_empty() {
            self.stamp.check(&self.path)?;
        }
        let uploaded = fresh.len();
        let (rendered, stats, _) = {
            let pieces: Vec<&UploadedScene> = selection
                .read
                .iter()
                .filter_map(|k| self.cache.peek(&(*k, selection.nodes[k])))
                .chain(fresh.iter().map(|(_, n)| n))
                .collect();
            self.rasterizer
                .render_gathered_timed(&pieces, settings, progress)?
        };
        for (id, node) in fresh {
            let bytes = node.gpu_bytes();
            // A node larger than the whole cache was drawn once and is dropped.
            let _ = self.cache.insert(id, node, bytes);
        }
        self.last = FrameNodes {
            nodes: selection.read.len(),
            points: selection.points,
            uploaded,
            hidden: stats.hidden_pieces,
            hidden_points: stats.hidden_points / settings.views().len().max(1) as u64,
        };
        self.hidden += stats.hidden_pieces;
        Ok(rendered)
    }
}
