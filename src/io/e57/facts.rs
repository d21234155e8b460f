//! What an E57 file's XML says about its scans and images, for `info` and for the readers.

use super::pose::Pose;
use glam::DVec3;
use serde_json::{Value, json};
use std::fmt;

/// How a scan stores its point positions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coordinates {
    /// `cartesianX/Y/Z`.
    Cartesian,
    /// `sphericalRange/Azimuth/Elevation`.
    Spherical,
    /// Neither: the scan holds no position.
    None,
}

/// One scan (`data3D` entry).
#[derive(Debug, Clone, PartialEq)]
pub struct ScanInfo {
    /// Index among the file's scans, from 0.
    pub index: usize,
    /// Its `name`, when it has one.
    pub name: Option<String>,
    /// Its GUID.
    pub guid: Option<String>,
    /// Point records stored.
    pub points: u64,
    /// Pose from the scan's frame to the file's.
    pub pose: Pose,
    /// How positions are stored.
    pub coordinates: Coordinates,
    /// The record fields present, by their E57 names (`cartesianX`, `intensity`, ...).
    pub fields: Vec<String>,
    /// Colour stored.
    pub has_color: bool,
    /// Intensity stored.
    pub has_intensity: bool,
    /// Rows and columns of the scan's grid (from its index bounds), when it has one.
    pub grid: Option<(u64, u64)>,
    /// Bounds in the file's frame (the scan's stated local bounds, their corners posed), when
    /// it states them.
    pub bounds: Option<(DVec3, DVec3)>,
    /// Scanner make and model, when stated.
    pub sensor: Option<String>,
    /// Indices of the projected images (spherical, pinhole, cylindrical) taken with it.
    pub images: Vec<usize>,
}

/// How an image maps directions to pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageKind {
    /// Equirectangular over the whole sphere or part of it.
    Spherical,
    /// A pinhole camera.
    Pinhole,
    /// A cylinder around the image's vertical axis.
    Cylindrical,
    /// A picture with no projection (a preview).
    VisualReference,
}

impl ImageKind {
    /// Lower-case name used in text and JSON.
    pub fn name(self) -> &'static str {
        match self {
            ImageKind::Spherical => "spherical",
            ImageKind::Pinhole => "pinhole",
            ImageKind::Cylindrical => "cylindrical",
            ImageKind::VisualReference => "visual reference",
        }
    }
}

/// One image (`images2D` entry).
#[derive(Debug, Clone, PartialEq)]
pub struct ImageInfo {
    /// Index among the file's images, from 0.
    pub index: usize,
    /// Its `name`, when it has one.
    pub name: Option<String>,
    /// Its GUID.
    pub guid: Option<String>,
    /// Projection kind (the richest representation the image has).
    pub kind: ImageKind,
    /// Pixels across and down.
    pub size: (u32, u32),
    /// `"jpeg"` or `"png"`.
    pub encoding: &'static str,
    /// Pose from the image's camera frame to the file's.
    pub pose: Pose,
    /// Index of the scan it was taken with (matched by GUID), when it names one.
    pub scan: Option<usize>,
}

/// What an E57 file holds beyond the facts every format has.
#[derive(Debug, Clone, PartialEq)]
pub struct E57Info {
    /// The file's GUID.
    pub guid: String,
    /// The library that wrote it (`e57LibraryVersion`).
    pub writer: Option<String>,
    /// Every scan of the file.
    pub scans: Vec<ScanInfo>,
    /// The scans read (indices into `scans`): all, or those a `#scan:` pick names.
    pub selected: Vec<usize>,
    /// Every image of the file.
    pub images: Vec<ImageInfo>,
    /// Every point coloured from its station's images (`#color:image`), stored colour or not.
    pub color_from_images: bool,
}

/// Where a scan's point colours come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColourFrom {
    /// The colour the scan stores.
    Stored,
    /// The images of its station (grey intensity where none sees the point).
    Images,
    /// Nowhere: the scan has neither.
    Nothing,
}

impl E57Info {
    /// The scans read, in order.
    pub fn selected_scans(&self) -> impl Iterator<Item = &ScanInfo> {
        self.selected.iter().map(|&i| &self.scans[i])
    }

    /// Where `scan`'s colours come from: the images when asked (`#color:image`) or when it
    /// stores none, else its stored colour.
    pub fn colour_from(&self, scan: &ScanInfo) -> ColourFrom {
        if (self.color_from_images || !scan.has_color) && !scan.images.is_empty() {
            ColourFrom::Images
        } else if self.color_from_images {
            ColourFrom::Nothing
        } else if scan.has_color {
            ColourFrom::Stored
        } else {
            ColourFrom::Nothing
        }
    }

    /// Facts as JSON (the `e57` object of `info --json`).
    pub fn to_json(&self) -> Value {
        let xyz = |v: DVec3| json!([v.x, v.y, v.z]);
        let pose = |p: &Pose| {
            json!({
                "rotation_wxyz": [p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z],
                "translation": xyz(p.translation),
                "yaw_degrees": p.yaw_degrees(),
            })
        };
        json!({
            "guid": self.guid,
            "writer": self.writer,
            "selected_scans": self.selected,
            "color_from_images": self.color_from_images,
            "scans": self.scans.iter().map(|s| json!({
                "index": s.index,
                "name": s.name,
                "guid": s.guid,
                "points": s.points,
                "pose": pose(&s.pose),
                "coordinates": match s.coordinates {
                    Coordinates::Cartesian => Some("cartesian"),
                    Coordinates::Spherical => Some("spherical"),
                    Coordinates::None => None,
                },
                "fields": s.fields,
                "grid": s.grid.map(|(r, c)| json!({"rows": r, "columns": c})),
                "bounds": s.bounds.map(|(lo, hi)| json!({"min": xyz(lo), "max": xyz(hi)})),
                "sensor": s.sensor,
                "images": s.images,
            })).collect::<Vec<_>>(),
            "images": self.images.iter().map(|i| json!({
                "index": i.index,
                "name": i.name,
                "guid": i.guid,
                "projection": i.kind.name(),
                "width": i.size.0,
                "height": i.size.1,
                "encoding": i.encoding,
                "pose": pose(&i.pose),
                "scan": i.scan,
            })).collect::<Vec<_>>(),
        })
    }
}

fn label(index: usize, name: &Option<String>) -> String {
    match name {
        Some(n) => format!("{index} '{n}'"),
        None => index.to_string(),
    }
}

impl fmt::Display for E57Info {
    /// Lines for `omnicloud info`: the writer, then one line per scan and per image.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "written by:    {}",
            self.writer.as_deref().unwrap_or("not stated")
        )?;
        for s in &self.scans {
            let t = s.pose.translation;
            let picked = if self.selected.contains(&s.index) {
                ""
            } else {
                " (not read)"
            };
            write!(
                f,
                "\nscan {}{picked}: {} points, {}, at {:.3},{:.3},{:.3} heading {:.1}°",
                label(s.index, &s.name),
                s.points,
                match s.coordinates {
                    Coordinates::Cartesian => "cartesian",
                    Coordinates::Spherical => "spherical",
                    Coordinates::None => "no coordinates",
                },
                t.x,
                t.y,
                t.z,
                s.pose.yaw_degrees()
            )?;
            if let Some((r, c)) = s.grid {
                write!(f, ", grid {r} x {c}")?;
            }
            if let Some((lo, hi)) = s.bounds {
                write!(
                    f,
                    "\n    bounds x {:.3} .. {:.3}, y {:.3} .. {:.3}, z {:.3} .. {:.3}",
                    lo.x, hi.x, lo.y, hi.y, lo.z, hi.z
                )?;
            }
            write!(f, "\n    fields {}", s.fields.join(", "))?;
            if let Some(g) = &s.guid {
                write!(f, "\n    guid {g}")?;
            }
        }
        for i in &self.images {
            let t = i.pose.translation;
            write!(
                f,
                "\nimage {}: {} {} x {} {}, at {:.3},{:.3},{:.3} heading {:.1}°, {}",
                label(i.index, &i.name),
                i.kind.name(),
                i.size.0,
                i.size.1,
                i.encoding,
                t.x,
                t.y,
                t.z,
                i.pose.yaw_degrees(),
                match i.scan {
                    Some(s) => format!("from scan {s}"),
                    None => "no scan named".into(),
                }
            )?;
        }
        Ok(())
    }
}
