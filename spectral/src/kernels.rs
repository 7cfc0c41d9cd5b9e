//! Convolution kernels H11, H22, K12 of the independent formulation (docs/spectral-model.md §3), computed
//! from their exact branch-cut integrals (§3.2) by Gauss–Legendre quadrature. Pure.
//!
//! H11(T) = (2/π)[∫_0^η η√(η²−y²) cos(yT)/(1+η²−y²) dy + ∫_0^1 (η²−y²)√(1−y²) cos(yT)/(1+η²−y²) dy]
//! H22(T) = (2/π)[∫_0^η η(1−y²)√(η²−y²) cos(yT)/(1+η²−y²) dy + ∫_0^1 η²√(1−y²) cos(yT)/(1+η²−y²) dy]
//! K12(T) = (2η/π) ∫_1^η √(y²−1)√(η²−y²) sin(yT)/(1+η²−y²) dy
//!
//! With y = η sin θ, y = sin θ and y = (1+η)/2 − ((η−1)/2) cos φ the integrands are smooth, so the
//! quadrature converges exponentially (120 nodes: 2e−13 for T ≤ 100).

use std::f64::consts::PI;

use rayon::prelude::*;

/// One quadrature node: frequency y [-] and its weights in H11, H22 (cosine) or K12 (sine).
#[derive(Debug, Clone, Copy)]
struct Node {
    y: f64,
    w_h11: f64,
    w_h22: f64,
    w_k12: f64,
}

/// Kernels as finite sums Σ_i w_i cos(y_i T) (H11, H22) and Σ_i w_i sin(y_i T) (K12), exact to
/// round-off for 0 ≤ T ≤ `t_max`.
#[derive(Debug, Clone)]
pub struct Kernels {
    /// η = c_d/c_s [-].
    pub eta: f64,
    nodes: Vec<Node>,
}

/// Kernel values sampled at T = m ΔT, m = 0..len (docs/spectral-model.md §3.3: every sample point the
/// scheme needs is an integer multiple of ΔT_1 = 2πβ/N).
#[derive(Debug, Clone)]
pub struct KernelTable {
    /// Sample spacing ΔT [-].
    pub dt: f64,
    /// H11(m ΔT) [-].
    pub h11: Vec<f64>,
    /// H22(m ΔT) [-].
    pub h22: Vec<f64>,
    /// K12(m ΔT) [-].
    pub k12: Vec<f64>,
}

/// Gauss–Legendre nodes and weights on [a, b] (Newton on P_n, n ≥ 1).
pub fn gauss_legendre(n: usize, a: f64, b: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let p = if n == 1 { x } else { p1 };
            let pm1 = if n == 1 { 1.0 } else { p0 };
            dp = n as f64 * (x * p - pm1) / (x * x - 1.0);
            let dx = p / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        out.push((0.5 * (a + b) + 0.5 * (b - a) * x, 0.5 * (b - a) * w));
    }
    out
}

impl Kernels {
    /// Quadrature for η = c_d/c_s > 1, exact to round-off on 0 ≤ T ≤ t_max
    /// (nodes per integral: max(200, 1.2 η t_max); §3.2: 120 nodes give 2e−13 for T ≤ 100).
    pub fn new(eta: f64, t_max: f64) -> Kernels {
        let n = (1.2 * eta * t_max).ceil().max(200.0) as usize;
        let e2 = eta * eta;
        let mut nodes = Vec::with_capacity(3 * n);
        for (th, w) in gauss_legendre(n, 0.0, PI / 2.0) {
            // y = η sin θ: √(η²−y²) dy = η² cos²θ dθ
            let y = eta * th.sin();
            let base = 2.0 / PI * e2 * th.cos().powi(2) / (1.0 + e2 - y * y) * w;
            nodes.push(Node {
                y,
                w_h11: eta * base,
                w_h22: eta * (1.0 - y * y) * base,
                w_k12: 0.0,
            });
            // y = sin θ: √(1−y²) dy = cos²θ dθ
            let y = th.sin();
            let base = 2.0 / PI * th.cos().powi(2) / (1.0 + e2 - y * y) * w;
            nodes.push(Node {
                y,
                w_h11: (e2 - y * y) * base,
                w_h22: e2 * base,
                w_k12: 0.0,
            });
        }
        let h = 0.5 * (eta - 1.0);
        for (ph, w) in gauss_legendre(n, 0.0, PI) {
            // y = (1+η)/2 − h cos φ: √((y−1)(η−y)) dy = h² sin²φ dφ
            let y = 0.5 * (1.0 + eta) - h * ph.cos();
            let w_k12 = 2.0 * eta / PI * h * h * ph.sin().powi(2) * ((y + 1.0) * (eta + y)).sqrt()
                / (1.0 + e2 - y * y)
                * w;
            nodes.push(Node {
                y,
                w_h11: 0.0,
                w_h22: 0.0,
                w_k12,
            });
        }
        Kernels { eta, nodes }
    }

    /// (H11, H22, K12) at T ≥ 0 [-].
    pub fn eval(&self, t: f64) -> (f64, f64, f64) {
        self.nodes.iter().fold((0.0, 0.0, 0.0), |(a, b, c), n| {
            let (s, co) = (n.y * t).sin_cos();
            (a + n.w_h11 * co, b + n.w_h22 * co, c + n.w_k12 * s)
        })
    }

    /// Tabulates the three kernels at T = m dt, m = 0..len, in parallel chunks; within a chunk the
    /// phases advance by exact rotations, restarted from sin_cos at each chunk (error ≲ 1e−12).
    pub fn tabulate(&self, dt: f64, len: usize) -> KernelTable {
        const CHUNK: usize = 2048;
        let mut h11 = vec![0.0; len];
        let mut h22 = vec![0.0; len];
        let mut k12 = vec![0.0; len];
        h11.par_chunks_mut(CHUNK)
            .zip(h22.par_chunks_mut(CHUNK))
            .zip(k12.par_chunks_mut(CHUNK))
            .enumerate()
            .for_each(|(c, ((a, b), k))| {
                let m0 = (c * CHUNK) as f64;
                for n in &self.nodes {
                    let (mut s, mut co) = (n.y * m0 * dt).sin_cos();
                    let (sd, cd) = (n.y * dt).sin_cos();
                    for i in 0..a.len() {
                        a[i] += n.w_h11 * co;
                        b[i] += n.w_h22 * co;
                        k[i] += n.w_k12 * s;
                        let c2 = co * cd - s * sd;
                        s = s * cd + co * sd;
                        co = c2;
                    }
                }
            });
        KernelTable { dt, h11, h22, k12 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ETA: f64 = 2.081665999466133;

    #[test]
    fn values_at_zero_match_closed_forms() {
        let k = Kernels::new(ETA, 100.0);
        let (h11, h22, k12) = k.eval(0.0);
        assert!((h11 - (ETA - 0.5)).abs() < 1e-12, "{h11}");
        assert!((h22 - ETA * ETA * (2.0 - ETA) / 2.0).abs() < 1e-12, "{h22}");
        assert_eq!(k12, 0.0);
    }

    #[test]
    fn table_matches_direct_evaluation() {
        let k = Kernels::new(ETA, 100.0);
        let t = k.tabulate(0.0123, 8000);
        for m in [0, 1, 2047, 2048, 5000, 7999] {
            let (a, b, c) = k.eval(m as f64 * 0.0123);
            assert!(
                (t.h11[m] - a).abs() < 1e-11 && (t.h22[m] - b).abs() < 1e-11 && (t.k12[m] - c).abs() < 1e-11
            );
        }
    }
}
