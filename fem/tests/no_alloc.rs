//! The no-allocation rule: nothing is allocated after `build()`. A counting global allocator watches
//! 200 steps of a small centre crack that exercises every part of the step (bulk, Westergaard
//! boundary, contact with friction, cohesive insertion and law, damping, sampling energies), and
//! 50 force evaluations of the unstructured T3/Q4 kernel on the committed mixed mesh, and 200 steps
//! of a scene on that mesh (prescribed ramp, rollers, a probe). The checks run one
//! after the other in the binary's only test: the test harness allocates on its own
//! threads while a second test runs, which the global counter would see.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

struct Counting;

static COUNTING: AtomicBool = AtomicBool::new(false);
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.load(Ordering::Relaxed) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if COUNTING.load(Ordering::Relaxed) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn nothing_allocates_after_set_up() {
    time_steps_do_not_allocate();
    unstructured_forces_do_not_allocate();
    unstructured_steps_do_not_allocate();
}

fn time_steps_do_not_allocate() {
    ALLOCATIONS.store(0, Ordering::SeqCst);
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/tiny-fem-center-crack.toml"
    );
    let scene = fem::Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let (model, mut state, mut ws) = fem::build(&scene).unwrap();
    // warm-up: rayon's pool, its deques and thread-local latches are created on first use
    // (broadcast waits until every worker thread has started: thread start-up allocates)
    rayon::broadcast(|_| ());
    rayon::scope(|_| {
        for _ in 0..5 {
            fem::step(&model, &mut state, &mut ws, true).unwrap();
        }
    });
    let before = state.num_inserted();
    // as in fem::run: the steps run on a rayon pool thread (jobs injected from outside the pool
    // go through a queue that allocates blocks; inside, each worker uses its own deque)
    rayon::scope(|_| {
        COUNTING.store(true, Ordering::SeqCst);
        for n in 0..400 {
            fem::step(&model, &mut state, &mut ws, n % 10 == 0).unwrap();
        }
        COUNTING.store(false, Ordering::SeqCst);
    });
    let allocations = ALLOCATIONS.load(Ordering::SeqCst);
    println!(
        "400 steps: {allocations} allocations; cohesive elements inserted {} -> {}",
        before,
        state.num_inserted()
    );
    assert!(
        state.num_inserted() > before,
        "the window must include insertions"
    );
    assert_eq!(allocations, 0, "the time step allocated");
}

fn unstructured_forces_do_not_allocate() {
    ALLOCATIONS.store(0, Ordering::SeqCst);
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../meshes/rect_mixed.msh");
    let mesh = fem::gmsh::UnstructuredMesh::read(std::path::Path::new(path)).unwrap();
    let mat = fem::law::elastic::PlaneStrain::new(70e6, 0.35, 1230.0);
    let bulk = fem::model::unstructured::UnstructuredBulk::new(&mesh, &mat.d_matrix(), mat.density).unwrap();
    let u: Vec<fem::nalgebra::Vector2<f64>> = mesh.positions.iter().map(|x| x * 1e-3).collect();
    let mut f = vec![fem::nalgebra::Vector2::zeros(); u.len()];
    // warm-up: rayon's pool and its thread-local state are created on first use; the calls run
    // on a pool thread, as the time loop's do (jobs injected from outside go through a queue
    // that allocates)
    rayon::broadcast(|_| ());
    rayon::scope(|_| bulk.internal_forces(&u, &mut f));
    rayon::scope(|_| {
        COUNTING.store(true, Ordering::SeqCst);
        for _ in 0..50 {
            bulk.internal_forces(&u, &mut f);
        }
        COUNTING.store(false, Ordering::SeqCst);
    });
    assert!(f.iter().any(|fa| fa.norm() > 0.0));
    assert_eq!(
        ALLOCATIONS.load(Ordering::SeqCst),
        0,
        "the unstructured force evaluation allocated"
    );
}

fn unstructured_steps_do_not_allocate() {
    ALLOCATIONS.store(0, Ordering::SeqCst);
    // the committed mixed T3/Q4 mesh, bulk only: a displacement ramp on the left side, rollers on
    // top and bottom, a probe inside
    let text = r#"
        name = "no-alloc-mixed-mesh"
        [material]
        youngs_modulus = 70e6
        poisson_ratio = 0.35
        density = 1230.0
        [loading]
        duration = 1e-2
        [fem]
        time_step_safety = 0.5
        output_interval = 1e-4
        probes = [[1.0, 0.5]]
        [fem.mesh]
        file = "rect_mixed.msh"
        bulk = ["bulk"]
        [fem.boundary.left]
        x = { kind = "displacement", initial = 0.0, final = 1e-5, ramp_start = 0.0, ramp_end = 1e-3 }
        [fem.boundary.top]
        y = { kind = "displacement", initial = 0.0, final = 0.0, ramp_start = 0.0, ramp_end = 0.0 }
        [fem.boundary.bottom]
        y = { kind = "displacement", initial = 0.0, final = 0.0, ramp_start = 0.0, ramp_end = 0.0 }
    "#;
    let meshes = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../meshes"));
    let scene = fem::Scene::from_toml_str_in(text, meshes).unwrap();
    let (model, mut state, mut ws) = fem::build(&scene).unwrap();
    rayon::broadcast(|_| ());
    rayon::scope(|_| {
        for _ in 0..10 {
            fem::step(&model, &mut state, &mut ws, true).unwrap();
        }
    });
    rayon::scope(|_| {
        COUNTING.store(true, Ordering::SeqCst);
        for n in 0..200 {
            fem::step(&model, &mut state, &mut ws, n % 2 == 0).unwrap();
        }
        COUNTING.store(false, Ordering::SeqCst);
    });
    assert!(state.displacements().iter().any(|u| u.x > 0.0));
    assert_eq!(
        ALLOCATIONS.load(Ordering::SeqCst),
        0,
        "a step on the Gmsh mesh allocated"
    );
}
