//! Analytic answers the cross-check suite measures both models against: the universal functions of
//! crack-tip speed and the bilateral-crack equation of motion (Freund 1990), the Griffith length,
//! and Andrews' (1976) supershear transition distance. Plain functions of the material and the
//! load; no model is run here.

pub mod freund;
mod quadrature;
