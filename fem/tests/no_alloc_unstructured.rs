//! The unstructured bulk kernel allocates nothing per evaluation: a counting global allocator
//! watches 50 force evaluations on the committed mixed T3/Q4 mesh (its own test binary, so no
//! other test allocates while it counts).

use fem::gmsh::UnstructuredMesh;
use fem::model::unstructured::UnstructuredBulk;
use fem::nalgebra::Vector2;
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
fn unstructured_forces_do_not_allocate() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../meshes/rect_mixed.msh");
    let mesh = UnstructuredMesh::read(std::path::Path::new(path)).unwrap();
    let mat = fem::law::elastic::PlaneStrain::new(70e6, 0.35, 1230.0);
    let bulk = UnstructuredBulk::new(&mesh, &mat.d_matrix(), mat.density).unwrap();
    let u: Vec<Vector2<f64>> = mesh.positions.iter().map(|x| x * 1e-3).collect();
    let mut f = vec![Vector2::zeros(); u.len()];
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
    assert_eq!(ALLOCATIONS.load(Ordering::SeqCst), 0);
}
