//! Lengths a person gives (`--ipd`, `--height`, `--radius`, `--max-distance`, a tour's
//! `--speed`, the depth map's distances) as the file's coordinates measure them.
//!
//! A person types metres; a scan's coordinate system may count in feet. [`LengthScale`]
//! turns the one into the other from the units the file declares (DESIGN: lengths are
//! metres, positions are file coordinates), or leaves lengths in the file's unit with
//! [`Units::File`].

use std::fmt;

use clap::ValueEnum;
use serde::Serialize;

use crate::io::{Across, CrsUnits, LinearUnit, Up};

/// What the lengths a person gives are measured in (`--units`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Units {
    /// Metres, converted to the file's unit when its coordinate system declares one.
    #[default]
    #[value(alias = "meters", alias = "m")]
    Metres,
    /// The file's own unit, whatever it is.
    File,
}

/// How a length given in [`Units`] becomes a length in file coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct LengthScale {
    /// What the lengths were given in.
    pub units: Units,
    /// File units per given unit, across (x and y; and every length but the eye height).
    pub across: f64,
    /// File units per given unit, up (the eye height above the ground).
    pub up: f64,
    /// Metres per file unit across (what a length in the file measures), when the file
    /// declares a unit of length; `None` for degrees or no declared unit.
    pub metres_per_unit: Option<f64>,
    /// The file's unit across, as a symbol (`ft`, `ftUS`, `m`); `m` when none is declared.
    pub file_symbol: String,
}

impl Default for LengthScale {
    /// Metres in a metric file: every factor 1.
    fn default() -> Self {
        LengthScale {
            units: Units::Metres,
            across: 1.0,
            up: 1.0,
            metres_per_unit: Some(1.0),
            file_symbol: "m".into(),
        }
    }
}

impl LengthScale {
    /// The scale for a file whose coordinate system declares `crs`, read with `up` as its
    /// vertical axis. A file that declares no unit of length (or degrees) is taken as metres,
    /// the LAS convention; with `--up y` the eye height runs along a horizontal axis, so it
    /// takes the horizontal unit.
    pub fn for_file(crs: &CrsUnits, units: Units, up: Up) -> Self {
        let across = match &crs.across {
            Across::Linear(u) => Some(u.clone()),
            Across::Unknown | Across::Degrees => None,
        };
        let vertical = match up {
            Up::Z => crs.up.clone().or_else(|| across.clone()),
            Up::Y => across.clone(),
        };
        let per_metre = |u: &Option<LinearUnit>| u.as_ref().map_or(1.0, |u| 1.0 / u.metres);
        let metres_per_unit = match &crs.across {
            Across::Linear(u) => Some(u.metres),
            Across::Unknown => Some(1.0),
            Across::Degrees => None,
        };
        let file_symbol = across
            .as_ref()
            .map_or_else(|| "m".into(), LinearUnit::symbol);
        match units {
            Units::Metres => LengthScale {
                units,
                across: per_metre(&across),
                up: per_metre(&vertical),
                metres_per_unit,
                file_symbol,
            },
            Units::File => LengthScale {
                units,
                across: 1.0,
                up: 1.0,
                metres_per_unit,
                file_symbol,
            },
        }
    }

    /// [`LengthScale::for_file`] for the units `info`'s coordinate system declares.
    pub fn for_info(info: &crate::io::FileInfo, units: Units, up: Up) -> Self {
        Self::for_file(&info.units(), units, up)
    }

    /// A length given in [`Self::units`] (a distance, a radius, an IPD), in file units.
    pub fn length(&self, given: f64) -> f64 {
        given * self.across
    }

    /// An eye height given in [`Self::units`], in file units along the up axis.
    pub fn height(&self, given: f64) -> f64 {
        given * self.up
    }

    /// A length in file units, in metres; `None` when the file's unit is not a length.
    pub fn to_metres(&self, file_length: f64) -> Option<f64> {
        self.metres_per_unit.map(|m| file_length * m)
    }

    /// True when lengths are converted (given in metres, the file counting in another unit).
    pub fn converts(&self) -> bool {
        self.across != 1.0 || self.up != 1.0
    }

    /// The unit lengths were taken in, as the summary names it: `m` or the file's symbol.
    pub fn given_symbol(&self) -> &str {
        match self.units {
            Units::Metres => "m",
            Units::File => &self.file_symbol,
        }
    }
}

impl fmt::Display for LengthScale {
    /// `lengths in metres (1 m = 3.2808 ft)`, `lengths in metres`, or `lengths in the file's
    /// unit (ft)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.units {
            Units::File => write!(f, "lengths in the file's unit ({})", self.file_symbol),
            Units::Metres if self.converts() => {
                write!(
                    f,
                    "lengths in metres (1 m = {:.4} {}",
                    self.across, self.file_symbol
                )?;
                if self.up != self.across {
                    write!(f, " across, {:.4} file units up", self.up)?;
                }
                f.write_str(")")
            }
            Units::Metres => f.write_str("lengths in metres"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::Crs;

    const AUTZEN: &str = r#"PROJCS["NAD_1983_HARN_Lambert_Conformal_Conic",GEOGCS["GCS",UNIT["degree",0.0174532925199433]],UNIT["foot",0.3048,AUTHORITY["EPSG","9002"]]]"#;

    #[test]
    fn metres_become_feet_in_a_file_that_counts_in_feet() {
        let crs = Crs::from_wkt(AUTZEN).units;
        let s = LengthScale::for_file(&crs, Units::Metres, Up::Z);
        assert!((s.length(0.064) - 0.064 / 0.3048).abs() < 1e-12);
        assert!((s.height(1.7) - 1.7 / 0.3048).abs() < 1e-12);
        assert_eq!(s.metres_per_unit, Some(0.3048));
        assert!((s.to_metres(s.length(2.5)).unwrap() - 2.5).abs() < 1e-12);
        assert_eq!(s.given_symbol(), "m");
        assert_eq!(s.to_string(), "lengths in metres (1 m = 3.2808 ft)");
        let file = LengthScale::for_file(&crs, Units::File, Up::Z);
        assert_eq!((file.length(0.064), file.height(1.7)), (0.064, 1.7));
        assert_eq!(file.given_symbol(), "ft");
        assert_eq!(file.to_string(), "lengths in the file's unit (ft)");
    }

    #[test]
    fn a_separate_vertical_unit_scales_the_eye_height_only() {
        let crs = Crs::from_wkt(
            r#"COMPD_CS["x",PROJCS["p",UNIT["metre",1]],VERT_CS["v",UNIT["US survey foot",0.304800609601219]]]"#,
        )
        .units;
        let s = LengthScale::for_file(&crs, Units::Metres, Up::Z);
        assert_eq!(s.length(0.064), 0.064);
        assert!((s.height(1.7) - 1.7 / 0.304800609601219).abs() < 1e-9);
        assert!(s.to_string().contains("file units up"), "{s}");
        // With y up the eye height runs along a metric axis.
        assert_eq!(
            LengthScale::for_file(&crs, Units::Metres, Up::Y).height(1.7),
            1.7
        );
    }

    #[test]
    fn undeclared_units_and_degrees_are_left_alone() {
        let none = LengthScale::for_file(&CrsUnits::default(), Units::Metres, Up::Z);
        assert_eq!(none, LengthScale::default());
        assert!(!none.converts());
        let geo = Crs::from_wkt(r#"GEOGCS["WGS 84",UNIT["degree",0.0174532925199433]]"#).units;
        let g = LengthScale::for_file(&geo, Units::Metres, Up::Z);
        assert_eq!((g.length(3.0), g.metres_per_unit), (3.0, None));
    }
}
