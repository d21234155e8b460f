// A building's walls and roof as an ASCII PLY: the stand-in for a real façade scan whose
// licence keeps it out of the repository. Like that scan it has float x/y/z, normals and an
// int `segment_index` (properties a reader must skip), no colour, and its points in no
// spatial order, so any block of the file samples the whole building. No inner doc comment:
// the library's unit tests `include!` this file too.

use std::fmt::Write as _;
use std::path::Path;

/// Points in the file.
pub const BUILDING_POINTS: usize = 100_000;

/// One planar face: a corner, its two edges, its outward normal.
struct Face {
    corner: [f64; 3],
    u: [f64; 3],
    v: [f64; 3],
    normal: [f64; 3],
}

impl Face {
    fn area(&self) -> f64 {
        let len = |a: [f64; 3]| a.iter().map(|c| c * c).sum::<f64>().sqrt();
        len(self.u) * len(self.v)
    }
}

/// A 16 m x 55 m block with walls from 3.2 m below the origin to 7.9 m above it under a flat
/// roof, and a 4 m tower on the roof's south end: nine faces, `segment_index` 0 to 8.
fn faces() -> Vec<Face> {
    let (x0, x1, y0, y1, z0, z1) = (-7.5, 8.3, -32.6, 22.2, -3.2, 7.9);
    let (tx0, tx1, ty0, ty1, tz1) = (-2.0, 4.0, -30.0, -24.0, 11.9);
    let face = |corner, u, v, normal| Face {
        corner,
        u,
        v,
        normal,
    };
    let (w, d, h) = (x1 - x0, y1 - y0, z1 - z0);
    let (tw, td, th) = (tx1 - tx0, ty1 - ty0, tz1 - z1);
    vec![
        face([x0, y0, z0], [w, 0.0, 0.0], [0.0, 0.0, h], [0.0, -1.0, 0.0]),
        face([x0, y1, z0], [w, 0.0, 0.0], [0.0, 0.0, h], [0.0, 1.0, 0.0]),
        face([x0, y0, z0], [0.0, d, 0.0], [0.0, 0.0, h], [-1.0, 0.0, 0.0]),
        face([x1, y0, z0], [0.0, d, 0.0], [0.0, 0.0, h], [1.0, 0.0, 0.0]),
        face([x0, y0, z1], [w, 0.0, 0.0], [0.0, d, 0.0], [0.0, 0.0, 1.0]),
        face(
            [tx0, ty0, z1],
            [tw, 0.0, 0.0],
            [0.0, 0.0, th],
            [0.0, -1.0, 0.0],
        ),
        face(
            [tx0, ty1, z1],
            [tw, 0.0, 0.0],
            [0.0, 0.0, th],
            [0.0, 1.0, 0.0],
        ),
        face(
            [tx0, ty0, z1],
            [0.0, td, 0.0],
            [0.0, 0.0, th],
            [-1.0, 0.0, 0.0],
        ),
        face(
            [tx0, ty0, tz1],
            [tw, 0.0, 0.0],
            [0.0, td, 0.0],
            [0.0, 0.0, 1.0],
        ),
    ]
}

/// SplitMix64: a fixed seed gives the same file on every machine.
struct Rng(u64);

impl Rng {
    /// Uniform in [0, 1).
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The file's text: each point on a face drawn in proportion to its area, 5 mm of noise
/// along the face's normal, coordinates to the tenth of a millimetre.
pub fn building_ply_text() -> String {
    let faces = faces();
    let total: f64 = faces.iter().map(Face::area).sum();
    let mut rng = Rng(0x6275_696c_6469_6e67);
    let mut text = String::with_capacity(BUILDING_POINTS * 56);
    text.push_str("ply\nformat ascii 1.0\ncomment a generated building\n");
    writeln!(text, "element vertex {BUILDING_POINTS}").unwrap();
    for name in ["x", "y", "z", "nx", "ny", "nz"] {
        writeln!(text, "property float {name}").unwrap();
    }
    text.push_str("property int segment_index\nend_header\n");
    for _ in 0..BUILDING_POINTS {
        let mut pick = rng.next() * total;
        let index = faces
            .iter()
            .position(|f| {
                pick -= f.area();
                pick < 0.0
            })
            .unwrap_or(faces.len() - 1);
        let f = &faces[index];
        let (s, t, noise) = (rng.next(), rng.next(), 0.01 * (rng.next() - 0.5));
        let p: [f64; 3] =
            std::array::from_fn(|k| f.corner[k] + s * f.u[k] + t * f.v[k] + noise * f.normal[k]);
        let n = f.normal;
        writeln!(
            text,
            "{:.4} {:.4} {:.4} {} {} {} {index}",
            p[0], p[1], p[2], n[0], n[1], n[2]
        )
        .unwrap();
    }
    text
}

/// Writes the file to `path`.
pub fn write_building_ply(path: &Path) -> std::io::Result<()> {
    std::fs::write(path, building_ply_text())
}
