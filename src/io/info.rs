//! What a point-cloud file's header says: format, version, point count, bounds, attributes,
//! and for LAS the scale, offset, VLRs and coordinate system. Printed by `omnicloud info`, as
//! text ([`fmt::Display`]) or JSON ([`FileInfo::to_json`]).

use glam::DVec3;
use serde_json::{Value, json};
use std::fmt;
use std::path::PathBuf;

use super::units::{Across, CrsUnits};
use super::wkt::{self, COMPOUND, VERTICAL, WktNode};

/// File format and its variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Uncompressed LAS.
    Las,
    /// LASzip-compressed LAS.
    Laz,
    /// PLY with the given encoding.
    Ply(PlyEncoding),
    /// ASTM E57 (scans with poses, and their images).
    E57,
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
    /// Scaled to 0–1 by the limits the file states (E57), then to 8 bits.
    Normalised,
    /// Taken from the scanner's images of each point's station (E57).
    FromImages,
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
    /// Return number and number of returns (always present in LAS).
    pub returns: bool,
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
    /// Whole point records the file's bytes hold, for formats with fixed-size records
    /// (uncompressed LAS); below `point_count` when the file is truncated.
    pub records_in_file: Option<u64>,
    /// LAS header facts (`None` for PLY).
    pub las: Option<LasHeaderInfo>,
    /// E57 scans, images and writer (`None` for other formats).
    pub e57: Option<super::e57::E57Info>,
}

/// What a LAS header says beyond the facts every format has.
#[derive(Debug, Clone, PartialEq)]
pub struct LasHeaderInfo {
    /// Coordinate scale factors (x, y, z): the stored integers' unit.
    pub scale: DVec3,
    /// Coordinate offsets (x, y, z).
    pub offset: DVec3,
    /// System identifier (the hardware or process that made the points).
    pub system_identifier: String,
    /// Generating software.
    pub generating_software: String,
    /// File creation day as YYYY-MM-DD, when the header gives one.
    pub creation_date: Option<String>,
    /// File source id (a flight line or tile number).
    pub file_source_id: u16,
    /// Bytes per point record (extra bytes included).
    pub record_length: u16,
    /// Point counts by return number as the header declares them: index 0 is return 1;
    /// trailing zeros left out.
    pub points_by_return: Vec<u64>,
    /// The variable-length records, extended ones last.
    pub vlrs: Vec<VlrInfo>,
    /// The coordinate system the VLRs declare.
    pub crs: Option<Crs>,
}

/// One (extended) variable-length record of a LAS header.
#[derive(Debug, Clone, PartialEq)]
pub struct VlrInfo {
    /// User id, e.g. `LASF_Projection`.
    pub user_id: String,
    /// Record id, e.g. 2112 (WKT) or 34735 (GeoTIFF keys).
    pub record_id: u16,
    /// Description.
    pub description: String,
    /// Payload size, bytes.
    pub bytes: u64,
    /// An extended VLR (after the points).
    pub extended: bool,
}

/// Where a coordinate system came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CrsSource {
    /// The OGC WKT VLR (`LASF_Projection` 2112).
    Wkt,
    /// The GeoTIFF key directory (`LASF_Projection` 34735, with 34736/34737).
    GeoTiff,
}

/// A coordinate system as a LAS file declares it. Nothing is looked up: the EPSG codes and
/// names are those the file states.
#[derive(Debug, Clone, PartialEq)]
pub struct Crs {
    /// WKT or GeoTIFF keys.
    pub source: CrsSource,
    /// The system's name: the WKT's root name (`PROJCS["NAD83 / Oregon GIC Lambert (ft)"`),
    /// or the GeoTIFF citation key.
    pub name: Option<String>,
    /// EPSG code of the (horizontal) system: the WKT root's `AUTHORITY["EPSG",..]`/`ID`, that
    /// of a compound system's horizontal part, or the GeoTIFF projected (else geographic) key.
    pub epsg: Option<u32>,
    /// EPSG code of the vertical system, when one is declared.
    pub vertical_epsg: Option<u32>,
    /// The WKT text (WKT source only).
    pub wkt: Option<String>,
    /// The units of x, y and z it declares.
    pub units: CrsUnits,
}

/// One GeoTIFF key's value, as [`Crs::from_geotiff_keys`] reads it.
#[derive(Debug, Clone, PartialEq)]
pub enum GeoKey {
    /// A SHORT value (codes).
    Code(u16),
    /// An ASCII value (citations).
    Text(String),
    /// Anything else (doubles).
    Other,
}

impl Crs {
    /// The system a WKT text declares: its root name and EPSG authority; for a compound
    /// system, the horizontal part's EPSG code when the root has none, and the vertical
    /// part's. Text that does not parse keeps only the WKT.
    pub fn from_wkt(text: &str) -> Crs {
        let mut crs = Crs {
            source: CrsSource::Wkt,
            name: None,
            epsg: None,
            vertical_epsg: None,
            wkt: Some(text.to_string()),
            units: CrsUnits::default(),
        };
        let Some(root) = wkt::parse(text) else {
            return crs;
        };
        crs.units = CrsUnits::from_wkt(&root);
        crs.name = root.name().map(str::to_string);
        crs.epsg = root.epsg();
        if COMPOUND.contains(&root.keyword.as_str()) {
            let (vertical, horizontal): (Vec<&WktNode>, Vec<&WktNode>) = root
                .children()
                .filter(|c| c.keyword != "AUTHORITY" && c.keyword != "ID")
                .partition(|c| VERTICAL.contains(&c.keyword.as_str()));
            crs.epsg = crs
                .epsg
                .or_else(|| horizontal.first().and_then(|h| h.epsg()));
            crs.vertical_epsg = vertical.first().and_then(|v| v.epsg());
        } else if VERTICAL.contains(&root.keyword.as_str()) {
            crs.vertical_epsg = crs.epsg.take();
        }
        crs
    }

    /// The system GeoTIFF keys declare, `key(id)` giving each key's value: EPSG from
    /// ProjectedCRSGeoKey (3072), else GeodeticCRSGeoKey (2048), vertical from 4096 (codes
    /// 1024–32766 are EPSG's; 32767 is user-defined); the name from the projected, geodetic
    /// or general citation (3073, 2049, 1026).
    pub fn from_geotiff_keys(key: impl Fn(u16) -> Option<GeoKey>) -> Crs {
        let code = |id| match key(id) {
            Some(GeoKey::Code(v)) if (1024..=32766).contains(&v) => Some(u32::from(v)),
            _ => None,
        };
        let name = [3073, 2049, 1026].into_iter().find_map(|id| match key(id) {
            Some(GeoKey::Text(t)) => {
                let t = t.trim_end_matches(['|', '\0', ' ']).replace('|', "; ");
                (!t.is_empty()).then_some(t)
            }
            _ => None,
        });
        Crs {
            source: CrsSource::GeoTiff,
            name,
            epsg: code(3072).or_else(|| code(2048)),
            vertical_epsg: code(4096),
            wkt: None,
            units: CrsUnits::from_geotiff_keys(|id| match key(id) {
                Some(GeoKey::Code(v)) => Some(v),
                _ => None,
            }),
        }
    }
}

/// The ASPRS name of a classification code (LAS 1.4 R15, Table 17; codes 8 and 12 were
/// "model key-point" and "overlap" before LAS 1.4).
pub fn asprs_class_name(code: u8) -> &'static str {
    match code {
        0 => "never classified",
        1 => "unclassified",
        2 => "ground",
        3 => "low vegetation",
        4 => "medium vegetation",
        5 => "high vegetation",
        6 => "building",
        7 => "low point (noise)",
        8 => "model key-point (reserved in 1.4)",
        9 => "water",
        10 => "rail",
        11 => "road surface",
        12 => "overlap (reserved in 1.4)",
        13 => "wire - guard (shield)",
        14 => "wire - conductor (phase)",
        15 => "transmission tower",
        16 => "wire-structure connector",
        17 => "bridge deck",
        18 => "high noise",
        19 => "overhead structure",
        20 => "ignored ground",
        21 => "snow",
        22 => "temporal exclusion",
        23..=63 => "reserved",
        _ => "user definable",
    }
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
            Format::E57 => f.write_str("E57 (ASTM E2807)"),
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
            ColorDepth::Normalised => "scaled by the file's colour limits to 8 bits",
            ColorDepth::FromImages => "from the scanner's images of each station",
        })
    }
}

/// A header number to 12 significant digits, trailing zeros dropped: scales are stored in
/// binary, so 0.000001 reads back as 0.0000010000000000000002.
fn short(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !v.is_finite() {
        return v.to_string();
    }
    let decimals = (11 - v.abs().log10().floor() as i32).clamp(0, 24) as usize;
    let text = format!("{v:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
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

impl fmt::Display for Crs {
    /// `NAD83 / Oregon GIC Lambert (ft) (EPSG:2992, vertical EPSG:6360; from the WKT VLR)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut codes = Vec::new();
        if let Some(e) = self.epsg {
            codes.push(format!("EPSG:{e}"));
        }
        if let Some(e) = self.vertical_epsg {
            codes.push(format!("vertical EPSG:{e}"));
        }
        codes.push(
            match self.source {
                CrsSource::Wkt => "from the WKT VLR",
                CrsSource::GeoTiff => "from GeoTIFF keys",
            }
            .to_string(),
        );
        write!(
            f,
            "{} ({})",
            self.name.as_deref().unwrap_or("unnamed"),
            codes.join(", ")
        )
    }
}

impl FileInfo {
    /// Attribute names present, in a fixed order.
    fn attribute_names(&self) -> Vec<&'static str> {
        let a = self.attributes;
        [
            (a.rgb, "rgb"),
            (a.intensity, "intensity"),
            (a.classification, "classification"),
            (a.returns, "returns"),
            (a.radius, "radius"),
        ]
        .iter()
        .filter(|(present, _)| *present)
        .map(|(_, name)| *name)
        .collect()
    }

    /// The symbol of the unit lengths in the file's frame are in ([`CrsUnits::size_unit`]),
    /// `file units` when x, y and z are not in one.
    pub fn length_symbol(&self) -> String {
        self.units()
            .size_unit()
            .unwrap_or_else(|| "file units".into())
    }

    /// The units the file's coordinate system declares (none known without one).
    pub fn units(&self) -> CrsUnits {
        self.las
            .as_ref()
            .and_then(|l| l.crs.as_ref())
            .map(|c| c.units.clone())
            .unwrap_or_default()
    }

    /// True when the file's bytes hold fewer point records than the header declares.
    pub fn is_truncated(&self) -> bool {
        self.records_in_file.is_some_and(|n| n < self.point_count)
    }

    /// The header facts as JSON, for scripts. Field names are stable (docs/guide/info.md,
    /// `info --json`); fields a format lacks are `null`.
    pub fn to_json(&self) -> Value {
        let (format, encoding) = match self.format {
            Format::Las => ("LAS", None),
            Format::Laz => ("LAZ", None),
            Format::Ply(e) => (
                "PLY",
                Some(match e {
                    PlyEncoding::Ascii => "ascii",
                    PlyEncoding::BinaryLittleEndian => "binary_little_endian",
                    PlyEncoding::BinaryBigEndian => "binary_big_endian",
                }),
            ),
            Format::E57 => ("E57", None),
        };
        let xyz = |v: DVec3| json!([v.x, v.y, v.z]);
        let las = self.las.as_ref();
        json!({
            "file": self.path.display().to_string(),
            "format": format,
            "encoding": encoding,
            "version": self.version,
            "point_format": self.point_format,
            "point_count": self.point_count,
            "records_in_file": self.records_in_file,
            "truncated": self.is_truncated(),
            "bounds": self.bounds.map(|(lo, hi)| json!({"min": xyz(lo), "max": xyz(hi)})),
            "scale": las.map(|l| xyz(l.scale)),
            "offset": las.map(|l| xyz(l.offset)),
            "crs": las.and_then(|l| l.crs.as_ref()).map(|c| json!({
                "source": match c.source { CrsSource::Wkt => "wkt", CrsSource::GeoTiff => "geotiff" },
                "name": c.name,
                "epsg": c.epsg,
                "vertical_epsg": c.vertical_epsg,
                "wkt": c.wkt,
                "units": units_json(&c.units),
            })),
            "attributes": self.attribute_names(),
            "color_depth": match self.color_depth {
                ColorDepth::None => "none",
                ColorDepth::Bits8 => "8-bit",
                ColorDepth::Bits16 => "16-bit",
                ColorDepth::Float => "float",
                ColorDepth::Normalised => "normalised",
                ColorDepth::FromImages => "images",
            },
            "system_identifier": las.map(|l| &l.system_identifier),
            "generating_software": las.map(|l| &l.generating_software),
            "creation_date": las.and_then(|l| l.creation_date.as_ref()),
            "file_source_id": las.map(|l| l.file_source_id),
            "record_length": las.map(|l| l.record_length),
            "points_by_return": las.map(|l| &l.points_by_return),
            "vlrs": las.map(|l| l.vlrs.iter().map(|v| json!({
                "user_id": v.user_id,
                "record_id": v.record_id,
                "description": v.description,
                "bytes": v.bytes,
                "extended": v.extended,
            })).collect::<Vec<_>>()),
            "ignored_properties": self.ignored_properties,
            "e57": self.e57.as_ref().map(|e| e.to_json()),
        })
    }
}

/// `{"across": "foot", "across_metres": 0.3048, "up": null, "up_metres": null}`; `across`
/// is `"degrees"` for a geographic system.
fn units_json(units: &CrsUnits) -> Value {
    let (across, across_metres) = match &units.across {
        Across::Unknown => (None, None),
        Across::Linear(u) => (Some(u.name.as_str()), Some(u.metres)),
        Across::Degrees => (Some("degrees"), None),
    };
    json!({
        "across": across,
        "across_metres": across_metres,
        "up": units.up.as_ref().map(|u| u.name.as_str()),
        "up_metres": units.up.as_ref().map(|u| u.metres),
    })
}

impl fmt::Display for FileInfo {
    /// What `omnicloud info FILE` prints: one item per line.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "file:          {}", self.path.display())?;
        writeln!(f, "format:        {}", self.format)?;
        writeln!(f, "version:       {}", self.version)?;
        match (self.point_format, &self.las) {
            (Some(n), Some(l)) => {
                writeln!(f, "point format:  {n} ({} bytes a record)", l.record_length)?
            }
            (Some(n), None) => writeln!(f, "point format:  {n}")?,
            (None, _) => writeln!(f, "point format:  n/a")?,
        }
        write!(f, "points:        {}", thousands(self.point_count))?;
        if let Some(held) = self.records_in_file.filter(|_| self.is_truncated()) {
            write!(
                f,
                " declared, but the file holds only {} records: truncated",
                thousands(held)
            )?;
        }
        writeln!(f)?;
        match self.bounds {
            Some((lo, hi)) => {
                let size = hi - lo;
                let unit = self.length_symbol();
                writeln!(
                    f,
                    "bounds:        x {:.3} .. {:.3}, y {:.3} .. {:.3}, z {:.3} .. {:.3} (size {:.3} x {:.3} x {:.3} {unit})",
                    lo.x, hi.x, lo.y, hi.y, lo.z, hi.z, size.x, size.y, size.z
                )?;
            }
            None => writeln!(f, "bounds:        not in the header")?,
        }
        if let Some(l) = &self.las {
            let (s, o) = (l.scale, l.offset);
            writeln!(
                f,
                "scale:         {} {} {}",
                short(s.x),
                short(s.y),
                short(s.z)
            )?;
            writeln!(
                f,
                "offset:        {} {} {}",
                short(o.x),
                short(o.y),
                short(o.z)
            )?;
            match &l.crs {
                Some(crs) => {
                    writeln!(f, "crs:           {crs}")?;
                    writeln!(f, "units:         {}", crs.units)?;
                }
                None => writeln!(f, "crs:           none declared")?,
            }
        }
        let names = self.attribute_names();
        if names.is_empty() {
            writeln!(f, "attributes:    none")?;
        } else {
            writeln!(f, "attributes:    {}", names.join(", "))?;
        }
        write!(f, "colour:        {}", self.color_depth)?;
        if let Some(l) = &self.las {
            if !l.points_by_return.is_empty() {
                let counts: Vec<String> = l
                    .points_by_return
                    .iter()
                    .enumerate()
                    .map(|(i, n)| format!("{}: {}", i + 1, thousands(*n)))
                    .collect();
                write!(f, "\nby return:     {} (header)", counts.join(", "))?;
            }
            let mut made = Vec::new();
            if !l.generating_software.is_empty() {
                made.push(format!("by {}", l.generating_software));
            }
            if !l.system_identifier.is_empty() {
                made.push(format!("system {}", l.system_identifier));
            }
            if let Some(d) = &l.creation_date {
                made.push(format!("on {d}"));
            }
            if l.file_source_id != 0 {
                made.push(format!("source id {}", l.file_source_id));
            }
            if !made.is_empty() {
                write!(f, "\ncreated:       {}", made.join(", "))?;
            }
            for (i, v) in l.vlrs.iter().enumerate() {
                write!(
                    f,
                    "\n{}{} {} ({} bytes{}){}",
                    if i == 0 {
                        "vlrs:          "
                    } else {
                        "               "
                    },
                    v.user_id,
                    v.record_id,
                    v.bytes,
                    if v.extended { ", extended" } else { "" },
                    if v.description.is_empty() {
                        String::new()
                    } else {
                        format!(": {}", v.description)
                    }
                )?;
            }
        }
        if !self.ignored_properties.is_empty() {
            write!(f, "\nignored:       {}", self.ignored_properties.join(", "))?;
        }
        if let Some(e) = &self.e57 {
            write!(f, "\n{e}")?;
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
    fn header_numbers_are_short() {
        assert_eq!(short(0.000_001_000_000_000_000_000_2), "0.000001");
        assert_eq!(short(1.000_000_000_000_000_2e-7), "0.0000001");
        assert_eq!(short(0.01), "0.01");
        assert_eq!(short(637_000.0), "637000");
        assert_eq!(short(-12.5), "-12.5");
        assert_eq!(short(0.0), "0");
        assert_eq!(short(-0.0), "0");
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
                returns: false,
                radius: false,
            },
            color_depth: ColorDepth::Bits16,
            ignored_properties: vec![],
            records_in_file: None,
            las: None,
            e57: None,
        };
        let text = info.to_string();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 8, "{text}");
        assert!(lines[4].ends_with("1,065"));
        assert!(lines[6].ends_with("rgb, intensity, classification"));
    }

    #[test]
    fn wkt_names_and_authorities_are_read() {
        let wkt = r#"COMPD_CS["NAD83 / Oregon GIC Lambert (ft) + NAVD88 height (ftUS)",PROJCS["NAD83 / Oregon GIC Lambert (ft)",GEOGCS["NAD83",DATUM["North_American_Datum_1983",SPHEROID["GRS 1980",6378137,298.257222101,AUTHORITY["EPSG","7019"]],AUTHORITY["EPSG","6269"]],AUTHORITY["EPSG","4269"]],PROJECTION["Lambert_Conformal_Conic_2SP"],UNIT["foot",0.3048,AUTHORITY["EPSG","9002"]],AUTHORITY["EPSG","2992"]],VERT_CS["NAVD88 height (ftUS)",VERT_DATUM["North American Vertical Datum 1988",2005,AUTHORITY["EPSG","5103"]],UNIT["US survey foot",0.304800609601219,AUTHORITY["EPSG","9003"]],AUTHORITY["EPSG","6360"]]]"#;
        let crs = Crs::from_wkt(wkt);
        assert_eq!(
            crs.name.as_deref(),
            Some("NAD83 / Oregon GIC Lambert (ft) + NAVD88 height (ftUS)")
        );
        assert_eq!((crs.epsg, crs.vertical_epsg), (Some(2992), Some(6360)));
        let wkt2 = r#"PROJCRS["WGS 84 / UTM zone 10N", BASEGEOGCRS["WGS 84", ID["EPSG",4326]], CONVERSION["UTM zone 10N", ID["EPSG",16010]], ID["EPSG",32610]]"#;
        let crs = Crs::from_wkt(wkt2);
        assert_eq!(crs.name.as_deref(), Some("WGS 84 / UTM zone 10N"));
        assert_eq!(crs.epsg, Some(32610));
        let broken = Crs::from_wkt("PROJCS[\"half");
        assert_eq!((broken.name, broken.epsg), (None, None));
        assert_eq!(broken.wkt.as_deref(), Some("PROJCS[\"half"));
    }

    #[test]
    fn geotiff_keys_give_epsg_and_citation() {
        let key = |id| match id {
            1024 => Some(GeoKey::Code(1)),
            3072 => Some(GeoKey::Code(32610)),
            2048 => Some(GeoKey::Code(4326)),
            4096 => Some(GeoKey::Code(32767)),
            3073 => Some(GeoKey::Text("WGS 84 / UTM zone 10N|".into())),
            _ => None,
        };
        let crs = Crs::from_geotiff_keys(key);
        assert_eq!(crs.epsg, Some(32610));
        assert_eq!(crs.vertical_epsg, None, "32767 is user-defined, not EPSG");
        assert_eq!(crs.name.as_deref(), Some("WGS 84 / UTM zone 10N"));
        assert_eq!(
            crs.to_string(),
            "WGS 84 / UTM zone 10N (EPSG:32610, from GeoTIFF keys)"
        );
    }
}
