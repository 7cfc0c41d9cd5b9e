//! Normal penalty laws: node-to-segment pressure p_N = eps_n p, and the compression penalty of eq. (4).
