//! Gauss–Legendre quadrature, nodes and weights found on the fly (no table, no allocation).

use std::f64::consts::PI;

/// Integral over `[−1, 1]` of `f` with the `n`-node Gauss–Legendre rule (nodes and weights found
/// on the fly by Newton iteration on the Legendre recurrence; no allocation).
pub(crate) fn gauss_legendre<F: FnMut(f64) -> f64>(n: usize, mut f: F) -> f64 {
    let mut sum = 0.0;
    for i in 0..n.div_ceil(2) {
        let (x, w) = legendre_node(n, i);
        if 2 * i + 1 == n {
            sum += w * f(0.0);
        } else {
            sum += w * (f(x) + f(-x));
        }
    }
    sum
}

/// The `i`-th positive node (counting down from the largest) and its weight of the `n`-point
/// Gauss–Legendre rule.
fn legendre_node(n: usize, i: usize) -> (f64, f64) {
    let nf = n as f64;
    let mut x = (PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
    for _ in 0..100 {
        let (p, dp) = legendre_with_derivative(n, x);
        let step = p / dp;
        x -= step;
        if step.abs() <= 4.0 * f64::EPSILON {
            break;
        }
    }
    let (_, dp) = legendre_with_derivative(n, x);
    (x, 2.0 / ((1.0 - x * x) * dp * dp))
}

/// Legendre polynomial `P_n(x)` and its derivative, by the three-term recurrence (`|x| < 1`).
fn legendre_with_derivative(n: usize, x: f64) -> (f64, f64) {
    let (mut p_prev, mut p) = (1.0_f64, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 1..n {
        let kf = k as f64;
        let next = ((2.0 * kf + 1.0) * x * p - kf * p_prev) / (kf + 1.0);
        p_prev = p;
        p = next;
    }
    (p, n as f64 * (x * p - p_prev) / (x * x - 1.0))
}
