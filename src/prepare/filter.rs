//! Point filters, as LiDAR tools name them: keep classes (`--classes 2,6`), drop classes
//! (`--drop-classes 7,18`), first or last returns (`--returns first|last`), a horizontal crop
//! in file coordinates (`--crop X0,Y0,X1,Y1`) and a horizontal distance from the camera
//! (`--max-distance M`).
//!
//! Each removed point is counted against the first filter, in that order (crop, classes,
//! drop-classes, returns, distance), that rejects it. The crop applies before the camera is
//! placed (an automatic camera stands in the cropped area); the others after it, so the eye
//! height still comes from the ground when `--drop-classes 2` hides it.

use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use glam::{DVec2, DVec3};

use crate::io::{FileInfo, Up};
use crate::scene::Scene;

/// A set of classification codes (0–255).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ClassSet([u64; 4]);

impl ClassSet {
    /// The set holding `codes`.
    pub fn of(codes: &[u8]) -> Self {
        let mut set = ClassSet::default();
        for &c in codes {
            set.0[usize::from(c >> 6)] |= 1 << (c & 63);
        }
        set
    }

    /// True when `code` is in the set.
    #[inline]
    pub fn contains(self, code: u8) -> bool {
        self.0[usize::from(code >> 6)] & (1 << (code & 63)) != 0
    }

    /// The codes, ascending.
    pub fn codes(self) -> Vec<u8> {
        (0..=255u8).filter(|&c| self.contains(c)).collect()
    }
}

impl FromStr for ClassSet {
    type Err = String;

    /// Comma-separated codes: `2,6` or `7, 18`.
    fn from_str(s: &str) -> Result<Self, String> {
        let codes = s
            .split(',')
            .map(|c| {
                let c = c.trim();
                c.parse::<u8>().map_err(|_| {
                    format!("'{c}' is not a classification code (a whole number 0 to 255)")
                })
            })
            .collect::<Result<Vec<u8>, String>>()?;
        Ok(ClassSet::of(&codes))
    }
}

impl fmt::Display for ClassSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let codes: Vec<String> = self.codes().iter().map(u8::to_string).collect();
        f.write_str(&codes.join(","))
    }
}

/// Which returns of each pulse to keep (`--returns`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum ReturnFilter {
    /// Every point.
    #[default]
    All,
    /// First returns (return number 1; also points whose file gives 0).
    First,
    /// Last returns (return number equal to the pulse's number of returns).
    Last,
}

/// A horizontal rectangle in file coordinates: X and Y, or for `--up y` files X and Z.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crop {
    /// Smallest corner.
    pub min: DVec2,
    /// Largest corner.
    pub max: DVec2,
}

impl Crop {
    /// The file's horizontal coordinates of a world (Z-up) point.
    #[inline]
    fn horizontal(world: DVec3, up: Up) -> DVec2 {
        match up {
            Up::Z => DVec2::new(world.x, world.y),
            // world (x, y, z) = file (x, -z, y)
            Up::Y => DVec2::new(world.x, -world.y),
        }
    }

    /// True when the world point lies inside (edges included).
    #[inline]
    pub fn contains(&self, world: DVec3, up: Up) -> bool {
        let h = Crop::horizontal(world, up);
        h.cmpge(self.min).all() && h.cmple(self.max).all()
    }

    /// The rectangle as `(min, max)` world XY.
    pub fn world_rect(&self, up: Up) -> (DVec2, DVec2) {
        match up {
            Up::Z => (self.min, self.max),
            Up::Y => (
                DVec2::new(self.min.x, -self.max.y),
                DVec2::new(self.max.x, -self.min.y),
            ),
        }
    }
}

impl FromStr for Crop {
    type Err = String;

    /// `X0,Y0,X1,Y1`, corners in either order.
    fn from_str(s: &str) -> Result<Self, String> {
        let v = s
            .split(',')
            .map(|x| {
                x.trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| format!("'{}' is not a finite number", x.trim()))
            })
            .collect::<Result<Vec<f64>, String>>()?;
        let [x0, y0, x1, y1] = v[..] else {
            return Err(format!(
                "expected X0,Y0,X1,Y1 (four numbers), got {} value(s)",
                v.len()
            ));
        };
        let (a, b) = (DVec2::new(x0, y0), DVec2::new(x1, y1));
        if a.x == b.x || a.y == b.y {
            return Err("the rectangle is empty (X0 = X1 or Y0 = Y1)".into());
        }
        Ok(Crop {
            min: a.min(b),
            max: a.max(b),
        })
    }
}

/// The filters a render asks for; the default keeps every point.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PointFilter {
    /// Keep only these classes (`--classes`).
    pub classes: Option<ClassSet>,
    /// Drop these classes (`--drop-classes`).
    pub drop_classes: Option<ClassSet>,
    /// Keep first or last returns (`--returns`).
    pub returns: ReturnFilter,
    /// Keep points inside this rectangle (`--crop`).
    pub crop: Option<Crop>,
    /// Keep points within this horizontal distance of the camera, metres (`--max-distance`).
    pub max_distance: Option<f64>,
}

/// Points each filter removed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FilterCounts {
    /// Outside `--crop`.
    pub crop: u64,
    /// Not in `--classes`.
    pub classes: u64,
    /// In `--drop-classes`.
    pub drop_classes: u64,
    /// Not the returns `--returns` keeps.
    pub returns: u64,
    /// Beyond `--max-distance`.
    pub max_distance: u64,
    /// Whole files left unread because their header bounds lie outside the crop or beyond
    /// the distance (their points are counted above).
    pub files_skipped: u64,
}

impl FilterCounts {
    /// Points removed by all filters.
    pub fn total(&self) -> u64 {
        self.crop + self.classes + self.drop_classes + self.returns + self.max_distance
    }
}

impl std::ops::AddAssign for FilterCounts {
    fn add_assign(&mut self, o: FilterCounts) {
        self.crop += o.crop;
        self.classes += o.classes;
        self.drop_classes += o.drop_classes;
        self.returns += o.returns;
        self.max_distance += o.max_distance;
        self.files_skipped += o.files_skipped;
    }
}

/// When a filter runs relative to camera placement.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// The crop, before the camera is placed.
    BeforeCamera,
    /// Classes, returns and distance, on a scene centred on the camera.
    AfterCamera,
    /// Every filter, on a scene centred on the camera (a streamed chunk).
    All,
}

/// Why a filter cannot run.
#[derive(Debug, thiserror::Error)]
pub enum FilterError {
    /// The file lacks the attribute a filter needs.
    #[error("{}: {option} needs {attribute}, and this file has none{hint}", path.display())]
    MissingAttribute {
        /// The file.
        path: PathBuf,
        /// The option, e.g. `--classes`.
        option: &'static str,
        /// What it needs, e.g. `a classification`.
        attribute: &'static str,
        /// Where the reader looks for it (PLY), or empty.
        hint: &'static str,
    },
    /// The filters left no point.
    #[error("the filters removed every point ({counts}); loosen them")]
    NothingLeft {
        /// What each removed.
        counts: FilterCounts,
    },
}

impl fmt::Display for FilterCounts {
    /// `--crop removed 120, --classes removed 3,400` (only filters that removed points).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let parts: Vec<String> = [
            ("--crop", self.crop),
            ("--classes", self.classes),
            ("--drop-classes", self.drop_classes),
            ("--returns", self.returns),
            ("--max-distance", self.max_distance),
        ]
        .iter()
        .filter(|(_, n)| *n > 0)
        .map(|(name, n)| format!("{name} removed {n}"))
        .collect();
        if parts.is_empty() {
            f.write_str("no point removed")?;
        } else {
            f.write_str(&parts.join(", "))?;
        }
        match self.files_skipped {
            0 => Ok(()),
            1 => f.write_str(" (1 file skipped unread)"),
            n => write!(f, " ({n} files skipped unread)"),
        }
    }
}

impl PointFilter {
    /// The attributes the filter reads besides positions (return numbers are always read).
    pub fn fields(&self) -> crate::io::PointFields {
        crate::io::PointFields {
            classification: self.classes.is_some() || self.drop_classes.is_some(),
            ..crate::io::PointFields::POSITIONS
        }
    }

    /// True when the filter keeps every point.
    pub fn keeps_all(&self) -> bool {
        *self == PointFilter::default()
    }

    /// Checks, from its header, that a file has what the filters need.
    ///
    /// # Errors
    /// [`FilterError::MissingAttribute`] naming the file and the option.
    pub fn check(&self, info: &FileInfo) -> Result<(), FilterError> {
        self.check_attributes(
            &info.path,
            info.attributes.classification,
            info.attributes.returns,
        )
    }

    /// [`PointFilter::check`] for points named `path` that have a classification and return
    /// numbers or not.
    ///
    /// # Errors
    /// [`FilterError::MissingAttribute`] naming the first filter that cannot run.
    pub fn check_attributes(
        &self,
        path: &Path,
        classification: bool,
        returns: bool,
    ) -> Result<(), FilterError> {
        let missing = |option, attribute, hint| FilterError::MissingAttribute {
            path: path.to_path_buf(),
            option,
            attribute,
            hint,
        };
        let class_hint =
            " (a PLY file gives it as a `classification` or `scalar_Classification` property)";
        if self.classes.is_some() && !classification {
            return Err(missing("--classes", "a classification", class_hint));
        }
        if self.drop_classes.is_some() && !classification {
            return Err(missing("--drop-classes", "a classification", class_hint));
        }
        if self.returns != ReturnFilter::All && !returns {
            return Err(missing(
                "--returns",
                "return numbers",
                " (a PLY file gives them as `return_number` and `number_of_returns` properties)",
            ));
        }
        Ok(())
    }

    /// The counts that skip a whole file, from its header bounds, when every point of it
    /// lies outside the crop, or (with a given `camera`) beyond the distance; `None` when
    /// the file must be read (also when its header has no bounds).
    pub fn skips_file(
        &self,
        info: &FileInfo,
        up: Up,
        camera: Option<DVec3>,
    ) -> Option<FilterCounts> {
        let (lo, hi) = info.bounds?;
        let (a, b) = (up.to_world(lo), up.to_world(hi));
        let (lo, hi) = (a.min(b).truncate(), a.max(b).truncate());
        let skipped = |counts: FilterCounts| {
            Some(FilterCounts {
                files_skipped: 1,
                ..counts
            })
        };
        if let Some(crop) = self.crop {
            let (clo, chi) = crop.world_rect(up);
            if hi.cmplt(clo).any() || lo.cmpgt(chi).any() {
                return skipped(FilterCounts {
                    crop: info.point_count,
                    ..FilterCounts::default()
                });
            }
        }
        if let (Some(m), Some(c)) = (self.max_distance, camera) {
            let nearest = c.truncate().clamp(lo, hi);
            if nearest.distance(c.truncate()) > m {
                return skipped(FilterCounts {
                    max_distance: info.point_count,
                    ..FilterCounts::default()
                });
            }
        }
        None
    }

    /// The points of `scene` the filters of `stage` keep, and what each removed. For
    /// [`Stage::AfterCamera`] and [`Stage::All`] the scene's origin is the camera. A filter
    /// whose attribute the scene lacks keeps every point ([`PointFilter::check`] the files
    /// first).
    pub fn apply(&self, scene: Scene, up: Up, stage: Stage) -> (Scene, FilterCounts) {
        let mut counts = FilterCounts::default();
        let crop = self.crop.filter(|_| stage != Stage::AfterCamera);
        let rest = stage != Stage::BeforeCamera;
        let classes = scene.attributes.classification.as_deref().filter(|_| rest);
        let returns = scene
            .attributes
            .returns
            .as_deref()
            .filter(|_| rest && self.returns != ReturnFilter::All);
        let max_distance = self.max_distance.filter(|_| rest);
        if crop.is_none()
            && max_distance.is_none()
            && returns.is_none()
            && (classes.is_none() || (self.classes.is_none() && self.drop_classes.is_none()))
        {
            return (scene, counts);
        }
        let keep: Vec<bool> = scene
            .positions
            .iter()
            .enumerate()
            .map(|(i, p)| {
                if let Some(c) = &crop
                    && !c.contains(scene.origin + p.as_dvec3(), up)
                {
                    counts.crop += 1;
                    return false;
                }
                if let Some(codes) = classes {
                    if self.classes.is_some_and(|k| !k.contains(codes[i])) {
                        counts.classes += 1;
                        return false;
                    }
                    if self.drop_classes.is_some_and(|d| d.contains(codes[i])) {
                        counts.drop_classes += 1;
                        return false;
                    }
                }
                if let Some(r) = returns {
                    let keep = match self.returns {
                        ReturnFilter::All => true,
                        ReturnFilter::First => r[i].is_first(),
                        ReturnFilter::Last => r[i].is_last(),
                    };
                    if !keep {
                        counts.returns += 1;
                        return false;
                    }
                }
                if let Some(m) = max_distance
                    && f64::from(p.x).hypot(f64::from(p.y)) > m
                {
                    counts.max_distance += 1;
                    return false;
                }
                true
            })
            .collect();
        if counts.total() == 0 {
            return (scene, counts);
        }
        (scene.select(&keep), counts)
    }
}

/// The files a preparation must read, and what the skipped ones count for: a file whose
/// header bounds lie wholly outside the crop (or beyond the distance from a given camera) is
/// not read ([`PointFilter::skips_file`]). `infos` are the files' headers, in order. With a
/// single file nothing is skipped: the filters then report on its points as usual.
pub fn files_to_read(
    paths: &[PathBuf],
    infos: &[FileInfo],
    options: &super::PrepareOptions,
) -> (Vec<PathBuf>, FilterCounts) {
    let mut counts = FilterCounts::default();
    if paths.len() < 2 {
        return (paths.to_vec(), counts);
    }
    let mut read = Vec::with_capacity(paths.len());
    for (path, info) in paths.iter().zip(infos) {
        match options
            .filter
            .skips_file(info, options.up, options.camera.given())
        {
            Some(c) => counts += c,
            None => read.push(path.clone()),
        }
    }
    (read, counts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Returns;
    use glam::Vec3;

    #[test]
    fn class_sets_parse_and_hold_codes() {
        let s: ClassSet = "2, 6,255,0".parse().unwrap();
        assert_eq!(s.codes(), [0, 2, 6, 255]);
        assert_eq!(s.to_string(), "0,2,6,255");
        assert!("2,300".parse::<ClassSet>().unwrap_err().contains("'300'"));
        assert!("".parse::<ClassSet>().is_err());
    }

    #[test]
    fn crops_parse_in_any_corner_order() {
        let c: Crop = "10,5,-2,8".parse().unwrap();
        assert_eq!(
            (c.min, c.max),
            (DVec2::new(-2.0, 5.0), DVec2::new(10.0, 8.0))
        );
        assert!("1,2,3".parse::<Crop>().unwrap_err().contains("four"));
        assert!("1,2,1,5".parse::<Crop>().unwrap_err().contains("empty"));
        assert!("1,nan,3,4".parse::<Crop>().is_err());
        // A Y-up file's X and Z: world y is -Z.
        assert!(c.contains(DVec3::new(0.0, -6.0, 100.0), Up::Y));
        assert!(!c.contains(DVec3::new(0.0, 6.0, 100.0), Up::Y));
    }

    #[test]
    fn each_removed_point_counts_against_the_first_filter_that_rejects_it() {
        let mut s = Scene::new(
            DVec3::new(100.0, 200.0, 0.0),
            vec![
                Vec3::new(0.0, 0.0, 0.0),  // kept
                Vec3::new(50.0, 0.0, 0.0), // outside the crop (and too far)
                Vec3::new(1.0, 0.0, 0.0),  // class 7
                Vec3::new(0.0, 1.0, 0.0),  // class 3: not kept
                Vec3::new(0.0, 2.0, 0.0),  // second of two returns
                Vec3::new(9.0, 0.0, 0.0),  // too far
            ],
            0.1,
        );
        s.attributes.classification = Some(vec![2, 2, 7, 3, 2, 2]);
        let one = Returns { number: 1, of: 1 };
        s.attributes.returns = Some(vec![one, one, one, one, Returns { number: 2, of: 2 }, one]);
        let f = PointFilter {
            classes: Some(ClassSet::of(&[2, 7])),
            drop_classes: Some(ClassSet::of(&[7])),
            returns: ReturnFilter::First,
            crop: Some("90,190,120,210".parse().unwrap()),
            max_distance: Some(5.0),
        };
        let (before, c1) = f.apply(s.clone(), Up::Z, Stage::BeforeCamera);
        assert_eq!((before.len(), c1.crop, c1.total()), (5, 1, 1));
        let (after, c2) = f.apply(before, Up::Z, Stage::AfterCamera);
        assert_eq!(after.positions, [Vec3::ZERO]);
        assert_eq!(
            c2,
            FilterCounts {
                crop: 0,
                classes: 1,
                drop_classes: 1,
                returns: 1,
                max_distance: 1,
                files_skipped: 0,
            }
        );
        let (all, c) = f.apply(s, Up::Z, Stage::All);
        assert_eq!(all.len(), 1);
        assert_eq!(c.total(), 5);
        assert_eq!(
            c.to_string(),
            "--crop removed 1, --classes removed 1, --drop-classes removed 1, --returns removed 1, --max-distance removed 1"
        );
    }
}
