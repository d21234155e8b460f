//! Silhouette error: how far each coverage mismatch lies from the reference silhouette.
//!
//! For a pixel whose coverage differs between reference and test, the error is the Euclidean
//! distance, in pixels between pixel centres, to the nearest pixel whose *reference*
//! coverage is the opposite of this pixel's reference coverage: a test-only pixel measures to
//! the nearest reference hit, a reference-only pixel to the nearest reference background. A
//! silhouette shifted by k pixels gives errors up to k; a missing object gives up to its
//! radius. Longitude wraps (columns 0 and W-1 are neighbours); latitude does not.

/// Squared distances beyond any image; kept finite so the envelope arithmetic stays exact.
const FAR: f64 = 1e20;

/// 1-D squared Euclidean distance transform (Felzenszwalb & Huttenlocher 2012) of `f`.
fn edt_1d(f: &[f64], out: &mut [f64]) {
    let n = f.len();
    let mut v = vec![0usize; n];
    let mut z = vec![0f64; n + 1];
    let mut k = 0;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    for q in 1..n {
        loop {
            let p = v[k];
            let s = ((f[q] + (q * q) as f64) - (f[p] + (p * p) as f64)) / (2.0 * (q - p) as f64);
            if s <= z[k] && k > 0 {
                k -= 1;
            } else {
                k += 1;
                v[k] = q;
                z[k] = s;
                z[k + 1] = f64::INFINITY;
                break;
            }
        }
    }
    k = 0;
    for (q, o) in out.iter_mut().enumerate() {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let d = q as f64 - v[k] as f64;
        *o = d * d + f[v[k]];
    }
}

/// Distance from every pixel to the nearest pixel where `target` is true (0 on targets),
/// `None` where there is no target at all. Rows wrap horizontally.
pub fn distance_to(target: &[bool], width: usize, height: usize) -> Vec<Option<f64>> {
    let mut g = vec![FAR; width * height];
    let mut col = vec![0.0; height];
    let mut col_out = vec![0.0; height];
    for i in 0..width {
        for j in 0..height {
            col[j] = if target[j * width + i] { 0.0 } else { FAR };
        }
        edt_1d(&col, &mut col_out);
        for j in 0..height {
            g[j * width + i] = col_out[j];
        }
    }
    // Three copies of each row make the wrap-around explicit; the middle copy is exact.
    let mut row = vec![0.0; 3 * width];
    let mut row_out = vec![0.0; 3 * width];
    let mut out = vec![None; width * height];
    for j in 0..height {
        let src = &g[j * width..(j + 1) * width];
        for c in 0..3 {
            row[c * width..(c + 1) * width].copy_from_slice(src);
        }
        edt_1d(&row, &mut row_out);
        for i in 0..width {
            let d2 = row_out[width + i];
            out[j * width + i] = (d2 < FAR / 2.0).then(|| d2.sqrt());
        }
    }
    out
}

/// Silhouette error of every pixel of one eye (see the module docs): `Some(d)` at coverage
/// mismatches that have a reference pixel of opposite coverage, `None` elsewhere.
pub fn silhouette_errors(
    ref_hit: &[bool],
    test_hit: &[bool],
    width: usize,
    height: usize,
) -> Vec<Option<f64>> {
    let ref_miss: Vec<bool> = ref_hit.iter().map(|h| !h).collect();
    let to_hit = distance_to(ref_hit, width, height);
    let to_miss = distance_to(&ref_miss, width, height);
    (0..width * height)
        .map(|k| match (ref_hit[k], test_hit[k]) {
            (true, false) => to_miss[k],
            (false, true) => to_hit[k],
            _ => None,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute(target: &[bool], w: usize, h: usize) -> Vec<Option<f64>> {
        (0..w * h)
            .map(|k| {
                let (i, j) = ((k % w) as i64, (k / w) as i64);
                (0..w * h)
                    .filter(|&t| target[t])
                    .map(|t| {
                        let (ti, tj) = ((t % w) as i64, (t / w) as i64);
                        let dx = (i - ti).abs().min(w as i64 - (i - ti).abs());
                        (((dx * dx) + (j - tj) * (j - tj)) as f64).sqrt()
                    })
                    .reduce(f64::min)
            })
            .collect()
    }

    #[test]
    fn matches_brute_force_with_wrap() {
        let (w, h) = (23, 11);
        let mut rng = crate::rng::SplitMix64::new(12345);
        let target: Vec<bool> = (0..w * h).map(|_| rng.next_f64() < 1.0 / 17.0).collect();
        assert_eq!(distance_to(&target, w, h), brute(&target, w, h));
    }

    #[test]
    fn no_target_gives_none() {
        assert!(distance_to(&[false; 6], 3, 2).iter().all(Option::is_none));
    }

    #[test]
    fn wraps_across_the_seam() {
        let mut t = vec![false; 10];
        t[0] = true;
        assert_eq!(distance_to(&t, 10, 1)[9], Some(1.0));
    }
}
