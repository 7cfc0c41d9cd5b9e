//! FE-versus-spectral comparison harness: runs both models on one scene, lines their crack-tip
//! histories up the way the paper does (Figures 5–8), measures agreement against fixed
//! tolerances, writes CSV and PNG.

pub mod align;
pub mod contact_windows;
pub mod contour;
pub mod fem_figures;
pub mod figures;
pub mod gate;
pub mod metrics;
pub mod models;
pub mod output;
pub mod penalty;
pub mod penalty_figures;
pub mod plot;
pub mod scene;
pub mod sinusoid;
pub mod sinusoid_contact;
pub mod sinusoid_figures;
pub mod sinusoid_metrics;
pub mod sinusoid_snapshot;
pub mod sweep;
