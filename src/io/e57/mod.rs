//! ASTM E57 terrestrial scans: every scan (`data3D`) posed into the file's frame, the
//! images (`images2D`) and their poses, read with the `e57` crate.
//!
//! A path may pick scans (`site.e57#scan:0,Hall`, see [`select`]); the points then come from
//! those scans only, in the order given.

mod facts;
pub mod photo;
pub mod pose;
pub mod select;
mod source;

pub use facts::{ColourFrom, Coordinates, E57Info, ImageInfo, ImageKind, ScanInfo};
pub use pose::Pose;
pub use select::{Parts, ScanPick, ScanSelection};

pub(crate) use source::E57Source;

use super::error::LoadError;
use super::guard::guarded;
use super::info::{AttributesPresent, ColorDepth, FileInfo, Format};
use glam::DVec3;
use std::io::{BufReader, Read, Seek};
use std::path::{Path, PathBuf};

/// The eight-byte signature every E57 file starts with.
pub const SIGNATURE: &[u8; 8] = b"ASTM-E57";

fn corrupt(path: &Path, detail: impl std::fmt::Display) -> LoadError {
    LoadError::CorruptHeader {
        path: path.to_path_buf(),
        format: "E57",
        detail: detail.to_string().replace('\n', " "),
    }
}

/// Opens `file` (the path without its `#` part) and checks its header against its length:
/// a file cut short says so before any section is read.
fn open_reader(
    shown: &Path,
    file: &Path,
) -> Result<e57::E57Reader<BufReader<std::fs::File>>, LoadError> {
    let mut f = std::fs::File::open(file).map_err(|e| LoadError::from_io(shown, e))?;
    let len = f
        .metadata()
        .map_err(|e| LoadError::from_io(shown, e))?
        .len();
    let header = e57::Header::read(&mut f).map_err(|e| corrupt(shown, e))?;
    if header.phys_length > len {
        return Err(corrupt(
            shown,
            format!(
                "the file is truncated: its header declares {} bytes but it holds {len}",
                header.phys_length
            ),
        ));
    }
    // The XML section is read whole into memory: its length must fit in the file first.
    if header.phys_xml_offset.saturating_add(header.xml_length) > len {
        return Err(corrupt(
            shown,
            format!(
                "the XML section ({} bytes at byte {}) runs past the end of the {len}-byte file",
                header.xml_length, header.phys_xml_offset
            ),
        ));
    }
    f.rewind().map_err(|e| LoadError::from_io(shown, e))?;
    let reader = guarded(shown, "reading the XML section", || {
        e57::E57Reader::new(BufReader::new(f)).map_err(|e| corrupt(shown, e))
    })?;
    check_sections(shown, file, &reader, len)?;
    Ok(reader)
}

/// Checks that each scan's points section (its 32-byte header at the scan's `fileOffset`)
/// lies inside the file: the `e57` crate reads packets without looking at the section's
/// length, so a length past the end would otherwise go unnoticed.
fn check_sections<T: Read + Seek>(
    shown: &Path,
    file: &Path,
    reader: &e57::E57Reader<T>,
    len: u64,
) -> Result<(), LoadError> {
    let page_size = reader.header().page_size;
    let mut f = std::fs::File::open(file).map_err(|e| LoadError::from_io(shown, e))?;
    for (index, pc) in reader.pointclouds().iter().enumerate() {
        let header = read_logical(&mut f, page_size, pc.file_offset, 32)
            .map_err(|e| LoadError::from_io(shown, e))?;
        let field = |at: usize| u64::from_le_bytes(header[at..at + 8].try_into().unwrap());
        let (section_length, data_offset) = (field(8), field(16));
        if pc.file_offset.saturating_add(section_length) > len || data_offset >= len {
            return Err(corrupt(
                shown,
                format!(
                    "the points section of scan {index} ({section_length} bytes at byte {}, \
                     data at byte {data_offset}) runs past the end of the {len}-byte file",
                    pc.file_offset
                ),
            ));
        }
    }
    Ok(())
}

/// `n` bytes of an E57 file's logical content from physical byte `at` on, skipping the
/// checksum that ends each page of `page_size` bytes.
fn read_logical(
    f: &mut std::fs::File,
    page_size: u64,
    mut at: u64,
    n: usize,
) -> std::io::Result<Vec<u8>> {
    const CHECKSUM: u64 = 4;
    let mut out = vec![0u8; n];
    let mut filled = 0;
    while filled < n {
        let data_end = (at / page_size) * page_size + page_size.saturating_sub(CHECKSUM);
        if at >= data_end {
            at = data_end + CHECKSUM;
            continue;
        }
        let take = ((data_end - at) as usize).min(n - filled);
        f.seek(std::io::SeekFrom::Start(at))?;
        f.read_exact(&mut out[filled..filled + take])?;
        filled += take;
        at += take as u64;
    }
    Ok(out)
}

/// The scans' and images' facts.
fn facts<T: Read + Seek>(reader: &e57::E57Reader<T>) -> E57Info {
    let clouds = reader.pointclouds();
    let mut scans: Vec<ScanInfo> = clouds
        .iter()
        .enumerate()
        .map(|(index, pc)| scan_info(index, pc))
        .collect();
    let images: Vec<ImageInfo> = reader
        .images()
        .iter()
        .enumerate()
        .map(|(index, img)| image_info(index, img, &scans))
        .collect();
    for image in &images {
        if let (Some(s), true) = (image.scan, image.kind != ImageKind::VisualReference) {
            scans[s].images.push(image.index);
        }
    }
    E57Info {
        guid: reader.guid().to_string(),
        writer: reader.library_version().map(str::to_string),
        selected: (0..scans.len()).collect(),
        scans,
        images,
        color_from_images: false,
    }
}

fn scan_info(index: usize, pc: &e57::PointCloud) -> ScanInfo {
    let pose = Pose::from_e57(pc.transform.as_ref());
    let coordinates = if pc.has_cartesian() {
        Coordinates::Cartesian
    } else if pc.has_spherical() {
        Coordinates::Spherical
    } else {
        Coordinates::None
    };
    let grid = pc.index_bounds.as_ref().and_then(|b| {
        let span = |lo: Option<i64>, hi: Option<i64>| {
            lo.zip(hi)
                .filter(|(lo, hi)| hi >= lo)
                .map(|(lo, hi)| (hi - lo) as u64 + 1)
        };
        span(b.row_min, b.row_max).zip(span(b.column_min, b.column_max))
    });
    let local = match coordinates {
        Coordinates::Cartesian => pc.cartesian_bounds.as_ref().and_then(|b| {
            Some((
                DVec3::new(b.x_min?, b.y_min?, b.z_min?),
                DVec3::new(b.x_max?, b.y_max?, b.z_max?),
            ))
        }),
        Coordinates::Spherical => pc
            .spherical_bounds
            .as_ref()
            .and_then(|b| b.range_max)
            .map(|r| (DVec3::splat(-r), DVec3::splat(r))),
        Coordinates::None => None,
    };
    let bounds = local
        .filter(|(lo, hi)| lo.is_finite() && hi.is_finite() && lo.cmple(*hi).all())
        .map(|(lo, hi)| posed_box(&pose, lo, hi));
    let sensor = [&pc.sensor_vendor, &pc.sensor_model]
        .iter()
        .filter_map(|s| s.as_deref())
        .filter(|s| !s.is_empty())
        .collect::<Vec<_>>()
        .join(" ");
    ScanInfo {
        index,
        name: pc.name.clone(),
        guid: pc.guid.clone(),
        points: pc.records,
        pose,
        coordinates,
        fields: pc.prototype.iter().map(|r| record_name(&r.name)).collect(),
        has_color: pc.has_color(),
        has_intensity: pc.has_intensity(),
        grid,
        bounds,
        sensor: (!sensor.is_empty()).then_some(sensor),
        images: Vec::new(),
    }
}

/// The E57 name of a record field (`cartesianX`, `intensity`, ...).
fn record_name(name: &e57::RecordName) -> String {
    let debug = format!("{name:?}");
    match name {
        e57::RecordName::Unknown { namespace, name } => format!("{namespace}:{name}"),
        _ => {
            let mut chars = debug.chars();
            chars
                .next()
                .map(|c| c.to_ascii_lowercase().to_string() + chars.as_str())
                .unwrap_or_default()
        }
    }
}

/// The box around the eight corners of a local box, posed.
fn posed_box(pose: &Pose, lo: DVec3, hi: DVec3) -> (DVec3, DVec3) {
    let mut out = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for i in 0..8 {
        let corner = DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        let p = pose.apply(corner);
        out = (out.0.min(p), out.1.max(p));
    }
    out
}

fn image_info(index: usize, img: &e57::Image, scans: &[ScanInfo]) -> ImageInfo {
    let (kind, size, blob) = match (&img.projection, &img.visual_reference) {
        (Some(e57::Projection::Spherical(s)), _) => (
            ImageKind::Spherical,
            (s.properties.width, s.properties.height),
            &s.blob,
        ),
        (Some(e57::Projection::Pinhole(p)), _) => (
            ImageKind::Pinhole,
            (p.properties.width, p.properties.height),
            &p.blob,
        ),
        (Some(e57::Projection::Cylindrical(c)), _) => (
            ImageKind::Cylindrical,
            (c.properties.width, c.properties.height),
            &c.blob,
        ),
        (None, Some(v)) => (
            ImageKind::VisualReference,
            (v.properties.width, v.properties.height),
            &v.blob,
        ),
        (None, None) => {
            return ImageInfo {
                index,
                name: img.name.clone(),
                guid: img.guid.clone(),
                kind: ImageKind::VisualReference,
                size: (0, 0),
                encoding: "none",
                pose: Pose::from_e57(img.transform.as_ref()),
                scan: None,
            };
        }
    };
    ImageInfo {
        index,
        name: img.name.clone(),
        guid: img.guid.clone(),
        kind,
        size,
        encoding: match blob.format {
            e57::ImageFormat::Png => "png",
            e57::ImageFormat::Jpeg => "jpeg",
        },
        pose: Pose::from_e57(img.transform.as_ref()),
        scan: img.pointcloud_guid.as_ref().and_then(|g| {
            scans
                .iter()
                .position(|s| s.guid.as_deref() == Some(g.as_str()))
        }),
    }
}

/// The file and the facts of `path` (which may carry a `#scan:` pick), with the pick
/// resolved into [`E57Info::selected`].
fn read_facts(
    path: &Path,
) -> Result<(PathBuf, e57::E57Reader<BufReader<std::fs::File>>, E57Info), LoadError> {
    let (file, parts) = select::split(path).map_err(|e| corrupt(path, e))?;
    let reader = open_reader(path, &file)?;
    let mut info = facts(&reader);
    info.color_from_images = parts.color_from_images;
    if let Some(selection) = parts.scans {
        let names: Vec<Option<String>> = info.scans.iter().map(|s| s.name.clone()).collect();
        info.selected = selection
            .resolve(&names)
            .map_err(|e| LoadError::NoSuchScan {
                path: file.clone(),
                detail: e,
            })?;
    }
    if info.color_from_images && info.selected_scans().all(|s| s.images.is_empty()) {
        return Err(LoadError::NoSuchScan {
            path: path.to_path_buf(),
            detail: "no scan read has an image to colour its points from (--color image)".into(),
        });
    }
    Ok((file, reader, info))
}

/// The E57 facts of `path` (scans, images, writer) without reading any point.
///
/// # Errors
/// Any [`LoadError`] about the file or its XML section.
pub fn read_e57_info(path: &Path) -> Result<E57Info, LoadError> {
    read_facts(path).map(|(_, _, info)| info)
}

/// Image `index` of an E57 file: its facts and its stored bytes (PNG or JPEG, as
/// [`ImageInfo::encoding`] says).
///
/// # Errors
/// The file's [`LoadError`]; [`LoadError::NoSuchScan`] for an index past the last image.
pub fn read_image(path: &Path, index: usize) -> Result<(ImageInfo, Vec<u8>), LoadError> {
    let (file, mut reader, info) = read_facts(path)?;
    let missing = || LoadError::NoSuchScan {
        path: file.clone(),
        detail: format!(
            "no image {index}: the file holds {} (numbered from 0)",
            info.images.len()
        ),
    };
    let image = reader.images().into_iter().nth(index).ok_or_else(missing)?;
    let blob = match (&image.projection, &image.visual_reference) {
        (Some(p), _) => photo::lens(p).1.data.clone(),
        (None, Some(v)) => v.blob.data.clone(),
        (None, None) => return Err(missing()),
    };
    let mut bytes = Vec::new();
    guarded(path, "reading an image", || {
        reader
            .blob(&blob, &mut bytes)
            .map(|_| ())
            .map_err(|e| corrupt(path, e))
    })?;
    Ok((info.images[index].clone(), bytes))
}

/// Image `index` of an E57 file decoded with its projection and pose, and the heading of
/// the station it was taken from (its scan's; its own pose's when it names no scan).
///
/// # Errors
/// As [`read_image`]; a picture without projection, or one that does not decode.
pub fn read_photo(path: &Path, index: usize) -> Result<(photo::Photo, f64), LoadError> {
    let (file, reader, info) = read_facts(path)?;
    let image = reader.images().into_iter().nth(index);
    let Some(projection) = image.as_ref().and_then(|i| i.projection.clone()) else {
        return Err(LoadError::NoSuchScan {
            path: file,
            detail: format!("image {index} has no projection to compare with"),
        });
    };
    let (_, bytes) = read_image(path, index)?;
    let pixels = image::load_from_memory(&bytes)
        .map_err(|e| corrupt(path, format!("image {index}: {e}")))?
        .to_rgb8();
    let facts = &info.images[index];
    let yaw = facts.scan.map_or(facts.pose.yaw_degrees(), |s| {
        info.scans[s].pose.yaw_degrees()
    });
    let lens = photo::lens(&projection).0;
    Ok((
        photo::Photo {
            pose: facts.pose,
            lens,
            pixels,
        },
        yaw,
    ))
}

/// Header facts of an E57 file (the picked scans' counts, bounds and attributes).
pub(crate) fn header_info(path: &Path) -> Result<FileInfo, LoadError> {
    read_facts(path).map(|(_, reader, info)| file_info(path, &reader, info))
}

fn file_info<T: Read + Seek>(path: &Path, reader: &e57::E57Reader<T>, info: E57Info) -> FileInfo {
    let picked: Vec<&ScanInfo> = info.selected_scans().collect();
    let sources: Vec<ColourFrom> = picked.iter().map(|s| info.colour_from(s)).collect();
    let rgb = !picked.is_empty()
        && (info.color_from_images || sources.iter().all(|s| *s != ColourFrom::Nothing));
    let from_images = rgb && sources.contains(&ColourFrom::Images);
    let intensity = !picked.is_empty() && picked.iter().all(|s| s.has_intensity);
    let bounds = picked
        .iter()
        .map(|s| s.bounds)
        .reduce(|a, b| a.zip(b).map(|(a, b)| (a.0.min(b.0), a.1.max(b.1))))
        .flatten();
    let header = reader.header();
    FileInfo {
        path: path.to_path_buf(),
        format: Format::E57,
        version: format!("{}.{}", header.major, header.minor),
        point_format: None,
        point_count: picked.iter().map(|s| s.points).sum(),
        bounds,
        attributes: AttributesPresent {
            rgb,
            intensity,
            ..AttributesPresent::default()
        },
        color_depth: if from_images {
            ColorDepth::FromImages
        } else if rgb {
            ColorDepth::Normalised
        } else {
            ColorDepth::None
        },
        ignored_properties: Vec::new(),
        records_in_file: None,
        las: None,
        e57: Some(info),
    }
}

/// Opens an E57 file for its points (all scans, or those its path picks).
pub(crate) fn open(path: &Path) -> Result<(FileInfo, E57Source), LoadError> {
    let (file, reader, info) = read_facts(path)?;
    let file_info = file_info(path, &reader, info);
    let source = E57Source::new(&file, &file_info);
    Ok((file_info, source))
}
