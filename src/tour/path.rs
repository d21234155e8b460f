//! Reading a camera path: CSV keyframes (`x,y,z` and optional `yaw,pitch,roll`) or a GeoJSON
//! `LineString` / `MultiLineString`, 2D or 3D, in file coordinates.

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::value::finite;

/// One keyframe as the file gives it.
#[derive(Debug, Clone, PartialEq)]
pub struct Keyframe {
    /// Position in file coordinates; `z` is `None` when the file gives none (the ground
    /// under the point decides it).
    pub x: f64,
    /// See [`Keyframe::x`].
    pub y: f64,
    /// See [`Keyframe::x`].
    pub z: Option<f64>,
    /// Heading in degrees when the file gives one (DESIGN §1).
    pub yaw: Option<f64>,
    /// Pitch in degrees (0 when not given).
    pub pitch: f64,
    /// Roll in degrees (0 when not given).
    pub roll: f64,
    /// Where in the file it stands, for messages: `line 4` or `feature 0, vertex 3`.
    pub at: String,
}

/// Why a path file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum PathError {
    /// The file could not be opened or read.
    #[error("{}: {source}", path.display())]
    Read {
        /// The path file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The file is readable but a part of it is not a valid path.
    #[error("{}: {at}: {message}", path.display())]
    Invalid {
        /// The path file.
        path: PathBuf,
        /// `line N`, `feature N`, `feature N, vertex M`, ...
        at: String,
        /// What is wrong.
        message: String,
    },
}

/// The columns a CSV path may have.
const COLUMNS: [&str; 6] = ["x", "y", "z", "yaw", "pitch", "roll"];

/// Reads the keyframes of `path`: GeoJSON when its name ends `.geojson` or `.json` or its
/// text starts with `{`, CSV otherwise.
pub fn read_path(path: &Path) -> Result<Vec<Keyframe>, PathError> {
    let text = std::fs::read_to_string(path).map_err(|source| PathError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let json =
        matches!(ext.as_deref(), Some("geojson" | "json")) || text.trim_start().starts_with('{');
    if json {
        parse_geojson(path, &text)
    } else {
        parse_csv(path, &text)
    }
}

fn invalid(path: &Path, at: impl Into<String>, message: impl Into<String>) -> PathError {
    PathError::Invalid {
        path: path.to_path_buf(),
        at: at.into(),
        message: message.into(),
    }
}

/// Parses CSV text with a header row naming its columns (any order and case; `#` starts a
/// comment line).
pub fn parse_csv(path: &Path, text: &str) -> Result<Vec<Keyframe>, PathError> {
    // The reader counts only the lines it reads records from; messages must name the line an
    // editor shows, so comment and blank lines are left out here and counted back.
    let kept: Vec<(usize, &str)> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .map(|(i, l)| (i + 1, l))
        .collect();
    let file_line = |reader_line: u64| {
        kept.get((reader_line as usize).saturating_sub(1))
            .map_or(reader_line as usize, |(n, _)| *n)
    };
    let blanked = kept.iter().map(|(_, l)| *l).collect::<Vec<_>>().join("\n");
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(blanked.as_bytes());
    let headers = reader
        .headers()
        .map_err(|e| csv_error(path, &e, &file_line))?
        .clone();
    let header_line = file_line(headers.position().map_or(1, |p| p.line()));
    let mut index = [None::<usize>; 6];
    for (i, name) in headers.iter().enumerate() {
        let lower = name.to_ascii_lowercase();
        let Some(c) = COLUMNS.iter().position(|&k| k == lower) else {
            let hint = if finite(name, "").is_ok() {
                " (the first line must name the columns, e.g. `x,y,z`)"
            } else {
                ""
            };
            return Err(invalid(
                path,
                format!("line {header_line}"),
                format!(
                    "unknown column `{name}`{hint}: expected x, y and optionally z, yaw, pitch, \
                     roll"
                ),
            ));
        };
        if index[c].is_some() {
            return Err(invalid(
                path,
                format!("line {header_line}"),
                format!("column `{lower}` appears twice"),
            ));
        }
        index[c] = Some(i);
    }
    let (Some(ix), Some(iy)) = (index[0], index[1]) else {
        return Err(invalid(
            path,
            format!("line {header_line}"),
            "the header needs columns `x` and `y`",
        ));
    };
    let mut keyframes = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| csv_error(path, &e, &file_line))?;
        let line = file_line(record.position().map_or(0, |p| p.line()));
        let at = format!("line {line}");
        let cell = |i: usize| record.get(i).unwrap_or("");
        let number = |i: usize, name: &str| -> Result<f64, PathError> {
            finite(cell(i), name).map_err(|m| invalid(path, at.clone(), m))
        };
        let optional = |c: usize| -> Result<Option<f64>, PathError> {
            match index[c] {
                Some(i) if !cell(i).is_empty() => number(i, COLUMNS[c]).map(Some),
                _ => Ok(None),
            }
        };
        let yaw = optional(3)?;
        if index[3].is_some() && yaw.is_none() {
            return Err(invalid(
                path,
                at,
                "yaw is empty: give every keyframe a yaw, or drop the column to follow the path",
            ));
        }
        keyframes.push(Keyframe {
            x: number(ix, "x")?,
            y: number(iy, "y")?,
            z: optional(2)?,
            yaw,
            pitch: optional(4)?.unwrap_or(0.0),
            roll: optional(5)?.unwrap_or(0.0),
            at,
        });
    }
    Ok(keyframes)
}

fn csv_error(path: &Path, e: &csv::Error, file_line: &dyn Fn(u64) -> usize) -> PathError {
    let at = e.position().map_or_else(
        || "CSV".to_string(),
        |p| format!("line {}", file_line(p.line())),
    );
    let message = match e.kind() {
        csv::ErrorKind::UnequalLengths {
            expected_len, len, ..
        } => format!("{len} fields where the header has {expected_len}"),
        _ => e.to_string(),
    };
    invalid(path, at, message)
}

/// Parses a GeoJSON `FeatureCollection`, `Feature` or bare geometry: every `LineString` and
/// `MultiLineString` in it, in order, joined into one path. Vertices are `[x, y]` or
/// `[x, y, z]` (further values, such as a measure, are ignored).
pub fn parse_geojson(path: &Path, text: &str) -> Result<Vec<Keyframe>, PathError> {
    let root: Value = serde_json::from_str(text).map_err(|e| {
        invalid(
            path,
            format!("line {}, column {}", e.line(), e.column()),
            format!("not valid JSON: {e}"),
        )
    })?;
    let mut keyframes = Vec::new();
    match kind(&root) {
        "FeatureCollection" => {
            let features = root
                .get("features")
                .and_then(Value::as_array)
                .ok_or_else(|| invalid(path, "FeatureCollection", "has no `features` array"))?;
            for (i, feature) in features.iter().enumerate() {
                let at = format!("feature {i}");
                let geometry = feature_geometry(path, feature, &at)?;
                lines(path, geometry, &at, &mut keyframes)?;
            }
        }
        "Feature" => {
            let geometry = feature_geometry(path, &root, "feature 0")?;
            lines(path, geometry, "feature 0", &mut keyframes)?;
        }
        _ => lines(path, &root, "geometry", &mut keyframes)?,
    }
    if keyframes.is_empty() {
        return Err(invalid(
            path,
            "GeoJSON",
            "holds no LineString or MultiLineString vertex",
        ));
    }
    Ok(keyframes)
}

fn kind(v: &Value) -> &str {
    v.get("type").and_then(Value::as_str).unwrap_or("")
}

fn feature_geometry<'v>(path: &Path, feature: &'v Value, at: &str) -> Result<&'v Value, PathError> {
    match feature.get("geometry") {
        Some(g) if !g.is_null() => Ok(g),
        _ => Err(invalid(path, at, "has no geometry")),
    }
}

/// Appends the vertices of a `LineString` or `MultiLineString` geometry.
fn lines(
    path: &Path,
    geometry: &Value,
    at: &str,
    out: &mut Vec<Keyframe>,
) -> Result<(), PathError> {
    let coords = geometry.get("coordinates").and_then(Value::as_array);
    match (kind(geometry), coords) {
        ("LineString", Some(c)) => line(path, c, at, out),
        ("MultiLineString", Some(parts)) => {
            for (p, part) in parts.iter().enumerate() {
                let c = part.as_array().ok_or_else(|| {
                    invalid(
                        path,
                        format!("{at}, line {p}"),
                        "is not an array of vertices",
                    )
                })?;
                line(path, c, &format!("{at}, line {p}"), out)?;
            }
            Ok(())
        }
        ("LineString" | "MultiLineString", None) => {
            Err(invalid(path, at, "has no `coordinates` array"))
        }
        (other, _) => Err(invalid(
            path,
            at,
            format!(
                "geometry is {}; a path is a LineString or MultiLineString",
                if other.is_empty() { "untyped" } else { other }
            ),
        )),
    }
}

fn line(path: &Path, coords: &[Value], at: &str, out: &mut Vec<Keyframe>) -> Result<(), PathError> {
    for (v, vertex) in coords.iter().enumerate() {
        let at = format!("{at}, vertex {v}");
        let numbers: Option<Vec<f64>> = vertex
            .as_array()
            .map(|a| a.iter().map(Value::as_f64).collect::<Option<Vec<f64>>>())
            .unwrap_or(None);
        let n = match numbers {
            Some(n) if n.len() >= 2 && n.iter().all(|x| x.is_finite()) => n,
            _ => {
                return Err(invalid(
                    path,
                    at,
                    format!("expected [x, y] or [x, y, z] (finite numbers), got {vertex}"),
                ));
            }
        };
        out.push(Keyframe {
            x: n[0],
            y: n[1],
            z: n.get(2).copied(),
            yaw: None,
            pitch: 0.0,
            roll: 0.0,
            at,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn csv(text: &str) -> Result<Vec<Keyframe>, String> {
        parse_csv(Path::new("p.csv"), text).map_err(|e| e.to_string())
    }

    fn geo(text: &str) -> Result<Vec<Keyframe>, String> {
        parse_geojson(Path::new("p.geojson"), text).map_err(|e| e.to_string())
    }

    #[test]
    fn csv_columns_in_any_order_and_case_with_optional_z() {
        let k = csv("Y, x ,z,yaw\n2,1,,45\n# a comment\n\n4,3,7.5,-90\n").unwrap();
        assert_eq!(k.len(), 2);
        assert_eq!(
            (k[0].x, k[0].y, k[0].z, k[0].yaw),
            (1.0, 2.0, None, Some(45.0))
        );
        assert_eq!((k[1].x, k[1].y, k[1].z), (3.0, 4.0, Some(7.5)));
        assert_eq!((k[0].at.as_str(), k[1].at.as_str()), ("line 2", "line 5"));
    }

    #[test]
    fn csv_errors_name_the_file_line_and_column() {
        let e = csv("x,y,speed\n1,2,3\n").unwrap_err();
        assert!(
            e.starts_with("p.csv: line 1: unknown column `speed`"),
            "{e}"
        );
        let e = csv("1,2,3\n4,5,6\n").unwrap_err();
        assert!(
            e.contains("line 1") && e.contains("must name the columns"),
            "{e}"
        );
        let e = csv("x,y,z\n1,2,3\n4,NaN,6\n").unwrap_err();
        assert!(e.starts_with("p.csv: line 3:") && e.contains("NaN"), "{e}");
        let e = csv("x,y,z\n1,2,3\n4,5\n").unwrap_err();
        assert!(e.contains("line 3") && e.contains("2 fields"), "{e}");
        let e = csv("x,z\n1,2\n").unwrap_err();
        assert!(e.contains("`x` and `y`"), "{e}");
        let e = csv("x,y,yaw\n1,2,\n").unwrap_err();
        assert!(e.contains("line 2: yaw is empty"), "{e}");
    }

    #[test]
    fn geojson_2d_3d_and_multi_lines() {
        let fc = r#"{"type":"FeatureCollection","features":[
            {"type":"Feature","properties":{},"geometry":{"type":"LineString",
             "coordinates":[[1,2],[3,4]]}},
            {"type":"Feature","properties":{},"geometry":{"type":"MultiLineString",
             "coordinates":[[[5,6,7],[8,9,10,0.5]]]}}]}"#;
        let k = geo(fc).unwrap();
        assert_eq!(k.len(), 4);
        assert_eq!((k[0].x, k[0].y, k[0].z), (1.0, 2.0, None));
        assert_eq!((k[3].x, k[3].y, k[3].z), (8.0, 9.0, Some(10.0)));
        assert_eq!(k[3].at, "feature 1, line 0, vertex 1");
        let bare = geo(r#"{"type":"LineString","coordinates":[[0,0,1],[1,1,1]]}"#).unwrap();
        assert_eq!(bare.len(), 2);
    }

    #[test]
    fn bad_geojson_names_the_feature_or_position() {
        let e = geo(r#"{"type":"Feature","geometry":{"type":"Point","coordinates":[1,2]}}"#)
            .unwrap_err();
        assert!(e.contains("feature 0: geometry is Point"), "{e}");
        let e = geo(
            r#"{"type":"FeatureCollection","features":[{"type":"Feature","geometry":
            {"type":"LineString","coordinates":[[1,2],[3,"x"]]}}]}"#,
        )
        .unwrap_err();
        assert!(e.contains("feature 0, vertex 1: expected [x, y]"), "{e}");
        let e = geo("{\"type\": \"LineString\",\n \"coordinates\": [[1,2],}").unwrap_err();
        assert!(
            e.contains("line 2, column") && e.contains("not valid JSON"),
            "{e}"
        );
    }
}
