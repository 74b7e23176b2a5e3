//! Small numeric helpers shared by the tables and the samplers.

/// The interval of a sorted array that contains `x`: the largest `i` with `a[i] <= x`, clamped to
/// `[0, a.len() − 2]` so that `a[i + 1]` exists (0 when `a` has fewer than two entries). Values
/// below `a[0]` give 0 and values at or above the last entry give `a.len() − 2`, so callers
/// extrapolate from the first or last interval or clamp their weight.
///
/// pbrt-v4's `FindInterval` (Pharr, Jakob and Humphreys, *Physically Based Rendering*, 4th ed.,
/// `util/math.h`), by binary search. Used for the sorted axes of spectra, the RGB-to-spectrum
/// table and tabulated BRDFs, and for the CDFs of [`crate::sampling::Distribution1D`].
#[inline]
pub fn find_interval(a: &[f32], x: f32) -> usize {
    // partition_point is the first index with a[i] > x (the array is sorted).
    a.partition_point(|&v| v <= x)
        .saturating_sub(1)
        .min(a.len().saturating_sub(2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_largest_lower_node_and_clamps() {
        let a = [0.0, 1.0, 2.0, 4.0];
        assert_eq!(find_interval(&a, -1.0), 0);
        assert_eq!(find_interval(&a, 0.0), 0);
        assert_eq!(find_interval(&a, 0.5), 0);
        assert_eq!(find_interval(&a, 1.0), 1);
        assert_eq!(find_interval(&a, 3.9), 2);
        assert_eq!(find_interval(&a, 4.0), 2);
        assert_eq!(find_interval(&a, 9.0), 2);
        // Repeated entries (empty CDF cells): the last of the equal nodes.
        let cdf = [0.0, 0.25, 0.25, 1.0];
        assert_eq!(find_interval(&cdf, 0.25), 2);
        assert_eq!(find_interval(&cdf, 0.2), 0);
        assert_eq!(find_interval(&[3.0], 5.0), 0);
        assert_eq!(find_interval(&[], 5.0), 0);
    }
}
