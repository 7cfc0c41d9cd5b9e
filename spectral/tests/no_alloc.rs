//! The no-allocation rule: nothing is allocated after `build()`. Two runs of the same scene that differ only
//! in the number of steps (100 vs 200) must make the same number of heap allocations, up to rayon's
//! internal queue blocks: everything the time loop needs is allocated once, before the loop (record
//! vectors are reserved for the run).

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicU64, Ordering};

struct Counting;

static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

// SAFETY: forwards to the system allocator; only counts calls.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: same contract as the caller's.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// `steps` steps of a small §7.7 crack; the direct path uses kernel_cutoff = 0.4 so that every window
/// L_j (≤ 64 steps) is set by the cutoff, not by the run length, and both runs build identical models.
fn scene(steps: u32, convolution: &str) -> spectral::Scene {
    let cutoff = if convolution == "direct" {
        "kernel_cutoff = 0.4"
    } else {
        "kernel_cutoff = 100.0"
    };
    let text = include_str!("../../scenes/tiny-spectral-andrews.toml")
        .replace("kernel_cutoff = 100.0", cutoff)
        .replace(
            "duration = 90.0",
            &format!("duration = {}", f64::from(steps) * 0.25 * 0.125),
        )
        .replace("grid_points = 2048", "grid_points = 256")
        .replace("length = 256.0", "length = 32.0")
        .replace(
            "output_interval = 1.0",
            &format!("output_interval = 0.1\nfield_output_interval = 0.5\nconvolution = \"{convolution}\""),
        );
    spectral::Scene::from_toml_str(&text).expect("scene")
}

fn allocations_of(s: &spectral::Scene) -> u64 {
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    let out = spectral::run(s).expect("run");
    let after = ALLOCATIONS.load(Ordering::SeqCst);
    assert!(out.stats.steps > 50);
    drop(out);
    after - before
}

// rayon's global injector (crossbeam `Injector`) allocates one 63-slot block per 63 parallel regions
// entered from outside the pool; the solver enters at most 2 per step (convolution, interface law),
// so 100 more steps may add ⌈200/63⌉ = 4 blocks. The solver's own code must add nothing: any per-step
// allocation would add ≥ 100. (At this size the fast path runs both loops inline: exactly 0.)
const RAYON_BLOCKS: u64 = 4;

#[test]
fn time_loop_does_not_allocate() {
    for conv in ["fast", "direct"] {
        // Warm-up: the rayon pool and its per-thread state are created on first use.
        allocations_of(&scene(100, conv));
        let a100 = allocations_of(&scene(100, conv));
        let a200 = allocations_of(&scene(200, conv));
        let extra = a200 - a100;
        println!("{conv}: allocations for 100 steps {a100}, for 200 steps {a200} ({extra} extra)");
        assert!(
            extra <= RAYON_BLOCKS,
            "{conv}: the time loop allocates ({extra} extra for 100 more steps)"
        );
    }
}
