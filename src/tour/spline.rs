//! The curve through the keyframes: a centripetal Catmull-Rom spline (no cusps or
//! self-intersections within a segment, unlike the uniform one), its arc-length table, and
//! positions and tangents at a given arc length.

use glam::DVec3;

/// Parameter steps per segment in the arc-length table: chords this fine differ from the
/// curve's length by far less than a millimetre per metre.
const STEPS_PER_SEGMENT: usize = 512;

/// A centripetal Catmull-Rom spline through at least two distinct points.
#[derive(Debug, Clone)]
pub struct Spline {
    /// Control points: the keyframes with one mirrored point before and after.
    points: Vec<DVec3>,
    /// Knots `t_i`, spaced by the square root of the distance between control points.
    knots: Vec<f64>,
    /// Arc length at each table entry; entry `k` is segment `k / STEPS`, step `k % STEPS`.
    table: Vec<f64>,
}

impl Spline {
    /// The spline through `keyframes` (consecutive duplicates must already be removed);
    /// `None` for fewer than two points or two equal neighbours.
    pub fn new(keyframes: &[DVec3]) -> Option<Spline> {
        let n = keyframes.len();
        if n < 2 || keyframes.windows(2).any(|w| w[0] == w[1]) {
            return None;
        }
        let mut points = Vec::with_capacity(n + 2);
        points.push(2.0 * keyframes[0] - keyframes[1]);
        points.extend_from_slice(keyframes);
        points.push(2.0 * keyframes[n - 1] - keyframes[n - 2]);
        let mut knots = vec![0.0];
        for w in points.windows(2) {
            let last = *knots.last().expect("one knot");
            knots.push(last + w[0].distance(w[1]).sqrt());
        }
        let mut spline = Spline {
            points,
            knots,
            table: Vec::new(),
        };
        let mut table = Vec::with_capacity((n - 1) * STEPS_PER_SEGMENT + 1);
        table.push(0.0);
        let mut previous = spline.at_parameter(0, 0.0);
        let mut length = 0.0;
        for segment in 0..n - 1 {
            for step in 1..=STEPS_PER_SEGMENT {
                let p = spline.at_parameter(segment, step as f64 / STEPS_PER_SEGMENT as f64);
                length += p.distance(previous);
                previous = p;
                table.push(length);
            }
        }
        spline.table = table;
        Some(spline)
    }

    /// Number of segments (keyframes - 1).
    pub fn segments(&self) -> usize {
        self.points.len() - 3
    }

    /// Total arc length, metres.
    pub fn length(&self) -> f64 {
        *self.table.last().expect("a table")
    }

    /// Arc length at keyframe `i`.
    pub fn keyframe_arc_length(&self, i: usize) -> f64 {
        self.table[i * STEPS_PER_SEGMENT]
    }

    /// The point of segment `segment` (from keyframe `segment` to the next) at `u` in [0, 1]
    /// (Barry and Goldman's pyramid over the centripetal knots).
    pub fn at_parameter(&self, segment: usize, u: f64) -> DVec3 {
        let p = &self.points[segment..segment + 4];
        let t = &self.knots[segment..segment + 4];
        let s = t[1] + u * (t[2] - t[1]);
        let lerp = |a: DVec3, b: DVec3, ta: f64, tb: f64| {
            a * ((tb - s) / (tb - ta)) + b * ((s - ta) / (tb - ta))
        };
        let a1 = lerp(p[0], p[1], t[0], t[1]);
        let a2 = lerp(p[1], p[2], t[1], t[2]);
        let a3 = lerp(p[2], p[3], t[2], t[3]);
        let b1 = lerp(a1, a2, t[0], t[2]);
        let b2 = lerp(a2, a3, t[1], t[3]);
        lerp(b1, b2, t[1], t[2])
    }

    /// The segment and parameter `u` in [0, 1] at arc length `s` (clamped to the curve).
    pub fn locate(&self, s: f64) -> (usize, f64) {
        let s = s.clamp(0.0, self.length());
        // The last entry whose length is <= s, kept below the table's end.
        let k = self
            .table
            .partition_point(|&l| l <= s)
            .saturating_sub(1)
            .min(self.table.len() - 2);
        let (l0, l1) = (self.table[k], self.table[k + 1]);
        let frac = if l1 > l0 { (s - l0) / (l1 - l0) } else { 0.0 };
        let segment = (k / STEPS_PER_SEGMENT).min(self.segments() - 1);
        let step = (k - segment * STEPS_PER_SEGMENT) as f64 + frac;
        (segment, (step / STEPS_PER_SEGMENT as f64).min(1.0))
    }

    /// The point at arc length `s`.
    pub fn position(&self, s: f64) -> DVec3 {
        let (segment, u) = self.locate(s);
        self.at_parameter(segment, u)
    }

    /// The unit tangent at arc length `s` (direction of travel).
    pub fn tangent(&self, s: f64) -> DVec3 {
        let (segment, u) = self.locate(s);
        let h = 1e-5;
        let (a, b) = ((u - h).max(0.0), (u + h).min(1.0));
        (self.at_parameter(segment, b) - self.at_parameter(segment, a)).normalize_or_zero()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Arc length of the curve between parameters, by a much finer polyline than the table's.
    fn fine_length(spline: &Spline, from: (usize, f64), to: (usize, f64)) -> f64 {
        let steps = 20_000;
        let mut total = 0.0;
        for segment in from.0..=to.0 {
            let u0 = if segment == from.0 { from.1 } else { 0.0 };
            let u1 = if segment == to.0 { to.1 } else { 1.0 };
            let mut prev = spline.at_parameter(segment, u0);
            for i in 1..=steps {
                let p = spline.at_parameter(segment, u0 + (u1 - u0) * i as f64 / steps as f64);
                total += p.distance(prev);
                prev = p;
            }
        }
        total
    }

    #[test]
    fn passes_through_the_keyframes() {
        let k = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(10.0, 0.0, 1.0),
            DVec3::new(10.0, 30.0, 2.0),
            DVec3::new(-5.0, 31.0, 2.0),
        ];
        let s = Spline::new(&k).unwrap();
        for (i, p) in k.iter().enumerate().take(3) {
            assert!((s.at_parameter(i, 0.0) - *p).length() < 1e-9);
            assert!((s.position(s.keyframe_arc_length(i)) - *p).length() < 1e-6);
        }
        assert!((s.at_parameter(2, 1.0) - k[3]).length() < 1e-9);
        assert!((s.position(s.length()) - k[3]).length() < 1e-9);
    }

    #[test]
    fn a_straight_line_is_itself() {
        let s = Spline::new(&[DVec3::ZERO, DVec3::new(3.0, 4.0, 0.0)]).unwrap();
        assert!((s.length() - 5.0).abs() < 1e-9, "{}", s.length());
        assert!((s.position(2.5) - DVec3::new(1.5, 2.0, 0.0)).length() < 1e-9);
        assert!((s.tangent(1.0) - DVec3::new(0.6, 0.8, 0.0)).length() < 1e-9);
    }

    #[test]
    fn refuses_too_few_or_repeated_points() {
        assert!(Spline::new(&[DVec3::ZERO]).is_none());
        assert!(Spline::new(&[DVec3::ZERO, DVec3::ZERO, DVec3::X]).is_none());
    }

    proptest! {
        /// Points found for equally spaced arc lengths are equally spaced along the curve, as a
        /// polyline forty times finer than the table measures it (within 0.1 %).
        #[test]
        fn sampling_is_at_constant_arc_length(
            raw in prop::collection::vec((-50.0f64..50.0, -50.0f64..50.0, -3.0f64..3.0), 2..6),
            samples in 3usize..12,
        ) {
            let mut k: Vec<DVec3> = raw.iter().map(|&(x, y, z)| DVec3::new(x, y, z)).collect();
            k.dedup_by(|a, b| a.distance(*b) < 0.5);
            prop_assume!(k.len() >= 2);
            let spline = Spline::new(&k).unwrap();
            let step = spline.length() / (samples - 1) as f64;
            let at: Vec<(usize, f64)> =
                (0..samples).map(|i| spline.locate(i as f64 * step)).collect();
            for w in at.windows(2) {
                let measured = fine_length(&spline, w[0], w[1]);
                prop_assert!((measured - step).abs() <= 1e-3 * step + 1e-6,
                    "{measured} vs {step}");
            }
        }
    }
}
