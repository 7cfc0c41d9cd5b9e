//! Analytic answers the cross-check suite measures both models against: the universal functions of
//! crack-tip speed and the bilateral-crack equation of motion (Freund 1990), the Griffith length,
//! Andrews' (1976) supershear transition distance, and the generalized Rayleigh speed of two
//! different half-spaces. Plain functions of the material and the load; no model is run here.

pub mod bimaterial;
pub mod freund;
mod quadrature;
