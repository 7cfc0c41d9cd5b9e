//! Wave numbers and per-mode truncation windows (docs/spectral-model.md §3.4, §4).

use std::f64::consts::PI;

/// Modes j = 0..=N/2 of a real field on N points; mode 0 carries no history (F(k=0) = 0, §2).
#[derive(Debug, Clone)]
pub struct Modes {
    /// ΔT_1 = k_1 c_s Δt = 2πβ/N [-]; mode j has ΔT_j = j ΔT_1.
    pub dt1: f64,
    /// Wave number k_j = 2πj/X [1/m], j = 0..=N/2.
    pub k: Vec<f64>,
    /// Window L_j (stored past steps), L_0 = 0 [-].
    pub window: Vec<usize>,
    /// Offset of mode j in the contiguous history/weight arrays.
    pub offset: Vec<usize>,
    /// Σ_j L_j [-].
    pub total: usize,
}

impl Modes {
    /// L_j = max(1, min(n_steps, floor(tcut/ΔT_j) − 1)) (cRacklet rule, §3.4; never below 1 so the
    /// current displacement always gets W_{j,0}).
    pub fn new(n: usize, length: f64, cfl: f64, kernel_cutoff: f64, n_steps: usize) -> Modes {
        let dt1 = 2.0 * PI * cfl / n as f64;
        let half = n / 2;
        let mut k = Vec::with_capacity(half + 1);
        let mut window = Vec::with_capacity(half + 1);
        let mut offset = Vec::with_capacity(half + 1);
        let mut total = 0;
        for j in 0..=half {
            k.push(2.0 * PI * j as f64 / length);
            let l = if j == 0 {
                0
            } else {
                let w = (kernel_cutoff / (j as f64 * dt1)).floor() as i64 - 1;
                w.clamp(1, n_steps.max(1) as i64) as usize
            };
            offset.push(total);
            window.push(l);
            total += l;
        }
        Modes {
            dt1,
            k,
            window,
            offset,
            total,
        }
    }

    /// Largest kernel sample index m (T = m ΔT_1) any weight needs: max_j j·L_j.
    pub fn max_sample(&self) -> usize {
        self.window
            .iter()
            .enumerate()
            .map(|(j, l)| j * l)
            .max()
            .unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn window_follows_cracklet_rule() {
        let m = Modes::new(4096, 3.75, 0.2, 100.0, usize::MAX / 2);
        // mode 1: floor(100 / (2π 0.2/4096)) − 1
        assert_eq!(
            m.window[1],
            (100.0 / (2.0 * PI * 0.2 / 4096.0)).floor() as usize - 1
        );
        // Σ L_j ≈ (tcut N/(2πβ))(ln(N/2) + 0.58) = 2.67e6 (§4)
        assert!((m.total as f64 / 2.67e6 - 1.0).abs() < 0.02, "{}", m.total);
        assert_eq!(m.window[0], 0);
    }
}
