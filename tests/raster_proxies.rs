//! Proxy modes measured against the reference: `quad` and `static:N` billboards (the paper's
//! imposters) lose coverage at the poles and the seam where `bounds` does not. The numbers
//! are printed for the accuracy chart.

mod raster_common;

use glam::DVec3;
use indicatif::ProgressBar;
use omnicloud::Rendered;
use omnicloud::projection::{Camera, OdsOffset, PoleMerge, PoleMerging, Stereo};
use omnicloud::render::{ColorMode, Imposter, Proxy, RenderSettings, base_colors};
use omnicloud::rng::SplitMix64;
use raster_common::*;

fn left_frame(r: &Rendered) -> &omnicloud::Frame {
    match r {
        Rendered::Mono(f) => f,
        Rendered::Stereo { left, .. } => left,
    }
}

#[test]
fn billboards_are_measurably_worse_than_bounds_at_poles_and_seam() {
    let Some(raster) = rasterizer() else { return };
    // Many spheres near the poles and the seam, none covering a pole (those become bands in
    // every mode), plus the stress scene.
    let mut scene = stress_scene(600);
    let mut rng = SplitMix64::new(7);
    let mut pos = scene.positions.clone();
    let radii0: Vec<f32> = (0..scene.len()).map(|i| scene.radii.get(i)).collect();
    let mut radii = radii0;
    for k in 0..400 {
        let phi: f64 = if k % 2 == 0 {
            rng.range(65.0, 86.0)
        } else {
            -rng.range(65.0, 86.0)
        };
        let lam: f64 = if k % 4 < 2 {
            rng.range(-180.0, 180.0)
        } else {
            rng.range(170.0, 190.0)
        };
        let d = rng.range(2.0, 8.0);
        let (l, p) = (lam.to_radians(), phi.to_radians());
        pos.push((d * DVec3::new(p.cos() * l.sin(), p.cos() * l.cos(), p.sin())).as_vec3());
        radii.push(rng.range(0.1, 0.4) as f32);
    }
    for _ in 0..200 {
        let lam: f64 = rng.range(172.0, 188.0);
        let phi: f64 = rng.range(-50.0, 50.0);
        let d = rng.range(1.0, 6.0);
        let (l, p) = (lam.to_radians(), phi.to_radians());
        pos.push((d * DVec3::new(p.cos() * l.sin(), p.cos() * l.cos(), p.sin())).as_vec3());
        radii.push(rng.range(0.05, 0.3) as f32);
    }
    let n = pos.len();
    scene.positions = pos;
    scene.radii = omnicloud::Radii::PerPoint(radii);
    scene.attributes.rgb = Some(
        (0..n)
            .map(|k| [(k % 250) as u8, (k / 250) as u8 * 40, 9])
            .collect(),
    );

    let mut base = RenderSettings::new(512, Camera::new(DVec3::ZERO, 0.0));
    base.color = ColorMode::Rgb;
    base.stereo = Stereo::Ods {
        ipd: 0.064,
        merging: PoleMerging::both(PoleMerge::COMFORTABLE),
        offset: OdsOffset::Exact,
    };
    let colors = base_colors(&scene, base.color).unwrap();
    let view = base.views()[0];
    let reference = reference(&scene, &base, &view);
    let mut results = Vec::new();
    for (proxy, imposter) in [
        (Proxy::Bounds, Imposter::Raycast),
        (Proxy::Quad, Imposter::Raycast),
        (Proxy::Static(4), Imposter::Raycast),
        (Proxy::Dynamic, Imposter::Raycast),
        (Proxy::Quad, Imposter::Sprite),
        (Proxy::Static(4), Imposter::Sprite),
    ] {
        let mut s = base;
        s.proxy = proxy;
        s.imposter = imposter;
        let (r, stats) = raster.render(&scene, &s, &ProgressBar::hidden()).unwrap();
        let a = compare(left_frame(&r), &reference, &colors, &s);
        eprintln!(
            "{proxy:?}+{imposter:?}: coverage error total {} px {:.4}%, poles {} px {:.4}%, seam {} px {:.4}%, depth p99 {:.2e} ({} vertices)",
            a.all().mismatch,
            100.0 * a.coverage_fraction(),
            a.pole().0,
            100.0 * a.pole_fraction(),
            a.seam().mismatch,
            100.0 * a.seam_fraction(),
            a.depth_rel_p99(),
            stats.vertices
        );
        results.push((proxy, imposter, a));
    }
    let bounds = &results[0].2;
    // Measured on lavapipe: bounds 0 px; the billboards 1.77-5.10 % of all pixels, the quad
    // 151 and 1051 px in the polar caps and 17 and 57 px in the seam columns.
    assert!(
        bounds.all().mismatch <= 8,
        "bounds: {}",
        bounds.all().mismatch
    );
    for (proxy, imposter, a) in &results[1..] {
        // Every billboard under-covers near spheres (a square of half-size r subtends
        // atan(r/d) < asin(r/d)) and bows at high latitude: a real, chartable difference.
        assert!(
            a.coverage_fraction() > 0.015 && a.all().mismatch > 20 * bounds.all().mismatch.max(1),
            "{proxy:?}+{imposter:?}: total {} vs bounds {}",
            a.all().mismatch,
            bounds.all().mismatch
        );
    }
    // The untessellated quad (the paper's "No Tess.") is worse than bounds at the poles and
    // the seam in particular, with either fragment model.
    for (proxy, imposter, a) in &results[1..] {
        if *proxy != Proxy::Quad {
            continue;
        }
        assert!(
            a.pole().0 > bounds.pole().0 + 120,
            "{proxy:?}+{imposter:?} poles: {} vs bounds {}",
            a.pole().0,
            bounds.pole().0
        );
        assert!(
            a.seam().mismatch > bounds.seam().mismatch + 12,
            "{proxy:?}+{imposter:?} seam: {} vs bounds {}",
            a.seam().mismatch,
            bounds.seam().mismatch
        );
    }
    // Tessellation fixes most of the pole error: static:4 sits between quad and bounds.
    let (quad, static4) = (&results[1].2, &results[2].2);
    assert!(static4.pole().0 < quad.pole().0);
    assert!(static4.pole().0 >= bounds.pole().0);
}
