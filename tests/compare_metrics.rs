//! Compare reports exactly the differences planted in synthetic images: shifted and removed
//! discs, shifted rectangles (closed-form silhouette error), a +1% depth offset, and
//! differences confined to a latitude band, the seam or one eye; plus heatmap and files.

use omnicloud::compare::{
    CompareError, LegendLayout, compare, compare_files, heatmap,
    heatmap::{REF_ONLY, TEST_ONLY, ramp},
};
use omnicloud::output::{Layout, LinearImage, write_image};
use omnicloud::{Frame, Rendered};

/// An all-background image.
fn blank(w: u32, h: u32) -> LinearImage {
    LinearImage::from_frame(&Frame::new(w, h))
}

/// Marks pixel `k` hit with a colour and depth derived from its position.
fn hit(img: &mut LinearImage, k: usize) {
    img.coverage[k] = 1.0;
    img.depth[k] = 2.0 + (k % 97) as f32 * 0.01;
    img.color[k] = [0.2, 0.5, (k % 7) as f32 / 7.0];
}

/// Hits every pixel whose centre satisfies `inside(x, y)`; returns how many.
fn paint(img: &mut LinearImage, inside: impl Fn(f64, f64) -> bool) -> u64 {
    let mut n = 0;
    for j in 0..img.height {
        for i in 0..img.width {
            if inside(i as f64 + 0.5, j as f64 + 0.5) {
                hit(img, (j * img.width + i) as usize);
                n += 1;
            }
        }
    }
    n
}

fn disc(cx: f64, cy: f64, r: f64) -> impl Fn(f64, f64) -> bool {
    move |x, y| (x - cx).powi(2) + (y - cy).powi(2) <= r * r
}

#[test]
fn identical_images_report_zero_error() {
    let mut a = blank(72, 36);
    paint(&mut a, disc(30.0, 18.0, 9.0));
    let r = compare(&a, &a).unwrap();
    assert!(r.is_identical());
    let all = &r.eyes[0].all;
    assert_eq!((all.mismatch, all.iou), (0, 1.0));
    assert_eq!(all.silhouette_max_px, 0.0);
    let d = all.depth_relative.as_ref().unwrap();
    assert_eq!((d.p50, d.p99, d.max), (0.0, 0.0, 0.0));
    assert_eq!(all.color_rmse, Some(0.0));
    assert_eq!(all.color_psnr_db, None);
    assert_eq!(r.layout, "mono");
}

#[test]
fn shifted_disc_mismatch_is_the_symmetric_difference() {
    let (w, h) = (200, 100);
    for k in [1.0, 3.0, 7.0] {
        let (mut a, mut b) = (blank(w, h), blank(w, h));
        let (da, db) = (disc(80.0, 50.0, 20.0), disc(80.0 + k, 50.0, 20.0));
        paint(&mut a, &da);
        paint(&mut b, &db);
        let mut only_a = 0;
        let mut only_b = 0;
        for j in 0..h {
            for i in 0..w {
                let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
                only_a += (da(x, y) && !db(x, y)) as u64;
                only_b += (!da(x, y) && db(x, y)) as u64;
            }
        }
        let all = &compare(&a, &b).unwrap().eyes[0].all;
        assert_eq!((all.only_ref, all.only_test), (only_a, only_b), "shift {k}");
        assert_eq!(all.mismatch, only_a + only_b);
        assert!(
            all.silhouette_max_px <= k + 1e-12 && all.silhouette_max_px >= k - 1.0,
            "shift {k}: max silhouette error {}",
            all.silhouette_max_px
        );
    }
}

#[test]
fn shifted_rectangle_has_closed_form_errors() {
    // A 30x20 rectangle shifted right by k: 2*k*20 mismatched pixels. Test-only pixel m
    // columns past the reference's right edge is m+1 from the nearest reference hit; a
    // reference-only pixel m columns in from the left edge and r rows in from the top is
    // min(m+1, r+1, 20-r) from the nearest reference background. Max: k.
    let (w, h) = (120, 60);
    for k in [1u32, 4, 9] {
        let (mut a, mut b) = (blank(w, h), blank(w, h));
        paint(&mut a, |x, y| {
            (40.0..70.0).contains(&x) && (20.0..40.0).contains(&y)
        });
        let s = k as f64;
        paint(&mut b, |x, y| {
            (40.0 + s..70.0 + s).contains(&x) && (20.0..40.0).contains(&y)
        });
        let all = &compare(&a, &b).unwrap().eyes[0].all;
        assert_eq!(all.mismatch, 2 * k as u64 * 20);
        assert_eq!(all.silhouette_max_px, s);
        let mut sum = 0.0;
        for m in 0..k {
            for r in 0..20 {
                sum += (m + 1) as f64 + (m + 1).min(r + 1).min(20 - r) as f64;
            }
        }
        let mean = sum / (2 * k * 20) as f64;
        assert!((all.silhouette_mean_px - mean).abs() < 1e-12, "shift {k}");
        let both = (30 - k) as f64 * 20.0;
        assert!((all.iou - both / (both + 2.0 * s * 20.0)).abs() < 1e-15);
    }
}

#[test]
fn removed_disc_counts_its_pixels_and_iou_is_exact() {
    let (mut a, mut b) = (blank(200, 100), blank(200, 100));
    let kept = paint(&mut a, disc(50.0, 50.0, 15.0));
    paint(&mut b, disc(50.0, 50.0, 15.0));
    let removed = paint(&mut a, disc(140.0, 40.0, 10.0));
    let all = &compare(&a, &b).unwrap().eyes[0].all;
    assert_eq!((all.only_ref, all.only_test), (removed, 0));
    assert_eq!(all.iou, kept as f64 / (kept + removed) as f64);
    // The removed disc's centre pixel lies ~radius from the nearest reference background.
    assert!(all.silhouette_max_px > 9.0 && all.silhouette_max_px <= 10.5);
}

#[test]
fn one_percent_depth_offset_gives_p99_and_max_of_one_percent() {
    let (w, h) = (100, 50);
    let mut a = blank(w, h);
    paint(&mut a, |_, _| true);
    let mut b = a.clone();
    // 5% of the pixels (the first 250) move 1% farther.
    for k in 0..250 {
        b.depth[k] *= 1.01;
    }
    let all = &compare(&a, &b).unwrap().eyes[0].all;
    let d = all.depth_relative.as_ref().unwrap();
    assert_eq!(d.pixels, 5000);
    assert_eq!(d.p50, 0.0);
    assert!((d.p99 - 0.01).abs() < 1e-6, "p99 {}", d.p99);
    assert!((d.max - 0.01).abs() < 1e-6, "max {}", d.max);
    assert_eq!(all.mismatch, 0);
    // Rows 0..5 are the whole difference; at 50 rows per 180° they are the top two bands.
    let bands = &compare(&a, &b).unwrap().eyes[0].latitude_bands;
    assert!(bands[0].depth_relative.as_ref().unwrap().max > 0.009);
    assert!(bands[5].depth_relative.as_ref().unwrap().max == 0.0);
}

#[test]
fn difference_in_top_rows_shows_only_in_the_top_band() {
    // 360x180: one row per degree, so band b is rows 10b..10b+10.
    let (w, h) = (360, 180);
    let mut a = blank(w, h);
    paint(&mut a, |_, y| y > 100.0);
    let mut b = a.clone();
    let planted = paint(&mut b, |x, y| y < 4.0 && (100.0..150.0).contains(&x));
    let r = compare(&a, &b).unwrap();
    let bands = &r.eyes[0].latitude_bands;
    assert_eq!(bands.len(), 18);
    assert_eq!(bands[0].region, "+90..+80");
    assert_eq!(bands[0].only_test, planted);
    assert_eq!(bands[0].pixels, 3600);
    for band in &bands[1..] {
        assert_eq!(band.mismatch, 0, "band {}", band.region);
    }
    assert_eq!(r.eyes[0].seam.as_ref().unwrap().mismatch, 0);
}

#[test]
fn difference_at_the_edge_columns_shows_in_the_seam() {
    let (w, h) = (400, 200);
    let a = blank(w, h);
    let mut b = a.clone();
    // Columns 0..2 and 398..400 of rows 50..60, plus the centre column (not seam).
    let seam = paint(&mut b, |x, y| {
        !(2.0..=398.0).contains(&x) && (50.0..60.0).contains(&y)
    });
    let centre = paint(&mut b, |x, y| {
        (200.0..201.0).contains(&x) && (50.0..60.0).contains(&y)
    });
    let r = compare(&a, &b).unwrap();
    assert_eq!(r.eyes[0].seam_columns_each_side, 4);
    assert_eq!(r.eyes[0].seam.as_ref().unwrap().pixels, 8 * 200);
    assert_eq!(r.eyes[0].seam.as_ref().unwrap().mismatch, seam);
    assert_eq!(r.eyes[0].all.mismatch, seam + centre);
}

#[test]
fn top_bottom_images_are_compared_per_eye() {
    let (w, h) = (360, 360);
    let mut a = blank(w, h);
    paint(&mut a, disc(100.0, 90.0, 30.0));
    paint(&mut a, disc(100.0, 270.0, 30.0));
    let mut b = a.clone();
    // Right eye (bottom half) only: a patch at its top rows (rows 180..183).
    let planted = paint(&mut b, |x, y| (180.0..183.0).contains(&y) && x < 20.0);
    let r = compare(&a, &b).unwrap();
    assert_eq!(r.layout, "top-bottom");
    assert_eq!(r.eyes.len(), 2);
    assert_eq!((r.eyes[0].eye.as_str(), r.eyes[0].height), ("left", 180));
    assert_eq!(r.eyes[0].all.mismatch, 0);
    assert_eq!(r.eyes[1].eye, "right");
    assert_eq!(r.eyes[1].all.mismatch, planted);
    assert_eq!(r.eyes[1].latitude_bands[0].mismatch, planted);
    let text = r.to_string();
    assert!(
        text.contains(" left: coverage mismatch 0 px (0.0000%")
            && text.contains(&format!("right: coverage mismatch {planted} px"))
            && text.contains(&format!(
                "worst latitude band +90..+80: {planted} px mismatch"
            )),
        "{text}"
    );
}

#[test]
fn size_mismatch_is_an_error() {
    let err = compare(&blank(8, 4), &blank(16, 8)).unwrap_err();
    assert!(matches!(err, CompareError::SizeMismatch { .. }));
    assert!(err.to_string().contains("8x4") && err.to_string().contains("16x8"));
}

#[test]
fn heatmap_colours_errors_and_draws_the_legend() {
    let (w, h) = (512, 256);
    let mut a = blank(w, h);
    paint(&mut a, |x, _| x < 100.0);
    let mut b = a.clone();
    paint(&mut b, |x, y| (100.0..110.0).contains(&x) && y < 10.0);
    let k_ref_only = (20 * w + 5) as usize;
    b.coverage[k_ref_only] = 0.0;
    let img = heatmap(&a, &b).unwrap();
    let legend = LegendLayout::new(w, h);
    assert_eq!(img.dimensions(), (w, h + legend.height));
    assert_eq!(*img.get_pixel(105, 5), TEST_ONLY);
    assert_eq!(*img.get_pixel(5, 20), REF_ONLY);
    assert_eq!(
        *img.get_pixel(50, 50),
        ramp(0.0),
        "zero depth error is the ramp bottom"
    );
    assert_eq!(img.get_pixel(300, 50).0, [0, 0, 0, 255]);
    // Legend: swatches and both ends of the ramp bar.
    let (sx, sy) = legend.swatches[0];
    assert_eq!(*img.get_pixel(sx + 1, sy + 1), REF_ONLY);
    let (sx, sy) = legend.swatches[1];
    assert_eq!(*img.get_pixel(sx + 1, sy + 1), TEST_ONLY);
    let (x0, x1) = legend.ramp_x;
    assert!(x1 < w && x1 > x0 + 50, "ramp {x0}..{x1} must fit in {w}");
    assert_eq!(*img.get_pixel(x0, legend.ramp_y + 1), ramp(0.0));
    assert_eq!(*img.get_pixel(x1, legend.ramp_y + 1), ramp(1.0));
    // A tick below the ramp's left end.
    assert_eq!(
        img.get_pixel(x0, legend.ramp_y + legend.swatch_size).0,
        [255, 255, 255, 255]
    );
}

#[test]
fn compare_files_writes_report_and_heatmap() {
    let dir = tempfile::tempdir().unwrap();
    let mut f = Frame::new(64, 32);
    for k in 0..400 {
        f.color[k] = [100, 150, 200, 255];
        f.depth[k] = 3.0;
    }
    let mut g = f.clone();
    g.depth[10] = 3.3;
    g.color[500] = [1, 2, 3, 255];
    g.depth[500] = 1.0;
    let (rp, tp) = (dir.path().join("ref.exr"), dir.path().join("test.exr"));
    write_image(&rp, &Rendered::Mono(f), Layout::TopBottom).unwrap();
    write_image(&tp, &Rendered::Mono(g), Layout::TopBottom).unwrap();
    let (jp, hp) = (dir.path().join("r.json"), dir.path().join("h.png"));
    let r = compare_files(&rp, &tp, Some(&jp), Some(&hp)).unwrap();
    assert_eq!(r.eyes[0].all.only_test, 1);
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(&jp).unwrap()).unwrap();
    assert_eq!(json["eyes"][0]["all"]["only_test"], 1);
    let max = json["eyes"][0]["all"]["depth_relative"]["max"]
        .as_f64()
        .unwrap();
    assert!((max - 0.1).abs() < 1e-6, "{max}");
    let heat = omnicloud::output::read_png(&hp).unwrap();
    assert_eq!(heat.width, 64);
    assert!(heat.height > 32);

    let bad = compare_files(&rp, &dir.path().join("missing.exr"), None, None).unwrap_err();
    assert!(bad.to_string().contains("missing.exr"), "{bad}");
    let small = dir.path().join("small.exr");
    write_image(&small, &Rendered::Mono(Frame::new(8, 4)), Layout::TopBottom).unwrap();
    let err = compare_files(&rp, &small, None, None).unwrap_err();
    assert!(err.to_string().contains("small.exr"), "{err}");
}
