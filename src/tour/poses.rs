//! Frame poses along the curve: constant speed (or a frame count), heading along the tangent
//! with heading changes smoothed, or the file's yaw interpolated between keyframes (DESIGN §10).

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use super::spline::Spline;

/// How frames are spaced along the curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sampling {
    /// Frame `k` at arc length `k * speed / fps`, up to the end of the curve.
    Speed {
        /// Metres per second.
        speed: f64,
        /// Frames per second.
        fps: f64,
    },
    /// `N` frames, frame `k` at arc length `k * L / (N - 1)` (the first at the start, the
    /// last at the end).
    Frames(usize),
}

impl Sampling {
    /// Arc lengths of the frames on a curve `length` metres long.
    pub fn arc_lengths(&self, length: f64) -> Vec<f64> {
        match *self {
            Sampling::Speed { speed, fps } => {
                let step = speed / fps;
                // A frame that lands on the end up to rounding still counts.
                let n = (length / step * (1.0 + 1e-12)).floor() as usize + 1;
                (0..n).map(|k| (k as f64 * step).min(length)).collect()
            }
            Sampling::Frames(1) => vec![0.0],
            Sampling::Frames(n) => (0..n).map(|k| length * k as f64 / (n - 1) as f64).collect(),
        }
    }
}

/// One frame's camera, in file coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Camera centre, file coordinates.
    pub position: [f64; 3],
    /// Heading in degrees, in (-180, 180] (DESIGN §1).
    pub yaw: f64,
    /// Pitch in degrees: positive looks up (DESIGN §8).
    #[serde(default)]
    pub pitch: f64,
    /// Roll in degrees: positive turns the rig clockwise as seen from behind it.
    #[serde(default)]
    pub roll: f64,
    /// Arc length along the curve from its start, metres.
    pub arc_length: f64,
}

/// Where headings come from.
#[derive(Debug, Clone, PartialEq)]
pub enum Heading {
    /// Along the curve's tangent, `yaw = atan2(dx, dy)`, averaged over `window` metres of
    /// path centred on the frame (0: the tangent itself) so that turns at keyframes ease in.
    Tangent {
        /// Metres of path the tangent is averaged over.
        window: f64,
    },
    /// The file's yaw at each keyframe (degrees), interpolated between keyframes by a
    /// Catmull-Rom curve over the unwrapped angles (continuous turning rate).
    Keyframes(Vec<f64>),
}

/// The poses of every frame on `spline` under `sampling` and `heading`, with `yaw_offset`
/// degrees added to every heading.
pub fn sample(
    spline: &Spline,
    sampling: Sampling,
    heading: &Heading,
    yaw_offset: f64,
) -> Vec<Pose> {
    let mut previous = 0.0;
    sampling
        .arc_lengths(spline.length())
        .into_iter()
        .map(|s| {
            let yaw = match heading {
                Heading::Tangent { window } => tangent_yaw(spline, s, *window).unwrap_or(previous),
                Heading::Keyframes(yaws) => {
                    let (segment, u) = spline.locate(s);
                    keyframe_yaw(yaws, segment, u)
                }
            };
            previous = yaw;
            Pose {
                position: spline.position(s).to_array(),
                yaw: wrap_degrees(yaw + yaw_offset),
                pitch: 0.0,
                roll: 0.0,
                arc_length: s,
            }
        })
        .collect()
}

/// Sets each pose's pitch and roll: the keyframes' values (one per keyframe of `spline`,
/// interpolated like keyframe headings) plus `pitch_offset` and `roll_offset` degrees.
pub fn tilt(
    poses: &mut [Pose],
    spline: &Spline,
    keyframes: Option<(&[f64], &[f64])>,
    pitch_offset: f64,
    roll_offset: f64,
) {
    for pose in poses {
        let (pitch, roll) = match keyframes {
            Some((pitches, rolls)) => {
                let (segment, u) = spline.locate(pose.arc_length);
                (
                    keyframe_yaw(pitches, segment, u),
                    keyframe_yaw(rolls, segment, u),
                )
            }
            None => (0.0, 0.0),
        };
        pose.pitch = pitch + pitch_offset;
        pose.roll = wrap_degrees(roll + roll_offset);
    }
}

/// `yaw = atan2(dx, dy)` (degrees) of a horizontal direction; `None` when it has no
/// horizontal part.
pub fn yaw_of(direction: DVec2) -> Option<f64> {
    (direction.length() > 1e-9).then(|| direction.x.atan2(direction.y).to_degrees())
}

/// Heading of the tangent averaged (triangular weights) over `window` metres around `s`.
fn tangent_yaw(spline: &Spline, s: f64, window: f64) -> Option<f64> {
    const TAPS: i32 = 8;
    let mut sum = DVec2::ZERO;
    for i in -TAPS..=TAPS {
        let weight = f64::from(TAPS + 1 - i.abs());
        let at = s + window * 0.5 * f64::from(i) / f64::from(TAPS);
        let t: DVec3 = spline.tangent(at.clamp(0.0, spline.length()));
        sum += weight * t.truncate().normalize_or_zero();
    }
    yaw_of(sum)
}

/// The keyframe yaws unwrapped (each within 180° of the one before) and interpolated by a
/// uniform Catmull-Rom curve at `u` of `segment`.
fn keyframe_yaw(yaws: &[f64], segment: usize, u: f64) -> f64 {
    let mut unwrapped = Vec::with_capacity(yaws.len());
    for &y in yaws {
        let y = match unwrapped.last() {
            Some(&prev) => prev + wrap_degrees(y - prev),
            None => y,
        };
        unwrapped.push(y);
    }
    let n = unwrapped.len();
    if n == 1 {
        return unwrapped[0];
    }
    let at = |i: isize| -> f64 {
        if i < 0 {
            2.0 * unwrapped[0] - unwrapped[1]
        } else if i as usize >= n {
            2.0 * unwrapped[n - 1] - unwrapped[n - 2]
        } else {
            unwrapped[i as usize]
        }
    };
    let i = segment as isize;
    let (p0, p1, p2, p3) = (at(i - 1), at(i), at(i + 1), at(i + 2));
    0.5 * (2.0 * p1
        + (p2 - p0) * u
        + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * u * u
        + (3.0 * p1 - p0 - 3.0 * p2 + p3) * u * u * u)
}

/// An angle in degrees brought into (-180, 180].
pub fn wrap_degrees(a: f64) -> f64 {
    let w = (a + 180.0).rem_euclid(360.0) - 180.0;
    if w == -180.0 { 180.0 } else { w }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn speed_and_frame_counts_space_frames_as_the_design_says() {
        let s = Sampling::Speed {
            speed: 1.5,
            fps: 30.0,
        };
        let a = s.arc_lengths(1.0);
        assert_eq!(a.len(), 21);
        assert!((a[20] - 1.0).abs() < 1e-12 && (a[1] - 0.05).abs() < 1e-12);
        let f = Sampling::Frames(5).arc_lengths(8.0);
        assert_eq!(f, vec![0.0, 2.0, 4.0, 6.0, 8.0]);
        assert_eq!(Sampling::Frames(1).arc_lengths(8.0), vec![0.0]);
    }

    #[test]
    fn headings_follow_the_tangent_and_ease_through_a_corner() {
        // East 20 m, then north 20 m: heading 90 on the first leg, 0 on the second.
        let spline = Spline::new(&[
            DVec3::ZERO,
            DVec3::new(20.0, 0.0, 0.0),
            DVec3::new(20.0, 20.0, 0.0),
        ])
        .unwrap();
        let poses = sample(
            &spline,
            Sampling::Frames(41),
            &Heading::Tangent { window: 2.0 },
            0.0,
        );
        assert!((poses[0].yaw - 90.0).abs() < 1.0, "{}", poses[0].yaw);
        assert!(poses[40].yaw.abs() < 1.0, "{}", poses[40].yaw);
        // The turn is spread: no step above 20 degrees a metre (measured 14.7), and the curve
        // bows out by under 3 degrees (measured 2.0) before it turns.
        let steps: Vec<f64> = poses.windows(2).map(|w| w[1].yaw - w[0].yaw).collect();
        let (lo, hi) = steps
            .iter()
            .fold((0.0f64, 0.0f64), |(a, b), &d| (a.min(d), b.max(d)));
        eprintln!("heading steps per metre: {lo:.2} .. {hi:.2}");
        assert!(lo > -20.0 && hi < 3.0, "{steps:?}");
    }

    #[test]
    fn keyframe_pitch_and_roll_interpolate_between_keyframes() {
        let spline = Spline::new(&[DVec3::ZERO, DVec3::new(0.0, 10.0, 0.0)]).unwrap();
        let mut poses = sample(
            &spline,
            Sampling::Frames(3),
            &Heading::Tangent { window: 0.0 },
            0.0,
        );
        tilt(
            &mut poses,
            &spline,
            Some((&[0.0, 20.0], &[-10.0, 10.0])),
            5.0,
            0.0,
        );
        assert!((poses[0].pitch - 5.0).abs() < 1e-9);
        assert!((poses[1].pitch - 15.0).abs() < 1e-9, "{}", poses[1].pitch);
        assert!((poses[2].pitch - 25.0).abs() < 1e-9);
        assert!(poses[1].roll.abs() < 1e-9 && (poses[2].roll - 10.0).abs() < 1e-9);
        tilt(&mut poses, &spline, None, 0.0, -30.0);
        assert!(poses.iter().all(|p| p.pitch == 0.0 && p.roll == -30.0));
    }

    #[test]
    fn keyframe_yaws_interpolate_across_the_seam() {
        // 170 -> -170 turns 20 degrees through 180, not 340 the other way.
        let y = keyframe_yaw(&[170.0, -170.0], 0, 0.5);
        assert!((wrap_degrees(y) - 180.0).abs() < 1e-9, "{y}");
        assert!((keyframe_yaw(&[10.0, 20.0, 40.0], 1, 0.0) - 20.0).abs() < 1e-12);
        assert_eq!(wrap_degrees(-180.0), 180.0);
        assert_eq!(wrap_degrees(540.0), 180.0);
        assert!((wrap_degrees(-190.0) - 170.0).abs() < 1e-12);
    }
}
