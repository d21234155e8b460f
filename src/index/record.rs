//! LAS 1.4 point records (formats 6 and 7) with the two stored radii as extra bytes: the
//! byte layout an index keeps in its temporary files and compresses into the COPC chunks.

use glam::DVec3;

/// Extra bytes after the standard record: the full-detail radius, then the stopping radius
/// (both f32; see [`crate::io::extra_bytes`]).
pub const EXTRA_BYTES: usize = 8;
/// Offset of the full-detail radius within the extra bytes.
pub const RADIUS_AT: usize = 0;
/// Offset of the stopping radius within the extra bytes.
pub const LOD_RADIUS_AT: usize = 4;

/// The point format and record length of an index's points.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layout {
    /// LAS point format: 6 (no colour) or 7 (RGB).
    pub format: u8,
    /// Bytes per record, extra bytes included.
    pub len: usize,
}

/// One point's attributes as the readers give them (`None`: the file has no such field).
#[derive(Debug, Clone, Copy, Default)]
pub struct Fields {
    /// Intensity.
    pub intensity: Option<u16>,
    /// Return number and number of returns (0–15 each).
    pub returns: Option<(u8, u8)>,
    /// ASPRS class.
    pub classification: Option<u8>,
    /// GPS time.
    pub gps_time: Option<f64>,
    /// Colour, 16 bits per channel.
    pub rgb: Option<[u16; 3]>,
    /// A radius the file gives the point (PLY `radius`), file units.
    pub radius: Option<f32>,
}

impl Layout {
    /// Format 7 when colour is kept, else 6.
    pub fn new(colour: bool) -> Layout {
        let (format, base) = if colour { (7, 36) } else { (6, 30) };
        Layout {
            format,
            len: base + EXTRA_BYTES,
        }
    }

    /// Bytes of the standard record (without the extra bytes).
    pub fn base_len(self) -> usize {
        self.len - EXTRA_BYTES
    }

    /// Appends one record at integer coordinates `xyz`; a missing return number becomes the
    /// single return of its pulse (LAS 1.4 requires one), the stored radii the file's radius
    /// (or NaN, decided later).
    pub fn push(self, out: &mut Vec<u8>, xyz: [i32; 3], f: &Fields) {
        let start = out.len();
        out.resize(start + self.len, 0);
        let r = &mut out[start..];
        for (i, v) in xyz.iter().enumerate() {
            r[i * 4..i * 4 + 4].copy_from_slice(&v.to_le_bytes());
        }
        r[12..14].copy_from_slice(&f.intensity.unwrap_or(0).to_le_bytes());
        let (number, of) = f.returns.unwrap_or((1, 1));
        r[14] = (number & 0x0F) | ((of & 0x0F) << 4);
        r[16] = f.classification.unwrap_or(0);
        r[22..30].copy_from_slice(&f.gps_time.unwrap_or(0.0).to_le_bytes());
        if self.format == 7 {
            let c = f.rgb.unwrap_or([0; 3]);
            for (i, v) in c.iter().enumerate() {
                r[30 + i * 2..32 + i * 2].copy_from_slice(&v.to_le_bytes());
            }
        }
        let radius = f.radius.unwrap_or(f32::NAN);
        self.set_radii(r, radius, radius);
    }

    /// The integer coordinates of a record.
    #[inline]
    pub fn xyz(record: &[u8]) -> [i32; 3] {
        let v =
            |i: usize| i32::from_le_bytes([record[i], record[i + 1], record[i + 2], record[i + 3]]);
        [v(0), v(4), v(8)]
    }

    /// Return number (1–15, or 0).
    #[inline]
    pub fn return_number(record: &[u8]) -> u8 {
        record[14] & 0x0F
    }

    /// GPS time.
    #[inline]
    pub fn gps_time(record: &[u8]) -> f64 {
        let mut b = [0u8; 8];
        b.copy_from_slice(&record[22..30]);
        f64::from_le_bytes(b)
    }

    /// The full-detail radius stored in a record.
    #[inline]
    pub fn radius(self, record: &[u8]) -> f32 {
        let at = self.base_len() + RADIUS_AT;
        f32::from_le_bytes([record[at], record[at + 1], record[at + 2], record[at + 3]])
    }

    /// Stores both radii in a record.
    #[inline]
    pub fn set_radii(self, record: &mut [u8], radius: f32, lod_radius: f32) {
        let at = self.base_len();
        record[at + RADIUS_AT..at + RADIUS_AT + 4].copy_from_slice(&radius.to_le_bytes());
        record[at + LOD_RADIUS_AT..at + LOD_RADIUS_AT + 4]
            .copy_from_slice(&lod_radius.to_le_bytes());
    }
}

/// Integer coordinates: `coordinate = offset + scale · integer` per axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantizer {
    /// Scale per axis.
    pub scale: DVec3,
    /// Offset per axis.
    pub offset: DVec3,
}

impl Quantizer {
    /// The integers of `p`; `None` when an axis falls outside i32.
    pub fn ints(&self, p: DVec3) -> Option<[i32; 3]> {
        let q = ((p - self.offset) / self.scale).round();
        let fits = |v: f64| v >= f64::from(i32::MIN) && v <= f64::from(i32::MAX);
        (fits(q.x) && fits(q.y) && fits(q.z)).then_some([q.x as i32, q.y as i32, q.z as i32])
    }

    /// The coordinates of integers `xyz`.
    #[inline]
    pub fn position(&self, xyz: [i32; 3]) -> DVec3 {
        self.offset
            + DVec3::new(f64::from(xyz[0]), f64::from(xyz[1]), f64::from(xyz[2])) * self.scale
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_keep_their_fields() {
        for colour in [false, true] {
            let layout = Layout::new(colour);
            let mut out = Vec::new();
            let fields = Fields {
                intensity: Some(513),
                returns: Some((2, 3)),
                classification: Some(6),
                gps_time: Some(1234.5),
                rgb: Some([1, 2, 65535]),
                radius: Some(0.25),
            };
            layout.push(&mut out, [-7, 8, 1 << 30], &fields);
            assert_eq!(out.len(), layout.len);
            assert_eq!(Layout::xyz(&out), [-7, 8, 1 << 30]);
            assert_eq!(Layout::return_number(&out), 2);
            assert_eq!(out[14] >> 4, 3);
            assert_eq!(Layout::gps_time(&out), 1234.5);
            assert_eq!(layout.radius(&out), 0.25);
            layout.set_radii(&mut out, 0.5, 2.0);
            assert_eq!(layout.radius(&out), 0.5);
            if colour {
                assert_eq!(&out[34..36], &65535u16.to_le_bytes());
            }
        }
        assert_eq!(Layout::new(false).len, 38);
        assert_eq!(Layout::new(true).len, 44);
    }

    #[test]
    fn quantizer_round_trips_and_refuses_overflow() {
        let q = Quantizer {
            scale: DVec3::splat(0.01),
            offset: DVec3::new(1000.0, 0.0, 0.0),
        };
        let p = DVec3::new(1012.34, -5.67, 0.01);
        let ints = q.ints(p).unwrap();
        assert_eq!(ints, [1234, -567, 1]);
        assert!((q.position(ints) - p).abs().max_element() < 1e-9);
        assert!(q.ints(DVec3::new(1e9, 0.0, 0.0)).is_none());
    }
}
