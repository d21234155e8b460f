//! XMP packets that make 360° players show a panorama as a sphere.
//!
//! - Photo Sphere (Google's GPano schema): projection, full and cropped sizes, heading.
//!   Google Photos, Facebook, Flickr and most web viewers read it from PNG and JPEG files.
//! - VR Photo (Google's format for stereo photos): the left eye is the image, the right eye
//!   a base64 JPEG in `GImage:Data`, carried in *extended* XMP because it exceeds the 64 KiB
//!   of one JPEG segment; the main packet names the extension by its MD5
//!   (`xmpNote:HasExtendedXMP`).
//!
//! Values written are numbers and fixed words, so no XML escaping is needed except for the
//! base64 data, whose alphabet needs none either.

use base64::Engine;
use md5::{Digest, Md5};

/// GPano namespace.
pub const GPANO_NS: &str = "http://ns.google.com/photos/1.0/panorama/";
/// GImage namespace (the second image of a VR photo).
pub const GIMAGE_NS: &str = "http://ns.google.com/photos/1.0/image/";
/// Namespace of `xmpNote:HasExtendedXMP`.
pub const XMP_NOTE_NS: &str = "http://ns.adobe.com/xmp/note/";

/// What a Photo Sphere packet says about one full equirectangular panorama.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhotoSphere {
    /// Width of the panorama in pixels (360° of longitude).
    pub width: u32,
    /// Height of the panorama in pixels (180° of latitude).
    pub height: u32,
    /// Compass heading of the image centre in degrees, in `[0, 360)`.
    pub heading_degrees: f64,
}

/// The GPano heading of a render with camera heading `yaw_degrees`.
///
/// The image centre looks along the camera's forward axis (DESIGN §2), and `yaw` is that
/// axis' angle clockwise from +Y seen from above (0 = +Y, 90 = +X). In projected LiDAR
/// coordinates (UTM, state plane) +Y is grid north and +X east, so `yaw` already is a
/// compass heading (up to the grid's convergence with true north, under 3° in a UTM zone);
/// GPano only wants it in `[0, 360)`.
pub fn heading_from_yaw(yaw_degrees: f64) -> f64 {
    let h = yaw_degrees.rem_euclid(360.0);
    // rem_euclid of a tiny negative number rounds up to 360.0 itself.
    if h >= 360.0 { 0.0 } else { h }
}

/// `omnicloud <version>`, the `CaptureSoftware` value.
pub fn software() -> String {
    format!("omnicloud {}", env!("CARGO_PKG_VERSION"))
}

/// Wraps `rdf:Description` attributes into a complete XMP packet.
fn packet(namespaces: &[(&str, &str)], attributes: &[(String, String)]) -> String {
    let mut xml = String::from(
        "<?xpacket begin=\"\u{FEFF}\" id=\"W5M0MpCehiHzreSzNTczkc9d\"?>\n\
         <x:xmpmeta xmlns:x=\"adobe:ns:meta/\">\n \
         <rdf:RDF xmlns:rdf=\"http://www.w3.org/1999/02/22-rdf-syntax-ns#\">\n  \
         <rdf:Description rdf:about=\"\"",
    );
    for (prefix, uri) in namespaces {
        xml.push_str(&format!("\n    xmlns:{prefix}=\"{uri}\""));
    }
    for (name, value) in attributes {
        xml.push_str(&format!("\n    {name}=\"{value}\""));
    }
    xml.push_str("/>\n </rdf:RDF>\n</x:xmpmeta>\n<?xpacket end=\"w\"?>");
    xml
}

/// The GPano attributes of a full (uncropped) equirectangular panorama.
fn gpano_attributes(p: &PhotoSphere) -> Vec<(String, String)> {
    let w = p.width.to_string();
    let h = p.height.to_string();
    [
        ("ProjectionType", "equirectangular".to_owned()),
        ("UsePanoramaViewer", "True".to_owned()),
        ("CaptureSoftware", software()),
        ("FullPanoWidthPixels", w.clone()),
        ("FullPanoHeightPixels", h.clone()),
        ("CroppedAreaImageWidthPixels", w),
        ("CroppedAreaImageHeightPixels", h),
        ("CroppedAreaLeftPixels", "0".to_owned()),
        ("CroppedAreaTopPixels", "0".to_owned()),
        ("PoseHeadingDegrees", format!("{:.1}", p.heading_degrees)),
        // The camera is level: the horizon is the middle row.
        ("PosePitchDegrees", "0.0".to_owned()),
        ("PoseRollDegrees", "0.0".to_owned()),
    ]
    .into_iter()
    .map(|(k, v)| (format!("GPano:{k}"), v))
    .collect()
}

/// A Photo Sphere packet for a mono panorama (PNG iTXt or JPEG APP1).
pub fn photo_sphere_packet(p: &PhotoSphere) -> String {
    packet(&[("GPano", GPANO_NS)], &gpano_attributes(p))
}

/// The two packets of a VR photo whose left eye is described by `left` and whose right eye
/// is the JPEG file `right_jpeg`: the main packet (GPano and the MD5 of the extension) and
/// the extended packet (`GImage:Mime`, `GImage:Data`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VrPhotoPackets {
    /// Goes in the main `http://ns.adobe.com/xap/1.0/` segment.
    pub main: String,
    /// Goes, split, in `http://ns.adobe.com/xmp/extension/` segments.
    pub extended: String,
    /// 32 uppercase hex digits: the MD5 of `extended`, which names it in every segment.
    pub extended_md5: String,
}

/// Builds the packets of a VR photo (see [`VrPhotoPackets`]).
pub fn vr_photo_packets(left: &PhotoSphere, right_jpeg: &[u8]) -> VrPhotoPackets {
    let data = base64::engine::general_purpose::STANDARD.encode(right_jpeg);
    let extended = packet(
        &[("GImage", GIMAGE_NS)],
        &[
            ("GImage:Mime".to_owned(), "image/jpeg".to_owned()),
            ("GImage:Data".to_owned(), data),
        ],
    );
    let extended_md5 = md5_hex(extended.as_bytes());
    let mut attributes = gpano_attributes(left);
    attributes.push(("xmpNote:HasExtendedXMP".to_owned(), extended_md5.clone()));
    let main = packet(
        &[("GPano", GPANO_NS), ("xmpNote", XMP_NOTE_NS)],
        &attributes,
    );
    VrPhotoPackets {
        main,
        extended,
        extended_md5,
    }
}

/// The MD5 of `bytes` as 32 uppercase hex digits, how extended XMP names its packet.
pub fn md5_hex(bytes: &[u8]) -> String {
    Md5::digest(bytes)
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The value of attribute `name="..."` in `xml`.
    fn attr<'a>(xml: &'a str, name: &str) -> Option<&'a str> {
        let start = xml.find(&format!("{name}=\""))? + name.len() + 2;
        let len = xml[start..].find('"')?;
        Some(&xml[start..start + len])
    }

    fn sphere() -> PhotoSphere {
        PhotoSphere {
            width: 4096,
            height: 2048,
            heading_degrees: heading_from_yaw(-30.0),
        }
    }

    #[test]
    fn heading_is_yaw_in_zero_to_360() {
        assert_eq!(heading_from_yaw(0.0), 0.0);
        assert_eq!(heading_from_yaw(90.0), 90.0);
        assert_eq!(heading_from_yaw(-30.0), 330.0);
        assert_eq!(heading_from_yaw(720.5), 0.5);
        assert_eq!(heading_from_yaw(-1e-17), 0.0);
        assert_eq!(heading_from_yaw(360.0), 0.0);
    }

    #[test]
    fn photo_sphere_packet_holds_every_gpano_field() {
        let xml = photo_sphere_packet(&sphere());
        for (name, want) in [
            ("GPano:ProjectionType", "equirectangular"),
            ("GPano:UsePanoramaViewer", "True"),
            ("GPano:FullPanoWidthPixels", "4096"),
            ("GPano:FullPanoHeightPixels", "2048"),
            ("GPano:CroppedAreaImageWidthPixels", "4096"),
            ("GPano:CroppedAreaImageHeightPixels", "2048"),
            ("GPano:CroppedAreaLeftPixels", "0"),
            ("GPano:CroppedAreaTopPixels", "0"),
            ("GPano:PoseHeadingDegrees", "330.0"),
            ("xmlns:GPano", GPANO_NS),
        ] {
            assert_eq!(attr(&xml, name), Some(want), "{name} in\n{xml}");
        }
        let sw = attr(&xml, "GPano:CaptureSoftware").unwrap();
        assert!(sw.starts_with("omnicloud 0."), "{sw}");
        assert!(xml.starts_with("<?xpacket begin=") && xml.ends_with("<?xpacket end=\"w\"?>"));
        assert!(!xml.contains("HasExtendedXMP"));
    }

    #[test]
    fn vr_packets_link_the_extension_by_its_md5() {
        let right = [0xFFu8, 0xD8, 1, 2, 3, 0xFF, 0xD9];
        let p = vr_photo_packets(&sphere(), &right);
        assert_eq!(p.extended_md5.len(), 32);
        assert!(
            p.extended_md5
                .chars()
                .all(|c| c.is_ascii_hexdigit() && !c.is_ascii_lowercase())
        );
        assert_eq!(p.extended_md5, md5_hex(p.extended.as_bytes()));
        assert_eq!(
            attr(&p.main, "xmpNote:HasExtendedXMP"),
            Some(&*p.extended_md5)
        );
        assert_eq!(attr(&p.main, "GPano:FullPanoWidthPixels"), Some("4096"));
        assert_eq!(attr(&p.extended, "GImage:Mime"), Some("image/jpeg"));
        let data = attr(&p.extended, "GImage:Data").unwrap();
        let back = base64::engine::general_purpose::STANDARD
            .decode(data)
            .unwrap();
        assert_eq!(back, right);
    }

    #[test]
    fn md5_matches_rfc_1321() {
        assert_eq!(md5_hex(b""), "D41D8CD98F00B204E9800998ECF8427E");
        assert_eq!(md5_hex(b"abc"), "900150983CD24FB0D6963F7D28E17F72");
    }
}
