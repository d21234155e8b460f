//! MP4 files with `mp4-atom`: one H.264 video track whose `avc1` sample entry carries the
//! Spherical Video V2 boxes that 360 players read (`st3d` with the stereo mode, then `sv3d`
//! with an `equi` projection), written with the index first ("fast start") so a browser or
//! headset can start playing before the whole file has arrived; and the reading back of
//! what such a file says.
//!
//! The frames go to an unnamed temporary file next to the output while they are encoded (a
//! long tour never sits in memory); [`Mp4Writer::finish`] then writes `ftyp`, `moov` and
//! `mdat` into the output atomically.

use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use mp4_atom::{
    Atom, Avc1, Avcc, Co64, Codec, Colr, Dinf, Dref, Encode, Equi, FourCC, Ftyp, Hdlr, Header,
    Mdhd, Mdia, Minf, Moov, Mvhd, Prhd, Proj, ProjKind, ReadAtom, ReadFrom, Spatial, St3d, Stbl,
    Stco, Stsc, StscEntry, Stsd, Stss, Stsz, StszSamples, Stts, SttsEntry, Sv3d, Svhd, Tkhd, Trak,
    Url, Visual, Vmhd,
};

use super::VideoError;
use super::encode::EncodedFrame;
use super::level::H264Level;
use crate::output::StereoLayout;

/// The `svhd` metadata source: the program that wrote the spherical metadata.
pub const METADATA_SOURCE: &str = "omnicloud";

/// Media time units per frame; the track's timescale is `fps` times this, so rates like
/// 29.97 fps are exact.
const TICKS_PER_FRAME: u32 = 1000;

/// Movie header time units per second.
const MOVIE_TIMESCALE: u32 = 1000;

/// What the video track holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackInfo {
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// Frames per second.
    pub fps: f64,
    /// How the frames hold the eyes.
    pub stereo: StereoLayout,
}

/// Writes one video track into an MP4 file; see the module docs.
pub struct Mp4Writer {
    dest: PathBuf,
    track: TrackInfo,
    payload: BufWriter<File>,
    sizes: Vec<u32>,
    keyframes: Vec<u32>,
    payload_len: u64,
}

impl Mp4Writer {
    /// Starts an MP4 at `dest` (nothing appears there until [`finish`](Self::finish)).
    pub fn create(dest: &Path, track: TrackInfo) -> Result<Self, VideoError> {
        let dir = match dest.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        let payload = tempfile::tempfile_in(dir).map_err(|source| VideoError::Io {
            path: dir.to_path_buf(),
            action: "create a temporary file in",
            source,
        })?;
        Ok(Self {
            dest: dest.to_path_buf(),
            track,
            payload: BufWriter::new(payload),
            sizes: Vec::new(),
            keyframes: Vec::new(),
            payload_len: 0,
        })
    }

    /// Appends one frame (its NAL units, each behind a 4-byte length, as `avcC` declares).
    pub fn write_frame(&mut self, frame: &EncodedFrame) -> Result<(), VideoError> {
        let mut size = 0u64;
        for nal in &frame.nal_units {
            let len = u32::try_from(nal.len()).map_err(|_| self.error("a NAL unit over 4 GiB"))?;
            self.payload
                .write_all(&len.to_be_bytes())
                .and_then(|()| self.payload.write_all(nal))
                .map_err(|source| self.io(source))?;
            size += 4 + nal.len() as u64;
        }
        let size = u32::try_from(size).map_err(|_| self.error("a frame over 4 GiB"))?;
        self.sizes.push(size);
        if frame.keyframe {
            self.keyframes.push(self.sizes.len() as u32);
        }
        self.payload_len += u64::from(size);
        Ok(())
    }

    /// Writes the file with the stream's parameter sets and its level; returns its size.
    pub fn finish(self, sps: &[u8], pps: &[u8], level: H264Level) -> Result<u64, VideoError> {
        if self.sizes.is_empty() {
            return Err(self.error("no frames to write"));
        }
        let Self {
            dest,
            track,
            payload,
            sizes,
            keyframes,
            payload_len,
        } = self;
        let mut payload = payload.into_inner().map_err(|e| VideoError::Io {
            path: dest.clone(),
            action: "write the frames of",
            source: e.into_error(),
        })?;
        let mp4_error = |reason: String| VideoError::Mp4 {
            path: dest.clone(),
            reason,
        };
        let mut avcc = Avcc::new(sps, pps).map_err(|e| mp4_error(e.to_string()))?;
        avcc.avc_level_indication = avcc.avc_level_indication.max(level.idc);
        let ftyp = Ftyp {
            major_brand: FourCC::new(b"isom"),
            minor_version: 512,
            compatible_brands: [b"isom", b"iso2", b"avc1", b"mp41"]
                .map(FourCC::new)
                .to_vec(),
        };
        let ftyp_bytes = encode_box(&ftyp).map_err(&mp4_error)?;
        let mdat_header = encode_box(&Header {
            kind: FourCC::new(b"mdat"),
            size: Some(payload_len as usize),
        })
        .map_err(&mp4_error)?;
        // Offsets past 4 GiB need `co64`. The moov's size depends only on that choice, so a
        // draft with placeholder offsets tells where the samples start; the last one must
        // end below 4 GiB for `stco`, else lay out again with `co64`.
        let wide = 1u64 << 32;
        let table = |start: u64| sample_offsets(start, &sizes);
        let draft_len = |use_co64: bool| -> Result<u64, VideoError> {
            let draft = moov(
                &track,
                avcc.clone(),
                &sizes,
                &keyframes,
                &table(0),
                use_co64,
            );
            Ok(encode_box(&draft).map_err(&mp4_error)?.len() as u64)
        };
        let header_len = (ftyp_bytes.len() + mdat_header.len()) as u64;
        let mut use_co64 = false;
        let mut moov_len = draft_len(false)?;
        if header_len + moov_len + payload_len >= wide {
            use_co64 = true;
            moov_len = draft_len(true)?;
        }
        let start = header_len + moov_len;
        let moov_bytes = encode_box(&moov(
            &track,
            avcc,
            &sizes,
            &keyframes,
            &table(start),
            use_co64,
        ))
        .map_err(&mp4_error)?;
        if moov_bytes.len() as u64 != moov_len {
            return Err(mp4_error(
                "the index changed size while being laid out".into(),
            ));
        }
        payload
            .seek(SeekFrom::Start(0))
            .map_err(|source| VideoError::Io {
                path: dest.clone(),
                action: "read back the frames of",
                source,
            })?;
        crate::output::write_atomically(&dest, |w| {
            let io = |source| crate::output::OutputError::Io {
                path: dest.clone(),
                action: "writing",
                source,
            };
            w.write_all(&ftyp_bytes).map_err(io)?;
            w.write_all(&moov_bytes).map_err(io)?;
            w.write_all(&mdat_header).map_err(io)?;
            let copied = std::io::copy(&mut payload, w).map_err(io)?;
            if copied != payload_len {
                return Err(io(std::io::Error::other(format!(
                    "copied {copied} of {payload_len} bytes of frames"
                ))));
            }
            Ok(())
        })?;
        Ok(start + payload_len)
    }

    fn error(&self, reason: &str) -> VideoError {
        VideoError::Mp4 {
            path: self.dest.clone(),
            reason: reason.to_owned(),
        }
    }

    fn io(&self, source: std::io::Error) -> VideoError {
        VideoError::Io {
            path: self.dest.clone(),
            action: "write the frames of",
            source,
        }
    }
}

fn encode_box(value: &impl Encode) -> Result<Vec<u8>, String> {
    let mut buf = Vec::new();
    value.encode(&mut buf).map_err(|e| e.to_string())?;
    Ok(buf)
}

fn sample_offsets(start: u64, sizes: &[u32]) -> Vec<u64> {
    sizes
        .iter()
        .scan(start, |at, &size| {
            let offset = *at;
            *at += u64::from(size);
            Some(offset)
        })
        .collect()
}

/// The `st3d` stereo mode of a layout.
pub fn stereo_mode(stereo: StereoLayout) -> u8 {
    match stereo {
        StereoLayout::Mono => St3d::MONO,
        StereoLayout::TopBottom => St3d::TOP_BOTTOM,
    }
}

/// The Spherical Video V2 boxes: `st3d`, then `sv3d` (`svhd`, `proj` with `prhd` and a full
/// `equi`).
pub fn spatial_boxes(stereo: StereoLayout) -> Spatial {
    Spatial {
        st3d: Some(St3d {
            stereo_mode: stereo_mode(stereo),
        }),
        sv3d: Some(Sv3d {
            svhd: Some(Svhd {
                metadata_source: METADATA_SOURCE.into(),
            }),
            proj: Some(Proj {
                // The frames' centre is the camera's heading: no extra pose.
                prhd: Some(Prhd::default()),
                kind: Some(ProjKind::Equi(Equi::default())),
                unknown: vec![],
            }),
            unknown: vec![],
        }),
        ..Spatial::default()
    }
}

fn moov(
    track: &TrackInfo,
    avcc: Avcc,
    sizes: &[u32],
    keyframes: &[u32],
    offsets: &[u64],
    use_co64: bool,
) -> Moov {
    let frames = sizes.len() as u64;
    let timescale = (track.fps * f64::from(TICKS_PER_FRAME)).round() as u32;
    let media_duration = frames * u64::from(TICKS_PER_FRAME);
    let movie_duration =
        (media_duration * u64::from(MOVIE_TIMESCALE)).div_ceil(u64::from(timescale));
    let (width, height) = (track.width as u16, track.height as u16);
    let avc1 = Avc1 {
        visual: Visual {
            data_reference_index: 1,
            width,
            height,
            compressor: "".into(),
            ..Visual::default()
        },
        avcc,
        // sRGB primaries and transfer, BT.601 matrix, limited range: what the encoder's
        // RGB to YUV conversion does, and what the SPS says too.
        colr: Some(Colr::Nclx {
            colour_primaries: 1,
            transfer_characteristics: 13,
            matrix_coefficients: 6,
            full_range_flag: false,
        }),
        spatial: Some(Box::new(spatial_boxes(track.stereo))),
        ..Avc1::default()
    };
    let all_keyframes = keyframes.len() == sizes.len();
    let stbl = Stbl {
        stsd: Stsd {
            codecs: vec![Codec::Avc1(avc1)],
        },
        stts: Stts {
            entries: vec![SttsEntry {
                sample_count: sizes.len() as u32,
                sample_delta: TICKS_PER_FRAME,
            }],
        },
        // Without `stss` every sample is a sync sample.
        stss: (!all_keyframes).then(|| Stss {
            entries: keyframes.to_vec(),
        }),
        // One sample per chunk: each offset points at its frame.
        stsc: Stsc {
            entries: vec![StscEntry {
                first_chunk: 1,
                samples_per_chunk: 1,
                sample_description_index: 1,
            }],
        },
        stsz: Stsz {
            samples: StszSamples::Different {
                sizes: sizes.to_vec(),
            },
        },
        stco: (!use_co64).then(|| Stco {
            entries: offsets.iter().map(|&o| o as u32).collect(),
        }),
        co64: use_co64.then(|| Co64 {
            entries: offsets.to_vec(),
        }),
        ..Stbl::default()
    };
    Moov {
        mvhd: Mvhd {
            timescale: MOVIE_TIMESCALE,
            duration: movie_duration,
            rate: 1.into(),
            volume: 1.into(),
            next_track_id: 2,
            ..Mvhd::default()
        },
        trak: vec![Trak {
            tkhd: Tkhd {
                track_id: 1,
                duration: movie_duration,
                enabled: true,
                in_movie: true,
                width: width.into(),
                height: height.into(),
                ..Tkhd::default()
            },
            mdia: Mdia {
                mdhd: Mdhd {
                    timescale,
                    duration: media_duration,
                    language: "und".into(),
                    ..Mdhd::default()
                },
                hdlr: Hdlr {
                    handler: FourCC::new(b"vide"),
                    name: "omnicloud video".into(),
                },
                minf: Minf {
                    vmhd: Some(Vmhd::default()),
                    dinf: Dinf {
                        dref: Dref {
                            entries: vec![Url::default().into()],
                        },
                    },
                    stbl,
                    ..Minf::default()
                },
            },
            ..Trak::default()
        }],
        ..Moov::default()
    }
}

/// The projection `sv3d` declares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Projection {
    /// Equirectangular, with its crop bounds (all 0: the whole sphere).
    Equirect {
        /// Cropped rows at the top, as a 0.32 fraction of the height.
        top: u32,
        /// Cropped rows at the bottom.
        bottom: u32,
        /// Cropped columns at the left.
        left: u32,
        /// Cropped columns at the right.
        right: u32,
    },
    /// A cube map or a mesh.
    Other,
}

/// What an MP4's first video track says: the frames, the rate and the 360/VR metadata.
#[derive(Debug, Clone, PartialEq)]
pub struct VideoInfo {
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// Number of frames.
    pub frames: usize,
    /// Frames per second (frames over the track's duration).
    pub fps: f64,
    /// The `st3d` stereo mode (0 mono, 1 top-bottom, 2 left-right), if the file has one.
    pub stereo_mode: Option<u8>,
    /// The `sv3d` projection, if the file has one.
    pub projection: Option<Projection>,
    /// The `svhd` metadata source.
    pub metadata_source: Option<String>,
    /// The `avcC` level (ten times the level).
    pub level_idc: u8,
    /// Where each frame lies in the file: (offset, size).
    pub samples: Vec<(u64, u32)>,
    /// The sequence and picture parameter sets.
    pub parameter_sets: (Vec<u8>, Vec<u8>),
}

impl VideoInfo {
    /// The stereo layout the metadata states, or `None` for left-right and unknown modes.
    pub fn stereo(&self) -> Option<StereoLayout> {
        match self.stereo_mode {
            None | Some(St3d::MONO) => Some(StereoLayout::Mono),
            Some(St3d::TOP_BOTTOM) => Some(StereoLayout::TopBottom),
            Some(_) => None,
        }
    }
}

/// Reads an MP4's index (`moov`, wherever it lies; the frames are not read) and describes its
/// first H.264 video track.
pub fn read_video_info(path: &Path) -> Result<VideoInfo, VideoError> {
    let bad = |reason: String| VideoError::Mp4 {
        path: path.to_path_buf(),
        reason,
    };
    let file = File::open(path).map_err(|source| VideoError::Io {
        path: path.to_path_buf(),
        action: "open",
        source,
    })?;
    let mut reader = BufReader::new(file);
    let moov = loop {
        let header = <Option<Header> as ReadFrom>::read_from(&mut reader)
            .map_err(|e| bad(format!("not an MP4 file ({e})")))?
            .ok_or_else(|| bad("no moov box: not an MP4 file, or an unfinished one".into()))?;
        if header.kind == Moov::KIND {
            break Moov::read_atom(&header, &mut reader)
                .map_err(|e| bad(format!("unreadable moov box: {e}")))?;
        }
        let Some(size) = header.size else {
            return Err(bad("no moov box before the end of the file".into()));
        };
        reader
            .seek_relative(size as i64)
            .map_err(|e| bad(format!("cannot skip a {} box: {e}", header.kind)))?;
    };
    describe(&moov).map_err(bad)
}

fn describe(moov: &Moov) -> Result<VideoInfo, String> {
    let (trak, avc1) = moov
        .trak
        .iter()
        .find_map(|t| match t.mdia.minf.stbl.stsd.codecs.first() {
            Some(Codec::Avc1(a)) => Some((t, a)),
            _ => None,
        })
        .ok_or("no H.264 (avc1) video track")?;
    let stbl = &trak.mdia.minf.stbl;
    let sizes: Vec<u32> = match &stbl.stsz.samples {
        StszSamples::Identical { count, size } => vec![*size; *count as usize],
        StszSamples::Different { sizes } => sizes.clone(),
    };
    let chunk_offsets: Vec<u64> = match (&stbl.stco, &stbl.co64) {
        (Some(stco), _) => stco.entries.iter().map(|&o| u64::from(o)).collect(),
        (None, Some(co64)) => co64.entries.clone(),
        (None, None) => return Err("no chunk offsets (stco/co64)".into()),
    };
    let samples = sample_positions(&stbl.stsc.entries, &chunk_offsets, &sizes)?;
    let ticks: u64 = stbl
        .stts
        .entries
        .iter()
        .map(|e| u64::from(e.sample_count) * u64::from(e.sample_delta))
        .sum();
    let timescale = f64::from(trak.mdia.mdhd.timescale);
    let fps = if ticks > 0 {
        samples.len() as f64 * timescale / ticks as f64
    } else {
        0.0
    };
    let spatial = avc1.spatial.as_deref();
    let sv3d = spatial.and_then(|s| s.sv3d.as_ref());
    let projection = sv3d.and_then(|s| s.proj.as_ref()).map(|p| match &p.kind {
        Some(ProjKind::Equi(e)) => Projection::Equirect {
            top: e.projection_bounds_top,
            bottom: e.projection_bounds_bottom,
            left: e.projection_bounds_left,
            right: e.projection_bounds_right,
        },
        _ => Projection::Other,
    });
    let avcc = &avc1.avcc;
    let first = |sets: &[Vec<u8>]| sets.first().cloned().unwrap_or_default();
    Ok(VideoInfo {
        width: u32::from(avc1.visual.width),
        height: u32::from(avc1.visual.height),
        frames: samples.len(),
        fps,
        stereo_mode: spatial.and_then(|s| s.st3d.as_ref()).map(|s| s.stereo_mode),
        projection,
        metadata_source: sv3d
            .and_then(|s| s.svhd.as_ref())
            .map(|s| s.metadata_source.clone()),
        level_idc: avcc.avc_level_indication,
        samples,
        parameter_sets: (
            first(&avcc.sequence_parameter_sets),
            first(&avcc.picture_parameter_sets),
        ),
    })
}

/// Each sample's (offset, size) from the sample-to-chunk table.
fn sample_positions(
    stsc: &[StscEntry],
    chunk_offsets: &[u64],
    sizes: &[u32],
) -> Result<Vec<(u64, u32)>, String> {
    let mut out = Vec::with_capacity(sizes.len());
    let mut next = sizes.iter();
    for (i, &offset) in chunk_offsets.iter().enumerate() {
        let chunk = i as u32 + 1;
        let per_chunk = stsc
            .iter()
            .rev()
            .find(|e| e.first_chunk <= chunk)
            .map(|e| e.samples_per_chunk)
            .ok_or("the sample-to-chunk table (stsc) is empty")?;
        let mut at = offset;
        for _ in 0..per_chunk {
            let Some(&size) = next.next() else {
                return Err("more samples in chunks than sizes (stsz)".into());
            };
            out.push((at, size));
            at += u64::from(size);
        }
    }
    if out.len() != sizes.len() {
        return Err("fewer samples in chunks than sizes (stsz)".into());
    }
    Ok(out)
}

/// Reads the bytes of sample `index` of a described file.
pub fn read_sample(
    file: &mut (impl Read + Seek),
    info: &VideoInfo,
    index: usize,
) -> std::io::Result<Vec<u8>> {
    let (offset, size) = info.samples[index];
    file.seek(SeekFrom::Start(offset))?;
    let mut buf = vec![0; size as usize];
    file.read_exact(&mut buf)?;
    Ok(buf)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mp4_atom::Decode;

    fn track() -> TrackInfo {
        TrackInfo {
            width: 64,
            height: 64,
            fps: 30.0,
            stereo: StereoLayout::TopBottom,
        }
    }

    fn avcc() -> Avcc {
        Avcc::new(&[0x67, 66, 0xc0, 21], &[0x68, 0xce]).unwrap()
    }

    /// The index as written, read back through its own bytes.
    fn round_trip(offsets: &[u64], sizes: &[u32], keyframes: &[u32], co64: bool) -> VideoInfo {
        let written = moov(&track(), avcc(), sizes, keyframes, offsets, co64);
        let bytes = encode_box(&written).unwrap();
        describe(&Moov::decode(&mut bytes.as_slice()).unwrap()).unwrap()
    }

    #[test]
    fn samples_past_4_gib_are_indexed_with_co64() {
        let sizes = [1000, 2000, 3000];
        let offsets = sample_offsets(u64::from(u32::MAX) - 1500, &sizes);
        let info = round_trip(&offsets, &sizes, &[1, 3], true);
        let expected: Vec<(u64, u32)> = offsets.iter().copied().zip(sizes).collect();
        assert_eq!(info.samples, expected);
        assert_eq!((info.frames, info.fps), (3, 30.0));
        assert_eq!(info.stereo(), Some(StereoLayout::TopBottom));
    }

    #[test]
    fn the_spherical_boxes_follow_the_layout() {
        let sizes = [10];
        let info = round_trip(&[48], &sizes, &[1], false);
        assert_eq!((info.stereo_mode, info.samples[0]), (Some(1), (48, 10)));
        let mono = spatial_boxes(StereoLayout::Mono);
        assert_eq!(mono.st3d.unwrap().stereo_mode, St3d::MONO);
        assert_eq!(
            mono.sv3d.unwrap().svhd.unwrap().metadata_source,
            METADATA_SOURCE
        );
    }
}
