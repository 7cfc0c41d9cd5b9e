//! Plane-strain wave speeds on an unstructured T3 mesh (`scenes/tiny-fem-plate-tri.toml` on
//! `meshes/plate_tri.msh`, 0.2 m × 0.02 m, h = 1 mm, Gmsh's default triangulation), run by the
//! same solver and with the same method as `fem_wave_speeds` on the structured grid: a smooth
//! displacement ramp on the left side; top and bottom are rollers that make the wave
//! one-dimensional (u_y = 0 for P, u_x = 0 for S); speed = probe distance / difference of the times
//! at which the probe displacement reaches half the imposed value. The probes are two mesh nodes on
//! the mid-line, at x = 0.05 m and 0.15 m (embedded points of the `.geo`).

// Arrival-time speeds within 1 % of c_d, c_s (`check`): the tolerance of the structured test. The
// time at which a smooth ramp's displacement reaches half its final value is insensitive to the
// mesh's dispersion when the ramp spans many elements (here 15 elements for P, 14.5 for S):
// dispersion spreads the front about that time, it does not move it.
use crate::fem_wave_speeds::{P_BOUNDARY, S_BOUNDARY, check, measured_speed};

/// P wave: u_x ramp over 5e-5 s (15 mm of travel at c_d); the front reaches the second probe at
/// about 5.2e-4 s, the reflection from the right side at 8.3e-4 s.
#[test]
fn unstructured_p_wave_travels_at_cd() {
    let (c, w) = measured_speed("tiny-fem-plate-tri", P_BOUNDARY, 7e-4, 0);
    check("T3 mesh, P wave vs c_d", c, w.cd);
}

/// S wave: u_y ramp over 1e-4 s (14.5 mm of travel at c_s); the front reaches the second probe
/// at about 1.08e-3 s, the reflection from the right side at 1.7e-3 s.
#[test]
fn unstructured_s_wave_travels_at_cs() {
    let (c, w) = measured_speed("tiny-fem-plate-tri", S_BOUNDARY, 1.4e-3, 1);
    check("T3 mesh, S wave vs c_s", c, w.cs);
}
