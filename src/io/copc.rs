//! COPC (Cloud Optimized Point Cloud, <https://copc.io>): a LAZ 1.4 file whose points are
//! grouped in the nodes of an octree, each node one compressed chunk, listed by a hierarchy
//! EVLR. Through `las`'s `CopcReader`: [`CopcFile::open`] reads and checks the header and the
//! hierarchy once, [`CopcFile::read_nodes`] then reads the points of chosen nodes (each
//! decoded by `laz` from its own chunk); [`read_octree`] and [`open_nodes`] do both for one
//! read. A plain read of the whole file needs none of this: [`super::open`] reads a COPC file
//! as the LAZ file it is.

use super::error::LoadError;
use super::guard::guarded;
use super::info::FileInfo;
use super::{PointFields, PointReader, RawChunk, Source};
use glam::DVec3;
use las::copc::{Entry, VoxelKey};
use std::collections::{HashMap, HashSet, VecDeque};
use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Deepest octree level accepted: node coordinates up to 2^30 fit the format's i32.
pub const MAX_DEPTH: u32 = 30;

/// An octree node's address: its depth and its integer position among the `2^depth` nodes
/// along each axis (x, y, z from the cube's low corner).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeKey {
    /// Level in the octree; the root is 0.
    pub depth: u32,
    /// Position along x.
    pub x: u32,
    /// Position along y.
    pub y: u32,
    /// Position along z.
    pub z: u32,
}

impl NodeKey {
    /// The root node: the whole cube.
    pub const ROOT: NodeKey = NodeKey {
        depth: 0,
        x: 0,
        y: 0,
        z: 0,
    };

    /// The eight children.
    pub fn children(self) -> impl Iterator<Item = NodeKey> {
        (0..8u32).map(move |i| NodeKey {
            depth: self.depth + 1,
            x: self.x * 2 + (i & 1),
            y: self.y * 2 + ((i >> 1) & 1),
            z: self.z * 2 + ((i >> 2) & 1),
        })
    }

    /// The node whose child this is; `None` for the root.
    pub fn parent(self) -> Option<NodeKey> {
        (self.depth > 0).then(|| NodeKey {
            depth: self.depth - 1,
            x: self.x / 2,
            y: self.y / 2,
            z: self.z / 2,
        })
    }

    fn from_las(key: &VoxelKey) -> Option<NodeKey> {
        let depth = u32::try_from(key.l).ok().filter(|d| *d <= MAX_DEPTH)?;
        let side = 1u64 << depth;
        let coord = |v: i32| u32::try_from(v).ok().filter(|v| u64::from(*v) < side);
        Some(NodeKey {
            depth,
            x: coord(key.x)?,
            y: coord(key.y)?,
            z: coord(key.z)?,
        })
    }

    fn to_las(self) -> VoxelKey {
        VoxelKey {
            l: self.depth as i32,
            x: self.x as i32,
            y: self.y as i32,
            z: self.z as i32,
        }
    }
}

/// A COPC file's octree: the cube, the point spacing and the points per node.
#[derive(Debug, Clone, PartialEq)]
pub struct Octree {
    /// Centre of the root cube, file coordinates.
    pub center: DVec3,
    /// Half the side of the root cube, metres.
    pub halfsize: f64,
    /// Distance between the root node's points; halved at each level.
    pub spacing: f64,
    /// Points of every node the hierarchy lists (0 for a node that only leads to children).
    pub nodes: HashMap<NodeKey, u64>,
    /// Points in the file (the header's count, which the nodes add up to).
    pub point_count: u64,
}

impl Octree {
    /// The deepest level that holds a node.
    pub fn depth(&self) -> u32 {
        self.nodes.keys().map(|k| k.depth).max().unwrap_or(0)
    }

    /// Nodes holding at least one point.
    pub fn nonempty_nodes(&self) -> usize {
        self.nodes.values().filter(|n| **n > 0).count()
    }

    /// The point spacing of the nodes at `depth`: [`Octree::spacing`] / 2^depth.
    pub fn node_spacing(&self, depth: u32) -> f64 {
        self.spacing / f64::from(depth).exp2()
    }

    /// `(low, high)` corners of a node, file coordinates.
    pub fn bounds(&self, key: NodeKey) -> (DVec3, DVec3) {
        let side = 2.0 * self.halfsize / f64::from(key.depth).exp2();
        let low = self.center - DVec3::splat(self.halfsize)
            + DVec3::new(f64::from(key.x), f64::from(key.y), f64::from(key.z)) * side;
        (low, low + DVec3::splat(side))
    }

    /// Distance from `p` to the cube of node `key` (0 inside it), file units.
    pub fn distance(&self, key: NodeKey, p: DVec3) -> f64 {
        let (lo, hi) = self.bounds(key);
        p.clamp(lo, hi).distance(p)
    }

    /// True when the hierarchy lists a child of `key`.
    pub fn has_children(&self, key: NodeKey) -> bool {
        key.depth < MAX_DEPTH && key.children().any(|c| self.nodes.contains_key(&c))
    }

    /// The child of `key` whose cube holds the file-coordinate point `p` (clamped to it).
    pub fn child_at(&self, key: NodeKey, p: DVec3) -> NodeKey {
        let (low, high) = self.bounds(key);
        let mid = (low + high) * 0.5;
        NodeKey {
            depth: key.depth + 1,
            x: key.x * 2 + u32::from(p.x >= mid.x),
            y: key.y * 2 + u32::from(p.y >= mid.y),
            z: key.z * 2 + u32::from(p.z >= mid.z),
        }
    }
}

/// True when the file's VLRs include the COPC info VLR (user id `copc`, record 1).
pub fn is_copc(info: &FileInfo) -> bool {
    info.las.as_ref().is_some_and(|l| {
        l.vlrs
            .iter()
            .any(|v| !v.extended && v.user_id.trim_end_matches('\0') == "copc" && v.record_id == 1)
    })
}

fn corrupt(path: &Path, detail: impl Into<String>) -> LoadError {
    LoadError::CorruptCopc {
        path: path.to_path_buf(),
        detail: detail.into(),
    }
}

type Reader = las::CopcReader<'static, BufReader<File>>;

/// Opens the COPC reader (header, info VLR, hierarchy) with typed errors; with it the
/// layered chunk shape its LASzip VLR gives.
fn open_reader(
    path: &Path,
) -> Result<(FileInfo, Reader, super::las::laz_chunks::NodeChunks), LoadError> {
    // The header checks (sizes against the file) come first: the las crate trusts them.
    let info = super::read_info(path)?;
    if !is_copc(&info) {
        return Err(LoadError::NotCopc {
            path: path.to_path_buf(),
        });
    }
    let reader = guarded(path, "reading the COPC hierarchy", || {
        let open = || File::open(path).map_err(|e| LoadError::from_io(path, e));
        let header = las::Header::new(&mut BufReader::new(open()?))
            .map_err(|e| corrupt(path, e.to_string()))?;
        check_pages(path, &header)?;
        // The decoder sets up its models from the LASzip VLR's items here.
        let (chunks, _, _) = node_chunks(path)?;
        let reader = las::CopcReader::new(BufReader::new(open()?)).map_err(|e| match e {
            las::Error::CopcHierarchyEvlrNotFound => corrupt(
                path,
                "the hierarchy EVLR is missing, or a page it points to lies outside it",
            ),
            las::Error::ReferencedPageMissingFromEvlr(entry) => corrupt(
                path,
                format!(
                    "the hierarchy refers to a page at byte {} that it does not hold",
                    entry.offset
                ),
            ),
            other => corrupt(path, other.to_string()),
        })?;
        Ok((reader, chunks))
    })?;
    Ok((info, reader.0, reader.1))
}

/// A hierarchy entry that refers to a child page: `(node, page offset, page size)`.
type PageRef = ([i32; 4], u64, i32);

/// The entries of a hierarchy page (32 bytes each) that refer to a child page.
fn page_refs(page: &[u8]) -> impl Iterator<Item = PageRef> + '_ {
    let i32_at = |e: &[u8], at: usize| i32::from_le_bytes(e[at..at + 4].try_into().unwrap());
    page.chunks_exact(32)
        .filter(move |e| i32_at(e, 28) == -1)
        .map(move |e| {
            let key = [i32_at(e, 0), i32_at(e, 4), i32_at(e, 8), i32_at(e, 12)];
            (
                key,
                u64::from_le_bytes(e[16..24].try_into().unwrap()),
                i32_at(e, 24),
            )
        })
}

/// Refuses a hierarchy whose pages refer to one page twice, as the `las` crate would follow
/// them: a page that refers to itself or to a page above it is otherwise followed forever
/// (memory growing all the while). Pages as the crate finds them: the first page read for a
/// node serves every reference to it; a page outside the EVLR is left for the crate to report.
fn check_pages(path: &Path, header: &las::Header) -> Result<(), LoadError> {
    let info = header.vlrs().iter().find(|v| v.is_copc_info());
    let hierarchy = header.evlrs().iter().find(|v| v.is_copc_hierarchy());
    let (Some(info), Some(hierarchy)) = (info, hierarchy) else {
        return Ok(());
    };
    let u64_at = |at: usize| {
        info.data
            .get(at..at + 8)
            .map(|b| u64::from_le_bytes(b.try_into().unwrap()))
    };
    // The root page's offset and size follow the cube and spacing in the info VLR.
    let (Some(root_offset), Some(root_size)) = (u64_at(40), u64_at(48)) else {
        return Ok(());
    };
    let page = |offset: u64, size: u64| {
        let start = usize::try_from(offset.checked_sub(root_offset)?).ok()?;
        let end = start.checked_add(usize::try_from(size).ok()?)?;
        hierarchy.data.get(start..end)
    };
    let Some(root) = page(root_offset, root_size) else {
        return Ok(());
    };
    let mut pages = HashMap::new();
    let mut pending: Vec<PageRef> = page_refs(root).collect();
    while let Some((key, offset, size)) = pending.pop() {
        if pages.contains_key(&key) {
            continue;
        }
        let Some(bytes) = u64::try_from(size).ok().and_then(|size| page(offset, size)) else {
            return Ok(());
        };
        pending.extend(page_refs(bytes));
        pages.insert(key, bytes);
    }
    let mut followed = HashSet::new();
    let mut stack = vec![root];
    while let Some(bytes) = stack.pop() {
        for (key, offset, _) in page_refs(bytes) {
            if !followed.insert(key) {
                return Err(corrupt(
                    path,
                    format!(
                        "the hierarchy page of node {}-{}-{}-{} (at byte {offset}) is reached \
                         twice: the pages refer back to themselves",
                        key[0], key[1], key[2], key[3]
                    ),
                ));
            }
            stack.extend(pages.get(&key));
        }
    }
    Ok(())
}

/// Reads and checks a COPC file's octree: every node a valid address, its chunk inside the
/// file and apart from the others, and the nodes reachable from the root holding exactly the
/// header's point count (a flipped byte in the hierarchy breaks one of these).
///
/// # Errors
/// [`LoadError::CorruptCopc`] naming the file and the fault; [`LoadError::NotCopc`]; any
/// header error of [`super::read_info`].
pub fn read_octree(path: &Path) -> Result<Octree, LoadError> {
    let (_, reader, _) = open_reader(path)?;
    Ok(octree_of(path, &reader)?.0)
}

/// The octree of the file `reader` reads, checked, and the hierarchy's entries by node.
fn octree_of(path: &Path, reader: &Reader) -> Result<(Octree, HashMap<NodeKey, Entry>), LoadError> {
    let header = reader.header();
    let info = header
        .copc_info_vlr()
        .ok_or_else(|| corrupt(path, "the COPC info VLR does not parse"))?;
    let center = DVec3::new(info.center_x, info.center_y, info.center_z);
    let usable = |v: f64| v.is_finite() && v > 0.0;
    // The cube's corners must be finite too (found by fuzzing: a halfsize of ~1e308 made
    // every node's bounds NaN).
    let corners_finite = (center.abs() + DVec3::splat(4.0 * info.halfsize)).is_finite();
    if !(center.is_finite() && usable(info.halfsize) && usable(info.spacing) && corners_finite) {
        return Err(corrupt(
            path,
            format!(
                "the info VLR's cube (centre {center}, halfsize {}) or spacing ({}) is not usable",
                info.halfsize, info.spacing
            ),
        ));
    }
    let file_len = std::fs::metadata(path)
        .map_err(|e| LoadError::from_io(path, e))?
        .len();
    let declared = header.number_of_points();
    let mut nodes = HashMap::new();
    let mut entries = HashMap::new();
    let mut chunks = Vec::new();
    for entry in reader.hierarchy_entries() {
        let key = NodeKey::from_las(&entry.key).ok_or_else(|| {
            corrupt(
                path,
                format!(
                    "the hierarchy lists an impossible node {}-{}-{}-{}",
                    entry.key.l, entry.key.x, entry.key.y, entry.key.z
                ),
            )
        })?;
        let count = check_entry(path, &entry, declared, file_len)?;
        if count > 0 {
            chunks.push((entry.offset, entry.byte_size as u64, key));
        }
        nodes.insert(key, count);
        entries.insert(key, entry);
    }
    // Chunks never share bytes: an offset or size off by a flipped bit mostly makes two meet.
    chunks.sort_unstable();
    for pair in chunks.windows(2) {
        let ((offset, size, a), (next, _, b)) = (pair[0], pair[1]);
        if offset + size > next {
            return Err(corrupt(
                path,
                format!(
                    "the chunks of nodes {}-{}-{}-{} and {}-{}-{}-{} overlap",
                    a.depth, a.x, a.y, a.z, b.depth, b.x, b.y, b.z
                ),
            ));
        }
    }
    if !nodes.contains_key(&NodeKey::ROOT) {
        return Err(corrupt(path, "the hierarchy has no root node"));
    }
    let mut reachable = 0u64;
    let mut pending = vec![NodeKey::ROOT];
    while let Some(key) = pending.pop() {
        if let Some(count) = nodes.get(&key) {
            reachable = reachable.saturating_add(*count);
            if key.depth < MAX_DEPTH {
                pending.extend(key.children());
            }
        }
    }
    if reachable != declared {
        return Err(corrupt(
            path,
            format!(
                "the hierarchy's nodes hold {reachable} points but the header declares {declared}"
            ),
        ));
    }
    let octree = Octree {
        center,
        halfsize: info.halfsize,
        spacing: info.spacing,
        nodes,
        point_count: declared,
    };
    Ok((octree, entries))
}

/// The points of one entry, checked against the file.
fn check_entry(path: &Path, entry: &Entry, declared: u64, file_len: u64) -> Result<u64, LoadError> {
    let key = entry.key;
    // Named only for an error: a hierarchy holds thousands of entries.
    let name = || format!("node {}-{}-{}-{}", key.l, key.x, key.y, key.z);
    let count = u64::try_from(entry.point_count)
        .map_err(|_| corrupt(path, format!("{} has {} points", name(), entry.point_count)))?;
    if count > declared {
        return Err(corrupt(
            path,
            format!(
                "{} claims {count} points, more than the file's {declared}",
                name()
            ),
        ));
    }
    if count > 0 {
        let size = u64::try_from(entry.byte_size).unwrap_or(0);
        if size == 0 || entry.offset.saturating_add(size) > file_len || entry.offset < 375 {
            return Err(corrupt(
                path,
                format!(
                    "{}'s chunk ({} bytes at byte {}) lies outside the {file_len}-byte file",
                    name(),
                    entry.byte_size,
                    entry.offset
                ),
            ));
        }
    }
    Ok(count)
}

/// A COPC file opened once for many reads of its nodes: its header, LASzip VLR and hierarchy
/// read and checked ([`read_octree`]'s checks), shared by every [`CopcFile::read_nodes`].
/// Reads open the file again (one handle each, so they may run on several threads); a file
/// changed on disk after `open` is the caller's to detect.
#[derive(Debug)]
pub struct CopcFile {
    path: PathBuf,
    info: FileInfo,
    octree: Octree,
    /// The hierarchy's entry of every node.
    entries: HashMap<NodeKey, Entry>,
    /// The layered chunk shape, to check a node's chunk before decoding it.
    node_chunks: super::las::laz_chunks::NodeChunks,
    file_len: u64,
    format: Arc<NodeFormat>,
}

/// What decoding a node's chunk needs.
#[derive(Debug)]
struct NodeFormat {
    /// The file's header: point format and extra bytes, for the decoded records.
    header: las::Header,
    /// The LASzip VLR; `None` when it does not parse (every node read then fails, naming it).
    vlr: Result<laz::LazVlr, String>,
    /// Where the stored full-detail radius lies in a record's extra bytes.
    radius_at: Option<usize>,
    /// Where the stored radius for a view stopping at the point's node lies.
    lod_radius_at: Option<usize>,
}

impl CopcFile {
    /// Opens `path` and reads and checks its header and hierarchy.
    ///
    /// # Errors
    /// As [`read_octree`].
    pub fn open(path: &Path) -> Result<Self, LoadError> {
        use super::extra_bytes::{LOD_RADIUS_FIELD, RADIUS_FIELD};
        let (info, reader, node_chunks) = open_reader(path)?;
        let (octree, entries) = octree_of(path, &reader)?;
        let header = reader.header().clone();
        let file_len = std::fs::metadata(path)
            .map_err(|e| LoadError::from_io(path, e))?
            .len();
        let format = NodeFormat {
            radius_at: super::las::stored_f32_field(&header, RADIUS_FIELD),
            lod_radius_at: super::las::stored_f32_field(&header, LOD_RADIUS_FIELD),
            vlr: header.laz_vlr().map_err(|e| e.to_string()),
            header,
        };
        Ok(CopcFile {
            path: path.to_path_buf(),
            info,
            octree,
            entries,
            node_chunks,
            file_len,
            format: Arc::new(format),
        })
    }

    /// The file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The whole file's header information.
    pub fn info(&self) -> &FileInfo {
        &self.info
    }

    /// The file's octree.
    pub fn octree(&self) -> &Octree {
        &self.octree
    }

    /// A reader of the points of `keys` only (nodes in the file's order, one chunk per node);
    /// its [`FileInfo`] is the whole file's. Where the file stores radii (an index made by
    /// omnicloud), the points of the nodes in `stopped`, where a level-of-detail read stops
    /// refining, get the radius stored for a view that stops there, the others their
    /// full-detail radius.
    ///
    /// # Errors
    /// A key the hierarchy does not list; a node chunk whose layers do not fit it; the file
    /// cannot be opened.
    pub fn read_nodes(
        &self,
        keys: &[NodeKey],
        stopped: &HashSet<NodeKey>,
    ) -> Result<PointReader, LoadError> {
        let path = &self.path;
        let mut entries = Vec::with_capacity(keys.len());
        for key in keys {
            let Some(entry) = self.entries.get(key) else {
                return Err(corrupt(
                    path,
                    format!(
                        "no node {}-{}-{}-{} in the hierarchy",
                        key.depth, key.x, key.y, key.z
                    ),
                ));
            };
            if entry.point_count > 0 {
                entries.push(*entry);
            }
        }
        entries.sort_by_key(|e| e.offset);
        let file = File::open(path).map_err(|e| LoadError::from_io(path, e))?;
        let mut chunks = BufReader::new(file);
        // The layer sizes are checked before the decoder zero-fills what they state.
        for entry in &entries {
            let size = u64::try_from(entry.byte_size).unwrap_or(0);
            self.node_chunks
                .check(path, &mut chunks, entry.offset, size)
                .map_err(|detail| corrupt(path, format!("{}: {detail}", node_name(entry))))?;
        }
        Ok(PointReader {
            info: self.info.clone(),
            source: Source::Copc(Box::new(CopcSource {
                path: path.clone(),
                chunks,
                file_len: self.file_len,
                format: Arc::clone(&self.format),
                pending: entries.into(),
                ready: VecDeque::new(),
                read: 0,
                broken: false,
                stopped: stopped.iter().map(|k| k.to_las()).collect(),
                fields: PointFields::ALL,
            })),
        })
    }
}

/// Opens a COPC file for reading the points of `keys` only ([`CopcFile::read_nodes`]).
///
/// # Errors
/// As [`read_octree`]; a key the hierarchy does not list.
pub fn open_nodes(path: &Path, keys: &[NodeKey]) -> Result<PointReader, LoadError> {
    open_nodes_stopping(path, keys, &HashSet::new())
}

/// [`open_nodes`] for a level-of-detail read that stops refining at the nodes `stopped`
/// ([`CopcFile::read_nodes`]).
///
/// # Errors
/// As [`open_nodes`].
pub fn open_nodes_stopping(
    path: &Path,
    keys: &[NodeKey],
    stopped: &HashSet<NodeKey>,
) -> Result<PointReader, LoadError> {
    CopcFile::open(path)?.read_nodes(keys, stopped)
}

/// `node l-x-y-z`, for messages.
fn node_name(entry: &Entry) -> String {
    let k = entry.key;
    format!("node {}-{}-{}-{}", k.l, k.x, k.y, k.z)
}

/// The file's LASzip VLR, checked against its header ([`NodeChunks::new`]), the file opened
/// for reading its chunks, and its length.
fn node_chunks(
    path: &Path,
) -> Result<(super::las::laz_chunks::NodeChunks, BufReader<File>, u64), LoadError> {
    use super::las::laz_chunks::{self, Layout, NodeChunks};
    let file = File::open(path).map_err(|e| LoadError::from_io(path, e))?;
    let file_len = file
        .metadata()
        .map_err(|e| LoadError::from_io(path, e))?
        .len();
    let mut read = BufReader::new(file);
    let raw = las::raw::Header::read_from(&mut read).map_err(|e| corrupt(path, e.to_string()))?;
    let layout = Layout {
        file_len,
        vlrs_at: laz_chunks::vlrs_at(&raw),
        number_of_vlrs: raw.number_of_variable_length_records,
        offset_to_point_data: u64::from(raw.offset_to_point_data),
        declared_points: 0,
        record_length: raw.point_data_record_length,
    };
    let chunks = NodeChunks::new(path, &mut read, &layout)?;
    Ok((chunks, read, file_len))
}

/// Decoded bytes of the nodes decoded together, at most.
const BATCH_BYTES: usize = 32 << 20;
/// Nodes decoded together, at most, per thread.
const BATCH_PER_THREAD: usize = 4;

/// Streams the points of chosen nodes, a node per chunk. Nodes are decoded several at once
/// on every core (each node is one independent LAZ chunk) and handed out in order.
pub(crate) struct CopcSource {
    path: PathBuf,
    /// The file, for the compressed bytes of the nodes.
    chunks: BufReader<File>,
    file_len: u64,
    format: Arc<NodeFormat>,
    pending: VecDeque<Entry>,
    /// Nodes decoded ahead, in order.
    ready: VecDeque<las::PointData>,
    read: u64,
    /// Set after the decoder panicked: its state is unknown.
    broken: bool,
    /// Nodes whose points take the stopping radius.
    stopped: HashSet<VoxelKey>,
    /// The attributes decoded.
    fields: PointFields,
}

impl CopcSource {
    /// Points the hierarchy lists for the nodes not yet read.
    pub(super) fn points_pending(&self) -> u64 {
        self.pending
            .iter()
            .map(|e| u64::try_from(e.point_count).unwrap_or(0))
            .sum()
    }

    pub(crate) fn next_raw(&mut self) -> Result<Option<RawChunk>, LoadError> {
        if self.broken {
            return Ok(None);
        }
        if self.ready.is_empty() {
            self.decode_batch();
        }
        let Some(entry) = self.pending.pop_front() else {
            return Ok(None);
        };
        let data = match self.ready.pop_front() {
            Some(data) => data,
            None => self.decode_one(&entry)?,
        };
        self.read += data.len() as u64;
        let at = match self.format.lod_radius_at {
            Some(at) if self.stopped.contains(&entry.key) => Some(at),
            _ => self.format.radius_at,
        };
        Ok(Some(super::las::raw_chunk(&data, at, self.fields)))
    }

    /// Decodes the next nodes of `pending` together into `ready` (leaving them pending),
    /// when there are several that fit [`BATCH_BYTES`]; leaves `ready` empty when there are
    /// not, or when any of them fails (each is then decoded alone, which names the one that
    /// fails).
    fn decode_batch(&mut self) {
        let record_len = usize::from(self.format.header.point_format().len());
        let most = rayon::current_num_threads().max(1) * BATCH_PER_THREAD;
        let mut bytes = 0usize;
        let mut batch = 0usize;
        for entry in self.pending.iter().take(most) {
            let n = usize::try_from(entry.point_count).unwrap_or(usize::MAX);
            let size = n.saturating_mul(record_len);
            if bytes.saturating_add(size) > BATCH_BYTES {
                break;
            }
            bytes += size;
            batch += 1;
        }
        if batch < 2 {
            return;
        }
        let entries: Vec<Entry> = self.pending.iter().take(batch).cloned().collect();
        if let Ok(nodes) = self.decode(&entries) {
            self.ready.extend(nodes);
        }
    }

    /// Decodes the node `entry` alone.
    fn decode_one(&mut self, entry: &Entry) -> Result<las::PointData, LoadError> {
        let mut nodes = self
            .decode(std::slice::from_ref(entry))
            .inspect_err(|e| self.broken = matches!(e, LoadError::DecoderPanic { .. }))?;
        Ok(nodes.pop().expect("one node decoded"))
    }

    /// Decodes the chunks of `entries` (in the file's order) on every core.
    fn decode(&mut self, entries: &[Entry]) -> Result<Vec<las::PointData>, LoadError> {
        use std::io::{Read, Seek, SeekFrom};
        let path = &self.path;
        let (read, declared) = (self.read, self.format.header.number_of_points());
        let failed = |entry: &Entry, detail: String| LoadError::CorruptPoints {
            path: path.clone(),
            read,
            declared,
            detail: format!("{}: {detail}", node_name(entry)),
        };
        let vlr = self
            .format
            .vlr
            .as_ref()
            .map_err(|e| failed(&entries[0], format!("the LASzip VLR does not parse: {e}")))?;
        let record_len = usize::from(self.format.header.point_format().len());
        let mut compressed = Vec::new();
        let mut table = Vec::with_capacity(entries.len());
        let mut decoded_len = 0usize;
        for entry in entries {
            let size = usize::try_from(entry.byte_size).unwrap_or(0);
            let end = entry.offset.saturating_add(size as u64);
            if size == 0 || end > self.file_len {
                let detail = format!("its chunk ends past the file's {} bytes", self.file_len);
                return Err(failed(entry, detail));
            }
            let at = compressed.len();
            compressed.resize(at + size, 0);
            self.chunks
                .seek(SeekFrom::Start(entry.offset))
                .and_then(|_| self.chunks.read_exact(&mut compressed[at..]))
                .map_err(|e| LoadError::from_io(path, e))?;
            let points = u64::try_from(entry.point_count).unwrap_or(0);
            table.push(laz::laszip::ChunkTableEntry {
                point_count: points,
                byte_count: size as u64,
            });
            decoded_len = usize::try_from(points)
                .ok()
                .and_then(|n| n.checked_mul(record_len))
                .and_then(|b| b.checked_add(decoded_len))
                .ok_or_else(|| failed(entry, "too many points to decode".into()))?;
        }
        let mut decoded = vec![0u8; decoded_len];
        guarded(path, "decoding COPC nodes", || {
            laz::par_decompress_selective(
                &compressed,
                &mut decoded,
                vlr,
                &table,
                self.fields.laz_selection(),
            )
            .map_err(|e| failed(&entries[0], e.to_string()))
        })?;
        let header = &self.format.header;
        let mut at = 0;
        let mut nodes = Vec::with_capacity(entries.len());
        for entry in entries {
            let size = entry.point_count as usize * record_len;
            let node = las::PointDataBuilder::new()
                .for_header(header)
                .build_from_bytes(decoded[at..at + size].to_vec())
                .map_err(|e| failed(entry, e.to_string()))?;
            at += size;
            nodes.push(node);
        }
        Ok(nodes)
    }

    /// Decodes only `fields` of the nodes still to read.
    pub(super) fn decode_only(&mut self, fields: PointFields) {
        self.fields = fields;
        self.ready.clear();
    }

    pub(crate) fn seek_unsupported(&self, point: u64) -> LoadError {
        LoadError::SeekFailed {
            path: self.path.clone(),
            point,
            detail: "a selection of COPC nodes is read in order only".into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn octree() -> Octree {
        Octree {
            center: DVec3::new(10.0, 20.0, 30.0),
            halfsize: 8.0,
            spacing: 1.0,
            nodes: HashMap::from([(NodeKey::ROOT, 5)]),
            point_count: 5,
        }
    }

    #[test]
    fn children_bounds_and_lookup_agree() {
        let o = octree();
        let (lo, hi) = o.bounds(NodeKey::ROOT);
        assert_eq!(
            (lo, hi),
            (DVec3::new(2.0, 12.0, 22.0), DVec3::new(18.0, 28.0, 38.0))
        );
        for child in NodeKey::ROOT.children() {
            let (clo, chi) = o.bounds(child);
            assert_eq!(chi - clo, DVec3::splat(8.0));
            assert_eq!(o.child_at(NodeKey::ROOT, (clo + chi) * 0.5), child);
        }
        let grand = NodeKey::ROOT
            .children()
            .nth(7)
            .unwrap()
            .children()
            .next()
            .unwrap();
        assert_eq!(
            grand,
            NodeKey {
                depth: 2,
                x: 2,
                y: 2,
                z: 2
            }
        );
        assert_eq!(o.bounds(grand).0, DVec3::new(10.0, 20.0, 30.0));
        assert_eq!(o.node_spacing(3), 0.125);
    }

    #[test]
    fn impossible_keys_are_refused() {
        let key = |l, x, y, z| VoxelKey { l, x, y, z };
        assert!(NodeKey::from_las(&key(0, 0, 0, 0)).is_some());
        assert!(NodeKey::from_las(&key(2, 3, 3, 3)).is_some());
        assert!(NodeKey::from_las(&key(2, 4, 0, 0)).is_none());
        assert!(NodeKey::from_las(&key(-1, 0, 0, 0)).is_none());
        assert!(NodeKey::from_las(&key(1, 0, -1, 0)).is_none());
        assert!(NodeKey::from_las(&key(31, 0, 0, 0)).is_none());
    }
}
