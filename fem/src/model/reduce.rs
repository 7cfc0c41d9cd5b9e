//! Sums over all nodes that give the same bits whatever the number of threads: the terms are
//! split into a fixed number of contiguous parts, each summed in order (in parallel), and the
//! partial sums added in order. A plain parallel `sum()` associates its terms in an order that
//! depends on work stealing, so energy records differed in their last digits from run to run.

use rayon::prelude::*;

/// Number of parts: more than the threads of any machine this runs on, few enough for the stack.
pub(crate) const PARTS: usize = 64;

/// Σ_{i < n} term(i), in an order that depends only on n. Allocates nothing.
pub(crate) fn ordered_sum(n: usize, term: impl Fn(usize) -> f64 + Sync) -> f64 {
    let mut partials = [0.0f64; PARTS];
    let size = n.div_ceil(PARTS).max(1);
    partials.par_iter_mut().enumerate().for_each(|(c, p)| {
        let (lo, hi) = ((c * size).min(n), ((c + 1) * size).min(n));
        *p = (lo..hi).map(&term).sum();
    });
    partials.iter().sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sum_does_not_depend_on_the_thread_count() {
        // terms of mixed magnitude, whose sum depends on the order of association
        let term = |i: usize| ((i as f64) * 0.7).sin() * 10f64.powi((i % 13) as i32 - 6);
        let n = 100_003;
        let reference = ordered_sum(n, term);
        for threads in [1, 2, 3, 8] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            for _ in 0..5 {
                assert_eq!(
                    pool.install(|| ordered_sum(n, term)).to_bits(),
                    reference.to_bits()
                );
            }
        }
        let plain: f64 = (0..n).map(term).sum();
        assert!((reference - plain).abs() <= 1e-12 * plain.abs().max(1.0));
        assert_eq!(ordered_sum(0, term), 0.0);
        assert_eq!(ordered_sum(3, |_| 1.0), 3.0);
    }
}
