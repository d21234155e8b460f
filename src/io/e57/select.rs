//! Picking parts of an E57 file: scans by index or name (`--scan 0,Hall`), written after the
//! file name as `site.e57#scan:0,Hall` so every reader that takes a path honours it; one
//! image as `site.e57#image:N`; points coloured from the scanner's images as
//! `site.e57#color:image`.

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

/// What follows `#` after an E57 file's name: `#scan:0,Hall`, `#image:N`, `#color:image`,
/// in any order.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Parts {
    /// `#scan:SELECTION`: these scans only.
    pub scans: Option<ScanSelection>,
    /// `#image:N`: the file's image N (from 0).
    pub image: Option<usize>,
    /// `#color:image`: every point coloured from its station's images, stored colour or not.
    pub color_from_images: bool,
}

const TAGS: [&str; 3] = ["#scan:", "#image:", "#color:"];

/// Splits `site.e57#scan:0,2` into the file and the parts asked for. A path that exists as
/// it is, or has no such suffix, is returned whole with no part.
///
/// # Errors
/// A message when a suffix is there but does not parse.
pub fn split(path: &Path) -> Result<(PathBuf, Parts), String> {
    let text = path.to_string_lossy();
    let Some(at) = TAGS.iter().filter_map(|tag| text.find(tag)).min() else {
        return Ok((path.to_path_buf(), Parts::default()));
    };
    if path.exists() {
        return Ok((path.to_path_buf(), Parts::default()));
    }
    let mut parts = Parts::default();
    for segment in text[at + 1..].split('#') {
        let (tag, value) = segment.split_once(':').unwrap_or((segment, ""));
        match tag {
            "scan" => parts.scans = Some(value.parse()?),
            "image" => {
                parts.image = Some(
                    value
                        .parse()
                        .map_err(|_| format!("'{value}' is not an image number"))?,
                );
            }
            "color" if value == "image" => parts.color_from_images = true,
            _ => {
                return Err(format!(
                    "'#{segment}': expected #scan:.., #image:N or #color:image"
                ));
            }
        }
    }
    Ok((PathBuf::from(&text[..at]), parts))
}

/// The path naming `file` with `parts`.
pub fn join(file: &Path, parts: &Parts) -> PathBuf {
    let mut text = file.as_os_str().to_os_string();
    if let Some(s) = &parts.scans {
        text.push(format!("#scan:{s}"));
    }
    if let Some(i) = parts.image {
        text.push(format!("#image:{i}"));
    }
    if parts.color_from_images {
        text.push("#color:image");
    }
    PathBuf::from(text)
}

/// `file` (which may name parts already) with these scans picked instead.
pub fn with_scans(file: &Path, selection: &ScanSelection) -> PathBuf {
    let (base, mut parts) = split(file).unwrap_or_else(|_| (file.to_path_buf(), Parts::default()));
    parts.scans = Some(selection.clone());
    join(&base, &parts)
}

/// `file` (which may name parts already) with its points coloured from its images.
pub fn with_image_colour(file: &Path) -> PathBuf {
    let (base, mut parts) = split(file).unwrap_or_else(|_| (file.to_path_buf(), Parts::default()));
    parts.color_from_images = true;
    join(&base, &parts)
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
        let (file, parts) = split(Path::new("/nowhere/site.e57#scan:0,Hall")).unwrap();
        assert_eq!(file, Path::new("/nowhere/site.e57"));
        assert_eq!(
            parts.scans,
            Some(ScanSelection(vec![
                ScanPick::Index(0),
                ScanPick::Name("Hall".into())
            ]))
        );
        let (file, parts) = split(Path::new("/nowhere/site.e57#image:3")).unwrap();
        assert_eq!(
            (file.to_str(), parts.image),
            (Some("/nowhere/site.e57"), Some(3))
        );
        assert!(split(Path::new("/nowhere/site.e57#image:x")).is_err());
        assert!(split(Path::new("/nowhere/site.e57#color:blue")).is_err());
        let (file, parts) = split(Path::new("/nowhere/plain.las")).unwrap();
        assert_eq!(
            (file.to_str(), parts),
            (Some("/nowhere/plain.las"), Parts::default())
        );
        let sel: ScanSelection = "2".parse().unwrap();
        let joined = with_scans(Path::new("/nowhere/site.e57#scan:0#color:image"), &sel);
        assert_eq!(joined, Path::new("/nowhere/site.e57#scan:2#color:image"));
        let coloured = with_image_colour(Path::new("/nowhere/site.e57"));
        let (_, parts) = split(&coloured).unwrap();
        assert!(parts.color_from_images && parts.scans.is_none());
    }
}
