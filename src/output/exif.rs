//! A minimal EXIF block (TIFF, little-endian, one IFD) for JPEG panoramas.
//!
//! Facebook's 360° photo page names GPano XMP as what it reads, and uploaders report that it
//! also wants a camera make and model in EXIF; so JPEG panoramas carry `Make` and `Model`
//! (`omnicloud`) and `Software` (`omnicloud <version>`). The JPEG encoder adds the `Exif\0\0` APP1 header.

/// TIFF field type 2: NUL-terminated ASCII.
const ASCII: u16 = 2;

/// The TIFF bytes of an EXIF block naming omnicloud as make, model and software.
pub fn omnicloud_exif() -> Vec<u8> {
    // Tags in increasing order, as TIFF requires.
    let fields: [(u16, String); 3] = [
        (0x010F, "omnicloud".to_owned()), // Make
        (0x0110, "omnicloud".to_owned()), // Model
        (0x0131, super::xmp::software()), // Software
    ];
    let ifd_start = 8u32;
    let ifd_len = 2 + 12 * fields.len() as u32 + 4;
    let mut data_at = ifd_start + ifd_len;
    let mut out = Vec::new();
    out.extend_from_slice(b"II");
    out.extend_from_slice(&42u16.to_le_bytes());
    out.extend_from_slice(&ifd_start.to_le_bytes());
    out.extend_from_slice(&(fields.len() as u16).to_le_bytes());
    let mut data = Vec::new();
    for (tag, text) in &fields {
        let mut value = text.as_bytes().to_vec();
        value.push(0);
        out.extend_from_slice(&tag.to_le_bytes());
        out.extend_from_slice(&ASCII.to_le_bytes());
        out.extend_from_slice(&(value.len() as u32).to_le_bytes());
        if value.len() <= 4 {
            value.resize(4, 0);
            out.extend_from_slice(&value);
        } else {
            out.extend_from_slice(&data_at.to_le_bytes());
            data_at += value.len() as u32;
            data.extend_from_slice(&value);
        }
    }
    out.extend_from_slice(&0u32.to_le_bytes()); // no next IFD
    out.extend_from_slice(&data);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ASCII value of `tag` in IFD0 of little-endian TIFF bytes.
    fn ascii_field(tiff: &[u8], tag: u16) -> Option<String> {
        let u16_at = |i: usize| u16::from_le_bytes([tiff[i], tiff[i + 1]]);
        let u32_at = |i: usize| u32::from_le_bytes(tiff[i..i + 4].try_into().unwrap());
        let ifd = u32_at(4) as usize;
        (0..u16_at(ifd) as usize).find_map(|k| {
            let e = ifd + 2 + 12 * k;
            (u16_at(e) == tag && u16_at(e + 2) == ASCII).then(|| {
                let n = u32_at(e + 4) as usize;
                let at = if n <= 4 {
                    e + 8
                } else {
                    u32_at(e + 8) as usize
                };
                String::from_utf8(tiff[at..at + n - 1].to_vec()).unwrap()
            })
        })
    }

    #[test]
    fn exif_names_make_model_and_software() {
        let tiff = omnicloud_exif();
        assert_eq!(&tiff[..4], b"II*\0");
        assert_eq!(ascii_field(&tiff, 0x010F).as_deref(), Some("omnicloud"));
        assert_eq!(ascii_field(&tiff, 0x0110).as_deref(), Some("omnicloud"));
        let sw = ascii_field(&tiff, 0x0131).unwrap();
        assert!(sw.starts_with("omnicloud "), "{sw}");
        assert_eq!(ascii_field(&tiff, 0x0112), None);
    }
}
