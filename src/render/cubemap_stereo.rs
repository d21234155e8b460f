//! Trapp et al.'s image-based stereo (DESIGN §9, `--stereo cubemap:N`): each eye renders a
//! cube map of `N x N` faces from its parallel camera; every output pixel then samples its
//! eye's cube map bilinearly in its direction.

use glam::DVec3;
use rayon::prelude::*;

use crate::frame::{Frame, Rendered};
use crate::projection::cubemap::{self, FACES};
use crate::projection::{Image, Projection, Stereo};

use super::RenderSettings;

/// The settings that render the cube maps of `settings` (stereo `cubemap:N`): the parallel
/// cameras, the cube-map strip `6N x N`; `None` for every other stereo mode.
pub fn face_settings(settings: &RenderSettings) -> Option<RenderSettings> {
    let Stereo::Cubemap { ipd, face } = settings.stereo else {
        return None;
    };
    Some(RenderSettings {
        image: Image {
            width: 6 * face,
            height: face,
            projection: Projection::Cubemap,
        },
        stereo: Stereo::Parallel { ipd },
        ..*settings
    })
}

/// Resamples the cube maps `faces` (as rendered under [`face_settings`]) to `settings.image`,
/// per eye. Colour and coverage are interpolated premultiplied; depth is the weighted mean of
/// the covered samples. Samples stay inside their face (clamped at its edges).
pub fn resample(faces: &Rendered, settings: &RenderSettings) -> Rendered {
    let eye = |f: &Frame| resample_eye(f, &settings.image);
    match faces {
        Rendered::Mono(f) => Rendered::Mono(eye(f)),
        Rendered::Stereo { left, right } => Rendered::Stereo {
            left: eye(left),
            right: eye(right),
        },
    }
}

fn resample_eye(strip: &Frame, image: &Image) -> Frame {
    let mut out = Frame::new(image.width, image.height);
    let w = image.width as usize;
    out.color
        .par_chunks_mut(w)
        .zip(out.depth.par_chunks_mut(w))
        .enumerate()
        .for_each(|(j, (colors, depths))| {
            for (i, (color, depth)) in colors.iter_mut().zip(depths.iter_mut()).enumerate() {
                let Some((lam, phi)) = image.pixel_angles(i as u32, j as u32) else {
                    continue;
                };
                let d = DVec3::new(phi.cos() * lam.sin(), phi.cos() * lam.cos(), phi.sin());
                (*color, *depth) = sample(strip, d);
            }
        });
    out
}

/// Bilinear sample of the cube-map strip in rig-frame direction `d`.
fn sample(strip: &Frame, d: DVec3) -> ([u8; 4], f32) {
    let n = strip.height as f64;
    let (k, a, b) = cubemap::face_coordinates(d);
    debug_assert!(k < FACES.len());
    // Continuous pixel position inside the face, sample centres at +0.5.
    let x = ((a + 1.0) / 2.0 * n - 0.5).clamp(0.0, n - 1.0);
    let y = ((1.0 - b) / 2.0 * n - 0.5).clamp(0.0, n - 1.0);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (x0, y0) = (x0 as u32, y0 as u32);
    let (x1, y1) = (
        (x0 + 1).min(strip.height - 1),
        (y0 + 1).min(strip.height - 1),
    );
    let base = k as u32 * strip.height;
    let taps = [
        (x0, y0, (1.0 - fx) * (1.0 - fy)),
        (x1, y0, fx * (1.0 - fy)),
        (x0, y1, (1.0 - fx) * fy),
        (x1, y1, fx * fy),
    ];
    let (mut rgb, mut alpha, mut depth, mut depth_w) = ([0.0f64; 3], 0.0f64, 0.0f64, 0.0f64);
    for (x, y, wgt) in taps {
        let idx = strip.index(base + x, y);
        let c = strip.color[idx];
        let a = f64::from(c[3]) / 255.0 * wgt;
        for (acc, v) in rgb.iter_mut().zip(c) {
            *acc += f64::from(v) * a;
        }
        alpha += a;
        let z = strip.depth[idx];
        if c[3] != 0 && z.is_finite() {
            depth += f64::from(z) * wgt;
            depth_w += wgt;
        }
    }
    if alpha <= 0.0 {
        return ([0, 0, 0, 0], f32::INFINITY);
    }
    let byte = |v: f64| v.round().clamp(0.0, 255.0) as u8;
    let color = [
        byte(rgb[0] / alpha),
        byte(rgb[1] / alpha),
        byte(rgb[2] / alpha),
        byte(alpha * 255.0),
    ];
    let z = if depth_w > 0.0 {
        (depth / depth_w) as f32
    } else {
        f32::INFINITY
    };
    (color, z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projection::Camera;

    fn settings(face: u32) -> RenderSettings {
        let mut s = RenderSettings::new(64, Camera::new(DVec3::ZERO, 0.0));
        s.stereo = Stereo::Cubemap { ipd: 0.064, face };
        s
    }

    #[test]
    fn faces_are_a_parallel_cube_strip() {
        let f = face_settings(&settings(32)).unwrap();
        assert_eq!((f.image.width, f.image.height), (192, 32));
        assert_eq!(f.image.projection, Projection::Cubemap);
        assert_eq!(f.stereo, Stereo::Parallel { ipd: 0.064 });
        assert!(face_settings(&RenderSettings::new(64, Camera::new(DVec3::ZERO, 0.0))).is_none());
    }

    #[test]
    fn a_uniform_cube_resamples_to_a_uniform_panorama() {
        let mut strip = Frame::new(6 * 8, 8);
        strip.color.fill([10, 200, 30, 255]);
        strip.depth.fill(4.5);
        let out = resample(&Rendered::Mono(strip), &settings(8));
        let Rendered::Mono(f) = out else { panic!() };
        assert!(f.color.iter().all(|c| *c == [10, 200, 30, 255]));
        assert!(f.depth.iter().all(|d| *d == 4.5));
    }

    #[test]
    fn each_output_direction_samples_its_own_face() {
        // Face k has colour k: the panorama's centre column shows front, its top row up.
        let n = 8;
        let mut strip = Frame::new(6 * n, n);
        for j in 0..n {
            for i in 0..6 * n {
                let idx = strip.index(i, j);
                strip.color[idx] = [(i / n) as u8 * 40, 0, 0, 255];
            }
        }
        let Rendered::Mono(f) = resample(&Rendered::Mono(strip), &settings(n)) else {
            panic!()
        };
        assert_eq!(f.color[f.index(32, 16)][0], 0);
        assert_eq!(f.color[f.index(48, 16)][0], 40);
        assert_eq!(f.color[f.index(0, 16)][0], 80);
        assert_eq!(f.color[f.index(16, 16)][0], 120);
        assert_eq!(f.color[f.index(5, 0)][0], 160);
        assert_eq!(f.color[f.index(5, 31)][0], 200);
    }
}
