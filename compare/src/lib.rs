//! FE-versus-spectral comparison harness: runs both models on one scene, lines their crack-tip
//! histories up the way the paper does (Figures 5–8), measures agreement against fixed
//! tolerances, writes CSV and PNG. One module folder per study over a shared reading of the
//! scene ([`study`]), running of the models ([`runner`]) and plotting ([`plot`]).

pub mod boundary;
pub mod concurrent;
pub mod converged;
pub mod gate;
pub mod output;
pub mod penalty;
pub mod plot;
pub mod quasi_static;
pub mod rough;
pub mod runner;
pub mod series;
pub mod sinusoid;
pub mod study;
pub mod suite;
pub mod sweep;
pub mod theory;
