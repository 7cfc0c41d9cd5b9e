//! Fast history convolution (issue 6): placeholder while the direct path is brought up.

use rustfft::num_complex::Complex64;

use crate::convolution::ModeSums;
use crate::error::BuildError;
use crate::history::Entry;
use crate::kernels::Kernels;
use crate::modes::Modes;

/// Sum-of-exponentials fit of the three kernels.
pub struct SoeFit {
    /// Achieved max error relative to max|K| [-].
    pub max_error: f64,
    poles: Vec<Complex64>,
}

impl SoeFit {
    /// Fits the kernels on [0, tcut].
    pub fn fit(_k: &Kernels, _tcut: f64, tol: f64) -> Result<SoeFit, BuildError> {
        Err(BuildError::FitFailed {
            kernel: "H11",
            achieved: f64::INFINITY,
            requested: tol,
        })
    }
    /// Number of exponential terms.
    pub fn terms(&self) -> usize {
        self.poles.len()
    }
}

/// Recursive convolution state.
pub struct FastConvolution {
    n: usize,
}

impl FastConvolution {
    /// State for all modes.
    pub fn new(modes: &Modes, _fit: &SoeFit) -> FastConvolution {
        FastConvolution { n: modes.n }
    }
    /// Bytes of state per step.
    pub fn bytes(&self) -> usize {
        self.n
    }
    /// One step.
    pub fn step(&mut self, _spectra: &[Entry], _out: &mut [ModeSums]) {}
}
