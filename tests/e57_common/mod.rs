//! A generated terrestrial survey as E57: two scans with different poses (one Cartesian with
//! colour, one spherical on a row/column grid without colour), a spherical image of the
//! second scan's station and a pinhole image of the first's, looking along its +X. Written
//! with the `e57` crate's writer.
#![allow(dead_code)]

use e57::{
    E57Writer, ImageFormat, IntensityLimits, PinholeImageProperties, Quaternion, Record,
    RecordDataType, RecordName, RecordValue, SphericalImageProperties, Transform, Translation,
};
use glam::DVec3;
use std::f64::consts::PI;
use std::path::Path;

/// Scan 0's pose: a quarter turn about Z (w, x, y, z), then this translation.
pub const POSE0_Q: [f64; 4] = [
    std::f64::consts::FRAC_1_SQRT_2,
    0.0,
    0.0,
    std::f64::consts::FRAC_1_SQRT_2,
];
pub const POSE0_T: [f64; 3] = [10.0, 20.0, 1.5];
/// Scan 1's pose: a turn of -60° about an axis tilted off Z, then this translation.
pub fn pose1_q() -> [f64; 4] {
    let axis = DVec3::new(0.1, -0.05, 1.0).normalize();
    let half = (-60f64).to_radians() / 2.0;
    [
        half.cos(),
        axis.x * half.sin(),
        axis.y * half.sin(),
        axis.z * half.sin(),
    ]
}
pub const POSE1_T: [f64; 3] = [-5.0, 3.0, 0.5];

/// `R(q) · p + t` written out from the quaternion's matrix (independent of glam).
pub fn posed(q: [f64; 4], t: [f64; 3], p: DVec3) -> DVec3 {
    let [w, x, y, z] = q;
    let r = [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ];
    DVec3::new(
        r[0][0] * p.x + r[0][1] * p.y + r[0][2] * p.z + t[0],
        r[1][0] * p.x + r[1][1] * p.y + r[1][2] * p.z + t[1],
        r[2][0] * p.x + r[2][1] * p.y + r[2][2] * p.z + t[2],
    )
}

fn transform(q: [f64; 4], t: [f64; 3]) -> Transform {
    Transform {
        rotation: Quaternion {
            w: q[0],
            x: q[1],
            y: q[2],
            z: q[3],
        },
        translation: Translation {
            x: t[0],
            y: t[1],
            z: t[2],
        },
    }
}

/// Scan 0's points in its own frame with their colours: a box of walls 4 m around the
/// scanner, floor and ceiling, coloured by face.
pub fn scan0_points() -> Vec<(DVec3, [u8; 3])> {
    let mut out = Vec::new();
    let n = 24;
    for i in 0..=n {
        for j in 0..=n {
            let a = -4.0 + 8.0 * i as f64 / n as f64;
            let b = -1.5 + 4.0 * j as f64 / n as f64;
            out.push((DVec3::new(4.0, a, b), [220, 40, 40]));
            out.push((DVec3::new(-4.0, a, b), [40, 220, 40]));
            out.push((DVec3::new(a, 4.0, b), [40, 40, 220]));
            out.push((DVec3::new(a, -4.0, b), [220, 220, 40]));
            let c = -4.0 + 8.0 * j as f64 / n as f64;
            out.push((DVec3::new(a, c, -1.5), [128, 128, 128]));
        }
    }
    out
}

/// The pinhole photo's pose: scan 0's turned a quarter about its Y axis, so the camera's +Z
/// (its line of sight) is the scan's +X and the camera's +X (image columns) the scan's -Z.
pub fn photo0_q() -> [f64; 4] {
    let [w, x, y, z] = POSE0_Q;
    let q = glam::DQuat::from_xyzw(x, y, z, w) * glam::DQuat::from_rotation_y(PI / 2.0);
    [q.w, q.x, q.y, q.z]
}

/// The pinhole photo: red on its left half, blue on its right half.
pub const PHOTO_LEFT: [u8; 3] = [255, 0, 0];
pub const PHOTO_RIGHT: [u8; 3] = [0, 0, 255];

/// Scan 1's grid: rows from the top down, columns with azimuth.
pub const ROWS: usize = 18;
pub const COLUMNS: usize = 36;

/// Scan 1's point at grid cell (row, column): range, azimuth, elevation (off the spherical
/// image's pixel edges, so each falls clearly in one pixel).
pub fn scan1_spherical(row: usize, column: usize) -> (f64, f64, f64) {
    let azimuth = -PI + (column as f64 + 0.3) * 2.0 * PI / COLUMNS as f64;
    let elevation = PI / 2.0 - (row as f64 + 0.3) * PI / ROWS as f64;
    let range = 3.0 + 0.5 * (column % 4) as f64 + 0.1 * row as f64;
    (range, azimuth, elevation)
}

/// The spherical image's size and its pattern: a colour per 8 x 8 block.
pub const PANO_W: u32 = 64;
pub const PANO_H: u32 = 32;
pub fn pano_color(x: u32, y: u32) -> [u8; 3] {
    let (bx, by) = (x / 8, y / 8);
    [
        (bx * 30 + 10) as u8,
        (by * 60 + 20) as u8,
        ((bx + by) % 2 * 200 + 20) as u8,
    ]
}

fn png(width: u32, height: u32, pixel: impl Fn(u32, u32) -> [u8; 3]) -> Vec<u8> {
    let img = image::RgbImage::from_fn(width, height, |x, y| image::Rgb(pixel(x, y)));
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .unwrap();
    bytes
}

fn record(name: RecordName, data_type: RecordDataType) -> Record {
    Record { name, data_type }
}

/// Writes the survey to `path`. Scan 0 also holds one point flagged invalid (dropped on
/// reading).
pub fn write_site(path: &Path) {
    let mut w = E57Writer::from_file(path, "{site-guid}").unwrap();
    {
        let proto = vec![
            record(RecordName::CartesianX, RecordDataType::F64),
            record(RecordName::CartesianY, RecordDataType::F64),
            record(RecordName::CartesianZ, RecordDataType::F64),
            record(
                RecordName::CartesianInvalidState,
                RecordDataType::Integer { min: 0, max: 2 },
            ),
            record(RecordName::ColorRed, RecordDataType::U8),
            record(RecordName::ColorGreen, RecordDataType::U8),
            record(RecordName::ColorBlue, RecordDataType::U8),
            record(
                RecordName::Intensity,
                RecordDataType::Integer { min: 0, max: 4095 },
            ),
        ];
        let mut pc = w.add_pointcloud("{scan-0}", proto).unwrap();
        pc.set_name(Some("North".into()));
        pc.set_transform(Some(transform(POSE0_Q, POSE0_T)));
        pc.set_intensity_limits(Some(IntensityLimits {
            intensity_min: Some(RecordValue::Integer(0)),
            intensity_max: Some(RecordValue::Integer(4095)),
        }));
        for (i, (p, c)) in scan0_points().into_iter().enumerate() {
            pc.add_point(vec![
                RecordValue::Double(p.x),
                RecordValue::Double(p.y),
                RecordValue::Double(p.z),
                RecordValue::Integer(0),
                RecordValue::Integer(i64::from(c[0])),
                RecordValue::Integer(i64::from(c[1])),
                RecordValue::Integer(i64::from(c[2])),
                RecordValue::Integer((i % 4096) as i64),
            ])
            .unwrap();
        }
        pc.add_point(vec![
            RecordValue::Double(1e9),
            RecordValue::Double(0.0),
            RecordValue::Double(0.0),
            RecordValue::Integer(2),
            RecordValue::Integer(0),
            RecordValue::Integer(0),
            RecordValue::Integer(0),
            RecordValue::Integer(0),
        ])
        .unwrap();
        pc.finalize().unwrap();
    }
    {
        let proto = vec![
            record(RecordName::SphericalRange, RecordDataType::F64),
            record(RecordName::SphericalAzimuth, RecordDataType::F64),
            record(RecordName::SphericalElevation, RecordDataType::F64),
            record(
                RecordName::RowIndex,
                RecordDataType::Integer {
                    min: 0,
                    max: ROWS as i64 - 1,
                },
            ),
            record(
                RecordName::ColumnIndex,
                RecordDataType::Integer {
                    min: 0,
                    max: COLUMNS as i64 - 1,
                },
            ),
            record(
                RecordName::Intensity,
                RecordDataType::Integer { min: 0, max: 4095 },
            ),
        ];
        let mut pc = w.add_pointcloud("{scan-1}", proto).unwrap();
        pc.set_name(Some("South".into()));
        pc.set_transform(Some(transform(pose1_q(), POSE1_T)));
        pc.set_intensity_limits(Some(IntensityLimits {
            intensity_min: Some(RecordValue::Integer(0)),
            intensity_max: Some(RecordValue::Integer(4095)),
        }));
        for row in 0..ROWS {
            for column in 0..COLUMNS {
                let (r, a, e) = scan1_spherical(row, column);
                pc.add_point(vec![
                    RecordValue::Double(r),
                    RecordValue::Double(a),
                    RecordValue::Double(e),
                    RecordValue::Integer(row as i64),
                    RecordValue::Integer(column as i64),
                    RecordValue::Integer(4095),
                ])
                .unwrap();
            }
        }
        pc.finalize().unwrap();
    }
    {
        let bytes = png(PANO_W, PANO_H, pano_color);
        let mut img = w.add_image("{pano-1}").unwrap();
        img.set_name("South panorama");
        img.set_pointcloud_guid("{scan-1}");
        img.set_transform(transform(pose1_q(), POSE1_T));
        img.add_spherical(
            ImageFormat::Png,
            &mut bytes.as_slice(),
            SphericalImageProperties {
                width: PANO_W,
                height: PANO_H,
                pixel_width: 2.0 * PI / PANO_W as f64,
                pixel_height: PI / PANO_H as f64,
            },
            None,
        )
        .unwrap();
        img.finalize().unwrap();
    }
    {
        let bytes = png(40, 30, |x, _| if x < 20 { PHOTO_LEFT } else { PHOTO_RIGHT });
        let mut img = w.add_image("{photo-0}").unwrap();
        img.set_name("North photo");
        img.set_pointcloud_guid("{scan-0}");
        img.set_transform(transform(photo0_q(), POSE0_T));
        img.add_pinhole(
            ImageFormat::Png,
            &mut bytes.as_slice(),
            PinholeImageProperties {
                width: 40,
                height: 30,
                focal_length: 0.01,
                pixel_width: 0.0005,
                pixel_height: 0.0005,
                principal_x: 20.0,
                principal_y: 15.0,
            },
            None,
        )
        .unwrap();
        img.finalize().unwrap();
    }
    w.finalize().unwrap();
}
