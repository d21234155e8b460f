//! Picking parts of an E57 file: scans by index or name (`--scan 0,Hall`), written after the
//! file name as `site.e57#scan:0,Hall` so every reader that takes a path honours it, and one
//! image as `site.e57#image:N`.

use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// One scan asked for: its index in the file (from 0) or its name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ScanPick {
    /// Index of the scan among the file's `data3D` entries, from 0.
    Index(usize),
    /// The scan's `name`.
    Name(String),
}

/// Scans asked for (`--scan N|NAME[,..]`), in the order given.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScanSelection(pub Vec<ScanPick>);

impl FromStr for ScanSelection {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let picks: Vec<ScanPick> = s
            .split(',')
            .map(str::trim)
            .map(|p| {
                if p.is_empty() {
                    Err(format!("'{s}': an empty scan in the list"))
                } else if let Ok(i) = p.parse::<usize>() {
                    Ok(ScanPick::Index(i))
                } else {
                    Ok(ScanPick::Name(p.to_string()))
                }
            })
            .collect::<Result<_, _>>()?;
        Ok(ScanSelection(picks))
    }
}

impl fmt::Display for ScanSelection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let parts: Vec<String> = self
            .0
            .iter()
            .map(|p| match p {
                ScanPick::Index(i) => i.to_string(),
                ScanPick::Name(n) => n.clone(),
            })
            .collect();
        f.write_str(&parts.join(","))
    }
}

impl ScanSelection {
    /// The indices of the picked scans among `names` (one per scan of the file, `None` for
    /// an unnamed scan), each once, in the order asked.
    ///
    /// # Errors
    /// A message naming the index past the end or the name no scan has.
    pub fn resolve(&self, names: &[Option<String>]) -> Result<Vec<usize>, String> {
        let mut picked = Vec::new();
        for pick in &self.0 {
            let index = match pick {
                ScanPick::Index(i) if *i < names.len() => *i,
                ScanPick::Index(i) => {
                    return Err(format!(
                        "no scan {i}: the file holds {} (numbered from 0)",
                        names.len()
                    ));
                }
                ScanPick::Name(n) => names
                    .iter()
                    .position(|m| m.as_deref() == Some(n.as_str()))
                    .ok_or_else(|| format!("no scan is named '{n}'"))?,
            };
            if !picked.contains(&index) {
                picked.push(index);
            }
        }
        Ok(picked)
    }
}

/// What follows `#` after an E57 file's name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Part {
    /// `#scan:SELECTION`: these scans only.
    Scans(ScanSelection),
    /// `#image:N`: the file's image N (from 0).
    Image(usize),
}

const SCAN_TAG: &str = "#scan:";
const IMAGE_TAG: &str = "#image:";

/// Splits `site.e57#scan:0,2` into the file and the part asked for. A path that exists as
/// it is, or has no such suffix, is returned whole.
///
/// # Errors
/// A message when the suffix is there but does not parse.
pub fn split(path: &Path) -> Result<(PathBuf, Option<Part>), String> {
    let text = path.to_string_lossy();
    let found = [SCAN_TAG, IMAGE_TAG]
        .iter()
        .filter_map(|tag| text.rfind(tag).map(|at| (at, *tag)))
        .max();
    let Some((at, tag)) = found else {
        return Ok((path.to_path_buf(), None));
    };
    if path.exists() {
        return Ok((path.to_path_buf(), None));
    }
    let file = PathBuf::from(&text[..at]);
    let rest = &text[at + tag.len()..];
    let part = if tag == SCAN_TAG {
        Part::Scans(rest.parse()?)
    } else {
        Part::Image(
            rest.parse()
                .map_err(|_| format!("'{rest}' is not an image number"))?,
        )
    };
    Ok((file, Some(part)))
}

/// `file` with these scans picked: `site.e57#scan:0,2`. A pick already on the path is
/// replaced.
pub fn with_scans(file: &Path, selection: &ScanSelection) -> PathBuf {
    let base = match split(file) {
        Ok((base, Some(Part::Scans(_)))) => base,
        _ => file.to_path_buf(),
    };
    let mut text = base.into_os_string();
    text.push(format!("{SCAN_TAG}{selection}"));
    PathBuf::from(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn selections_parse_and_resolve() {
        let s: ScanSelection = "1, Hall,1".parse().unwrap();
        let names = [Some("Yard".to_string()), None, Some("Hall".to_string())];
        assert_eq!(s.resolve(&names).unwrap(), vec![1, 2]);
        assert!(
            "3".parse::<ScanSelection>()
                .unwrap()
                .resolve(&names)
                .unwrap_err()
                .contains("holds 3")
        );
        assert!(
            "Roof"
                .parse::<ScanSelection>()
                .unwrap()
                .resolve(&names)
                .unwrap_err()
                .contains("'Roof'")
        );
        assert!("1,,2".parse::<ScanSelection>().is_err());
    }

    #[test]
    fn suffixes_split_and_join() {
        let (file, part) = split(Path::new("/nowhere/site.e57#scan:0,Hall")).unwrap();
        assert_eq!(file, Path::new("/nowhere/site.e57"));
        assert_eq!(
            part,
            Some(Part::Scans(ScanSelection(vec![
                ScanPick::Index(0),
                ScanPick::Name("Hall".into())
            ])))
        );
        let (file, part) = split(Path::new("/nowhere/site.e57#image:3")).unwrap();
        assert_eq!(
            (file.to_str(), part),
            (Some("/nowhere/site.e57"), Some(Part::Image(3)))
        );
        assert!(split(Path::new("/nowhere/site.e57#image:x")).is_err());
        let (file, part) = split(Path::new("/nowhere/plain.las")).unwrap();
        assert_eq!((file.to_str(), part), (Some("/nowhere/plain.las"), None));
        let sel: ScanSelection = "2".parse().unwrap();
        let joined = with_scans(Path::new("/nowhere/site.e57#scan:0"), &sel);
        assert_eq!(joined, Path::new("/nowhere/site.e57#scan:2"));
    }
}
