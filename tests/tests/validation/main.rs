//! One test binary, one module per physical claim. Each model's modules are
//! behind that model's feature so one can be built while the other is being edited; the
//! README's test command builds them all.

// ---- spectral claims ----
#[cfg(feature = "spectral")]
mod spectral_bimaterial;
#[cfg(feature = "spectral")]
mod spectral_common;
#[cfg(feature = "spectral")]
mod spectral_fast;
#[cfg(feature = "spectral")]
mod spectral_friction;
#[cfg(feature = "spectral")]
mod spectral_kernels;
#[cfg(feature = "spectral")]
mod spectral_onset;
#[cfg(feature = "spectral")]
mod spectral_radiation;
#[cfg(feature = "spectral")]
mod spectral_rayleigh_limit;
#[cfg(feature = "spectral")]
mod spectral_resolution;
#[cfg(feature = "spectral")]
mod spectral_single_mode;
#[cfg(feature = "spectral")]
mod spectral_supershear;

// ---- fem claims ----
#[cfg(feature = "fem")]
mod fem_absorbing;
#[cfg(feature = "fem")]
mod fem_arc_interface;
#[cfg(feature = "fem")]
mod fem_bimaterial;
#[cfg(feature = "fem")]
mod fem_bimaterial_grid;
#[cfg(feature = "fem")]
mod fem_center_crack;
#[cfg(feature = "fem")]
mod fem_chains;
#[cfg(feature = "fem")]
mod fem_cohesive_law;
#[cfg(feature = "fem")]
mod fem_contact_energy;
#[cfg(feature = "fem")]
mod fem_contact_pressure;
#[cfg(feature = "fem")]
mod fem_energy_conservation;
#[cfg(feature = "fem")]
mod fem_friction_sliding;
#[cfg(feature = "fem")]
mod fem_insertion_oscillations;
#[cfg(feature = "fem")]
mod fem_junction;
#[cfg(feature = "fem")]
mod fem_mesh_center_crack;
#[cfg(feature = "fem")]
mod fem_patch_test;
#[cfg(feature = "fem")]
mod fem_point_loads;
#[cfg(feature = "fem")]
mod fem_prakash;
#[cfg(feature = "fem")]
mod fem_unstructured_waves;
#[cfg(feature = "fem")]
mod fem_wave_speeds;

// ---- Section 4 claims ----
#[cfg(feature = "fem")]
mod fem_sinusoid;

// ---- beyond the paper: its Section 5 outlook ----
#[cfg(feature = "fem")]
mod fem_rough;

// ---- FE against spectral, and the FE model at its extremes ----
#[cfg(all(feature = "fem", feature = "spectral"))]
mod compare_converged;
#[cfg(feature = "fem")]
mod fem_extremes;

// ---- reproducibility ----
mod determinism;
