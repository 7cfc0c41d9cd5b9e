//! Spectral boundary-integral solver for a planar interface between identical half-spaces.
#![warn(missing_docs)]
