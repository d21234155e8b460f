//! LAS Extra Bytes (user `LASF_Spec`, record 4): one 192-byte descriptor per field stored after
//! the standard point record. Used for the sphere radii an index stores with each point
//! ([`RADIUS_FIELD`], [`LOD_RADIUS_FIELD`]), read back by the LAS/COPC readers.

/// User id of the Extra Bytes VLR.
pub const USER_ID: &str = "LASF_Spec";
/// Record id of the Extra Bytes VLR.
pub const RECORD_ID: u16 = 4;
/// Bytes per field descriptor.
pub const DESCRIPTOR_LEN: usize = 192;
/// The LAS data type code of a 32-bit float.
pub const DATA_TYPE_F32: u8 = 9;

/// Extra-bytes field holding a point's sphere radius at full detail (f32, file units): the
/// radius that closes the surface around it among every point of the scan.
pub const RADIUS_FIELD: &str = "omnicloud_radius";
/// Extra-bytes field holding a point's sphere radius where a level-of-detail read stops at the
/// point's octree node (f32, file units): the radius that closes the surface drawn by that
/// node's points and its ancestors' points; never below [`RADIUS_FIELD`].
pub const LOD_RADIUS_FIELD: &str = "omnicloud_lod_radius";

/// One descriptor for an f32 field named `name` (at most 32 bytes), no scale, offset or
/// no-data value.
pub fn f32_descriptor(name: &str, description: &str) -> [u8; DESCRIPTOR_LEN] {
    let mut d = [0u8; DESCRIPTOR_LEN];
    d[2] = DATA_TYPE_F32;
    copy_text(&mut d[4..36], name);
    copy_text(&mut d[160..192], description);
    d
}

fn copy_text(field: &mut [u8], text: &str) {
    let bytes = text.as_bytes();
    let n = bytes.len().min(field.len());
    field[..n].copy_from_slice(&bytes[..n]);
}

/// Bytes a field of LAS data type `code` takes (codes 1–10; 0 = `options` bytes of
/// undocumented extra bytes); `None` for a deprecated or unknown code.
fn type_len(code: u8, options: u8) -> Option<usize> {
    match code {
        0 => Some(usize::from(options)),
        1 | 2 => Some(1),
        3 | 4 => Some(2),
        5 | 6 | 9 => Some(4),
        7 | 8 | 10 => Some(8),
        _ => None,
    }
}

/// Byte offset, within the extra bytes of a record, of the f32 field named `name` in the
/// Extra Bytes VLR payload `vlr`; `None` when no such f32 field is described (or a field
/// before it has a size this reader cannot tell).
pub fn f32_field_offset(vlr: &[u8], name: &str) -> Option<usize> {
    let mut offset = 0;
    for d in vlr.chunks_exact(DESCRIPTOR_LEN) {
        let (code, options) = (d[2], d[3]);
        let field_name = String::from_utf8_lossy(&d[4..36]);
        if field_name.trim_end_matches('\0') == name && code == DATA_TYPE_F32 {
            return Some(offset);
        }
        offset += type_len(code, options)?;
    }
    None
}

/// The f32 values of the field `at` bytes into the extra bytes of each record of `bytes`
/// (records of `record_len` bytes whose last `extra_len` bytes are the extra bytes).
pub fn f32_column(bytes: &[u8], record_len: usize, extra_len: usize, at: usize) -> Vec<f32> {
    let start = record_len - extra_len + at;
    bytes
        .chunks_exact(record_len)
        .map(|r| f32::from_le_bytes([r[start], r[start + 1], r[start + 2], r[start + 3]]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn descriptors_locate_their_fields() {
        let mut vlr = Vec::new();
        // An undocumented 3-byte field, then two f32 fields.
        let mut raw = [0u8; DESCRIPTOR_LEN];
        raw[3] = 3;
        vlr.extend_from_slice(&raw);
        vlr.extend_from_slice(&f32_descriptor(RADIUS_FIELD, "radius"));
        vlr.extend_from_slice(&f32_descriptor(LOD_RADIUS_FIELD, "lod radius"));
        assert_eq!(f32_field_offset(&vlr, RADIUS_FIELD), Some(3));
        assert_eq!(f32_field_offset(&vlr, LOD_RADIUS_FIELD), Some(7));
        assert_eq!(f32_field_offset(&vlr, "other"), None);
        // Two records of 5 standard bytes + 11 extra bytes.
        let mut bytes = Vec::new();
        for v in [1.5f32, -2.25] {
            bytes.extend_from_slice(&[0; 5]);
            bytes.extend_from_slice(&[9; 3]);
            bytes.extend_from_slice(&v.to_le_bytes());
            bytes.extend_from_slice(&(v * 2.0).to_le_bytes());
        }
        assert_eq!(f32_column(&bytes, 16, 11, 3), vec![1.5, -2.25]);
        assert_eq!(f32_column(&bytes, 16, 11, 7), vec![3.0, -4.5]);
    }
}
