//! What a run will cost, from its validated scene and before anything is allocated: the number of
//! time steps and the memory of the model and of the records kept for output. The run's records
//! are held in memory until it ends (they are written as CSV afterwards), so a tiny
//! `fem.output_interval` costs as much as a fine mesh.

use crate::records::{
    BoundaryRecord, ContactMeanRecord, CrackRecord, CrackTipRecord, EnergyRecord, FaceRecord, FieldRecord,
    InterfaceRecord, KktRecord, ProbeRecord, ProfileRecord, TipRecord,
};
use crate::scene::Scene;
use preflight::budget::bytes_of;
use preflight::{Estimate, Part};
use std::mem::size_of;

/// Memory of the model per bulk element (nodes, element operators, state, workspace, contact and
/// cohesive arrays) [B]. Measured peak resident memory of the centre crack minus the process's
/// baseline: 221 B at 500 × 250 elements, 212 B at 1000 × 500, 209 B at 2000 × 1000
/// (docs/outputs.md); rounded up.
const BYTES_PER_ELEMENT: usize = 256;

/// Wall time per element and step on 2 cores, contact and cohesive work included [s]. Measured on
/// the centre crack (`compare sweep`, docs/performance.md): 5.1e-9 at h = 2 mm (1.6 s), 3.8e-9 at
/// 1 mm (7.7 s), 3.7e-9 at 0.5 mm (46.8 s); rounded up.
const SECONDS_PER_ELEMENT_STEP: f64 = 5e-9;

/// Memory of the model per element of a Gmsh mesh (`[fem.mesh]`) [B]: the mesh as read and
/// prepared, the edge kernel's blocks, the element operators of the interface and the state.
/// Measured peak resident memory minus the process's baseline, T shortened to a few samples: 695 B
/// on `scenes/center-crack-tri.toml` (43 138 triangles), 877 B on `scenes/three-point-bend.toml`
/// (9 882 triangles); rounded up (docs/outputs.md, "Budgets").
const GMSH_BYTES_PER_ELEMENT: usize = 1024;

/// Wall time per element and step on 2 cores on a Gmsh mesh (`[fem.mesh]`), contact and cohesive
/// work included [s]: `scenes/center-crack-tri.toml` (37 947 steps, 43 138 triangles) ran in
/// 6.0–6.9 s (3.7–4.2e-9) on the third machine and 9.8 s (6.0e-9) on the seventh of
/// docs/performance.md; `scenes/three-point-bend.toml` (553 882 steps, 9 882 triangles, whose
/// steps carry more than their elements) in 44 s (8.0e-9, docs/results.md); rounded up.
const GMSH_SECONDS_PER_ELEMENT_STEP: f64 = 1e-8;

/// The same on a mesh mapped onto an interface polyline (`fem.interface_polyline` or a sine
/// interface: every element its own shape, its forces computed on the fly in the one-pass sweep)
/// [s]: 2.9e-8 was measured on the sinusoidal interface (750 × 250, 14 632 steps, 80 s on 2
/// threads for either model) when those meshes took the separate passes. With the sweep and the
/// mapped kernel's eight lanes, on the fifth machine of docs/performance.md (2 cores, AVX-512):
/// `fem scenes/sinusoidal-interface.toml` 21.5 s (7.8e-9), `fem scenes/rough-interface.toml`
/// 13.0 s (8712 steps, 8.0e-9); rounded up.
const MAPPED_SECONDS_PER_ELEMENT_STEP: f64 = 1e-8;

/// The same on a grid of two materials (a split `[material]`) that keeps one K_e an element and
/// takes the separate passes (its y = 0 row not twinned, or mapped onto an interface path) [s];
/// priced as the mapped meshes were before their sweep (2.9e-8, rounded up), not measured on its
/// own. A split grid that keeps one K_e a material (`model::build::split_grid_keeps_stencils`)
/// takes the stencils and the one-pass sweep of one material and is priced as it is
/// ([`SECONDS_PER_ELEMENT_STEP`]): `scenes/bimaterial-crack.toml` (15 705 steps, 125 000 elements)
/// ran in 8.4 s on two threads (4.3e-9) and 9.2 s on one (4.7e-9), the centre crack of one
/// material in 10.2 s on one (6.2e-9), on the fifth machine of docs/performance.md.
const PER_ELEMENT_SECONDS_PER_ELEMENT_STEP: f64 = 3e-8;

/// Wall time per element and step on 2 cores while the far field's ramps accelerate and its body
/// load acts on every node (`far_field = true`: those steps take the separate passes) [s]:
/// 1.74e-8 measured over a whole run of `scenes/suite/freund-mode2.toml` at h = 0.5 mm
/// (3.24 M elements, 15 709 steps, 12 567 of them in the ramp, 886 s); rounded up.
const FAR_FIELD_SECONDS_PER_ELEMENT_STEP: f64 = 2e-8;

/// Peak memory while one ParaView snapshot is built and written, per bulk element [B]: the
/// snapshot's arrays, vtkio's copies of them and their base64 text (docs/outputs.md, "Budgets").
/// Measured peak resident memory with `[fem.paraview]` minus without, centre crack: 1.54 kB at
/// 500 × 250 elements, 0.82 kB at 1000 × 500, 0.77 kB at 2000 × 1000 (the allocator keeps more
/// of a small one); the largest, rounded up.
const FIELD_BYTES_PER_ELEMENT: usize = 1600;

/// Wall time to build and write one snapshot, per bulk element [s]: 1.7e-6 at 500 × 250
/// elements, 2.4e-6 at 1000 × 500, 2.8e-6 at 2000 × 1000 (centre crack, 2 cores); rounded up.
const FIELD_SECONDS_PER_ELEMENT: f64 = 3e-6;

/// Size of a snapshot's files per bulk element and per facet of the interface row [B]: the
/// binary arrays (points, u, v, connectivity, offsets, type, five stresses: 153 B per element;
/// two points and two lines per facet: 354 B) as base64 text, 4/3 of that.
const FIELD_FILE_BYTES: [f64; 2] = [205.0, 480.0];

/// The ParaView snapshots of a run of `scene`: (how many, bytes on disk of each), `None`
/// without `[fem.paraview]`.
pub fn field_files(scene: &Scene) -> Option<(u64, u64)> {
    let p = scene.fem.paraview?;
    let b = bulk(scene);
    let dt = scene.time_step();
    let count = p.count(dt, (scene.duration() / dt).ceil() as u64);
    Some((
        count,
        (FIELD_FILE_BYTES[0] * b.elements + FIELD_FILE_BYTES[1] * b.facets) as u64,
    ))
}

/// Steps while the far field's ramps accelerate, when a part carries the far field (0 otherwise).
fn far_field_steps(scene: &Scene) -> f64 {
    let far_field = scene
        .fem
        .boundary
        .as_ref()
        .is_some_and(|b| b.curves.iter().any(|c| c.far_field));
    if !far_field {
        return 0.0;
    }
    let l = &scene.loading;
    let span = |r: &crate::scene::Ramp| {
        let (a, b) = (r.ramp_start.min(l.duration), r.ramp_end.min(l.duration));
        (r.initial != r.final_value && b > a).then_some((a, b))
    };
    let (a, b) = match (span(&l.normal), span(&l.shear)) {
        (Some(p), Some(q)) => (p.0.min(q.0), p.1.max(q.1)),
        (Some(p), None) | (None, Some(p)) => p,
        (None, None) => return 0.0,
    };
    ((b - a) / scene.time_step()).ceil()
}

/// The model of a run as the estimate counts it: a Gmsh mesh's own elements and interface row (its
/// `[fem]` form holds its bounding box and the mean facet of its interface, whose grid would count
/// a graded mesh's elements many times over), else the grid's.
struct Bulk {
    /// Bulk elements [-].
    elements: f64,
    /// Facets of the interface row [-].
    facets: f64,
    /// Nodes of the interface row, one stress-profile row each in a snapshot [-].
    row_nodes: f64,
    /// Crack chains, one crack record each per sample [-].
    chains: f64,
    /// Memory of the model per element [B].
    bytes_each: usize,
    /// The model's part as printed, and the key that scales it.
    what: String,
    key: &'static str,
}

/// [`Bulk`] of a run of `scene`.
fn bulk(scene: &Scene) -> Bulk {
    match &scene.fem.mesh {
        Some(m) => {
            let row = m.prepared.row.as_ref();
            let elements = m.prepared.mesh.elements.len() as f64;
            let facets = row.map_or(0, |r| r.num_facets()) as f64;
            Bulk {
                elements,
                facets,
                row_nodes: facets + 1.0,
                chains: row.map_or(0, |r| r.num_chains()) as f64,
                bytes_each: GMSH_BYTES_PER_ELEMENT,
                what: format!("model ({elements} elements of the mesh)"),
                key: "fem.mesh.file",
            }
        }
        None => {
            let (nx, ny) = elements(scene);
            // one crack chain on the grid, along its interface row
            let interface = scene.interface.is_some() || scene.crack.is_some();
            Bulk {
                elements: nx * ny,
                facets: if interface { nx } else { 0.0 },
                row_nodes: nx + 1.0,
                chains: if interface { 1.0 } else { 0.0 },
                bytes_each: BYTES_PER_ELEMENT,
                what: format!("model ({nx} × {ny} elements)"),
                key: "fem.element_size",
            }
        }
    }
}

/// Elements along x and y.
fn elements(scene: &Scene) -> (f64, f64) {
    let f = &scene.fem;
    let h = f.element_size;
    (
        ((f.x_range[1] - f.x_range[0]) / h).round(),
        ((f.y_range[1] - f.y_range[0]) / h).round(),
    )
}

/// The bulk kernel a scene's mesh takes, as far as its time and its sharing of the cores go.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kernel {
    /// A Gmsh mesh.
    Gmsh,
    /// A grid of two materials that keeps one K_e an element (the separate passes).
    PerElement,
    /// A grid mapped onto an interface polyline or a sine (the mapped kernel).
    Mapped,
    /// The structured grid's stencils.
    Structured,
}

/// The bulk kernel of `scene`'s mesh, as the estimates price it.
fn kernel(scene: &Scene) -> Kernel {
    let f = &scene.fem;
    if f.mesh.is_some() {
        Kernel::Gmsh
    } else if scene.bottom_material.is_some() && !crate::model::build::split_grid_keeps_stencils(scene) {
        Kernel::PerElement
    } else if f.interface_polyline.is_some() {
        Kernel::Mapped
    } else {
        Kernel::Structured
    }
}

/// Whether runs of `scene` finish sooner one after the other, each on two cores, than two at a
/// time on one core each: true on a mesh mapped onto an interface (the mapped kernel). Measured on
/// 2 cores of an AMD EPYC with 32 MiB of L3 (docs/performance.md, "The comparison and the other
/// jobs"): such a run takes 1.79 times as long on one core as on two, and two side by side took a
/// third longer each again (`compare -- sinusoid` 46.9–47.1 s side by side against 37.0–38.2 s
/// one after the other, `compare -- rough` 27.4–29.6 against 19.3–20.5 s). Runs on the structured
/// grid came out even (`compare -- penalty` 20.8–21.5 against 20.2–22.7 s), so they keep sharing
/// the cores; the other kernels were not measured this way and keep it too.
pub fn runs_best_on_two_cores(scene: &Scene) -> bool {
    kernel(scene) == Kernel::Mapped
}

/// Steps and memory of a run of `scene` (docs/outputs.md, "Budgets").
pub fn estimate(scene: &Scene) -> Estimate {
    let f = &scene.fem;
    let h = f.element_size;
    let per_element_step = match kernel(scene) {
        Kernel::Gmsh => GMSH_SECONDS_PER_ELEMENT_STEP,
        Kernel::PerElement => PER_ELEMENT_SECONDS_PER_ELEMENT_STEP,
        Kernel::Mapped => MAPPED_SECONDS_PER_ELEMENT_STEP,
        Kernel::Structured => SECONDS_PER_ELEMENT_STEP,
    };
    let (nx, ny) = elements(scene);
    let dt = scene.time_step();
    let steps_f = (scene.duration() / dt).ceil();
    let every = (f.output_interval / dt).round().max(1.0);
    let samples = (steps_f / every).floor() + 2.0;
    let b = bulk(scene);
    // per sample: damage at 2 Gauss points per facet, face tractions per node of the row
    let row = if b.facets > 0.0 {
        2.0 * b.facets * size_of::<InterfaceRecord>() as f64 + b.row_nodes * size_of::<FaceRecord>() as f64
    } else {
        0.0
    };
    let d = &f.diagnostics;
    let per_sample = row
        + (size_of::<TipRecord>() + size_of::<EnergyRecord>() + size_of::<ContactMeanRecord>()) as f64
        + b.chains * size_of::<CrackRecord>() as f64
        // one crack-tip record per crack: counted as two cracks per chain
        + 2.0 * b.chains * size_of::<CrackTipRecord>() as f64
        + f.probes.len() as f64 * size_of::<ProbeRecord>() as f64
        // one boundary record per side, curve or point of [fem.boundary]
        + f.boundary.as_ref().map_or(0, |bd| bd.curves.len()) as f64 * size_of::<BoundaryRecord>() as f64
        + if d.kkt_metric {
            size_of::<KktRecord>() as f64
        } else {
            0.0
        };
    let [[x0, x1], [y0, y1]] = d.snapshot_window;
    let window_elements =
        (((x1 - x0).max(0.0) / h).ceil().min(nx) * ((y1 - y0).max(0.0) / h).ceil().min(ny)).min(b.elements);
    let snapshots = d.snapshot_times.len() as f64
        * (window_elements * size_of::<FieldRecord>() as f64
            + b.row_nodes * size_of::<ProfileRecord>() as f64);
    let fields = field_files(scene).map_or(0.0, |(count, _)| count as f64);
    let mut estimate = Estimate {
        steps: if steps_f.is_finite() {
            steps_f as u64
        } else {
            u64::MAX
        },
        steps_keys: "loading.duration, fem.element_size or fem.time_step_safety",
        seconds: (steps_f * per_element_step
            + far_field_steps(scene) * (FAR_FIELD_SECONDS_PER_ELEMENT_STEP - per_element_step).max(0.0)
            + fields * FIELD_SECONDS_PER_ELEMENT)
            * b.elements,
        parts: vec![
            Part {
                what: b.what,
                bytes: bytes_of(b.elements, b.bytes_each),
                key: b.key,
            },
            Part {
                what: format!("records ({samples} samples)"),
                bytes: bytes_of(samples, 1).saturating_mul(per_sample as u64),
                key: "fem.output_interval",
            },
            Part {
                what: "stress snapshots".to_string(),
                bytes: bytes_of(snapshots, 1),
                key: "fem.diagnostics.snapshot_times",
            },
        ],
    };
    if fields > 0.0 {
        estimate.parts.push(Part {
            what: "ParaView snapshot (one at a time)".to_string(),
            bytes: bytes_of(b.elements, FIELD_BYTES_PER_ELEMENT),
            key: "fem.paraview",
        });
    }
    estimate
}

#[cfg(test)]
mod tests {
    use super::*;
    use preflight::Budget;

    fn scene(edit: &[(&str, &str)]) -> Scene {
        let mut text = include_str!("../../../scenes/center-crack.toml").to_string();
        for (from, to) in edit {
            assert!(text.contains(from), "{from}");
            text = text.replace(from, to);
        }
        Scene::from_toml_str(&text).unwrap()
    }

    #[test]
    fn the_centre_crack_fits_the_default_budget() {
        let e = estimate(&scene(&[]));
        // 500 × 250 elements at 256 B, 1001 samples of a 500-facet row
        assert!(e.bytes() > 30 << 20 && e.bytes() < 1 << 30, "{}", e.summary());
        assert!((10_000..20_000).contains(&e.steps), "{}", e.steps);
        assert!(Budget::default().check(&e).is_ok());
    }

    #[test]
    fn a_tiny_output_interval_is_priced_and_refused() {
        // a sample every step (the interval is rounded to whole steps) for 20 T: 262 000 samples, 14 GB
        let e = estimate(&scene(&[
            (
                "output_interval = 2e-5          # s\n",
                "output_interval = 1e-15\n",
            ),
            ("duration = 0.02 ", "duration = 0.4 "),
        ]));
        let msg = Budget::default().check(&e).unwrap_err();
        assert!(msg.contains("fem.output_interval"), "{msg}");
    }

    #[test]
    fn field_snapshots_are_priced_only_when_declared() {
        let off = estimate(&scene(&[]));
        let on = estimate(&scene(&[(
            "\n[spectral]",
            "\n[fem.paraview]\ninterval = 1e-3\n\n[spectral]",
        )]));
        // 500 × 250 elements at 1.6 kB while a snapshot is written
        assert_eq!(on.bytes() - off.bytes(), 125_000 * 1600);
        assert!(on.seconds > off.seconds);
        assert_eq!(field_files(&scene(&[])), None);
        let (count, bytes) = field_files(&scene(&[(
            "\n[spectral]",
            "\n[fem.paraview]\ninterval = 1e-3\n\n[spectral]",
        )]))
        .unwrap();
        // T = 0.02 s: t = 0, 20 intervals (to whole steps) and possibly the last step
        assert!((21..=22).contains(&count), "{count}");
        // a 125 000-element bulk file measured 25.6 MB, the 500-facet crack file 0.24 MB
        assert!((25_000_000..26_500_000).contains(&bytes), "{bytes}");
    }

    #[test]
    fn a_gmsh_mesh_is_priced_by_its_own_elements_and_facets() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/center-crack-tri.toml");
        let scene = Scene::from_file(&path).unwrap();
        let m = scene.fem.mesh.as_ref().unwrap();
        let (elements, facets) = (
            m.prepared.mesh.elements.len(),
            m.prepared.row.as_ref().unwrap().num_facets(),
        );
        // the file's 43 138 triangles, not the 653 × 327 of a grid of its mean interface facet
        // over its bounding box
        assert_eq!(elements, 43_138);
        let b = bulk(&scene);
        assert_eq!((b.elements, b.facets), (elements as f64, facets as f64));
        let e = estimate(&scene);
        let model = &e.parts[0];
        assert!(
            model.what.contains("43138 elements of the mesh"),
            "{}",
            model.what
        );
        assert_eq!(model.bytes, 43_138 * GMSH_BYTES_PER_ELEMENT as u64);
        assert_eq!(model.key, "fem.mesh.file");
        // about 1.6e10 element-steps at 1e-8 s: the run measured 6–10 s on two machines
        let element_steps = e.steps as f64 * elements as f64;
        assert!((e.seconds - element_steps * GMSH_SECONDS_PER_ELEMENT_STEP).abs() < 1e-9 * e.seconds);
    }

    /// A split `[material]` is priced by the path its build takes: with its y = 0 row twinned the
    /// grid keeps the stencils and the sweep of one material (the structured grid's rate, where a
    /// price of one K_e an element made `scenes/bimaterial-crack.toml` about 59 s on two cores
    /// against 9.2 s measured on one thread); without the twin, one K_e an element.
    #[test]
    fn a_split_grid_is_priced_by_the_path_its_build_takes() {
        let text = crate::test_scenes::scene_text("tiny-fem-bimaterial-grid");
        let interface = &text[text.find("[interface]").unwrap()..text.find("[loading]").unwrap()];
        let dir = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes"));
        for (body, rate) in [
            (text.clone(), SECONDS_PER_ELEMENT_STEP),
            (text.replace(interface, ""), PER_ELEMENT_SECONDS_PER_ELEMENT_STEP),
        ] {
            let scene = Scene::from_toml_str_in(&body, dir).unwrap();
            let e = estimate(&scene);
            let steps = e.steps as f64;
            let far = far_field_steps(&scene);
            let want = (steps * rate + far * (FAR_FIELD_SECONDS_PER_ELEMENT_STEP - rate).max(0.0))
                * bulk(&scene).elements;
            assert!(
                (e.seconds - want).abs() < 1e-9 * want,
                "{} s against {want} s",
                e.seconds
            );
        }
    }

    #[test]
    fn a_fine_mesh_is_priced_and_refused() {
        let e = estimate(&scene(&[("element_size = 1e-3", "element_size = 1e-5")]));
        let msg = Budget::default().check(&e).unwrap_err();
        assert!(
            msg.contains("fem.element_size") || msg.contains("--max-steps"),
            "{msg}"
        );
    }
}
