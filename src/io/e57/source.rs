//! Streaming an E57 file's points: a thread owns the decoder (whose point iterator borrows
//! it, so the two cannot live in one struct) and answers requests for up to `n` points.
//!
//! Each picked scan is read in turn; positions are posed into the file's frame
//! (`R · local + t`, f64), spherical ones converted first; points whose position is
//! flagged invalid or a bare direction are dropped. Intensity and colour come normalised by
//! the file's limits and are stored as 16-bit intensity and 8-bit colour.

use super::super::chunk::{RawChunk, RawRgb};
use super::super::error::LoadError;
use super::super::guard::guarded;
use super::super::info::FileInfo;
use super::facts::ColourFrom;
use super::photo::{self, Photo};
use super::pose::{Pose, spherical_to_local};
use glam::DVec3;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};

/// What the reading thread needs, copied out of the file's facts.
#[derive(Debug, Clone)]
struct Plan {
    /// The file to open.
    file: PathBuf,
    /// The path as given (with its pick), for messages.
    path: PathBuf,
    /// Each picked scan: its index, pose, where its colours come from and its images.
    scans: Vec<(usize, Pose, ColourFrom, Vec<usize>)>,
    rgb: bool,
    intensity: bool,
    declared: u64,
}

/// A request: up to this many points.
type Request = usize;
/// An answer: a chunk, `None` at the end, or the error that ended the stream.
type Answer = Result<Option<RawChunk>, LoadError>;

/// Points of an opened E57 file, read on a thread of their own.
pub(crate) struct E57Source {
    plan: Plan,
    requests: Option<SyncSender<Request>>,
    answers: Option<Receiver<Answer>>,
    read: u64,
}

impl E57Source {
    /// The source of `file`'s picked scans, with the attributes `info` promises.
    pub(crate) fn new(file: &Path, info: &FileInfo) -> Self {
        let e57 = info.e57.as_ref();
        let plan = Plan {
            file: file.to_path_buf(),
            path: info.path.clone(),
            scans: e57
                .map(|e| {
                    e.selected_scans()
                        .map(|s| (s.index, s.pose, e.colour_from(s), s.images.clone()))
                        .collect()
                })
                .unwrap_or_default(),
            rgb: info.attributes.rgb,
            intensity: info.attributes.intensity,
            declared: info.point_count,
        };
        E57Source {
            plan,
            requests: None,
            answers: None,
            read: 0,
        }
    }

    fn start(&mut self, skip: u64) {
        let (req_tx, req_rx) = sync_channel::<Request>(1);
        let (ans_tx, ans_rx) = sync_channel::<Answer>(1);
        let plan = self.plan.clone();
        std::thread::spawn(move || serve(&plan, skip, &req_rx, &ans_tx));
        self.requests = Some(req_tx);
        self.answers = Some(ans_rx);
    }

    fn ended(&self, detail: &str) -> LoadError {
        LoadError::CorruptPoints {
            path: self.plan.path.clone(),
            read: self.read,
            declared: self.plan.declared,
            detail: detail.into(),
        }
    }

    pub(crate) fn next_raw(&mut self, n: usize) -> Result<Option<RawChunk>, LoadError> {
        if self.requests.is_none() {
            self.start(0);
        }
        let (Some(req), Some(ans)) = (&self.requests, &self.answers) else {
            return Ok(None);
        };
        if req.send(n.max(1)).is_err() {
            return Ok(None);
        }
        let answer = ans
            .recv()
            .map_err(|_| self.ended("the reading thread stopped"))?;
        match &answer {
            Ok(Some(chunk)) => self.read += chunk.positions.len() as u64,
            Ok(None) | Err(_) => {
                self.requests = None;
                self.answers = None;
                // A later call reads nothing rather than starting over.
                self.plan.scans.clear();
            }
        }
        answer
    }

    /// Starts again at point record `point` (invalid records count): reads and drops the
    /// records before it.
    pub(crate) fn seek(&mut self, point: u64) -> Result<(), LoadError> {
        if point > self.plan.declared {
            return Err(LoadError::SeekPastEnd {
                path: self.plan.path.clone(),
                point,
                declared: self.plan.declared,
            });
        }
        self.requests = None;
        self.answers = None;
        self.read = 0;
        self.start(point);
        Ok(())
    }
}

/// The reading thread: opens the file, then answers each request until the end, an error,
/// or the requester going away.
fn serve(plan: &Plan, skip: u64, requests: &Receiver<Request>, answers: &SyncSender<Answer>) {
    let result = guarded(&plan.path, "decoding points", || {
        read_all(plan, skip, requests, answers)
    });
    if let Err(e) = result {
        // The answer slot is free: every earlier answer was followed by a request. The
        // requester takes the error with its next request.
        let _ = answers.send(Err(e));
    }
}

/// Reads the picked scans, answering requests; `Ok` when done or the requester left.
fn read_all(
    plan: &Plan,
    mut skip: u64,
    requests: &Receiver<Request>,
    answers: &SyncSender<Answer>,
) -> Result<(), LoadError> {
    let corrupt = |read: u64, e: &dyn std::fmt::Display| LoadError::CorruptPoints {
        path: plan.path.clone(),
        read,
        declared: plan.declared,
        detail: e.to_string().replace('\n', " "),
    };
    let mut reader = e57::E57Reader::from_file(&plan.file).map_err(|e| corrupt(0, &e))?;
    let clouds = reader.pointclouds();
    let images = reader.images();
    let mut chunk = RawChunk::default();
    let mut want = match requests.recv() {
        Ok(n) => n,
        Err(_) => return Ok(()),
    };
    let mut records = 0u64;
    for (index, pose, colour, photo_indices) in &plan.scans {
        let (index, pose) = (*index, *pose);
        let Some(cloud) = clouds.get(index) else {
            continue;
        };
        let photos = if plan.rgb && *colour == ColourFrom::Images && skip < cloud.records {
            decode_photos(&mut reader, &images, photo_indices)
                .map_err(|detail| corrupt(records, &detail))?
        } else {
            Vec::new()
        };
        if skip >= cloud.records {
            skip -= cloud.records;
            records += cloud.records;
            continue;
        }
        let mut points = reader
            .pointcloud_simple(cloud)
            .map_err(|e| corrupt(records, &e))?;
        points.apply_pose(false);
        points.spherical_to_cartesian(false);
        points.intensity_to_color(false);
        for point in points.by_ref() {
            let point = point.map_err(|e| corrupt(records, &e))?;
            records += 1;
            if skip > 0 {
                skip -= 1;
                continue;
            }
            let Some(local) = local_position(&point) else {
                continue;
            };
            push(
                &mut chunk,
                plan,
                pose.apply(local),
                &point,
                *colour,
                &photos,
            );
            if chunk.positions.len() >= want {
                if answers.send(Ok(Some(std::mem::take(&mut chunk)))).is_err() {
                    return Ok(());
                }
                want = match requests.recv() {
                    Ok(n) => n,
                    Err(_) => return Ok(()),
                };
            }
        }
    }
    if !chunk.positions.is_empty() {
        if answers.send(Ok(Some(chunk))).is_err() {
            return Ok(());
        }
        if requests.recv().is_err() {
            return Ok(());
        }
    }
    let _ = answers.send(Ok(None));
    Ok(())
}

/// The point's position in its scan's frame: Cartesian when valid, else spherical when
/// valid; `None` for invalid positions and bare directions.
pub(crate) fn local_position(point: &e57::Point) -> Option<DVec3> {
    match point.cartesian {
        e57::CartesianCoordinate::Valid { x, y, z } => Some(DVec3::new(x, y, z)),
        _ => match point.spherical {
            e57::SphericalCoordinate::Valid {
                range,
                azimuth,
                elevation,
            } => Some(spherical_to_local(range, azimuth, elevation)),
            _ => None,
        },
    }
}

/// A normalised value (0–1) as an integer of `max` steps.
fn unit_to(v: f32, max: f32) -> f32 {
    (if v.is_finite() {
        v.clamp(0.0, 1.0)
    } else {
        0.0
    } * max)
        .round()
}

/// The projected images `indices` of the file, decoded.
fn decode_photos<T: std::io::Read + std::io::Seek>(
    reader: &mut e57::E57Reader<T>,
    images: &[e57::Image],
    indices: &[usize],
) -> Result<Vec<Photo>, String> {
    let mut photos = Vec::with_capacity(indices.len());
    for &i in indices {
        let Some(projection) = images.get(i).and_then(|img| img.projection.as_ref()) else {
            continue;
        };
        let (lens, blob) = photo::lens(projection);
        let mut bytes = Vec::new();
        reader
            .blob(&blob.data, &mut bytes)
            .map_err(|e| format!("image {i}: {e}"))?;
        let pixels = image::load_from_memory(&bytes)
            .map_err(|e| format!("image {i}: {e}"))?
            .to_rgb8();
        photos.push(Photo {
            pose: Pose::from_e57(images[i].transform.as_ref()),
            lens,
            pixels,
        });
    }
    Ok(photos)
}

fn push(
    chunk: &mut RawChunk,
    plan: &Plan,
    world: DVec3,
    point: &e57::Point,
    colour: ColourFrom,
    photos: &[Photo],
) {
    chunk.positions.push(world);
    if plan.intensity {
        let i = point.intensity.map_or(0, |v| unit_to(v, 65535.0) as u16);
        chunk.intensity.get_or_insert_with(Vec::new).push(i);
    }
    if plan.rgb {
        // A point without a colour (flagged invalid, or seen by no image) shows its
        // intensity as grey.
        let grey = || [unit_to(point.intensity.unwrap_or(0.5), 255.0) as u8; 3];
        let c = match (colour, &point.color) {
            (ColourFrom::Images, _) => photo::colour_from(photos, world).unwrap_or_else(grey),
            (ColourFrom::Stored, Some(c)) => {
                [c.red, c.green, c.blue].map(|v| unit_to(v, 255.0) as u8)
            }
            _ => grey(),
        };
        match chunk.rgb.get_or_insert_with(|| RawRgb::Bits8(Vec::new())) {
            RawRgb::Bits8(v) => v.push(c),
            RawRgb::Bits16(_) => unreachable!("E57 colour is gathered as 8 bits"),
        }
    }
}
