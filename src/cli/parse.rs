//! Parsers for command-line values that are not plain numbers: they turn user text into the
//! library's settings, or into one clear message saying what was expected.

use glam::DVec3;

use crate::projection::PoleMerge;
use crate::render::{ColorMode, Imposter, Proxy, RendererKind, Shading};

pub use crate::radius::RadiusChoice;

fn finite(s: &str, what: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a number ({what})"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("`{s}` is not a finite number ({what})"))
    }
}

/// `X,Y,Z` in file coordinates.
pub fn vec3(s: &str) -> Result<DVec3, String> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 3 {
        return Err(format!(
            "expected X,Y,Z (three comma-separated numbers), got `{s}`"
        ));
    }
    let v: Result<Vec<f64>, String> = parts.iter().map(|p| finite(p, "coordinate")).collect();
    let v = v?;
    Ok(DVec3::new(v[0], v[1], v[2]))
}

/// A positive, finite length in metres.
pub fn positive_metres(s: &str) -> Result<f64, String> {
    let v = finite(s, "metres")?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(format!("expected a length > 0 in metres, got `{s}`"))
    }
}

/// A non-negative interocular distance in metres (0 makes both eyes the mono view).
pub fn ipd(s: &str) -> Result<f64, String> {
    let v = finite(s, "interocular distance in metres")?;
    if (0.0..=10.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!(
            "the interocular distance must lie in 0..=10 metres, got `{s}`"
        ))
    }
}

/// A finite angle in degrees.
pub fn degrees(s: &str) -> Result<f64, String> {
    finite(s, "degrees")
}

/// An even image width from 16 to 16384 pixels (the height is half of it).
pub fn width(s: &str) -> Result<u32, String> {
    let w: u32 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a whole number of pixels"))?;
    if !(16..=16384).contains(&w) || !w.is_multiple_of(2) {
        return Err(format!(
            "the width must be even and within 16..=16384, got {w}"
        ));
    }
    Ok(w)
}

/// `M` metres or `auto`.
pub fn radius(s: &str) -> Result<RadiusChoice, String> {
    if s.trim().eq_ignore_ascii_case("auto") {
        return Ok(RadiusChoice::Auto);
    }
    let v = positive_metres(s).map_err(|e| format!("{e} (or `auto`)"))?;
    Ok(RadiusChoice::Fixed(v as f32))
}

/// `off`, `comfortable`, `cycles`, `marrinan:START,END,EXP` or `cycles:FROM,TO` (degrees).
pub fn pole_merge(s: &str) -> Result<PoleMerge, String> {
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
            "comfortable" => Ok(PoleMerge::COMFORTABLE),
            "cycles" => Ok(PoleMerge::CYCLES_DEFAULT),
            "marrinan" => Ok(PoleMerge::COMFORTABLE),
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
                if !(0.0..=90.0).contains(&v[0]) || !(v[0]..=90.0).contains(&v[1]) || v[0] == v[1] {
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

/// `quad`, `static:N` (N in 1..=64), `dynamic` or `bounds`.
pub fn proxy(s: &str) -> Result<Proxy, String> {
    let s = s.trim().to_ascii_lowercase();
    match s.split_once(':') {
        Some(("static", n)) => {
            let n: u32 = n
                .parse()
                .map_err(|_| format!("expected static:N with N a whole number, got `{s}`"))?;
            if (1..=64).contains(&n) {
                Ok(Proxy::Static(n))
            } else {
                Err(format!("static:N needs 1 <= N <= 64, got {n}"))
            }
        }
        None if s == "quad" => Ok(Proxy::Quad),
        None if s == "dynamic" => Ok(Proxy::Dynamic),
        None if s == "bounds" => Ok(Proxy::Bounds),
        None if s == "static" => Ok(Proxy::Static(4)),
        _ => Err(format!(
            "unknown proxy `{s}`: use quad, static:N, dynamic or bounds"
        )),
    }
}

fn choose<T: Copy>(s: &str, what: &str, options: &[(&str, T)]) -> Result<T, String> {
    let key = s.trim().to_ascii_lowercase();
    options
        .iter()
        .find(|(name, _)| *name == key)
        .map(|(_, v)| *v)
        .ok_or_else(|| {
            let names: Vec<&str> = options.iter().map(|(n, _)| *n).collect();
            format!("unknown {what} `{s}`: use {}", names.join(", "))
        })
}

/// `sprite` or `raycast`.
pub fn imposter(s: &str) -> Result<Imposter, String> {
    choose(
        s,
        "imposter",
        &[("sprite", Imposter::Sprite), ("raycast", Imposter::Raycast)],
    )
}

/// `raster` or `raytrace`.
pub fn renderer(s: &str) -> Result<RendererKind, String> {
    choose(
        s,
        "renderer",
        &[
            ("raster", RendererKind::Raster),
            ("raytrace", RendererKind::Raytrace),
        ],
    )
}

/// `auto`, `rgb`, `intensity`, `classification`, `elevation` or `flat`.
pub fn color(s: &str) -> Result<ColorMode, String> {
    choose(
        s,
        "colour mode",
        &[
            ("auto", ColorMode::Auto),
            ("rgb", ColorMode::Rgb),
            ("intensity", ColorMode::Intensity),
            ("classification", ColorMode::Classification),
            ("elevation", ColorMode::Elevation),
            ("flat", ColorMode::Flat),
        ],
    )
}

/// `unlit`, `phong` or `normal`.
pub fn shading(s: &str) -> Result<Shading, String> {
    choose(
        s,
        "shading",
        &[
            ("unlit", Shading::Unlit),
            ("phong", Shading::Phong),
            ("normal", Shading::Normal),
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pole_merge_forms() {
        assert_eq!(pole_merge("off").unwrap(), PoleMerge::Off);
        assert_eq!(pole_merge("comfortable").unwrap(), PoleMerge::COMFORTABLE);
        assert_eq!(
            pole_merge("marrinan:45,0,3").unwrap(),
            PoleMerge::Marrinan {
                start_deg: 45.0,
                end_deg: 0.0,
                exponent: 3.0
            }
        );
        assert_eq!(
            pole_merge("cycles:60,75").unwrap(),
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
            assert!(pole_merge(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn other_values() {
        assert_eq!(vec3("1,2.5,-3").unwrap(), DVec3::new(1.0, 2.5, -3.0));
        assert!(vec3("1,2").is_err() && vec3("1,inf,2").is_err());
        assert_eq!(proxy("static:16").unwrap(), Proxy::Static(16));
        assert!(proxy("static:0").is_err() && proxy("static:x").is_err());
        assert_eq!(radius("AUTO").unwrap(), RadiusChoice::Auto);
        assert!(radius("-1").is_err() && radius("0").is_err());
        assert!(width("3841").is_err() && width("8").is_err());
        assert_eq!(width("3840").unwrap(), 3840);
        assert!(ipd("-0.1").is_err());
        assert_eq!(renderer("raytrace").unwrap(), RendererKind::Raytrace);
        assert!(
            shading("toon")
                .unwrap_err()
                .contains("unlit, phong, normal")
        );
    }
}
