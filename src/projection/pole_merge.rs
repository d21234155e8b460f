//! Pole merging: how the interocular distance shrinks towards the poles (DESIGN §4).

use std::f64::consts::FRAC_PI_2;
use std::str::FromStr;

use crate::value::finite;

/// One pole's merge profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PoleMerge {
    /// Full interocular distance at every latitude.
    Off,
    /// Marrinan & Papka: start and end angles from the pole (degrees), exponent.
    Marrinan {
        /// Angle from the pole where merging starts (0 disables merging).
        start_deg: f64,
        /// Angle from the pole where the eyes have fully merged.
        end_deg: f64,
        /// Falloff exponent.
        exponent: f64,
    },
    /// Blender Cycles: altitudes from the horizon (degrees) between which `cos` falls off.
    Cycles {
        /// Altitude where merging starts (Cycles' default 60).
        from_deg: f64,
        /// Altitude where the eyes have fully merged (Cycles' default 75).
        to_deg: f64,
    },
}

impl PoleMerge {
    /// The "comfortable" Marrinan preset: start 45°, end 0°, exponent 3.
    pub const COMFORTABLE: PoleMerge = PoleMerge::Marrinan {
        start_deg: 45.0,
        end_deg: 0.0,
        exponent: 3.0,
    };

    /// Cycles' default profile (from 60°, to 75°).
    pub const CYCLES_DEFAULT: PoleMerge = PoleMerge::Cycles {
        from_deg: 60.0,
        to_deg: 75.0,
    };

    /// The merge factor in [0, 1] at absolute latitude `abs_phi` (radians).
    pub fn factor(&self, abs_phi: f64) -> f64 {
        let deg = abs_phi.abs().min(FRAC_PI_2).to_degrees();
        match *self {
            PoleMerge::Off => 1.0,
            PoleMerge::Marrinan {
                start_deg,
                end_deg,
                exponent,
            } => {
                if start_deg <= 0.0 {
                    return 1.0;
                }
                let lo = 90.0 - start_deg;
                let hi = 90.0 - end_deg;
                let f = if hi > lo {
                    ((deg - lo) / (hi - lo)).clamp(0.0, 1.0)
                } else if deg >= lo {
                    1.0
                } else {
                    0.0
                };
                (1.0 - f).powf(exponent)
            }
            PoleMerge::Cycles { from_deg, to_deg } => {
                if deg <= from_deg {
                    1.0
                } else if deg >= to_deg {
                    0.0
                } else {
                    let fac = (deg - from_deg) / (to_deg - from_deg);
                    (fac * FRAC_PI_2).cos()
                }
            }
        }
    }

    /// The latitude (radians, from the horizon) above which the factor is 0, if any.
    pub fn full_merge_latitude(&self) -> Option<f64> {
        match *self {
            PoleMerge::Off => None,
            PoleMerge::Marrinan {
                start_deg, end_deg, ..
            } if start_deg > 0.0 => Some((90.0 - end_deg).to_radians()),
            PoleMerge::Marrinan { .. } => None,
            PoleMerge::Cycles { to_deg, .. } => Some(to_deg.to_radians()),
        }
    }
}

/// `off`, `marrinan:START,END,EXP` or `cycles:FROM,TO` (degrees): what [`FromStr`] reads back
/// to the same profile.
impl std::fmt::Display for PoleMerge {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            PoleMerge::Off => f.write_str("off"),
            PoleMerge::Marrinan {
                start_deg,
                end_deg,
                exponent,
            } => write!(f, "marrinan:{start_deg},{end_deg},{exponent}"),
            PoleMerge::Cycles { from_deg, to_deg } => write!(f, "cycles:{from_deg},{to_deg}"),
        }
    }
}

/// `off`, `comfortable`, `cycles`, `marrinan:START,END,EXP` or `cycles:FROM,TO` (degrees), as
/// `--pole-merge` and the suite manifest spell a profile.
impl FromStr for PoleMerge {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let s = s.trim();
        let numbers = |args: &str, n: usize, form: &str| -> Result<Vec<f64>, String> {
            let v: Result<Vec<f64>, String> = args
                .split(',')
                .map(|p| finite(p, "pole-merge angle"))
                .collect();
            let v = v?;
            if v.len() != n {
                return Err(format!("expected {form}, got `{s}`"));
            }
            Ok(v)
        };
        match s.split_once(':') {
            None => match s.to_ascii_lowercase().as_str() {
                "off" | "none" => Ok(PoleMerge::Off),
                "comfortable" | "marrinan" => Ok(PoleMerge::COMFORTABLE),
                "cycles" => Ok(PoleMerge::CYCLES_DEFAULT),
                _ => Err(format!(
                    "unknown pole merge `{s}`: use off, comfortable, cycles, \
                     marrinan:START,END,EXP or cycles:FROM,TO"
                )),
            },
            Some((kind, args)) => match kind.to_ascii_lowercase().as_str() {
                "marrinan" => {
                    let v = numbers(args, 3, "marrinan:START,END,EXP")?;
                    let (start, end, exp) = (v[0], v[1], v[2]);
                    if !(0.0..=90.0).contains(&start) || !(0.0..=start).contains(&end) {
                        return Err(format!(
                            "marrinan angles are measured from the pole: need 0 <= END <= START <= 90, got `{s}`"
                        ));
                    }
                    if exp <= 0.0 {
                        return Err(format!("the marrinan exponent must be > 0, got `{s}`"));
                    }
                    Ok(PoleMerge::Marrinan {
                        start_deg: start,
                        end_deg: end,
                        exponent: exp,
                    })
                }
                "cycles" => {
                    let v = numbers(args, 2, "cycles:FROM,TO")?;
                    if !(0.0..=90.0).contains(&v[0])
                        || !(v[0]..=90.0).contains(&v[1])
                        || v[0] == v[1]
                    {
                        return Err(format!(
                            "cycles angles are altitudes from the horizon: need 0 <= FROM < TO <= 90, got `{s}`"
                        ));
                    }
                    Ok(PoleMerge::Cycles {
                        from_deg: v[0],
                        to_deg: v[1],
                    })
                }
                _ => Err(format!(
                    "unknown pole merge `{kind}`: use marrinan:START,END,EXP or cycles:FROM,TO"
                )),
            },
        }
    }
}

/// Merge profiles for both poles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoleMerging {
    /// Profile for latitudes above the horizon.
    pub north: PoleMerge,
    /// Profile for latitudes below the horizon.
    pub south: PoleMerge,
}

impl PoleMerging {
    /// No merging at either pole.
    pub const OFF: PoleMerging = PoleMerging {
        north: PoleMerge::Off,
        south: PoleMerge::Off,
    };

    /// The same profile at both poles.
    pub const fn both(profile: PoleMerge) -> Self {
        PoleMerging {
            north: profile,
            south: profile,
        }
    }

    /// The merge factor at latitude `phi` (radians), using the profile of its hemisphere.
    #[inline]
    pub fn factor(&self, phi: f64) -> f64 {
        if phi >= 0.0 {
            self.north.factor(phi)
        } else {
            self.south.factor(-phi)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profiles_print_as_they_parse() {
        for p in [
            PoleMerge::Off,
            PoleMerge::COMFORTABLE,
            PoleMerge::CYCLES_DEFAULT,
            "marrinan:37.5,2.25,1.5".parse().unwrap(),
        ] {
            assert_eq!(p.to_string().parse::<PoleMerge>(), Ok(p), "{p}");
        }
        assert_eq!(PoleMerge::COMFORTABLE.to_string(), "marrinan:45,0,3");
    }

    #[test]
    fn marrinan_comfortable_preset() {
        let p = PoleMerge::COMFORTABLE;
        assert_eq!(p.factor(0.0), 1.0);
        assert_eq!(p.factor(45f64.to_radians()), 1.0);
        assert!((p.factor(67.5f64.to_radians()) - 0.125).abs() < 1e-12);
        assert_eq!(p.factor(FRAC_PI_2), 0.0);
    }

    #[test]
    fn marrinan_start_zero_disables() {
        let p = PoleMerge::Marrinan {
            start_deg: 0.0,
            end_deg: 0.0,
            exponent: 1.0,
        };
        assert_eq!(p.factor(FRAC_PI_2), 1.0);
    }

    #[test]
    fn cycles_profile_matches_cosine() {
        let p = PoleMerge::CYCLES_DEFAULT;
        assert_eq!(p.factor(59f64.to_radians()), 1.0);
        assert!(
            (p.factor(67.5f64.to_radians()) - (0.25 * std::f64::consts::PI).cos()).abs() < 1e-12
        );
        assert_eq!(p.factor(76f64.to_radians()), 0.0);
    }

    #[test]
    fn per_pole_profiles() {
        let m = PoleMerging {
            north: PoleMerge::CYCLES_DEFAULT,
            south: PoleMerge::Off,
        };
        assert_eq!(m.factor(80f64.to_radians()), 0.0);
        assert_eq!(m.factor(-80f64.to_radians()), 1.0);
    }

    #[test]
    fn parses_every_form_and_rejects_bad_ones() {
        let parse = |s: &str| s.parse::<PoleMerge>();
        assert_eq!(parse("off").unwrap(), PoleMerge::Off);
        assert_eq!(parse("comfortable").unwrap(), PoleMerge::COMFORTABLE);
        assert_eq!(
            parse("marrinan:45,0,3").unwrap(),
            PoleMerge::Marrinan {
                start_deg: 45.0,
                end_deg: 0.0,
                exponent: 3.0
            }
        );
        assert_eq!(
            parse("cycles:60,75").unwrap(),
            PoleMerge::Cycles {
                from_deg: 60.0,
                to_deg: 75.0
            }
        );
        for bad in [
            "cycles:75,60",
            "marrinan:10,20,1",
            "marrinan:45,0",
            "cycles:a,b",
            "x",
            "marrinan:45,0,NaN",
        ] {
            assert!(parse(bad).is_err(), "{bad}");
        }
    }
}
