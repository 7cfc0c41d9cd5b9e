//! One test binary, one module per physical claim (style.md). Each model's modules are
//! behind that model's feature so one can be built while the other is being edited; the
//! README's test command builds them all.

// ---- spectral claims (issue: spectral) ----
#[cfg(feature = "spectral")]
mod spectral_common;
#[cfg(feature = "spectral")]
mod spectral_kernels;
#[cfg(feature = "spectral")]
mod spectral_radiation;
#[cfg(feature = "spectral")]
mod spectral_single_mode;

// ---- fem claims (issue: fem) ----

// ---- compare claims (issue: compare) ----
