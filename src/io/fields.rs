//! Which point attributes a read needs decoded besides positions and stored radii.

/// The attributes a read asks for. A reader that can skip an attribute without decoding it
/// (a COPC node: LAS 1.4 layered LAZ keeps each field in its own layer) leaves those not
/// asked for out of its chunks (`None`); the other readers return every attribute they have.
/// Return numbers are always read: layered LAZ stores them with the coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PointFields {
    /// Red, green, blue.
    pub rgb: bool,
    /// Intensity.
    pub intensity: bool,
    /// ASPRS classification.
    pub classification: bool,
    /// GPS time.
    pub gps_time: bool,
}

impl PointFields {
    /// Every attribute.
    pub const ALL: PointFields = PointFields {
        rgb: true,
        intensity: true,
        classification: true,
        gps_time: true,
    };

    /// Positions (and return numbers) only.
    pub const POSITIONS: PointFields = PointFields {
        rgb: false,
        intensity: false,
        classification: false,
        gps_time: false,
    };

    /// The attributes of either.
    pub fn or(self, other: PointFields) -> PointFields {
        PointFields {
            rgb: self.rgb || other.rgb,
            intensity: self.intensity || other.intensity,
            classification: self.classification || other.classification,
            gps_time: self.gps_time || other.gps_time,
        }
    }

    /// The layers of a LAS 1.4 layered LAZ chunk to decode: coordinates, return numbers and
    /// extra bytes (stored radii) always, the attributes asked for, never the fields no
    /// reader returns (scan angle, user data, point source, the classification flags, NIR,
    /// wave packets).
    pub(crate) fn laz_selection(self) -> laz::DecompressionSelection {
        let mut s = laz::DecompressionSelection::base()
            .decompress_z()
            .decompress_extra_bytes();
        if self.rgb {
            s = s.decompress_rgb();
        }
        if self.intensity {
            s = s.decompress_intensity();
        }
        if self.classification {
            s = s.decompress_classification();
        }
        if self.gps_time {
            s = s.decompress_gps_time();
        }
        s
    }
}

impl Default for PointFields {
    /// [`PointFields::ALL`].
    fn default() -> Self {
        PointFields::ALL
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_selection_keeps_what_is_asked_and_the_coordinates() {
        let s = PointFields::POSITIONS.laz_selection();
        assert!(s.should_decompress_z() && s.should_decompress_extra_bytes());
        assert!(!s.should_decompress_rgb() && !s.should_decompress_intensity());
        assert!(!s.should_decompress_gps_time() && !s.should_decompress_classification());
        assert!(!s.should_decompress_scan_angle() && !s.should_decompress_user_data());
        let rgb = PointFields {
            rgb: true,
            ..PointFields::POSITIONS
        };
        let s = rgb.or(PointFields::POSITIONS).laz_selection();
        assert!(s.should_decompress_rgb() && !s.should_decompress_intensity());
        let all = PointFields::ALL.laz_selection();
        assert!(all.should_decompress_intensity() && all.should_decompress_classification());
        assert!(all.should_decompress_gps_time() && all.should_decompress_rgb());
    }
}
