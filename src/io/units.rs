//! The units a LAS file's coordinate system gives its coordinates in: a length unit across
//! (or degrees, for a geographic system) and one up, read from the WKT or the GeoTIFF keys.
//! Nothing is looked up: a system that names no unit leaves it unknown.

use std::fmt;

use super::wkt::{COMPOUND, GEOGRAPHIC, LENGTH_UNIT, PROJECTED, VERTICAL, WktArg, WktNode};

/// A unit of length.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearUnit {
    /// Its name as the file gives it (`foot`, `US survey foot`, `metre`).
    pub name: String,
    /// Metres per unit.
    pub metres: f64,
}

impl LinearUnit {
    /// The metre.
    pub fn metre() -> Self {
        LinearUnit {
            name: "metre".into(),
            metres: 1.0,
        }
    }

    /// True for the metre (whatever the file calls it).
    pub fn is_metre(&self) -> bool {
        (self.metres - 1.0).abs() < 1e-9
    }

    /// The unit of EPSG code `code` for the units a GeoTIFF key or WKT authority names
    /// (metre, foot, US survey foot, kilometre); `None` for others.
    pub fn from_epsg(code: u32) -> Option<Self> {
        let (name, metres) = match code {
            9001 => ("metre", 1.0),
            9002 => ("foot", 0.3048),
            9003 => ("US survey foot", 1200.0 / 3937.0),
            9036 => ("kilometre", 1000.0),
            _ => return None,
        };
        Some(LinearUnit {
            name: name.into(),
            metres,
        })
    }

    /// The symbol sizes are given in: `m`, `ft`, `ftUS`, `km`, else the name.
    pub fn symbol(&self) -> String {
        let near = |m: f64| (self.metres - m).abs() < 1e-12;
        if self.is_metre() {
            "m".into()
        } else if near(0.3048) {
            "ft".into()
        } else if near(1200.0 / 3937.0) {
            "ftUS".into()
        } else if near(1000.0) {
            "km".into()
        } else {
            self.name.clone()
        }
    }
}

impl fmt::Display for LinearUnit {
    /// `foot (0.3048 m)`, or `metre`: the factor to nine decimals, trailing zeros dropped.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_metre() {
            return f.write_str(&self.name);
        }
        let metres = format!("{:.9}", self.metres);
        let metres = metres.trim_end_matches('0').trim_end_matches('.');
        write!(f, "{} ({metres} m)", self.name)
    }
}

/// What the horizontal coordinates are.
#[derive(Debug, Clone, PartialEq)]
pub enum Across {
    /// Not declared.
    Unknown,
    /// Projected coordinates in a unit of length.
    Linear(LinearUnit),
    /// Longitude and latitude, in degrees (a geographic system).
    Degrees,
}

/// The units of a coordinate system's x, y and z.
#[derive(Debug, Clone, PartialEq)]
pub struct CrsUnits {
    /// Of x and y.
    pub across: Across,
    /// Of z, when the system declares a vertical part or unit.
    pub up: Option<LinearUnit>,
}

impl Default for CrsUnits {
    fn default() -> Self {
        CrsUnits {
            across: Across::Unknown,
            up: None,
        }
    }
}

impl CrsUnits {
    /// The units a parsed WKT system declares: a projected system's own unit (or its first
    /// axis's), degrees for a geographic one, a vertical system's unit; a compound system's
    /// parts each give theirs.
    pub(super) fn from_wkt(root: &WktNode) -> Self {
        let mut units = CrsUnits::default();
        let mut visit = |node: &WktNode| {
            let keyword = node.keyword.as_str();
            if PROJECTED.contains(&keyword) {
                if let Some(u) = own_length_unit(node) {
                    units.across = Across::Linear(u);
                }
            } else if GEOGRAPHIC.contains(&keyword) {
                units.across = Across::Degrees;
            } else if VERTICAL.contains(&keyword) {
                units.up = own_length_unit(node);
            }
        };
        if COMPOUND.contains(&root.keyword.as_str()) {
            root.children().for_each(visit);
        } else {
            visit(root);
        }
        units
    }

    /// The units GeoTIFF keys declare: `code(id)` is a SHORT key's value. The model type
    /// (1024: 2 geographic), the projected linear units (3076) and the vertical units (4099).
    pub fn from_geotiff_keys(code: impl Fn(u16) -> Option<u16>) -> Self {
        let across = if code(1024) == Some(2) {
            Across::Degrees
        } else {
            match code(3076).and_then(|c| LinearUnit::from_epsg(c.into())) {
                Some(u) => Across::Linear(u),
                None => Across::Unknown,
            }
        };
        CrsUnits {
            across,
            up: code(4099).and_then(|c| LinearUnit::from_epsg(c.into())),
        }
    }

    /// `self`, its unknowns filled in from `other`.
    pub fn or(self, other: CrsUnits) -> CrsUnits {
        CrsUnits {
            across: match self.across {
                Across::Unknown => other.across,
                a => a,
            },
            up: self.up.or(other.up),
        }
    }

    /// The unit of x and y when it is a length other than the metre.
    pub fn non_metric_across(&self) -> Option<&LinearUnit> {
        match &self.across {
            Across::Linear(u) if !u.is_metre() => Some(u),
            _ => None,
        }
    }

    /// The symbol to give sizes in ([`LinearUnit::symbol`]): x and y's unit, z taken to be in
    /// it unless declared otherwise; `m` when nothing is declared (the LAS convention
    /// omnicloud assumes); `None` when x, y and z are not in one unit of length.
    pub fn size_unit(&self) -> Option<String> {
        match (&self.across, &self.up) {
            (Across::Unknown, None) => Some("m".into()),
            (Across::Linear(a), None) => Some(a.symbol()),
            (Across::Linear(a), Some(u)) if (a.metres - u.metres).abs() < 1e-12 => Some(a.symbol()),
            _ => None,
        }
    }
}

impl fmt::Display for CrsUnits {
    /// `x, y in foot (0.3048 m); z not declared`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.across, &self.up) {
            (Across::Linear(a), Some(u)) if a == u => write!(f, "x, y, z in {a}"),
            (across, up) => {
                match across {
                    Across::Unknown => f.write_str("x, y not declared")?,
                    Across::Linear(a) => write!(f, "x, y in {a}")?,
                    Across::Degrees => f.write_str("x, y in degrees (geographic)")?,
                }
                match up {
                    Some(u) => write!(f, "; z in {u}"),
                    None => f.write_str("; z not declared"),
                }
            }
        }
    }
}

/// A system node's own length unit: a `UNIT`/`LENGTHUNIT` child, else (WKT2) that of its
/// first `AXIS`.
fn own_length_unit(node: &WktNode) -> Option<LinearUnit> {
    node.children()
        .find(|c| LENGTH_UNIT.contains(&c.keyword.as_str()))
        .or_else(|| {
            node.children()
                .filter(|c| c.keyword == "AXIS")
                .find_map(|axis| {
                    axis.children()
                        .find(|c| LENGTH_UNIT.contains(&c.keyword.as_str()))
                })
        })
        .and_then(unit_of)
}

/// `UNIT["foot",0.3048,...]`: its name and factor; the EPSG unit it names when the factor
/// is missing or not a positive number.
fn unit_of(node: &WktNode) -> Option<LinearUnit> {
    let name = node.name()?.to_string();
    let factor = node.args.iter().find_map(|a| match a {
        WktArg::Word(w) => w.trim().parse::<f64>().ok(),
        _ => None,
    });
    match factor {
        Some(metres) if metres.is_finite() && metres > 0.0 => Some(LinearUnit { name, metres }),
        _ => node.epsg().and_then(LinearUnit::from_epsg),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::Crs;

    fn units(wkt: &str) -> CrsUnits {
        Crs::from_wkt(wkt).units
    }

    #[test]
    fn wkt1_projected_systems_give_their_own_unit_not_their_datum_degrees() {
        // Autzen's (data/autzen_trim.laz), shortened.
        let u = units(
            r#"PROJCS["NAD_1983_HARN_Lambert_Conformal_Conic",GEOGCS["GCS_North_American_1983_HARN",DATUM["D",SPHEROID["GRS_1980",6378137,298.257222101]],PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433]],PROJECTION["Lambert_Conformal_Conic_2SP"],PARAMETER["false_easting",1312335.958005249],UNIT["foot",0.3048,AUTHORITY["EPSG","9002"]]]"#,
        );
        let foot = LinearUnit {
            name: "foot".into(),
            metres: 0.3048,
        };
        assert_eq!(u.across, Across::Linear(foot.clone()));
        assert_eq!(u.up, None);
        assert_eq!(u.non_metric_across(), Some(&foot));
        assert_eq!(u.size_unit().as_deref(), Some("ft"));
        assert_eq!(u.to_string(), "x, y in foot (0.3048 m); z not declared");
    }

    #[test]
    fn compound_systems_give_each_part_its_unit() {
        let u = units(
            r#"COMPD_CS["NAD83 / Oregon GIC Lambert (ft) + NAVD88 height (ftUS)",PROJCS["NAD83 / Oregon GIC Lambert (ft)",GEOGCS["NAD83",UNIT["degree",0.0174532925199433]],UNIT["foot",0.3048,AUTHORITY["EPSG","9002"]]],VERT_CS["NAVD88 height (ftUS)",VERT_DATUM["North American Vertical Datum 1988",2005],UNIT["US survey foot",0.304800609601219,AUTHORITY["EPSG","9003"]]]]"#,
        );
        assert!(matches!(&u.across, Across::Linear(a) if a.name == "foot"));
        assert_eq!(
            u.up.as_ref().map(|v| v.name.as_str()),
            Some("US survey foot")
        );
        assert_eq!(u.size_unit(), None, "feet across, survey feet up");
        assert_eq!(
            u.to_string(),
            "x, y in foot (0.3048 m); z in US survey foot (0.30480061 m)"
        );
    }

    #[test]
    fn wkt2_units_come_from_the_system_or_its_axes() {
        let u = units(
            r#"PROJCRS["WGS 84 / UTM zone 10N",BASEGEOGCRS["WGS 84",ANGLEUNIT["degree",0.0174532925199433]],CONVERSION["UTM zone 10N",METHOD["Transverse Mercator"]],CS[Cartesian,2],AXIS["(E)",east,ORDER[1],LENGTHUNIT["metre",1]],AXIS["(N)",north,ORDER[2],LENGTHUNIT["metre",1]],ID["EPSG",32610]]"#,
        );
        assert_eq!(u.across, Across::Linear(LinearUnit::metre()));
        assert_eq!(u.non_metric_across(), None);
        assert_eq!(u.size_unit().as_deref(), Some("m"));
        let g = units(r#"GEOGCS["WGS 84",DATUM["WGS_1984"],UNIT["degree",0.0174532925199433]]"#);
        assert_eq!(g.across, Across::Degrees);
        assert_eq!(g.size_unit(), None);
        assert_eq!(
            g.to_string(),
            "x, y in degrees (geographic); z not declared"
        );
    }

    #[test]
    fn a_unit_without_a_usable_factor_falls_back_to_its_epsg_code() {
        let u = units(r#"PROJCS["x",UNIT["US survey foot",nan,AUTHORITY["EPSG","9003"]]]"#);
        assert!(matches!(&u.across, Across::Linear(a) if (a.metres - 0.3048006096).abs() < 1e-9));
        let none = units(r#"PROJCS["x",UNIT["furlong",-1]]"#);
        assert_eq!(none.across, Across::Unknown);
    }

    #[test]
    fn geotiff_keys_give_units_by_epsg_code() {
        let keys = |pairs: &'static [(u16, u16)]| {
            CrsUnits::from_geotiff_keys(move |id| {
                pairs.iter().find(|(k, _)| *k == id).map(|(_, v)| *v)
            })
        };
        let u = keys(&[(1024, 1), (3076, 9002), (4099, 9003)]);
        assert!(matches!(&u.across, Across::Linear(a) if a.name == "foot"));
        assert_eq!(u.up.map(|v| v.name), Some("US survey foot".to_string()));
        assert_eq!(keys(&[(1024, 2)]).across, Across::Degrees);
        assert_eq!(keys(&[(3076, 9999)]), CrsUnits::default());
        // Unknowns are filled from the other source, knowns kept.
        let filled = CrsUnits::default().or(keys(&[(3076, 9001)]));
        assert_eq!(filled.across, Across::Linear(LinearUnit::metre()));
    }
}
