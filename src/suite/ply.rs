//! Writes suite scenes as binary little-endian PLY: double x/y/z, uchar red/green/blue,
//! float radius (the layout the PLY reader takes per-point radii from).

use ply_rs_bw::ply::{
    Addable, DefaultElement, ElementDef, Encoding, Ply, Property, PropertyDef, PropertyType,
    ScalarType,
};
use ply_rs_bw::writer::Writer;

use super::scenes::SuitePoint;

/// The PLY bytes of `points`, with `comment` in the header.
pub fn ply_bytes(points: &[SuitePoint], comment: &str) -> std::io::Result<Vec<u8>> {
    let mut ply = Ply::<DefaultElement>::new();
    ply.header.encoding = Encoding::BinaryLittleEndian;
    ply.header.comments.push(comment.to_string());
    let mut vertex = ElementDef::new("vertex".to_string());
    let scalar =
        |name: &str, t: ScalarType| PropertyDef::new(name.to_string(), PropertyType::Scalar(t));
    for axis in ["x", "y", "z"] {
        vertex.properties.add(scalar(axis, ScalarType::Double));
    }
    for channel in ["red", "green", "blue"] {
        vertex.properties.add(scalar(channel, ScalarType::UChar));
    }
    vertex.properties.add(scalar("radius", ScalarType::Float));
    ply.header.elements.add(vertex);

    let rows = points
        .iter()
        .map(|p| {
            let mut e = DefaultElement::new();
            e.insert("x".to_string(), Property::Double(p.position.x));
            e.insert("y".to_string(), Property::Double(p.position.y));
            e.insert("z".to_string(), Property::Double(p.position.z));
            e.insert("red".to_string(), Property::UChar(p.rgb[0]));
            e.insert("green".to_string(), Property::UChar(p.rgb[1]));
            e.insert("blue".to_string(), Property::UChar(p.rgb[2]));
            e.insert("radius".to_string(), Property::Float(p.radius));
            e
        })
        .collect();
    ply.payload.insert("vertex".to_string(), rows);

    let mut out = Vec::new();
    Writer::new().write_ply(&mut out, &mut ply)?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn layout_is_header_then_31_bytes_per_point() {
        let p = SuitePoint {
            position: DVec3::new(637_000.25, -1.5, 2.0),
            rgb: [1, 2, 3],
            radius: 0.5,
        };
        let bytes = ply_bytes(&[p, p], "test").unwrap();
        let text = String::from_utf8_lossy(&bytes);
        let end = text.find("end_header\n").unwrap() + "end_header\n".len();
        assert!(text.starts_with("ply\nformat binary_little_endian 1.0\n"));
        assert!(text[..end].contains("property double x\n"));
        assert!(text[..end].contains("property float radius\n"));
        let body = &bytes[end..];
        assert_eq!(body.len(), 2 * 31);
        assert_eq!(
            f64::from_le_bytes(body[0..8].try_into().unwrap()),
            637_000.25
        );
        assert_eq!(&body[24..27], &[1, 2, 3]);
        assert_eq!(f32::from_le_bytes(body[27..31].try_into().unwrap()), 0.5);
    }
}
