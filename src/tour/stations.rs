//! The stations of an E57 survey: where each scan's scanner stood and where it looked
//! (DESIGN §12), as cameras for `--camera station:N` and as the stops of a station tour.

use std::path::Path;

use glam::DVec3;

use crate::io::{LoadError, e57};

/// One scan's station.
#[derive(Debug, Clone, PartialEq)]
pub struct Station {
    /// The scan's index in the file, from 0.
    pub index: usize,
    /// The scan's name, when it has one.
    pub name: Option<String>,
    /// The scanner's position (the scan pose's translation), file coordinates.
    pub position: DVec3,
    /// Heading in degrees (0 along +Y, 90 along +X): where the scan's +Y axis points.
    pub yaw: f64,
}

/// Why stations could not be had.
#[derive(Debug, thiserror::Error)]
pub enum StationError {
    /// The file could not be read.
    #[error(transparent)]
    Load(#[from] LoadError),
    /// The file is not E57, so it has no stations.
    #[error("{}: --camera station:.. needs an E57 file (its scans' poses are the stations)", path.display())]
    NotE57 {
        /// The file.
        path: std::path::PathBuf,
    },
    /// No scan has this index.
    #[error("{}: no station {index}: the file holds {count} scans (numbered from 0)", path.display())]
    NoSuchStation {
        /// The file.
        path: std::path::PathBuf,
        /// The index asked for.
        index: usize,
        /// Scans in the file.
        count: usize,
    },
}

/// The stations of the scans `path` reads (all, or those its `#scan:` pick names), in order.
///
/// # Errors
/// The file's [`LoadError`]; [`StationError::NotE57`] for other formats.
pub fn read_stations(path: &Path) -> Result<Vec<Station>, StationError> {
    let info = crate::io::read_info(path)?;
    let e57 = info.e57.ok_or_else(|| StationError::NotE57 {
        path: path.to_path_buf(),
    })?;
    Ok(e57.selected_scans().map(station).collect())
}

/// Scan `index`'s station (counted among all the file's scans, whatever `#scan:` picks).
///
/// # Errors
/// As [`read_stations`]; [`StationError::NoSuchStation`] past the last scan.
pub fn read_station(path: &Path, index: usize) -> Result<Station, StationError> {
    let info = crate::io::read_info(path)?;
    let e57 = info.e57.ok_or_else(|| StationError::NotE57 {
        path: path.to_path_buf(),
    })?;
    e57.scans
        .get(index)
        .map(station)
        .ok_or(StationError::NoSuchStation {
            path: path.to_path_buf(),
            index,
            count: e57.scans.len(),
        })
}

fn station(scan: &e57::ScanInfo) -> Station {
    Station {
        index: scan.index,
        name: scan.name.clone(),
        position: scan.pose.translation,
        yaw: scan.pose.yaw_degrees(),
    }
}
