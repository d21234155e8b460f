//! What an omnicloud image file says it holds: its projection and which eyes it stores, one
//! line of text (`projection=fisheye:180 eyes=mono`) under the key [`KEY`] in every PNG
//! (`tEXt`), JPEG (`COM`) and EXR (a text attribute) it writes. Readers of our own files
//! (`compare`, `view`) trust it over the image's shape: a square image can be a 180° fisheye
//! as well as a top-bottom ODS pair, and a 2:1 image a Hammer map as well as an equirect.

use std::fmt;
use std::fs::File;
use std::io::{BufReader, Read};
use std::path::Path;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::{ImageFormat, OutputError};
use crate::projection::Projection;

/// The PNG keyword, EXR attribute name and JPEG comment prefix of the description.
pub const KEY: &str = "omnicloud";

/// How each frame file of a tour or video holds the eyes: what `tour` writes into its
/// manifest and `video` reads from it or from the frames.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StereoLayout {
    /// One equirectangular panorama (2:1).
    Mono,
    /// An ODS pair, left eye on top (DESIGN §6; 1:1).
    TopBottom,
}

impl StereoLayout {
    /// The name the command line, the manifest and reports use.
    pub fn name(self) -> &'static str {
        StoredEyes::from(self).name()
    }
}

impl From<StereoLayout> for StoredEyes {
    fn from(layout: StereoLayout) -> Self {
        match layout {
            StereoLayout::Mono => StoredEyes::Mono,
            StereoLayout::TopBottom => StoredEyes::TopBottom,
        }
    }
}

/// Which eyes a file stores.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StoredEyes {
    /// One mono image.
    Mono,
    /// The left eye of a stereo render written as separate files.
    Left,
    /// The right eye of a stereo render written as separate files.
    Right,
    /// Both eyes, left on top (DESIGN §6); in EXR, a multi-view file.
    TopBottom,
}

impl StoredEyes {
    /// The word the description uses.
    pub fn name(self) -> &'static str {
        match self {
            StoredEyes::Mono => "mono",
            StoredEyes::Left => "left",
            StoredEyes::Right => "right",
            StoredEyes::TopBottom => "top-bottom",
        }
    }

    /// Number of eye images stacked in the file.
    pub fn count(self) -> u32 {
        if self == StoredEyes::TopBottom { 2 } else { 1 }
    }
}

impl FromStr for StoredEyes {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        [
            StoredEyes::Mono,
            StoredEyes::Left,
            StoredEyes::Right,
            StoredEyes::TopBottom,
        ]
        .into_iter()
        .find(|e| e.name() == s)
        .ok_or_else(|| format!("eyes must be mono, left, right or top-bottom, got `{s}`"))
    }
}

/// A file's description.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImageDescription {
    /// The projection of each eye image.
    pub projection: Projection,
    /// The eyes stored.
    pub eyes: StoredEyes,
    /// Metres per unit of the scan's coordinates (0.3048 for a scan in feet): the scale the
    /// image's depths, and the IPD that made its stereo, are measured in. `None` when the
    /// scan declares no unit of length.
    pub metres_per_unit: Option<f64>,
}

impl ImageDescription {
    /// True for a full 360° x 180° equirect, where latitude bands and the seam mean something.
    pub fn is_panorama(&self) -> bool {
        self.projection.is_full_equirect()
    }
}

/// `projection=P eyes=E metres_per_unit=M`, `P` as `--projection` parses it, the scale
/// only when known.
impl fmt::Display for ImageDescription {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "projection={} eyes={}",
            self.projection,
            self.eyes.name()
        )?;
        match self.metres_per_unit {
            Some(m) => write!(f, " metres_per_unit={m}"),
            None => Ok(()),
        }
    }
}

/// Parses what [`fmt::Display`] writes; fields in any order, projection and eyes required,
/// no others.
impl FromStr for ImageDescription {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let (mut projection, mut eyes, mut metres_per_unit) = (None, None, None);
        for field in s.split_whitespace() {
            let (key, value) = field
                .split_once('=')
                .ok_or_else(|| format!("expected KEY=VALUE, got `{field}`"))?;
            match key {
                "projection" => projection = Some(value.parse::<Projection>()?),
                "eyes" => eyes = Some(value.parse::<StoredEyes>()?),
                "metres_per_unit" => {
                    metres_per_unit = Some(
                        value
                            .parse::<f64>()
                            .ok()
                            .filter(|m| m.is_finite() && *m > 0.0)
                            .ok_or_else(|| {
                                format!("metres_per_unit must be a positive number, got `{value}`")
                            })?,
                    )
                }
                _ => return Err(format!("unknown field `{key}`")),
            }
        }
        match (projection, eyes) {
            (Some(projection), Some(eyes)) => Ok(ImageDescription {
                projection,
                eyes,
                metres_per_unit,
            }),
            (None, _) => Err("no projection= field".into()),
            (_, None) => Err("no eyes= field".into()),
        }
    }
}

/// The description `path` carries (by its extension: PNG, JPEG, EXR), read from its header;
/// `None` for a file without one (another program's, or a VR photo, which its own XMP
/// describes).
///
/// # Errors
/// The file cannot be opened or its header read, or its description does not parse.
pub fn read_description(path: &Path) -> Result<Option<ImageDescription>, OutputError> {
    let text = match ImageFormat::from_path(path)? {
        ImageFormat::Png => png_text(path)?,
        ImageFormat::Jpeg => jpeg_comment(path)?,
        ImageFormat::Exr => exr_attribute(path)?,
        ImageFormat::VrJpeg => None,
    };
    text.map(|text| {
        text.parse().map_err(|reason| OutputError::BadDescription {
            path: path.to_path_buf(),
            text,
            reason,
        })
    })
    .transpose()
}

fn open(path: &Path) -> Result<BufReader<File>, OutputError> {
    File::open(path)
        .map(BufReader::new)
        .map_err(|source| OutputError::Io {
            path: path.to_path_buf(),
            action: "opening",
            source,
        })
}

fn metadata_error(path: &Path, reason: impl fmt::Display) -> OutputError {
    OutputError::Metadata {
        path: path.to_path_buf(),
        reason: reason.to_string(),
    }
}

/// The `tEXt` chunk [`KEY`] ahead of a PNG's image data.
fn png_text(path: &Path) -> Result<Option<String>, OutputError> {
    let reader = png::Decoder::new(open(path)?)
        .read_info()
        .map_err(|e| metadata_error(path, e))?;
    Ok(reader
        .info()
        .uncompressed_latin1_text
        .iter()
        .find(|t| t.keyword == KEY)
        .map(|t| t.text.clone()))
}

/// The comment segment starting with [`KEY`] and a space, among a JPEG's segments ahead of its
/// image data. A header that does not parse holds no description: the image decoder reports
/// what is wrong with the file.
fn jpeg_comment(path: &Path) -> Result<Option<String>, OutputError> {
    let mut file = open(path)?;
    let prefix = format!("{KEY} ");
    let mut read = |bytes: &mut [u8]| file.read_exact(bytes).is_ok();
    let mut soi = [0u8; 2];
    if !read(&mut soi) || soi != [0xFF, 0xD8] {
        return Ok(None);
    }
    let mut marker = [0u8; 2];
    while read(&mut marker) && marker[0] == 0xFF {
        // Fill bytes may precede a marker.
        while marker[1] == 0xFF {
            let mut next = [0u8; 1];
            if !read(&mut next) {
                return Ok(None);
            }
            marker[1] = next[0];
        }
        // Start of scan: the image data follows; the header ends.
        if marker[1] == 0xDA {
            break;
        }
        let mut len = [0u8; 2];
        if !read(&mut len) || u16::from_be_bytes(len) < 2 {
            break;
        }
        let mut body = vec![0u8; usize::from(u16::from_be_bytes(len) - 2)];
        if !read(&mut body) {
            break;
        }
        if marker[1] == 0xFE
            && let Some(text) = std::str::from_utf8(&body)
                .ok()
                .and_then(|t| t.strip_prefix(&prefix))
        {
            return Ok(Some(text.to_owned()));
        }
    }
    Ok(None)
}

/// The text attribute [`KEY`] of an EXR's first layer.
fn exr_attribute(path: &Path) -> Result<Option<String>, OutputError> {
    let meta = exr::meta::MetaData::read_from_buffered(open(path)?, false)
        .map_err(|e| metadata_error(path, e))?;
    let Some(header) = meta.headers.first() else {
        return Ok(None);
    };
    Ok(
        match header
            .own_attributes
            .other
            .get(&exr::prelude::Text::from(KEY))
        {
            Some(exr::meta::attribute::AttributeValue::Text(t)) => Some(t.to_string()),
            _ => None,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn descriptions_read_back_as_written() {
        for projection in ["equirect", "fisheye:180", "equirect:120,60", "hammer"] {
            for eyes in ["mono", "left", "right", "top-bottom"] {
                let text = format!("projection={projection} eyes={eyes}");
                let d: ImageDescription = text.parse().unwrap();
                assert_eq!(d.to_string(), text);
            }
        }
        let feet = "projection=equirect eyes=top-bottom metres_per_unit=0.3048";
        let d: ImageDescription = feet.parse().unwrap();
        assert_eq!(d.metres_per_unit, Some(0.3048));
        assert_eq!(d.to_string(), feet);
        let d: ImageDescription = "eyes=mono  projection=cylindrical:90".parse().unwrap();
        assert_eq!(d.metres_per_unit, None);
        assert_eq!(d.projection, Projection::Cylindrical { vfov_deg: 90.0 });
        assert!(!d.is_panorama());
        assert!(
            "projection=equirect eyes=top-bottom"
                .parse::<ImageDescription>()
                .unwrap()
                .is_panorama()
        );
    }

    #[test]
    fn bad_descriptions_say_what_is_wrong() {
        let err = |s: &str| s.parse::<ImageDescription>().unwrap_err();
        assert!(err("projection=equirect").contains("no eyes"));
        assert!(err("eyes=mono").contains("no projection"));
        assert!(err("projection=globe eyes=mono").contains("unknown projection"));
        assert!(err("projection=equirect eyes=both").contains("top-bottom"));
        assert!(err("projection=equirect eyes=mono extra").contains("KEY=VALUE"));
        assert!(err("projection=equirect eyes=mono tint=red").contains("unknown field `tint`"));
        for bad in ["0", "-1", "nan", "foot"] {
            let e = err(&format!(
                "projection=equirect eyes=mono metres_per_unit={bad}"
            ));
            assert!(
                e.contains("metres_per_unit must be a positive number"),
                "{e}"
            );
        }
    }
}
