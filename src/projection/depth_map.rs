//! The depth budget `--depth-map B0=D0,...,Bn=Dn` (DESIGN §9): how far away each sphere is
//! made to look, as a per-sphere ODS radius.
//!
//! With `a = ipd/2` and `s(D) = a/D`, a sphere whose centre lies at horizontal distance
//! `rho_c` from the camera gets the scale `s` below and the ODS radius `r_s = rho_c * s`; its
//! centre is then seen at the disparity of a point at distance `a/s` (`2 asin(s)`).
//!
//! Identity pairs (`Bi == Di`) give `r_s = a` up to rounding for every `rho_c >= B0`;
//! spheres nearer than `B0` still get `s(D0)`, the disparity of `B0`.

use std::fmt;
use std::str::FromStr;

/// Most breakpoints a depth map holds (the size of the shader's arrays).
pub const MAX_PAIRS: usize = 8;

/// Why a depth map was rejected; every message names the pair at fault (1-based).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DepthMapError {
    /// No pair at all.
    #[error("the depth map needs at least one pair `B=D` (metres), e.g. `0.5=1.5`")]
    Empty,
    /// More than [`MAX_PAIRS`] pairs.
    #[error("the depth map has {count} pairs, at most {MAX_PAIRS} are allowed")]
    TooMany {
        /// Pairs given.
        count: usize,
    },
    /// A pair is not of the form `B=D`.
    #[error("depth map pair {index} `{pair}`: expected `B=D` (two distances in metres)")]
    Syntax {
        /// 1-based position of the pair.
        index: usize,
        /// The pair as written.
        pair: String,
    },
    /// `B` or `D` of a pair is not a number.
    #[error("depth map pair {index} `{pair}`: {field} is not a number")]
    NotANumber {
        /// 1-based position of the pair.
        index: usize,
        /// The pair as written.
        pair: String,
        /// `B` or `D`.
        field: &'static str,
    },
    /// `B` or `D` of a pair is not finite and positive.
    #[error("depth map pair {index} `{pair}`: {field} must be finite and > 0 metres")]
    NotPositive {
        /// 1-based position of the pair.
        index: usize,
        /// The pair as written.
        pair: String,
        /// `B` or `D`.
        field: &'static str,
    },
    /// `B` or `D` does not exceed the previous pair's.
    #[error(
        "depth map pair {index} `{pair}`: {field} must be greater than the previous pair's ({previous})"
    )]
    NotIncreasing {
        /// 1-based position of the pair.
        index: usize,
        /// The pair as written.
        pair: String,
        /// `B` or `D`.
        field: &'static str,
        /// The previous pair's value of `field`.
        previous: f64,
    },
}

/// Breakpoints `Bi` (horizontal distances of sphere centres) and the distances `Di` they are
/// made to look at, metres; both strictly increasing, 1 to [`MAX_PAIRS`] pairs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthMap {
    b: [f64; MAX_PAIRS],
    d: [f64; MAX_PAIRS],
    len: usize,
}

impl DepthMap {
    /// The map of `pairs` `(Bi, Di)`.
    ///
    /// # Errors
    /// No pair, more than [`MAX_PAIRS`], a value not finite and > 0, or a sequence not
    /// strictly increasing; the error names the pair.
    pub fn new(pairs: &[(f64, f64)]) -> Result<Self, DepthMapError> {
        let written: Vec<String> = pairs.iter().map(|(b, d)| format!("{b}={d}")).collect();
        Self::checked(pairs, &written)
    }

    fn checked(pairs: &[(f64, f64)], written: &[String]) -> Result<Self, DepthMapError> {
        if pairs.is_empty() {
            return Err(DepthMapError::Empty);
        }
        if pairs.len() > MAX_PAIRS {
            return Err(DepthMapError::TooMany { count: pairs.len() });
        }
        let mut map = DepthMap {
            b: [0.0; MAX_PAIRS],
            d: [0.0; MAX_PAIRS],
            len: pairs.len(),
        };
        for (k, (&(b, d), pair)) in pairs.iter().zip(written).enumerate() {
            let index = k + 1;
            for (field, value) in [("B", b), ("D", d)] {
                if !(value.is_finite() && value > 0.0) {
                    return Err(DepthMapError::NotPositive {
                        index,
                        pair: pair.clone(),
                        field,
                    });
                }
            }
            if k > 0 {
                for (field, value, previous) in [("B", b, map.b[k - 1]), ("D", d, map.d[k - 1])] {
                    if value <= previous {
                        return Err(DepthMapError::NotIncreasing {
                            index,
                            pair: pair.clone(),
                            field,
                            previous,
                        });
                    }
                }
            }
            map.b[k] = b;
            map.d[k] = d;
        }
        Ok(map)
    }

    /// Number of pairs (at least 1).
    pub fn len(&self) -> usize {
        self.len
    }

    /// Always false: a map holds at least one pair.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The same map with every distance times `factor` (positive): its pairs measured in
    /// another unit of length.
    pub fn scaled(&self, factor: f64) -> DepthMap {
        let mut map = *self;
        for v in map.b[..map.len]
            .iter_mut()
            .chain(map.d[..map.len].iter_mut())
        {
            *v *= factor;
        }
        map
    }

    /// The pairs `(Bi, Di)` in order.
    pub fn pairs(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.b[..self.len]
            .iter()
            .copied()
            .zip(self.d[..self.len].iter().copied())
    }

    /// The breakpoints `Bi`, metres.
    pub fn breakpoints(&self) -> &[f64] {
        &self.b[..self.len]
    }

    /// The distances `Di`, metres.
    pub fn distances(&self) -> &[f64] {
        &self.d[..self.len]
    }

    /// `B` and `D` in f32, four to a `vec4` (pair `k` at `[k / 4][k % 4]`), unused slots
    /// repeating the last pair: the arrays `depth_map_scale` in `shaders/depth_map.wgsl` takes.
    pub fn packed_f32(&self) -> ([[f32; 4]; 2], [[f32; 4]; 2]) {
        let pack = |values: &[f64]| {
            let mut out = [[0.0f32; 4]; 2];
            for k in 0..MAX_PAIRS {
                out[k / 4][k % 4] = values[k.min(values.len() - 1)] as f32;
            }
            out
        };
        (pack(self.breakpoints()), pack(self.distances()))
    }

    /// True when every `Bi == Di`: plain ODS for spheres at `rho_c >= B0`.
    pub fn is_identity(&self) -> bool {
        self.pairs().all(|(b, d)| b == d)
    }

    /// The scale `s` of a sphere whose centre lies at horizontal distance `rho_c` (metres)
    /// from the camera, for half interocular distance `half_ipd` (DESIGN §9):
    /// `s(D0)` up to `B0`, affine in `1/rho_c` between breakpoints, `s(Dn) * Bn / rho_c`
    /// beyond `Bn`, where `s(D) = half_ipd / D`.
    pub fn scale(&self, half_ipd: f64, rho_c: f64) -> f64 {
        let s = |d: f64| half_ipd / d;
        let (b, d) = (self.breakpoints(), self.distances());
        if rho_c <= b[0] {
            return s(d[0]);
        }
        for i in 0..self.len - 1 {
            if rho_c <= b[i + 1] {
                let t = (1.0 / b[i] - 1.0 / rho_c) / (1.0 / b[i] - 1.0 / b[i + 1]);
                return s(d[i]) + t * (s(d[i + 1]) - s(d[i]));
            }
        }
        let n = self.len - 1;
        // `Bn / rho_c` is exactly 1 at `rho_c = Bn`, so the last piece starts at `s(Dn)`.
        s(d[n]) * (b[n] / rho_c)
    }

    /// The sphere's own ODS radius `r_s = rho_c * scale(half_ipd, rho_c)`, metres.
    pub fn ods_radius(&self, half_ipd: f64, rho_c: f64) -> f64 {
        rho_c * self.scale(half_ipd, rho_c)
    }
}

impl FromStr for DepthMap {
    type Err = DepthMapError;

    /// Parses `B0=D0,B1=D1,...` (metres; spaces around numbers allowed).
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        if text.trim().is_empty() {
            return Err(DepthMapError::Empty);
        }
        let written: Vec<String> = text.split(',').map(|p| p.trim().to_owned()).collect();
        if written.len() > MAX_PAIRS {
            return Err(DepthMapError::TooMany {
                count: written.len(),
            });
        }
        let mut pairs = Vec::with_capacity(written.len());
        for (k, pair) in written.iter().enumerate() {
            let index = k + 1;
            let Some((b, d)) = pair.split_once('=') else {
                return Err(DepthMapError::Syntax {
                    index,
                    pair: pair.clone(),
                });
            };
            let number = |field: &'static str, v: &str| {
                v.trim()
                    .parse::<f64>()
                    .map_err(|_| DepthMapError::NotANumber {
                        index,
                        pair: pair.clone(),
                        field,
                    })
            };
            pairs.push((number("B", b)?, number("D", d)?));
        }
        Self::checked(&pairs, &written)
    }
}

impl fmt::Display for DepthMap {
    /// `B0=D0,B1=D1,...` with the shortest decimals that read back to the same values.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, (b, d)) in self.pairs().enumerate() {
            if k > 0 {
                f.write_str(",")?;
            }
            write!(f, "{b}={d}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: f64 = 0.032;

    fn map(text: &str) -> DepthMap {
        text.parse().unwrap()
    }

    fn err(text: &str) -> String {
        text.parse::<DepthMap>().unwrap_err().to_string()
    }

    #[test]
    fn parses_and_prints_round_trip() {
        for text in ["0.5=1.5", "0.5=1.5,2=3,10=12.25", "1e-3=0.1,7=8"] {
            let m = map(text);
            assert_eq!(map(&m.to_string()), m);
        }
        assert_eq!(map(" 0.5 = 1.5 , 2=3 ").to_string(), "0.5=1.5,2=3");
        let m = map("0.5=1.5,2=3");
        assert_eq!(m.len(), 2);
        assert_eq!(m.pairs().collect::<Vec<_>>(), vec![(0.5, 1.5), (2.0, 3.0)]);
        let eight = (1..=8).map(|k| format!("{k}={k}")).collect::<Vec<_>>();
        assert_eq!(map(&eight.join(",")).len(), MAX_PAIRS);
        assert_eq!(DepthMap::new(&[(0.5, 1.5)]).unwrap(), map("0.5=1.5"));
    }

    #[test]
    fn bad_maps_name_the_pair() {
        assert!(err("").contains("at least one pair"));
        assert!(err("0.5").contains("pair 1 `0.5`: expected `B=D`"));
        assert!(err("1=2,x=3").contains("pair 2 `x=3`: B is not a number"));
        assert!(err("1=2,3=").contains("pair 2 `3=`: D is not a number"));
        assert!(err("0=1").contains("pair 1 `0=1`: B must be finite and > 0"));
        assert!(err("1=-2").contains("pair 1 `1=-2`: D must be finite and > 0"));
        assert!(err("1=inf").contains("D must be finite"));
        assert!(err("1=NaN").contains("D must be finite"));
        assert!(
            err("1=2,1=3").contains("pair 2 `1=3`: B must be greater than the previous pair's (1)")
        );
        assert!(
            err("1=2,3=2").contains("pair 2 `3=2`: D must be greater than the previous pair's (2)")
        );
        let nine = (1..=9).map(|k| format!("{k}={k}")).collect::<Vec<_>>();
        assert!(err(&nine.join(",")).contains("9 pairs, at most 8"));
        assert!(DepthMap::new(&[]).is_err());
    }

    #[test]
    fn identity_pairs_give_the_plain_ods_radius_beyond_the_first_breakpoint() {
        let m = map("0.5=0.5,1=1,3=3,20=20");
        assert!(m.is_identity());
        assert!(!map("0.5=1.5").is_identity());
        let mut worst = 0.0f64;
        for k in 0..4000 {
            let rho = 0.5 * 1.002f64.powi(k);
            worst = worst.max((m.ods_radius(A, rho) - A).abs() / A);
        }
        // Measured worst relative error 1.95e-15 (the affine pieces round, ~9 ulps of `a`).
        assert!(worst <= 2.5e-15, "worst relative error {worst:e}");
        // Nearer than B0 the sphere keeps the disparity of B0: a smaller radius.
        assert_eq!(m.scale(A, 0.25), A / 0.5);
        assert_eq!(m.ods_radius(A, 0.25), 0.25 * (A / 0.5));
    }

    #[test]
    fn one_pair_pushes_near_spheres_back_and_scales_far_ones() {
        let m = map("0.5=1.5");
        let s15 = A / 1.5;
        for rho in [0.01, 0.2, 0.5] {
            assert_eq!(m.scale(A, rho), s15);
            // The centre's disparity 2 asin(s) is that of a point 1.5 m away.
            let disparity = 2.0 * m.scale(A, rho).asin();
            assert!((disparity - 2.0 * (A / 1.5).asin()).abs() < 1e-15);
        }
        for rho in [0.6, 1.0, 1.5, 10.0] {
            assert_eq!(m.scale(A, rho), s15 * (0.5 / rho));
            assert_eq!(m.ods_radius(A, rho), rho * (s15 * (0.5 / rho)));
        }
        assert!(m.scale(A, 10.0) < m.scale(A, 1.0));
    }

    #[test]
    fn scale_is_continuous_at_every_breakpoint() {
        let m = map("0.4=1,1=2,2.5=3,6=10");
        for &b in m.breakpoints() {
            let below = m.scale(A, b * (1.0 - 1e-12));
            let at = m.scale(A, b);
            let above = m.scale(A, b * (1.0 + 1e-12));
            // A step of 1e-12 in rho moves s by ~1e-12 relative; a jump would be ~1e-1.
            assert!(
                (below - at).abs() <= 1e-10 * at,
                "below {b}: {below} vs {at}"
            );
            assert!(
                (above - at).abs() <= 1e-10 * at,
                "above {b}: {above} vs {at}"
            );
        }
        // At Bi the interpolation reaches s(Di) (t = 1 exactly).
        for (b, d) in m.pairs() {
            assert!((m.scale(A, b) - A / d).abs() <= 1e-17, "at {b}");
        }
    }

    #[test]
    fn packs_pairs_four_to_a_vec4() {
        let (b, d) = map("0.5=1.5,2=3,4=5,6=7,8=9").packed_f32();
        assert_eq!(b, [[0.5, 2.0, 4.0, 6.0], [8.0, 8.0, 8.0, 8.0]]);
        assert_eq!(d, [[1.5, 3.0, 5.0, 7.0], [9.0, 9.0, 9.0, 9.0]]);
    }

    #[cfg(feature = "gpu")]
    #[test]
    fn wgsl_mirror_parses_and_validates() {
        use wgpu::naga::valid::{Capabilities, ValidationFlags, Validator};
        let source = include_str!("../../shaders/depth_map.wgsl");
        let module = wgpu::naga::front::wgsl::parse_str(source)
            .unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
        Validator::new(ValidationFlags::all(), Capabilities::all())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
        let names: Vec<_> = module
            .functions
            .iter()
            .filter_map(|(_, f)| f.name.clone())
            .collect();
        assert!(names.contains(&"depth_map_scale".to_string()), "{names:?}");
        assert!(
            names.contains(&"depth_map_ods_radius".to_string()),
            "{names:?}"
        );
    }

    #[test]
    fn scale_never_grows_with_distance() {
        for m in [map("0.5=1.5"), map("0.4=1,1=2,2.5=3,6=10"), map("1=1,2=8")] {
            let mut last = f64::INFINITY;
            for k in 0..3000 {
                let rho = 0.01 * 1.003f64.powi(k);
                let s = m.scale(A, rho);
                assert!(s <= last, "{m}: s grows at rho {rho}");
                last = s;
            }
        }
    }
}
