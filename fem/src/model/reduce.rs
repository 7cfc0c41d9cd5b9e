//! Sums over all nodes that give the same bits whatever the number of threads: the terms are
//! split into a fixed number of contiguous parts, each summed in order (in parallel), and the
//! partial sums added in order. A plain parallel `sum()` associates its terms in an order that
//! depends on work stealing, so energy records differed in their last digits from run to run.

use rayon::prelude::*;

/// Number of parts: more than the threads of any machine this runs on, few enough for the stack.
pub(crate) const PARTS: usize = 64;

/// Parts summed side by side by one task: each part's sum is a chain of dependent adds, so one
/// part at a time waits on the adder's latency at every term; eight chains keep it busy.
const INTERLEAVED: usize = 8;
const _: () = assert!(
    PARTS.is_multiple_of(INTERLEAVED),
    "every task takes a whole group of parts"
);

/// Σ_{i < n} term(i), in an order that depends only on n: each of the [`PARTS`] parts summed in
/// order from the value of an empty `sum()`, then the partial sums added in order. A task takes
/// [`INTERLEAVED`] parts and advances them together, a term of each in turn, which changes no
/// part's order of addition. Allocates nothing.
pub(crate) fn ordered_sum(n: usize, term: impl Fn(usize) -> f64 + Sync) -> f64 {
    let mut partials = [0.0f64; PARTS];
    let size = n.div_ceil(PARTS).max(1);
    let range = |c: usize| (c * size).min(n)..((c + 1) * size).min(n);
    partials
        .par_chunks_exact_mut(INTERLEAVED)
        .enumerate()
        .for_each(|(g, group)| {
            let first = g * INTERLEAVED;
            // the terms every part of the group has, a term of each part in turn
            let common = (0..INTERLEAVED)
                .map(|q| range(first + q).len())
                .min()
                .unwrap_or(0);
            let mut sums = [std::iter::empty::<f64>().sum::<f64>(); INTERLEAVED];
            // a loop of constant length, so that the sums stay in registers: over the group's
            // length, unknown to the compiler, they went through the stack at every term
            for k in 0..common {
                for (q, s) in sums.iter_mut().enumerate() {
                    *s += term((first + q) * size + k);
                }
            }
            // then the rest of each part, in order
            for (q, (p, s)) in group.iter_mut().zip(sums).enumerate() {
                let r = range(first + q);
                *p = (r.start + common..r.end).fold(s, |a, i| a + term(i));
            }
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

    /// The definition written out: every part summed alone, in order, by `sum()`, then the
    /// partial sums in order. The interleaved parts give its bits, for counts that leave parts
    /// short or empty, and for terms of mixed magnitude and zeros of either sign.
    #[test]
    fn interleaved_parts_give_the_bits_of_each_part_summed_alone() {
        let reference = |n: usize, term: &dyn Fn(usize) -> f64| -> f64 {
            let size = n.div_ceil(PARTS).max(1);
            (0..PARTS)
                .map(|c| {
                    ((c * size).min(n)..((c + 1) * size).min(n))
                        .map(term)
                        .sum::<f64>()
                })
                .sum()
        };
        let mixed = |i: usize| ((i as f64) * 0.7).sin() * 10f64.powi((i % 13) as i32 - 6);
        let zeros = |i: usize| if i.is_multiple_of(3) { -0.0 } else { 0.0 };
        let negative_zeros = |_: usize| -0.0;
        for n in [1, 7, 63, 64, 65, 130, 511, 1000, 4097, 100_003] {
            for term in [&mixed as &(dyn Fn(usize) -> f64 + Sync), &zeros, &negative_zeros] {
                assert_eq!(
                    ordered_sum(n, term).to_bits(),
                    reference(n, term).to_bits(),
                    "n = {n}"
                );
            }
        }
    }
}
