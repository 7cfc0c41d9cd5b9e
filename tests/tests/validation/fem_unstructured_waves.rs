//! Plane-strain wave speeds on an unstructured T3 mesh (`meshes/plate_tri.msh`, 0.2 m × 0.02 m,
//! h = 1 mm, Gmsh's default triangulation), run by the bulk-only unstructured driver
//! (`fem::solver::unstructured`). The method of `fem_wave_speeds` (the structured grid): a smooth
//! displacement ramp on the left side; top and bottom are rollers that make the wave
//! one-dimensional (u_y = 0 for P, u_x = 0 for S); speed = probe distance / difference of the
//! times at which the probe displacement reaches half the imposed value. The probes are two mesh
//! nodes on the mid-line, at x = 0.05 m and 0.15 m (embedded points of the `.geo`).

use fem::WaveSpeeds;
use fem::gmsh::UnstructuredMesh;
use fem::law::elastic::PlaneStrain;
use fem::nalgebra::Vector2;
use fem::scene::Ramp;
use fem::solver::unstructured::{Axis, DriverOptions, GroupBc, Prescribed, UnstructuredDriver};
use validation::repo_root;

// Arrival-time speeds within 1 % of c_d, c_s (`check`): the tolerance of the structured test, not
// tuned. The time at which a smooth ramp's displacement reaches half its final value is
// insensitive to the mesh's dispersion when the ramp spans many elements (here 15 elements for P,
// 14.5 for S): dispersion spreads the front about that time, it does not move it.
use crate::fem_wave_speeds::{check, crossing};

/// Imposed displacement [m].
const AMPLITUDE: f64 = 1e-5;

/// The paper's material (E = 70 MPa, ν = 0.35, ρ = 1230 kg/m³), that of the structured test.
fn material() -> PlaneStrain {
    PlaneStrain::new(70e6, 0.35, 1230.0)
}

/// Runs the plate with the ramp on `axis` of the left side (rise time `ramp_end` [s]), rollers on
/// the other axis at top and bottom, until `duration` [s]; returns the measured speed [m/s].
fn measured_speed(axis: Axis, ramp_end: f64, duration: f64) -> (f64, WaveSpeeds) {
    let mesh = UnstructuredMesh::read(&repo_root().join("meshes/plate_tri.msh")).unwrap();
    let other = match axis {
        Axis::X => Axis::Y,
        Axis::Y => Axis::X,
    };
    let ramp = Ramp {
        initial: 0.0,
        final_value: AMPLITUDE,
        ramp_start: 0.0,
        ramp_end,
    };
    let bcs = [
        GroupBc::prescribed("left", axis, Prescribed::Ramp(ramp)),
        GroupBc::roller("top", other),
        GroupBc::roller("bottom", other),
    ];
    let options = DriverOptions {
        alpha: 0.5,
        probes: vec![Vector2::new(0.05, 0.01), Vector2::new(0.15, 0.01)],
        probe_every: 1,
    };
    let mat = material();
    let mut driver = UnstructuredDriver::new(&mesh, &mat, &bcs, &options).unwrap();
    driver.run_until(duration).unwrap();
    let records = driver.records();
    let component = match axis {
        Axis::X => 0,
        Axis::Y => 1,
    };
    let (t1, t2) = (
        crossing(records, 0, 0.5 * AMPLITUDE, component),
        crossing(records, 1, 0.5 * AMPLITUDE, component),
    );
    // the probe nodes' own positions (the embedded points put them at 0.05 m and 0.15 m)
    let (x1, x2) = (records[0].x, records[1].x);
    assert!((x2 - x1 - 0.1).abs() < 1e-12, "probe nodes at x = {x1}, {x2} m");
    println!(
        "{} nodes, {} steps of {:.3e} s",
        driver.bulk().num_nodes(),
        driver.steps(),
        driver.dt()
    );
    ((x2 - x1) / (t2 - t1), mat.wave_speeds())
}

/// P wave: u_x ramp over 5e-5 s (15 mm of travel at c_d); the front reaches the second probe at
/// about 5.2e-4 s, the reflection from the right side at 8.3e-4 s.
#[test]
fn unstructured_p_wave_travels_at_cd() {
    let (c, w) = measured_speed(Axis::X, 5e-5, 7e-4);
    check("T3 mesh, P wave vs c_d", c, w.cd);
}

/// S wave: u_y ramp over 1e-4 s (14.5 mm of travel at c_s); the front reaches the second probe
/// at about 1.08e-3 s, the reflection from the right side at 1.7e-3 s.
#[test]
fn unstructured_s_wave_travels_at_cs() {
    let (c, w) = measured_speed(Axis::Y, 1e-4, 1.4e-3);
    check("T3 mesh, S wave vs c_s", c, w.cs);
}
