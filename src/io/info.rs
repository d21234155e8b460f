//! What a point-cloud file's header says: format, version, point count, bounds, attributes.

use glam::DVec3;
use std::fmt;
use std::path::PathBuf;

/// File format and its variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Uncompressed LAS.
    Las,
    /// LASzip-compressed LAS.
    Laz,
    /// PLY with the given encoding.
    Ply(PlyEncoding),
}

/// How a PLY file stores its payload.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlyEncoding {
    /// Text, one element per line.
    Ascii,
    /// Binary, little endian.
    BinaryLittleEndian,
    /// Binary, big endian.
    BinaryBigEndian,
}

/// How the file stores colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColorDepth {
    /// No colour.
    None,
    /// 8 bits per channel (PLY `uchar`).
    Bits8,
    /// 16-bit fields (LAS RGB, PLY `ushort`); whether the values use 0–255 or 0–65535 is decided
    /// from the points when reading (see [`crate::io::ColorScale`]).
    Bits16,
    /// Floating point in 0–1 (PLY `float`/`double`).
    Float,
}

/// Which per-point attributes the file carries.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct AttributesPresent {
    /// Red, green, blue.
    pub rgb: bool,
    /// Intensity (always present in LAS, even when every value is 0).
    pub intensity: bool,
    /// ASPRS classification (always present in LAS).
    pub classification: bool,
    /// Per-point sphere radius (PLY `radius`).
    pub radius: bool,
}

/// Header facts about one point-cloud file, read without touching the point data.
#[derive(Debug, Clone, PartialEq)]
pub struct FileInfo {
    /// The file.
    pub path: PathBuf,
    /// Format and variant.
    pub format: Format,
    /// Format version, e.g. "1.2" (LAS) or "1.0" (PLY).
    pub version: String,
    /// LAS point data record format (0–10); `None` for PLY.
    pub point_format: Option<u8>,
    /// Point count declared by the header.
    pub point_count: u64,
    /// `(min, max)` in file coordinates from the LAS header. Always `None` for PLY: its header
    /// holds no bounds and computing them would mean reading every point.
    pub bounds: Option<(DVec3, DVec3)>,
    /// Attributes present.
    pub attributes: AttributesPresent,
    /// Colour storage.
    pub color_depth: ColorDepth,
    /// PLY vertex properties that are read past and ignored (e.g. normals); empty for LAS.
    pub ignored_properties: Vec<String>,
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Format::Las => f.write_str("LAS"),
            Format::Laz => f.write_str("LAZ (LASzip-compressed LAS)"),
            Format::Ply(PlyEncoding::Ascii) => f.write_str("PLY (ascii)"),
            Format::Ply(PlyEncoding::BinaryLittleEndian) => {
                f.write_str("PLY (binary little endian)")
            }
            Format::Ply(PlyEncoding::BinaryBigEndian) => f.write_str("PLY (binary big endian)"),
        }
    }
}

impl fmt::Display for ColorDepth {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ColorDepth::None => "none",
            ColorDepth::Bits8 => "8-bit",
            ColorDepth::Bits16 => "16-bit fields (scaled to 8 bits as the values need)",
            ColorDepth::Float => "floating point (0-1)",
        })
    }
}

/// `1234567` as `1,234,567`.
fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

impl fmt::Display for FileInfo {
    /// What `omnicloud info FILE` prints: one item per line.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "file:          {}", self.path.display())?;
        writeln!(f, "format:        {}", self.format)?;
        writeln!(f, "version:       {}", self.version)?;
        match self.point_format {
            Some(n) => writeln!(f, "point format:  {n}")?,
            None => writeln!(f, "point format:  n/a")?,
        }
        writeln!(f, "points:        {}", thousands(self.point_count))?;
        match self.bounds {
            Some((lo, hi)) => {
                let size = hi - lo;
                writeln!(
                    f,
                    "bounds:        x {:.3} .. {:.3}, y {:.3} .. {:.3}, z {:.3} .. {:.3} (size {:.3} x {:.3} x {:.3} m)",
                    lo.x, hi.x, lo.y, hi.y, lo.z, hi.z, size.x, size.y, size.z
                )?;
            }
            None => writeln!(f, "bounds:        not in the header")?,
        }
        let a = self.attributes;
        let names: Vec<&str> = [
            (a.rgb, "rgb"),
            (a.intensity, "intensity"),
            (a.classification, "classification"),
            (a.radius, "radius"),
        ]
        .iter()
        .filter(|(present, _)| *present)
        .map(|(_, name)| *name)
        .collect();
        if names.is_empty() {
            writeln!(f, "attributes:    none")?;
        } else {
            writeln!(f, "attributes:    {}", names.join(", "))?;
        }
        write!(f, "colour:        {}", self.color_depth)?;
        if !self.ignored_properties.is_empty() {
            write!(f, "\nignored:       {}", self.ignored_properties.join(", "))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thousands_groups_digits() {
        assert_eq!(thousands(0), "0");
        assert_eq!(thousands(999), "999");
        assert_eq!(thousands(1000), "1,000");
        assert_eq!(thousands(341_989), "341,989");
        assert_eq!(thousands(12_345_678), "12,345,678");
    }

    #[test]
    fn display_has_one_item_per_line() {
        let info = FileInfo {
            path: PathBuf::from("a.las"),
            format: Format::Las,
            version: "1.2".into(),
            point_format: Some(3),
            point_count: 1065,
            bounds: Some((DVec3::ZERO, DVec3::ONE)),
            attributes: AttributesPresent {
                rgb: true,
                intensity: true,
                classification: true,
                radius: false,
            },
            color_depth: ColorDepth::Bits16,
            ignored_properties: vec![],
        };
        let text = info.to_string();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 8, "{text}");
        assert!(lines[4].ends_with("1,065"));
        assert!(lines[6].ends_with("rgb, intensity, classification"));
    }
}
