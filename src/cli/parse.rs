//! Parsers for the command line's numeric values: they turn user text into numbers, or into
//! one clear message saying what was expected. Library settings parse themselves (`FromStr`,
//! clap's `ValueEnum`).

use glam::DVec3;

use crate::projection::{Equirect, Stereo};
use crate::value::finite;

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

/// A non-negative interocular distance in metres (0 makes both eyes the mono view).
pub fn ipd(s: &str) -> Result<f64, String> {
    Stereo::check_ipd(finite(s, "interocular distance in metres")?)
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
    Equirect::check_width(w)
}

/// A positive, finite distance in metres.
pub fn distance(s: &str) -> Result<f64, String> {
    let d = finite(s, "distance in metres")?;
    if d > 0.0 {
        Ok(d)
    } else {
        Err(format!("the distance must be above 0 m, got {d}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_their_ranges() {
        assert_eq!(vec3("1,2.5,-3").unwrap(), DVec3::new(1.0, 2.5, -3.0));
        assert!(vec3("1,2").is_err() && vec3("1,inf,2").is_err());
        assert!(width("3841").is_err() && width("8").is_err());
        assert_eq!(width("3840").unwrap(), 3840);
        assert!(ipd("-0.1").is_err() && ipd("10.5").is_err());
        assert_eq!(ipd("0").unwrap(), 0.0);
        assert_eq!(degrees("-30").unwrap(), -30.0);
    }
}
