//! Node-to-segment penalty contact with regularised Coulomb friction (paper Section 2, eqs. 5-10, Algorithm 1).
