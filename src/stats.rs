//! Order statistics of samples, for every layer that summarises values: error statistics,
//! colour ranges and the tests.

/// The `p`-th percentile (`p` in [0, 1]) of ascending `sorted` by nearest rank: the smallest
/// value that at least a fraction `p` of the values do not exceed (`p = 0` gives the
/// smallest, `p = 1` the largest); `None` when `sorted` is empty. The one percentile of the
/// crate: error statistics, colour ranges and the tests use it.
pub fn percentile<T: Copy>(sorted: &[T], p: f64) -> Option<T> {
    let rank = (p * sorted.len() as f64).ceil() as usize;
    sorted.get(rank.clamp(1, sorted.len().max(1)) - 1).copied()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_rank_percentiles() {
        let v: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(percentile(&v, 0.5), Some(50.0));
        assert_eq!(percentile(&v, 0.99), Some(99.0));
        assert_eq!(percentile(&v, 0.0), Some(1.0));
        assert_eq!(percentile(&v, 1.0), Some(100.0));
        assert_eq!(percentile(&[7.0], 0.99), Some(7.0));
        assert_eq!(percentile::<f64>(&[], 0.5), None);
    }
}
