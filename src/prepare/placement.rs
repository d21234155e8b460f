//! Camera placement (`--camera auto|center|X,Y,Z`, `--height H`): where the eye stands.
//!
//! `center` stands at the XY centre of the scan, [`EYE_HEIGHT`] above the ground estimated
//! there ([`ground_height`], the one ground estimator). `auto` (the default) searches outward
//! from the centre for open space: a spot whose eye has no point within [`clearance`] of it
//! (not inside a tree, a hedge or a wall) and ground right below it. The default eye height
//! is [`default_eye_height`]: a person's eye height, raised over sparse (aerial) data so the
//! nearest ground spheres stay small in the image.

use crate::scene::Scene;
use glam::{DVec3, Vec2, Vec3};
use std::collections::HashMap;
use std::str::FromStr;

/// Eye height above the estimated ground (metres) over dense data.
pub const EYE_HEIGHT: f64 = 1.7;

/// Eye heights per point spacing over sparse data ([`default_eye_height`]).
pub const SPACING_HEIGHTS: f64 = 20.0;

/// Share of the eye height kept free of points around the eye ([`clearance`]).
pub const CLEARANCE_SHARE: f64 = 0.6;

/// The eye height a placement stands the camera at, in file units: the one given
/// (`--height`), else the default rule ([`default_eye_height`]) for a person whose eye stands
/// `person` file units above the ground ([`EYE_HEIGHT`] metres in the file's unit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EyeHeight {
    /// The height given, file units.
    pub given: Option<f64>,
    /// A person's eye height, file units.
    pub person: f64,
}

impl Default for EyeHeight {
    /// No height given, a person's eye [`EYE_HEIGHT`] file units up (a metric file).
    fn default() -> Self {
        EyeHeight {
            given: None,
            person: EYE_HEIGHT,
        }
    }
}

impl EyeHeight {
    /// `given` (file units) or the default rule, for a file whose up axis counts `per_metre`
    /// units a metre.
    pub fn new(given: Option<f64>, per_metre: f64) -> Self {
        EyeHeight {
            given,
            person: EYE_HEIGHT * per_metre,
        }
    }

    /// The height given, else a person's eye height (`--camera center`).
    pub fn or_person(self) -> f64 {
        self.given.unwrap_or(self.person)
    }

    /// The height given, else [`default_eye_height`] over a cloud of median `spacing`.
    pub fn over(self, spacing: Option<f32>) -> f64 {
        self.given
            .unwrap_or_else(|| default_eye_height(spacing, self.person))
    }
}

/// Where the camera goes (`--camera`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub enum CameraChoice {
    /// Open space near the scan's centre ([`open_camera_position`]); the centre when none.
    #[default]
    Auto,
    /// The XY centre of the scan, above the ground there ([`auto_camera_position`]).
    Center,
    /// This position, in file coordinates.
    At(DVec3),
    /// An E57 scan's station: where its scanner stood, with its heading. The command line
    /// turns it into [`CameraChoice::At`] and a yaw from the file's poses
    /// ([`crate::tour::stations`]) before placement, which takes an unresolved one as `Auto`.
    Station(StationPick),
}

/// Which stations `--camera station:..` asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StationPick {
    /// Scan N's station (from 0).
    Index(usize),
    /// Every station, one panorama each.
    All,
}

impl CameraChoice {
    /// The position given, in file coordinates; `None` for the automatic choices.
    pub fn given(self) -> Option<DVec3> {
        match self {
            CameraChoice::At(c) => Some(c),
            CameraChoice::Auto | CameraChoice::Center | CameraChoice::Station(_) => None,
        }
    }
}

/// `auto`, `center` (or `centre`), `X,Y,Z` in file coordinates, `station:N` or
/// `station:all`.
impl FromStr for CameraChoice {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let t = s.trim();
        if let Some(which) = t.strip_prefix("station:") {
            if which.eq_ignore_ascii_case("all") {
                return Ok(CameraChoice::Station(StationPick::All));
            }
            return which
                .parse()
                .map(|n| CameraChoice::Station(StationPick::Index(n)))
                .map_err(|_| {
                    format!("expected station:N (a scan number from 0) or station:all, got `{s}`")
                });
        }
        if t.eq_ignore_ascii_case("auto") {
            return Ok(CameraChoice::Auto);
        }
        if t.eq_ignore_ascii_case("center") || t.eq_ignore_ascii_case("centre") {
            return Ok(CameraChoice::Center);
        }
        let parts: Vec<&str> = t.split(',').collect();
        if parts.len() != 3 {
            return Err(format!(
                "expected `auto`, `center`, X,Y,Z (three comma-separated numbers) or \
                 station:N|all, got `{s}`"
            ));
        }
        let mut v = [0.0; 3];
        for (slot, part) in v.iter_mut().zip(parts) {
            *slot = crate::value::finite(part, "coordinate")?;
        }
        Ok(CameraChoice::At(DVec3::from_array(v)))
    }
}

/// The default eye height above the ground for a cloud of median point `spacing`: a
/// `person`'s eye height ([`EYE_HEIGHT`] metres, in the file's unit), or [`SPACING_HEIGHTS`]
/// spacings when that is higher.
///
/// A ground sphere straight below the eye, of radius half the spacing, then spans at most
/// 2·atan(1/40) ≈ 2.9° (1/126 of the panorama's width, 31 px at 3840) whatever the width
/// renders: a rule in spacings keeps the picture's composition the same at every width. Dense
/// scans (spacing under 8.5 cm) keep a person's eye height; the 1.3 m-spaced aerial sample
/// puts the eye 27 m up, where its ground reads as a surface instead of a few dozen bubbles
/// the size of a car (10 spacings, 13 m, still filled the lower half with bubbles).
pub fn default_eye_height(spacing: Option<f32>, person: f64) -> f64 {
    spacing.map_or(person, |s| person.max(SPACING_HEIGHTS * f64::from(s)))
}

/// Distance from the eye that `auto` keeps free of points, for an eye `height` metres above the
/// ground: [`CLEARANCE_SHARE`] of it (1.02 m at 1.7 m, 16 m at 27 m): grass and kerbs below
/// pass; foliage, hedges and walls next to the eye do not. (0.8 found no open spot on the
/// lion scan and more holes on Autzen; see docs/PICTURES.md.)
pub fn clearance(height: f64) -> f64 {
    CLEARANCE_SHARE * height
}
/// Non-empty cells the neighbourhood must reach before the ground is estimated.
const MIN_CELLS: usize = 24;
/// Cells per neighbourhood radius.
const CELLS_PER_RADIUS: f32 = 4.0;
/// Percentile of heights taken as a cell's ground: low enough to ignore objects standing on
/// the ground, high enough to ignore a few noise points below it.
const CELL_PERCENTILE: f32 = 0.1;

/// A camera position (local frame) [`EYE_HEIGHT`] above open ground near the local zero: the
/// nearest point of a 10 m grid (out to 80 m) whose ground, a low height percentile within
/// 5 m, has no point more than 0.5 m above it; the local zero at eye height when none is.
///
/// For benchmarks and tests that want an unobstructed view (no canopy or wall next to the
/// eye), unlike [`auto_camera_position`], which stands exactly at the scan's centre.
pub fn open_ground_camera_position(scene: &Scene) -> DVec3 {
    let mut candidates: Vec<(f32, f32)> = (-8..=8)
        .flat_map(|i| (-8..=8).map(move |j| (i as f32 * 10.0, j as f32 * 10.0)))
        .collect();
    candidates.sort_by(|a, b| a.0.hypot(a.1).total_cmp(&b.0.hypot(b.1)));
    let (x, y, ground) = candidates
        .iter()
        .find_map(|&(x, y)| {
            let mut near: Vec<f32> = scene
                .positions
                .iter()
                .filter(|p| (p.x - x).hypot(p.y - y) < 5.0)
                .map(|p| p.z)
                .collect();
            if near.len() < 10 {
                return None;
            }
            near.sort_by(f32::total_cmp);
            let ground = near[near.len() / 20];
            (near[near.len() - 1] < ground + 0.5).then_some((x, y, ground))
        })
        .unwrap_or((0.0, 0.0, 0.0));
    DVec3::new(x as f64, y as f64, ground as f64 + EYE_HEIGHT)
}

/// Moves the scene's frame onto the camera (DESIGN §1: the origin is the camera position)
/// and returns the camera's world position ([`camera_position`]). `None` for an empty scene
/// without a given camera.
pub fn center_on_camera(
    scene: &mut Scene,
    choice: CameraChoice,
    height: EyeHeight,
) -> Option<DVec3> {
    let world = match choice {
        CameraChoice::At(c) => c,
        _ => scene.origin + camera_position(scene, choice, height)?,
    };
    scene.recenter(world);
    Some(world)
}

/// The camera position (local frame) a choice gives over the scene's own bounds: `auto`
/// `height` above the ground (default [`default_eye_height`]), at the centre when no spot is
/// open; `center` `height` (default a person's eye height) above the ground at the centre, as
/// [`auto_camera_position`]. `None` for an empty scene.
pub fn camera_position(scene: &Scene, choice: CameraChoice, height: EyeHeight) -> Option<DVec3> {
    if let CameraChoice::At(c) = choice {
        return Some(c - scene.origin);
    }
    let (lo, hi) = scene.bounds()?;
    let centre = (lo.truncate() + hi.truncate()) * 0.5;
    let extent = (hi.truncate() - lo.truncate()).max_element();
    camera_position_in(scene, centre, extent, choice, height)
}

/// [`camera_position`] around a given XY `centre` (local frame) of a cloud `extent` metres
/// wide (for a scene sampled from a larger cloud, as [`ground_camera_position`]).
pub fn camera_position_in(
    scene: &Scene,
    centre: Vec2,
    extent: f32,
    choice: CameraChoice,
    height: EyeHeight,
) -> Option<DVec3> {
    if let CameraChoice::At(c) = choice {
        return Some(c - scene.origin);
    }
    let at_centre = |height: f64| {
        ground_height(scene, centre, extent)
            .map(|g| DVec3::new(f64::from(centre.x), f64::from(centre.y), g + height))
    };
    if choice == CameraChoice::Center {
        return at_centre(height.or_person());
    }
    let spacing = crate::prepare::radius::median_spacing(scene);
    let height = height.over(spacing);
    open_camera_position(scene, centre, extent, height, spacing).or_else(|| at_centre(height))
}

/// Most share of the points at a spot's foot that may lie below its ground (noise; more
/// means the "ground" is a canopy or a roof over the real ground).
const MAX_BELOW_GROUND: f32 = 0.05;

/// Steps of the candidate grid across the cloud's extent.
const SEARCH_STEPS: f32 = 64.0;

/// The nearest spot to `centre` (local frame, within half the `extent` of it) whose eye,
/// `height` above the ground there, is open: no point within [`clearance`] of the eye, and
/// ground below (points within two point spacings horizontally at the ground's height, at
/// most 5 % of them below it).
/// Candidates lie on a grid of extent/64 (at least the clearance); the ground at each is
/// [`ground_height`] over the points within a few grid steps. `None` when no spot is open.
pub fn open_camera_position(
    scene: &Scene,
    centre: Vec2,
    extent: f32,
    height: f64,
    spacing: Option<f32>,
) -> Option<DVec3> {
    let clear = clearance(height) as f32;
    let step = (extent / SEARCH_STEPS).max(clear).max(0.1);
    let columns = Columns::new(&scene.positions, step);
    let below = spacing.map_or(1.0, |s| 2.0 * s).max(0.25);
    let level = spacing.unwrap_or(0.5).max(0.5);
    let reach = (extent * 0.5).max(step);
    let n = (reach / step).ceil() as i32;
    let mut candidates: Vec<Vec2> = (-n..=n)
        .flat_map(|i| (-n..=n).map(move |j| Vec2::new(i as f32, j as f32) * step))
        .filter(|d| d.length() <= reach)
        .map(|d| centre + d)
        .collect();
    candidates.sort_by(|a, b| a.distance(centre).total_cmp(&b.distance(centre)));
    candidates.into_iter().find_map(|xy| {
        // The ground from the points within four steps: a local estimate, not a distant one.
        let local = columns.near(xy, 4.0 * step);
        if local.is_empty() {
            return None;
        }
        let ground = ground_height_of(&local, xy, 4.0 * step)? as f32;
        let eye = xy.extend(ground + height as f32);
        // Ground below: points at the ground's height at the foot, and few below it (under
        // a dense canopy the estimate finds the canopy, and the real ground lies beneath).
        let foot: Vec<f32> = local
            .iter()
            .filter(|p| p.truncate().distance_squared(xy) <= below * below)
            .map(|p| p.z - ground)
            .collect();
        let sunk = foot.iter().filter(|dz| **dz < -level).count();
        let grounded = foot.iter().any(|dz| dz.abs() <= level)
            && (sunk as f32) <= MAX_BELOW_GROUND * foot.len() as f32;
        let open = columns
            .near(xy, clear)
            .iter()
            .all(|p| p.distance_squared(eye) > clear * clear);
        (grounded && open).then(|| eye.as_dvec3())
    })
}

/// Points bucketed by XY column, for the placement search's local look-ups.
struct Columns<'a> {
    cell: f32,
    positions: &'a [Vec3],
    cells: HashMap<(i32, i32), Vec<u32>>,
}

impl<'a> Columns<'a> {
    fn new(positions: &'a [Vec3], cell: f32) -> Self {
        let mut cells: HashMap<(i32, i32), Vec<u32>> = HashMap::new();
        for (i, p) in positions.iter().enumerate() {
            if p.is_finite() {
                cells
                    .entry(Self::key(p.truncate(), cell))
                    .or_default()
                    .push(i as u32);
            }
        }
        Columns {
            cell,
            positions,
            cells,
        }
    }

    fn key(xy: Vec2, cell: f32) -> (i32, i32) {
        ((xy.x / cell).floor() as i32, (xy.y / cell).floor() as i32)
    }

    /// The points within horizontal distance `r` of `xy`.
    fn near(&self, xy: Vec2, r: f32) -> Vec<Vec3> {
        let (lo, hi) = (Self::key(xy - r, self.cell), Self::key(xy + r, self.cell));
        let mut out = Vec::new();
        for i in lo.0..=hi.0 {
            for j in lo.1..=hi.1 {
                for &k in self.cells.get(&(i, j)).map_or(&[][..], Vec::as_slice) {
                    let p = self.positions[k as usize];
                    if p.truncate().distance_squared(xy) <= r * r {
                        out.push(p);
                    }
                }
            }
        }
        out
    }
}

/// A camera position (local frame) at the XY centre of the scene's bounds, [`EYE_HEIGHT`]
/// above the ground there; `None` for an empty scene.
///
/// The ground is estimated in a disk around the centre whose radius doubles (from 1/64 of the
/// scene's XY extent) until it covers at least 24 non-empty cells of a grid of radius/4: each
/// cell's ground is the 10th percentile of its heights (sparse noise below the ground and
/// objects on it do not move it), and the scene's ground is the median over cells (a pole or a
/// tree trunk at the centre fills one cell; a centre over a hole grows the disk until it
/// reaches the ground around the hole; on a slope the median is the height at the centre).
pub fn auto_camera_position(scene: &Scene) -> Option<DVec3> {
    let (lo, hi) = scene.bounds()?;
    let centre = (lo.truncate() + hi.truncate()) * 0.5;
    let extent = (hi.truncate() - lo.truncate()).max_element();
    ground_camera_position(scene, centre, extent)
}

/// [`auto_camera_position`] at a given XY `centre` (local frame) of a cloud `extent` metres
/// wide: for a scene that is a sample of a larger cloud, whose own bounds may miss the
/// cloud's edges (the centre and extent then come from the file's header). `None` when no
/// point of the scene lies within `extent` of the centre.
pub fn ground_camera_position(scene: &Scene, centre: Vec2, extent: f32) -> Option<DVec3> {
    let ground = ground_height(scene, centre, extent)?;
    Some(DVec3::new(
        f64::from(centre.x),
        f64::from(centre.y),
        ground + EYE_HEIGHT,
    ))
}

/// The ground's height (local frame) under the XY point `centre` of a cloud `extent` metres
/// wide, estimated as [`auto_camera_position`] describes; `None` when no point lies within
/// `extent` of it.
pub fn ground_height(scene: &Scene, centre: Vec2, extent: f32) -> Option<f64> {
    ground_height_of(&scene.positions, centre, extent)
}

/// [`ground_height`] over a set of positions.
fn ground_height_of(positions: &[Vec3], centre: Vec2, extent: f32) -> Option<f64> {
    let mut radius = if extent > 0.0 { extent / 64.0 } else { 1.0 };
    let mut cells: HashMap<(i32, i32), Vec<f32>> = HashMap::new();
    loop {
        cells.clear();
        let cell = radius / CELLS_PER_RADIUS;
        for p in positions {
            let d = p.truncate() - centre;
            if d.length_squared() <= radius * radius {
                let key = ((d.x / cell).floor() as i32, (d.y / cell).floor() as i32);
                cells.entry(key).or_default().push(p.z);
            }
        }
        if cells.len() >= MIN_CELLS || radius >= extent {
            break;
        }
        radius *= 2.0;
    }
    let mut grounds: Vec<f32> = cells
        .into_values()
        .map(|mut z| {
            let rank = ((z.len() - 1) as f32 * CELL_PERCENTILE) as usize;
            *z.select_nth_unstable_by(rank, f32::total_cmp).1
        })
        .collect();
    if grounds.is_empty() {
        return None;
    }
    let mid = (grounds.len() - 1) / 2;
    let ground = *grounds.select_nth_unstable_by(mid, f32::total_cmp).1;
    Some(f64::from(ground))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A deterministic pseudo-random sequence in [0, 1).
    fn lcg(seed: &mut u64) -> f32 {
        let mut rng = crate::rng::SplitMix64::new(*seed);
        let x = rng.next_f64() as f32;
        *seed = rng.state();
        x
    }

    /// A 20 m x 20 m ground grid at `z`, centred on (10, 10), with `hole` metres of radius left
    /// empty around the centre.
    fn ground(z: f32, hole: f32) -> Vec<Vec3> {
        let mut pts = Vec::new();
        for i in 0..=100 {
            for j in 0..=100 {
                let p = Vec3::new(i as f32 * 0.2, j as f32 * 0.2, z);
                if p.truncate().distance(Vec2::splat(10.0)) >= hole {
                    pts.push(p);
                }
            }
        }
        pts
    }

    #[test]
    fn camera_choices_parse() {
        assert_eq!("auto".parse(), Ok(CameraChoice::Auto));
        assert_eq!(" Center".parse(), Ok(CameraChoice::Center));
        assert_eq!("centre".parse(), Ok(CameraChoice::Center));
        assert_eq!(
            "-637000.5,851000,12".parse(),
            Ok(CameraChoice::At(DVec3::new(-637000.5, 851000.0, 12.0)))
        );
        for bad in ["", "1,2", "1,2,x", "1,2,inf", "middle"] {
            let e = bad.parse::<CameraChoice>().unwrap_err();
            assert!(e.contains('`'), "{bad}: {e}");
        }
        assert_eq!(CameraChoice::default(), CameraChoice::Auto);
        assert_eq!(
            "station:2".parse(),
            Ok(CameraChoice::Station(StationPick::Index(2)))
        );
        assert_eq!(
            "station:ALL".parse(),
            Ok(CameraChoice::Station(StationPick::All))
        );
        assert!("station:x".parse::<CameraChoice>().is_err());
        assert_eq!(CameraChoice::Center.given(), None);
    }

    #[test]
    fn eye_height_rises_over_sparse_data() {
        assert_eq!(default_eye_height(None, EYE_HEIGHT), EYE_HEIGHT);
        assert_eq!(default_eye_height(Some(0.05), EYE_HEIGHT), EYE_HEIGHT);
        assert!((default_eye_height(Some(1.3), EYE_HEIGHT) - 26.0).abs() < 1e-5);
        assert!((clearance(1.7) - 1.02).abs() < 1e-12);
    }

    /// Nearest distance from `eye` to a point of the scene.
    fn nearest(scene: &Scene, eye: DVec3) -> f64 {
        scene
            .positions
            .iter()
            .map(|p| p.as_dvec3().distance(eye))
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn auto_leaves_a_tree_at_the_centre_and_center_stays_under_it() {
        let mut pts = ground(0.0, 0.0);
        // A crown of leaves 1 to 4 m up, 3 m around the centre.
        let mut seed = 3;
        for _ in 0..6000 {
            let (a, r) = (
                lcg(&mut seed) * std::f32::consts::TAU,
                3.0 * lcg(&mut seed).sqrt(),
            );
            let z = 1.0 + 3.0 * lcg(&mut seed);
            pts.push(Vec3::new(10.0 + r * a.cos(), 10.0 + r * a.sin(), z));
        }
        let scene = Scene::new(DVec3::ZERO, pts, 0.1);
        let centre = camera_position(&scene, CameraChoice::Center, EyeHeight::default()).unwrap();
        assert!(
            (centre.truncate() - glam::DVec2::splat(10.0)).length() < 1e-5,
            "{centre}"
        );
        assert!(nearest(&scene, centre) < 0.5, "{centre}");
        let height = EYE_HEIGHT;
        let auto = camera_position(
            &scene,
            CameraChoice::Auto,
            EyeHeight::new(Some(height), 1.0),
        )
        .unwrap();
        let clear = nearest(&scene, auto);
        assert!(clear > clearance(height), "{auto}: nearest point {clear}");
        assert!((auto.z - height).abs() < 1e-5, "{auto}");
        // The nearest open spot: just outside the crown.
        let off = auto.truncate().distance(glam::DVec2::splat(10.0));
        assert!((3.0..6.0).contains(&off), "{auto}");
        // A given height stands that far above the ground.
        let high =
            camera_position(&scene, CameraChoice::Auto, EyeHeight::new(Some(6.0), 1.0)).unwrap();
        assert!((high.z - 6.0).abs() < 1e-5, "{high}");
        assert!(nearest(&scene, high) > clearance(6.0));
    }

    #[test]
    fn auto_does_not_stand_over_a_hole_in_the_ground() {
        // No ground within 4 m of the centre: the eye moves to where ground lies below.
        let scene = Scene::new(DVec3::ZERO, ground(-2.0, 4.0), 0.1);
        let auto = camera_position(
            &scene,
            CameraChoice::Auto,
            EyeHeight::new(Some(EYE_HEIGHT), 1.0),
        )
        .unwrap();
        let off = auto.truncate().distance(glam::DVec2::splat(10.0));
        // Ground within two spacings (0.4 m) of the eye's foot.
        assert!((3.6..5.5).contains(&off), "{auto}");
        assert!((auto.z - -0.3).abs() < 1e-4, "{auto}");
        // Without a height: 20 spacings (4 m) up.
        let auto = camera_position(&scene, CameraChoice::Auto, EyeHeight::default()).unwrap();
        assert!((auto.z - 2.0).abs() < 1e-3, "{auto}");
    }

    #[test]
    fn empty_scene_has_no_position() {
        let scene = Scene::new(DVec3::ZERO, vec![], 0.1);
        assert_eq!(auto_camera_position(&scene), None);
    }

    #[test]
    fn flat_ground_gives_eye_height() {
        let scene = Scene::new(DVec3::ZERO, ground(3.0, 0.0), 0.1);
        let p = auto_camera_position(&scene).unwrap();
        assert!((p - DVec3::new(10.0, 10.0, 4.7)).length() < 1e-5, "{p}");
    }

    #[test]
    fn noise_below_ground_is_ignored() {
        let mut seed = 7;
        let mut pts = ground(0.0, 0.0);
        // 3 % of the points scattered up to 5 m below the ground.
        for _ in 0..pts.len() * 3 / 100 {
            let x = lcg(&mut seed) * 20.0;
            let y = lcg(&mut seed) * 20.0;
            pts.push(Vec3::new(x, y, -5.0 * lcg(&mut seed)));
        }
        let scene = Scene::new(DVec3::ZERO, pts, 0.1);
        let p = auto_camera_position(&scene).unwrap();
        assert!((p.z - 1.7).abs() < 0.05, "{p}");
    }

    #[test]
    fn objects_on_the_ground_do_not_lift_the_camera() {
        let mut pts = ground(1.0, 0.0);
        // A 10 m pole of points standing right at the centre.
        for i in 0..2000 {
            pts.push(Vec3::new(10.0, 10.0, 1.0 + i as f32 * 0.005));
        }
        let scene = Scene::new(DVec3::ZERO, pts, 0.1);
        let p = auto_camera_position(&scene).unwrap();
        assert!((p.z - 2.7).abs() < 1e-5, "{p}");
    }

    #[test]
    fn centre_over_a_hole_finds_surrounding_ground() {
        let scene = Scene::new(DVec3::ZERO, ground(-2.0, 4.0), 0.1);
        let p = auto_camera_position(&scene).unwrap();
        assert!((p - DVec3::new(10.0, 10.0, -0.3)).length() < 1e-5, "{p}");
    }

    #[test]
    fn sloped_ground_uses_local_height_not_global_minimum() {
        // Ground rising 0.5 m per metre along x: global minimum 0, height at the centre 5.
        let pts: Vec<Vec3> = ground(0.0, 0.0)
            .into_iter()
            .map(|p| Vec3::new(p.x, p.y, 0.5 * p.x))
            .collect();
        let scene = Scene::new(DVec3::ZERO, pts, 0.1);
        let p = auto_camera_position(&scene).unwrap();
        assert!((p.z - 6.7).abs() < 0.5, "{p}");
    }
}
