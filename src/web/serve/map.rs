//! The top-down map of a scan: an orthographic view from above over its XY bounds, north
//! (+Y) up, as DESIGN §8's `map` projection lays it out. [`MapGrid`] is the one mapping
//! between map pixels and file coordinates; [`render_map`] draws the highest sphere top in
//! each pixel with its base colour, shaded by height.

use glam::{DVec2, Vec2};
use serde::Serialize;

use crate::frame::Frame;
use crate::render::color::MissingAttribute;
use crate::render::{ColorMode, base_colors};
use crate::scene::Scene;

/// Square map pixels over an XY box of file coordinates, row 0 at the north edge.
///
/// Pixel `(i, j)` covers `x0 + [i, i+1) * pixel` by `y1 - [j, j+1) * pixel`; continuous map
/// coordinates `(px, py)` (pixel centres at `i + 0.5`) map to `(x0 + px * pixel,
/// y1 - py * pixel)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MapGrid {
    /// West edge, file X.
    pub x0: f64,
    /// North edge, file Y.
    pub y1: f64,
    /// Metres per pixel side.
    pub pixel: f64,
    /// Pixels across (west to east).
    pub width: u32,
    /// Pixels down (north to south).
    pub height: u32,
}

impl MapGrid {
    /// The grid over the box `lo..hi` (file XY) whose longer side is `max_side` pixels; the
    /// shorter side gets as many whole pixels as it needs and the box is padded equally on
    /// both sides to fill them.
    pub fn over(lo: DVec2, hi: DVec2, max_side: u32) -> Self {
        let max_side = max_side.max(1);
        let size = (hi - lo).max(DVec2::ZERO);
        let longer = size.max_element();
        // A single point or a line still gets a map one metre across.
        let pixel = if longer > 0.0 {
            longer / f64::from(max_side)
        } else {
            1.0 / f64::from(max_side)
        };
        let cells = |extent: f64| ((extent / pixel).ceil() as u32).clamp(1, max_side);
        let (width, height) = (cells(size.x), cells(size.y));
        let centre = (lo + hi) * 0.5;
        MapGrid {
            x0: centre.x - 0.5 * f64::from(width) * pixel,
            y1: centre.y + 0.5 * f64::from(height) * pixel,
            pixel,
            width,
            height,
        }
    }

    /// File XY of continuous map coordinates (pixel centres at `i + 0.5`).
    pub fn to_file(&self, map: DVec2) -> DVec2 {
        DVec2::new(self.x0 + map.x * self.pixel, self.y1 - map.y * self.pixel)
    }

    /// Continuous map coordinates of a file XY position.
    pub fn to_map(&self, file: DVec2) -> DVec2 {
        DVec2::new(
            (file.x - self.x0) / self.pixel,
            (self.y1 - file.y) / self.pixel,
        )
    }

    /// The pixel that holds a file XY position, if it lies on the map.
    pub fn pixel_of(&self, file: DVec2) -> Option<(u32, u32)> {
        let m = self.to_map(file).floor();
        let inside =
            m.x >= 0.0 && m.y >= 0.0 && m.x < f64::from(self.width) && m.y < f64::from(self.height);
        inside.then_some((m.x as u32, m.y as u32))
    }
}

/// Brightness of the lowest surface; the highest has 1. Height reads as light.
const LOW_SHADE: f32 = 0.45;

/// Gap-filling passes: an empty pixel takes its highest covered neighbour, so gaps up to
/// twice this many pixels between sparse points close while open land stays empty.
const FILL_PASSES: usize = 3;

/// Renders `scene` (local frame, `scene.origin` its file position) from above onto `grid`:
/// each pixel shows the sphere whose top is highest there (a sphere covers the pixels whose
/// centres lie within its radius, and at least its own), in its `color` base colour scaled
/// from [`LOW_SHADE`] to 1 between the 2nd and 98th percentile of the tops. Gaps narrower
/// than `2 * FILL_PASSES` pixels take their neighbours' top; pixels further from any sphere
/// are transparent (alpha 0).
///
/// # Errors
/// The colour mode needs an attribute the scene lacks.
pub fn render_map(
    scene: &Scene,
    grid: &MapGrid,
    color: ColorMode,
) -> Result<Frame, MissingAttribute> {
    let colors = base_colors(scene, color)?;
    let mut tops = splat_tops(scene, grid);
    fill_gaps(&mut tops, grid.width as usize, FILL_PASSES);
    let (low, high) = height_range(&tops);
    let mut frame = Frame::new(grid.width, grid.height);
    for (k, top) in tops.iter().enumerate() {
        let Some((z, owner)) = *top else { continue };
        let t = if high > low {
            ((z - low) / (high - low)).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let shade = LOW_SHADE + (1.0 - LOW_SHADE) * t;
        let [r, g, b] = colors[owner as usize].map(|c| (f32::from(c) * shade).round() as u8);
        frame.color[k] = [r, g, b, 255];
    }
    Ok(frame)
}

/// Per pixel (row-major), the highest sphere top over it (local z) and its point.
type Tops = Vec<Option<(f32, u32)>>;

/// Draws every sphere's footprint, keeping the highest top per pixel.
fn splat_tops(scene: &Scene, grid: &MapGrid) -> Tops {
    let (w, h) = (grid.width as usize, grid.height as usize);
    let mut tops: Tops = vec![None; w * h];
    let step = grid.pixel as f32;
    // Map coordinates of the local frame's zero, so each point costs f32 arithmetic only.
    let zero = grid.to_map(scene.origin.truncate()).as_vec2();
    let last = Vec2::new(w as f32 - 1.0, h as f32 - 1.0);
    for (i, p) in scene.positions.iter().enumerate() {
        let r = scene.radii.get(i);
        let centre = zero + Vec2::new(p.x, -p.y) / step;
        let reach = r / step;
        let z = p.z + r;
        let own = centre.floor();
        let lo = (centre - Vec2::splat(reach))
            .floor()
            .min(own)
            .max(Vec2::ZERO);
        let hi = (centre + Vec2::splat(reach)).floor().max(own).min(last);
        for py in lo.y as usize..=hi.y as usize {
            for px in lo.x as usize..=hi.x as usize {
                let d = Vec2::new(px as f32 + 0.5, py as f32 + 0.5) - centre;
                let covers =
                    d.length_squared() <= reach * reach || own == Vec2::new(px as f32, py as f32);
                let k = py * w + px;
                if covers && px < w && py < h && tops[k].is_none_or(|(t, _)| z > t) {
                    tops[k] = Some((z, i as u32));
                }
            }
        }
    }
    tops
}

/// Up to `passes` times, gives each empty pixel the highest top among its eight neighbours.
fn fill_gaps(tops: &mut Tops, width: usize, passes: usize) {
    let height = tops.len() / width.max(1);
    for _ in 0..passes {
        let before = tops.clone();
        let mut filled = false;
        for y in 0..height {
            for x in 0..width {
                if before[y * width + x].is_some() {
                    continue;
                }
                let mut best: Option<(f32, u32)> = None;
                for ny in y.saturating_sub(1)..=(y + 1).min(height - 1) {
                    for nx in x.saturating_sub(1)..=(x + 1).min(width - 1) {
                        if let Some((z, o)) = before[ny * width + nx]
                            && best.is_none_or(|(b, _)| z > b)
                        {
                            best = Some((z, o));
                        }
                    }
                }
                if best.is_some() {
                    tops[y * width + x] = best;
                    filled = true;
                }
            }
        }
        if !filled {
            break;
        }
    }
}

/// 2nd and 98th percentile of the covered pixels' tops (a few stray high or low points do
/// not wash out the shading).
fn height_range(tops: &Tops) -> (f32, f32) {
    let mut zs: Vec<f32> = tops.iter().flatten().map(|&(z, _)| z).collect();
    if zs.is_empty() {
        return (0.0, 0.0);
    }
    zs.sort_unstable_by(f32::total_cmp);
    let at = |q: f64| zs[((zs.len() - 1) as f64 * q).round() as usize];
    (at(0.02), at(0.98))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec3, Vec3};

    #[test]
    fn the_grid_maps_pixel_centres_and_file_positions_both_ways() {
        // 200 m east-west, 100 m north-south, 400 px on the longer side.
        let g = MapGrid::over(DVec2::new(1000.0, 5000.0), DVec2::new(1200.0, 5100.0), 400);
        assert_eq!((g.width, g.height), (400, 200));
        assert_eq!(g.pixel, 0.5);
        // The north-west corner is map (0, 0); the first pixel's centre is 0.25 m in.
        assert_eq!(g.to_file(DVec2::ZERO), DVec2::new(1000.0, 5100.0));
        assert_eq!(
            g.to_file(DVec2::new(0.5, 0.5)),
            DVec2::new(1000.25, 5099.75)
        );
        // East is +x on the map, north is up (smaller rows).
        assert_eq!(g.pixel_of(DVec2::new(1199.9, 5000.1)), Some((399, 199)));
        assert_eq!(g.pixel_of(DVec2::new(1100.0, 5050.0)), Some((200, 100)));
        assert_eq!(g.pixel_of(DVec2::new(999.9, 5050.0)), None);
        assert_eq!(g.pixel_of(DVec2::new(1100.0, 5100.1)), None);
        for m in [DVec2::new(3.5, 7.25), DVec2::new(399.0, 0.0)] {
            assert!((g.to_map(g.to_file(m)) - m).length() < 1e-9, "{m}");
        }
    }

    #[test]
    fn a_tall_box_is_padded_to_whole_square_pixels_about_its_centre() {
        let g = MapGrid::over(DVec2::new(0.0, 0.0), DVec2::new(10.0, 30.0), 64);
        assert_eq!((g.width, g.height), (22, 64));
        assert!((g.pixel - 30.0 / 64.0).abs() < 1e-12);
        // 22 pixels span 10.3125 m, centred on x = 5.
        assert!((g.x0 - (5.0 - 11.0 * g.pixel)).abs() < 1e-12);
        assert_eq!(g.y1, 30.0);
        let single = MapGrid::over(DVec2::splat(7.0), DVec2::splat(7.0), 16);
        assert_eq!((single.width, single.height), (1, 1));
    }

    /// Two colours at known places: a low red point and a high green one 5 m further east.
    fn two_points() -> Scene {
        let mut scene = Scene::new(
            DVec3::new(500.0, 800.0, 10.0),
            vec![Vec3::new(-5.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 4.0)],
            0.4,
        );
        scene.attributes.rgb = Some(vec![[200, 0, 0], [0, 200, 0]]);
        scene
    }

    #[test]
    fn each_pixel_shows_the_highest_sphere_there_shaded_by_height() {
        let scene = two_points();
        let grid = MapGrid::over(DVec2::new(490.0, 790.0), DVec2::new(510.0, 810.0), 40);
        let map = render_map(&scene, &grid, ColorMode::Rgb).unwrap();
        let at = |x: f64, y: f64| {
            let (i, j) = grid.pixel_of(DVec2::new(x, y)).unwrap();
            map.color[map.index(i, j)]
        };
        // The high point at its full colour, the low one darkened to LOW_SHADE.
        assert_eq!(at(500.0, 800.0), [0, 200, 0, 255]);
        assert_eq!(at(495.0, 800.0), [90, 0, 0, 255]);
        // Gaps close up to FILL_PASSES pixels (0.5 m each) from a sphere's edge, no further.
        assert_eq!(at(501.75, 800.0), [0, 200, 0, 255]);
        assert_eq!(at(502.25, 800.0)[3], 0, "beyond the gap fill: background");
        let tops = splat_tops(&scene, &grid);
        assert_eq!(
            tops.iter().flatten().count(),
            2 * 4,
            "a 0.4 m sphere covers 2x2 half-metre pixels"
        );
    }

    #[test]
    fn gaps_between_sparse_points_close_and_open_land_stays_empty() {
        // Two 1-pixel points 4 pixels apart on a row of 12.
        let mut tops: Tops = vec![None; 12];
        tops[2] = Some((1.0, 0));
        tops[6] = Some((5.0, 1));
        fill_gaps(&mut tops, 12, 2);
        let owners: Vec<Option<u32>> = tops.iter().map(|t| t.map(|(_, o)| o)).collect();
        let (a, b, n) = (Some(0), Some(1), None);
        assert_eq!(owners, [a, a, a, a, b, b, b, b, b, n, n, n]);
    }

    #[test]
    fn a_higher_sphere_hides_a_lower_one_under_it() {
        let mut scene = two_points();
        scene.positions[0] = Vec3::new(0.0, 0.0, 1.0);
        scene.positions.push(Vec3::new(0.0, 0.0, -3.0));
        scene.attributes.rgb.as_mut().unwrap().push([0, 0, 200]);
        let grid = MapGrid::over(DVec2::new(499.0, 799.0), DVec2::new(501.0, 801.0), 4);
        let map = render_map(&scene, &grid, ColorMode::Rgb).unwrap();
        let (i, j) = grid.pixel_of(DVec2::new(500.2, 800.2)).unwrap();
        assert_eq!(map.color[map.index(i, j)], [0, 200, 0, 255]);
        assert!(render_map(&scene, &grid, ColorMode::Intensity).is_err());
    }
}
