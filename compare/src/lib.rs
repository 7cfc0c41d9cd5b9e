//! FE-versus-spectral comparison harness.
