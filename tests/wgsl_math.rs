//! The WGSL math agrees with the f64 Rust functions it mirrors, through the probe kernel
//! (`shaders/probe.wgsl`): `project`, `ray` and the merge factor (`ods.wgsl`,
//! `pole_merge.wgsl`, `equirect.wgsl`) on random points and angles, for mono, parallel and
//! ODS views with each merge profile and both offsets; `intersect_sphere` (`sphere.wgsl`), `shade`
//! (`shading.wgsl`) and `sphere_bounds` (`sphere_bounds.wgsl`) on random inputs. Each test
//! prints its worst difference.
//!
//! Tolerances (f32 on the GPU): inputs are the same f32 values on both sides, so the
//! differences are f32 arithmetic only. Angles: 2e-5 rad, 1/80 of a pixel at 3840 wide
//! (1.6e-3 rad/px); a few ulp of atan2/asin of values near 1 plus the fixed point's f32
//! convergence. Ray origins: 1e-6 m (|origin| <= 0.032 m). Directions: 1e-6. Merge factors:
//! 1e-5 (f32 pow/cos of degrees). Points within 1% of the viewing circle may
//! legitimately flip between projectable and not, and their latitude is ill-conditioned in
//! the circle radius; they are skipped (and counted: under 5% of a sample that over-samples the eye region).
//! Intersection distances: 2e-6 of `|origin - centre| + radius` (measured 7.6e-7 on
//! lavapipe). Bounds corners: 5e-5 rad (measured 3.0e-5: `asin` of ratios near 1 and the
//! `tan`/`atan` latitude growth). Shading: unlit and normal colours equal; phong equal but for
//! rare off-by-one bytes (none on lavapipe).

mod raster_common;

use glam::{DVec2, DVec3, Vec3};
use omnicloud::projection::sphere;
use omnicloud::projection::{
    Camera, Eye, EyeModel, OdsOffset, PoleMerge, PoleMerging, Stereo, View, equirect, sphere_bounds,
};
use omnicloud::raster::probe::ProbeItem;
use omnicloud::render::RenderSettings;
use omnicloud::render::shading::{self, Shading};
use omnicloud::rng::SplitMix64 as Rng;
use raster_common::rasterizer;

const ANGLE_TOL: f64 = 2e-5;
/// Intersection distance, relative to `|origin - centre| + radius`.
const T_TOL: f64 = 2e-6;
/// Corners of `sphere_bounds`, radians.
const BOUNDS_TOL: f64 = 5e-5;

fn cases() -> Vec<(String, Stereo)> {
    let mut v = vec![
        ("mono".to_string(), Stereo::Mono),
        ("parallel".to_string(), Stereo::Parallel { ipd: 0.064 }),
    ];
    for (name, merging) in [
        ("off", PoleMerging::OFF),
        ("marrinan", PoleMerging::both(PoleMerge::COMFORTABLE)),
        ("cycles", PoleMerging::both(PoleMerge::CYCLES_DEFAULT)),
        (
            "cycles/marrinan",
            PoleMerging {
                north: PoleMerge::CYCLES_DEFAULT,
                south: PoleMerge::Marrinan {
                    start_deg: 30.0,
                    end_deg: 10.0,
                    exponent: 1.5,
                },
            },
        ),
    ] {
        for offset in [OdsOffset::Exact, OdsOffset::Paper] {
            v.push((
                format!("{name} {offset:?}"),
                Stereo::Ods {
                    ipd: 0.064,
                    merging,
                    offset,
                },
            ));
        }
    }
    v
}

#[test]
fn wgsl_project_ray_and_merge_match_rust() {
    let Some(raster) = rasterizer() else { return };
    let camera = Camera::new(DVec3::new(3.0, -2.0, 1.5), 23.0);
    let mut rng = Rng::new(99);
    let n = 4000;
    let mut items = Vec::new();
    for k in 0..n {
        // Log-uniform distance 0.01..200 m, uniform on the sphere; some near the axis.
        let d = 10f64.powf(rng.range(-2.0, 2.3));
        let z = rng.range(-1.0, 1.0);
        let z = if k % 10 == 0 { z.signum() * 0.9999 } else { z };
        let a = rng.range(-std::f64::consts::PI, std::f64::consts::PI);
        let s = (1.0 - z * z).sqrt();
        let p = d * DVec3::new(s * a.cos(), s * a.sin(), z);
        items.push(ProbeItem {
            point: p.as_vec3().to_array(),
            angles: [
                rng.range(-std::f64::consts::PI, std::f64::consts::PI) as f32,
                rng.range(-std::f64::consts::FRAC_PI_2, std::f64::consts::FRAC_PI_2) as f32,
            ],
            ..Default::default()
        });
    }
    let mut worst = [0f64; 4];
    for (name, stereo) in cases() {
        let mut settings = RenderSettings::new(512, camera);
        settings.stereo = stereo;
        for eye in [Eye::Left, Eye::Right] {
            let view = View::eye(camera, &stereo, eye);
            let got = raster.probe_math(&view, &settings, &items).expect("probe");
            let (mut projected, mut skipped) = (0, 0);
            for i in 0..n {
                let p = DVec3::from_array(items[i].point.map(|x| x as f64));
                let want = view.project(camera.center + p);
                let rho = p.truncate().length();
                // Within 1% of the viewing circle (r/rho > 0.99) phi = atan2(z, sqrt(rho^2 -
                // r^2)) is ill-conditioned in r: f32 cannot match f64 there, nor does it need
                // to (such points are centimetres from the eye).
                let z = p.z;
                let r = view.solve_circle_radius(rho, z).unwrap_or(rho);
                let near_circle = view.model == EyeModel::Ods
                    && view.offset == OdsOffset::Exact
                    && r >= 0.99 * rho;
                match (want, got[i].projected) {
                    (Some(_), Some(_)) if near_circle => skipped += 1,
                    (Some((wl, wp)), Some((gl, gp))) => {
                        let dl = equirect::wrap_longitude(wl - gl as f64).abs();
                        let dp = (wp - gp as f64).abs();
                        // Near the poles longitude is ill-conditioned: scale it by cos(phi).
                        let dl = dl * wp.cos().max(1e-3);
                        worst[0] = worst[0].max(dl);
                        worst[1] = worst[1].max(dp);
                        assert!(
                            dl <= ANGLE_TOL && dp <= ANGLE_TOL,
                            "{name} {eye:?} point {p:?}: rust ({wl}, {wp}) wgsl ({gl}, {gp})"
                        );
                        projected += 1;
                    }
                    (None, None) => {}
                    _ if near_circle => skipped += 1,
                    (w, g) => panic!("{name} {eye:?} point {p:?}: rust {w:?} wgsl {g:?}"),
                }
                let [lam, phi] = items[i].angles.map(|x| x as f64);
                let (o, d) = view.ray(lam, phi);
                let go = DVec3::from_array(got[i].ray_origin.map(|x| x as f64));
                let gd = DVec3::from_array(got[i].ray_dir.map(|x| x as f64));
                worst[2] = worst[2].max((o - camera.center - go).length());
                worst[2] = worst[2].max((d - gd).length());
                assert!(
                    (o - camera.center - go).length() <= 1e-6,
                    "{name} ray origin"
                );
                assert!((d - gd).length() <= 1e-6, "{name} ray dir");
                let m = view.merging.factor(phi);
                worst[3] = worst[3].max((m - got[i].merge as f64).abs());
                assert!(
                    (m - got[i].merge as f64).abs() <= 1e-5,
                    "{name} merge at {phi}"
                );
            }
            assert!(projected > n / 2, "{name}: only {projected} projected");
            assert!(
                skipped < n / 20,
                "{name}: {skipped} skipped near the circle"
            );
        }
    }
    eprintln!(
        "worst |dlam|cos(phi) {:.2e}, |dphi| {:.2e}, ray {:.2e}, merge {:.2e}",
        worst[0], worst[1], worst[2], worst[3]
    );
}

fn log_uniform(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
    10f64.powf(rng.range(lo.log10(), hi.log10()))
}

fn unit(rng: &mut Rng) -> DVec3 {
    let z = rng.range(-1.0, 1.0);
    let a = rng.range(-std::f64::consts::PI, std::f64::consts::PI);
    let s = (1.0 - z * z).sqrt();
    DVec3::new(s * a.cos(), s * a.sin(), z)
}

fn f32x3(v: DVec3) -> [f32; 3] {
    v.as_vec3().to_array()
}

fn f64x3(v: [f32; 3]) -> DVec3 {
    DVec3::from_array(v.map(f64::from))
}

/// `intersect_sphere` (sphere.wgsl) against `projection::sphere::intersect` on the same f32
/// rays and spheres: rays from within the viewing circle aimed at or beside spheres 5 cm to
/// 300 m away, some enclosing the origin. Distance tolerance relative to `|origin - centre| +
/// radius`; rays within 1e-3 radius of grazing, or starting within 1e-4 radius of the
/// surface, decide hit or miss by rounding and are skipped (counted).
#[test]
fn wgsl_sphere_intersection_matches_rust() {
    let Some(raster) = rasterizer() else { return };
    let camera = Camera::new(DVec3::ZERO, 0.0);
    let settings = RenderSettings::new(512, camera);
    let view = View::mono(camera);
    let mut rng = Rng::new(7);
    let n = 20000;
    let items: Vec<ProbeItem> = (0..n)
        .map(|k| {
            let centre = log_uniform(&mut rng, 0.05, 300.0) * unit(&mut rng);
            let rel_max = if k % 10 == 0 { 3.0 } else { 0.5 };
            let radius = centre.length() * log_uniform(&mut rng, 1e-4, rel_max);
            let origin = 0.032 * rng.next_f64() * unit(&mut rng);
            let target = centre + radius * rng.range(0.0, 1.5) * unit(&mut rng);
            let dir = (target - origin).normalize();
            let c = f32x3(centre);
            ProbeItem {
                ray_origin: f32x3(origin),
                ray_dir: f32x3(dir),
                sphere: [c[0], c[1], c[2], radius as f32],
                ..Default::default()
            }
        })
        .collect();
    let got = raster.probe_math(&view, &settings, &items).expect("probe");
    let (mut worst, mut hits, mut skipped) = (0f64, 0, 0);
    for (it, g) in items.iter().zip(&got) {
        let (o, d) = (f64x3(it.ray_origin), f64x3(it.ray_dir));
        let (c, r) = (
            f64x3([it.sphere[0], it.sphere[1], it.sphere[2]]),
            it.sphere[3] as f64,
        );
        let oc = o - c;
        let perp = (oc - oc.dot(d) * d).length();
        if ((r - perp) / r).abs() < 1e-3 || (oc.length() - r).abs() < 1e-4 * r {
            skipped += 1;
            continue;
        }
        let want = sphere::intersect(o, d, c, r);
        match (want, g.hit_t) {
            (Some(w), Some(t)) => {
                let err = (w - t as f64).abs() / (oc.length() + r);
                worst = worst.max(err);
                assert!(err <= T_TOL, "ray {it:?}: rust {w} wgsl {t}");
                hits += 1;
            }
            (None, None) => {}
            (w, t) => panic!("ray {it:?}: rust {w:?} wgsl {t:?}"),
        }
    }
    eprintln!("intersection: worst |dt|/(|oc|+r) {worst:.2e}, {hits} hits, {skipped} skipped");
    assert!(hits > n * 3 / 4, "only {hits} hits");
    assert!(skipped < n / 200, "{skipped} skipped");
}

/// `shade` (shading.wgsl) against `render::shading::shade` on the same f32 inputs, in each
/// mode, with the lights of a camera away from the origin. Unlit colours are equal; phong
/// and normal may round the other way where a value sits within f32 noise of a byte
/// boundary (normalising the normal differs by an ulp between GPU and CPU).
#[test]
fn wgsl_shading_matches_rust() {
    let Some(raster) = rasterizer() else { return };
    let camera = Camera::new(DVec3::new(3.0, -2.0, 1.5), 23.0);
    let settings = RenderSettings::new(512, camera);
    let view = View::mono(camera);
    let ls = shading::lights(&camera);
    let mut rng = Rng::new(11);
    let n = 30000;
    let modes = [Shading::Unlit, Shading::Phong, Shading::Normal];
    let items: Vec<ProbeItem> = (0..n)
        .map(|k| {
            let hit = log_uniform(&mut rng, 0.05, 100.0) * unit(&mut rng);
            let eye = 0.032 * rng.next_f64() * unit(&mut rng);
            let mut normal = unit(&mut rng);
            if normal.dot(eye - hit) < 0.0 {
                normal = -normal;
            }
            // Off unit length by up to 1e-3, as a rounded normal may be: both sides normalise.
            let normal = normal * rng.range(0.999, 1.001);
            ProbeItem {
                shading: modes[k % 3],
                base: [0; 3].map(|_| (rng.next_f64() * 256.0) as u8),
                normal: f32x3(normal),
                hit: f32x3(hit),
                eye: f32x3(eye),
                ..Default::default()
            }
        })
        .collect();
    let got = raster.probe_math(&view, &settings, &items).expect("probe");
    let mut off = [0usize; 3];
    let mut worst = [0f32; 3];
    for (k, (it, g)) in items.iter().zip(&got).enumerate() {
        let at = |v: [f32; 3]| (camera.center + f64x3(v)).as_vec3();
        let want = shading::shade(
            it.shading,
            it.base,
            Vec3::from_array(it.normal),
            at(it.hit),
            at(it.eye),
            &ls,
        );
        for (w, g) in want.iter().zip(g.shaded) {
            let diff = (*w as f32 - g).abs();
            worst[k % 3] = worst[k % 3].max(diff);
            off[k % 3] += (diff != 0.0) as usize;
        }
    }
    eprintln!(
        "shading: channels off (unlit, phong, normal) {off:?} of {} each, worst {worst:?}",
        n
    );
    assert_eq!(worst[0], 0.0, "unlit");
    for (mode, k) in [("phong", 1), ("normal", 2)] {
        assert!(worst[k] <= 1.0, "{mode} off by {}", worst[k]);
        assert!(
            off[k] <= n / 10_000,
            "{mode}: {} channels off by one",
            off[k]
        );
    }
}

/// `sphere_bounds` (sphere_bounds.wgsl) against the f64 `projection::sphere_bounds` on the
/// same f32 spheres, for every view of `cases()`: spheres anywhere, near the poles and
/// straddling the seam, 1 cm to 200 m away, some enclosing the eye. The special flag is
/// equal and the corners agree to BOUNDS_TOL (longitudes modulo 2 pi). Spheres within f32
/// noise of one of the branch tests (eye in the ball, ball meeting the viewing cylinder or
/// the vertical axis) may take the other branch and are skipped (counted). Bounds that are
/// not special have a projected centre, with no skipping.
#[test]
fn wgsl_sphere_bounds_match_rust() {
    let Some(raster) = rasterizer() else { return };
    let camera = Camera::new(DVec3::new(3.0, -2.0, 1.5), 23.0);
    let mut rng = Rng::new(5);
    let n = 4000;
    let items: Vec<ProbeItem> = (0..n)
        .map(|k| {
            let mut u = unit(&mut rng);
            if k % 5 == 0 {
                u.z = u.z.signum() * rng.range(0.99, 1.0);
            } else if k % 5 == 1 {
                u.y = -u.y.abs();
                u.x *= 0.02;
            }
            let centre = log_uniform(&mut rng, 0.01, 200.0) * u.normalize();
            let radius = centre.length() * log_uniform(&mut rng, 1e-4, 1.5);
            let c = f32x3(centre);
            ProbeItem {
                point: c,
                sphere: [c[0], c[1], c[2], radius as f32],
                ..Default::default()
            }
        })
        .collect();
    let (mut worst, mut skipped, mut special) = (0f64, 0, 0);
    for (name, stereo) in cases() {
        let mut settings = RenderSettings::new(512, camera);
        settings.stereo = stereo;
        for eye in [Eye::Left, Eye::Right] {
            let view = View::eye(camera, &stereo, eye);
            let got = raster.probe_math(&view, &settings, &items).expect("probe");
            for (it, g) in items.iter().zip(&got) {
                let s = f64x3([it.sphere[0], it.sphere[1], it.sphere[2]]);
                let r = it.sphere[3] as f64;
                // The splat takes bounds that are not special as a projected centre.
                assert!(
                    g.bounds_special || g.projected.is_some(),
                    "{name} {eye:?} sphere {s:?} r {r}: ordinary bounds, centre unprojected"
                );
                if near_a_branch_test(&view, s, r) {
                    skipped += 1;
                    continue;
                }
                let want = sphere_bounds(&view, s, r);
                assert_eq!(
                    want.special, g.bounds_special,
                    "{name} {eye:?} sphere {s:?} r {r}"
                );
                special += want.special as usize;
                let lo = DVec2::from_array(g.bounds_lo.map(f64::from));
                let hi = DVec2::from_array(g.bounds_hi.map(f64::from));
                let dl = equirect::wrap_longitude(want.rect.lo.x - lo.x).abs();
                let dh = equirect::wrap_longitude(want.rect.hi.x - hi.x).abs();
                let dp = (want.rect.lo.y - lo.y)
                    .abs()
                    .max((want.rect.hi.y - hi.y).abs());
                let err = dl.max(dh).max(dp);
                worst = worst.max(err);
                assert!(
                    err <= BOUNDS_TOL,
                    "{name} {eye:?} sphere {s:?} r {r}: rust {want:?} wgsl {lo} {hi}"
                );
            }
        }
    }
    let total = n * 2 * cases().len();
    eprintln!(
        "sphere bounds: worst corner error {worst:.2e} rad, {special} special, {skipped} skipped of {total}"
    );
    assert!(skipped < total / 1000, "{skipped} skipped");
    assert!(
        special > total / 20 && special < total / 2,
        "{special} special"
    );
}

/// Whether the sphere (`s`, `r`) sits within f32 noise of one of `sphere_bounds`' branch
/// tests, so the GPU may take the other branch.
fn near_a_branch_test(view: &View, s: DVec3, r: f64) -> bool {
    use omnicloud::projection::sphere_bounds::{
        ABSOLUTE_SLACK, AXIS_SLACK, CYLINDER_SLACK, ENCLOSE_SLACK,
    };
    let close = |a: f64, b: f64, scale: f64| (a - b).abs() <= 1e-5 * scale;
    let b = view.basis();
    // A parallel eye is the mono view from its camera.
    let (s, h) = match view.model {
        EyeModel::Parallel => (s - view.eye_sign * view.half_ipd * b.right, 0.0),
        EyeModel::Ods => (s, view.half_ipd * view.eye_sign.abs()),
    };
    let rho = s.dot(b.right).hypot(s.dot(b.forward));
    let d = s.length();
    close(d, (r + h) * (1.0 + ENCLOSE_SLACK) + ABSOLUTE_SLACK, d)
        || close(
            rho - r,
            h * (1.0 + CYLINDER_SLACK) + ABSOLUTE_SLACK,
            rho + r,
        )
        || close(r, rho * (1.0 - AXIS_SLACK), rho + r)
        || close(r + h, rho * (1.0 - AXIS_SLACK), rho + r + h)
}

/// `image_ray` (`projection.wgsl`) and `image_bounds` (`image_bounds.wgsl`) against
/// `View::image_ray` and `projection::image_bounds` (same margins) in every projection, mono,
/// ODS and pitched and rolled: ray origins within 1e-6 m (1e-6 relative for the map's),
/// directions within [`IMAGE_DIR_TOL`]; rectangle corners within [`RECT_TOL_PX`]. Pixels within f32 noise
/// of the Hammer ellipse or the fisheye circle, spheres within f32 noise of a branch test,
/// and rectangles that just touch an edge, may legitimately differ; they are counted.
#[test]
fn wgsl_image_ray_and_image_bounds_match_rust() {
    use omnicloud::projection::Image;
    use omnicloud::projection::image_bounds::{self, cone_of};
    use omnicloud::raster::probe::bounds_margins;
    let Some(raster) = rasterizer() else { return };
    let mut rng = Rng::new(4242);
    let level = Camera::new(DVec3::new(3.0, -2.0, 1.5), 23.0);
    let tilted = level.with_orientation(35.0, -25.0);
    let stereo = Stereo::Ods {
        ipd: 0.064,
        merging: PoleMerging::both(PoleMerge::COMFORTABLE),
        offset: OdsOffset::Exact,
    };
    let map = Image::map(
        DVec3::new(-40.0, -25.0, -4.0),
        DVec3::new(35.0, 30.0, 9.0),
        512,
    )
    .expect("map");
    let mut images: Vec<Image> = [
        "equirect",
        "equirect:200,100",
        "hammer",
        "cylindrical:100",
        "fisheye:200",
        "cubemap",
    ]
    .iter()
    .map(|p| Image::new(p.parse().unwrap(), 510).unwrap())
    .collect();
    images.push(map);
    let n = 3000;
    let (mut worst_o, mut worst_d, mut worst_rect) = (0f64, 0f64, 0f64);
    let (mut rays, mut flipped, mut rects, mut skipped, mut counts_differ) = (0, 0, 0, 0, 0);
    for image in images {
        for (camera, stereo, eye) in [
            (level, Stereo::Mono, Eye::Left),
            (level, stereo, Eye::Right),
            (tilted, stereo, Eye::Left),
        ] {
            let view = View::eye(camera, &stereo, eye);
            let mut settings = RenderSettings::new(image.width, camera);
            settings.image = image;
            settings.stereo = stereo;
            let items: Vec<ProbeItem> = (0..n)
                .map(|_| {
                    let i = (rng.next_f64() * image.width as f64) as u32;
                    let j = (rng.next_f64() * image.height as f64) as u32;
                    let s = log_uniform(&mut rng, 0.05, 100.0) * unit(&mut rng);
                    let r = s.length() * log_uniform(&mut rng, 1e-3, 0.8);
                    let c = f32x3(s);
                    ProbeItem {
                        pixel: [i as f32 + 0.5, j as f32 + 0.5],
                        sphere: [c[0], c[1], c[2], r as f32],
                        ..Default::default()
                    }
                })
                .collect();
            let got = raster.probe_math(&view, &settings, &items).expect("probe");
            let label = format!("{} {eye:?} {:?}", image.projection, camera.pitch_deg);
            for (it, g) in items.iter().zip(&got) {
                let (i, j) = (it.pixel[0] as u32, it.pixel[1] as u32);
                match (view.image_ray(&image, i, j), g.image_ray) {
                    (Some((o, d)), Some((go, gd))) => {
                        let o = o - camera.center;
                        let eo = (o - f64x3(go)).length() / o.length().max(1.0);
                        let ed = (d - f64x3(gd)).length();
                        worst_o = worst_o.max(eo);
                        worst_d = worst_d.max(ed);
                        assert!(
                            eo <= 1e-6 && ed <= IMAGE_DIR_TOL,
                            "{label} pixel ({i}, {j}): origin {eo:.2e} dir {ed:.2e}"
                        );
                        rays += 1;
                    }
                    (None, None) => {}
                    _ => flipped += 1,
                }
                let s = f64x3([it.sphere[0], it.sphere[1], it.sphere[2]]);
                let r = f64::from(it.sphere[3]);
                let near_cone = cone_of(&view, s, r, 0.0)
                    .is_some_and(|(axis, a)| near_a_cone_branch(&image.projection, axis, a));
                if near_a_branch_test(&view, s, r) || near_cone {
                    skipped += 1;
                    continue;
                }
                let want = image_bounds::image_bounds(&image, &view, s, r, bounds_margins());
                // A rectangle that just touches an edge of the image or of a cube face's
                // quarter may be empty on one side only.
                if want.len() != g.rect_count {
                    counts_differ += 1;
                    continue;
                }
                for (w, q) in want.iter().zip(&g.rects) {
                    let err = (w.lo.x - f64::from(q[0]))
                        .abs()
                        .max((w.lo.y - f64::from(q[1])).abs())
                        .max((w.hi.x - f64::from(q[2])).abs())
                        .max((w.hi.y - f64::from(q[3])).abs());
                    worst_rect = worst_rect.max(err);
                    assert!(
                        err <= RECT_TOL_PX,
                        "{label} sphere {s} r {r}: rust {w:?} wgsl {q:?}"
                    );
                    rects += 1;
                }
            }
        }
    }
    eprintln!(
        "image rays: {rays} compared, origin {worst_o:.2e}, dir {worst_d:.2e}, {flipped} \
         flipped at an edge; rects: {rects} compared, worst corner {worst_rect:.2e} px, \
         {skipped} spheres skipped, {counts_differ} with a different count"
    );
    assert!(
        counts_differ <= 5,
        "{counts_differ} spheres got a different count"
    );
    assert!(flipped <= 3, "{flipped} pixels flipped");
    assert!(skipped <= 50, "{skipped} skipped");
}

/// `image_ray` directions (measured 4.2e-7 on lavapipe: the projections get the sines and
/// cosines algebraically, without an f32 `atan2` round trip).
const IMAGE_DIR_TOL: f64 = 1e-6;

/// Rectangle corners, pixels at 510 px wide (measured 3.1e-3 on lavapipe).
const RECT_TOL_PX: f64 = 0.01;

/// Whether the cone (rig axis, half-angle) sits within f32 noise of a fisheye or cube-face
/// branch test of `image_bounds`.
fn near_a_cone_branch(p: &omnicloud::projection::Projection, axis: DVec3, alpha: f64) -> bool {
    use omnicloud::projection::Projection;
    use omnicloud::projection::cubemap::FACES;
    let a = alpha + omnicloud::raster::probe::bounds_margins().angle;
    let sin_a = a.min(std::f64::consts::FRAC_PI_2).sin();
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-4;
    match p {
        Projection::Fisheye { .. } => {
            let t = axis.x.hypot(axis.z).atan2(axis.y);
            close(sin_a, t.sin() * (1.0 - 1e-4))
        }
        Projection::Cubemap => FACES.iter().any(|[fa, fb, fc]| {
            let ka = axis.dot(*fa);
            let rho = |k: f64| ka.hypot(k) * (1.0 - 1e-4);
            close(ka, -sin_a)
                || close(sin_a, rho(axis.dot(*fb)))
                || close(sin_a, rho(axis.dot(*fc)))
        }),
        _ => false,
    }
}
